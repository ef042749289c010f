//! Seeded random rays for the map tests (SplitMix64: small, deterministic, no dependency).

use relief::heightfield::reference::RefRay;

/// A SplitMix64 stream of uniform numbers in [0, 1).
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }

    /// Elevation in [5, 90] degrees, any azimuth, entry anywhere in the first tile.
    pub fn ray(&mut self) -> RefRay {
        let e = self.range(5.0, 90.0).to_radians();
        let a = self.range(0.0, 360.0).to_radians();
        RefRay {
            u0: self.next(),
            v0: self.next(),
            dx: e.cos() * a.cos(),
            dy: e.cos() * a.sin(),
            dz: e.sin(),
        }
    }
}

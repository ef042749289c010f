//! Small deterministic random numbers for the synthetic generators.
//!
//! SplitMix64 (Steele, Lea and Flood 2014): one 64-bit state, a Weyl increment and a strong output mix. It is
//! not cryptographic; it is tiny, fast, portable and gives the same stream on every platform, which is what
//! reproducible benchmarks need. `hash` exposes the same output mix as a stateless function so that lattice
//! values (value noise, per-brick offsets) depend only on their coordinates, never on visiting order.

/// The golden-ratio Weyl increment of SplitMix64.
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// A seeded SplitMix64 stream.
#[derive(Debug, Clone)]
pub(crate) struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A stream determined entirely by `seed`.
    pub(crate) fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GAMMA);
        mix(self.state)
    }

    /// Uniform in [0, 1), on a 2^-24 grid so that every value is exact in `f32`.
    pub(crate) fn next_f32(&mut self) -> f32 {
        unit_f32(self.next_u64())
    }

    /// Uniform in `0..n` (`n > 0`), by Lemire's multiply-high; the bias is below 2^-32 for any `u32` range.
    pub(crate) fn below(&mut self, n: u32) -> u32 {
        (((self.next_u64() >> 32) * u64::from(n)) >> 32) as u32
    }
}

/// The SplitMix64 output mix: a bijection on `u64` with full avalanche.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Maps 64 random bits to [0, 1) using the top 24 bits.
fn unit_f32(bits: u64) -> f32 {
    (bits >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// A stateless hash of a seed and three coordinates to [0, 1).
///
/// Each coordinate is folded in through a full mix so that nearby coordinates give unrelated values.
pub(crate) fn hash_unit(seed: u64, a: u64, b: u64, c: u64) -> f32 {
    let mut h = mix(seed.wrapping_add(GAMMA));
    for x in [a, b, c] {
        h = mix(h ^ x.wrapping_mul(GAMMA));
    }
    unit_f32(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_the_reference_stream() {
        // First outputs of the reference C implementation seeded with 1234567.
        let mut rng = SplitMix64::new(1234567);
        let expected = [
            6457827717110365317u64,
            3203168211198807973,
            9817491932198370423,
            4593380528125082431,
            16408922859458223821,
        ];
        for e in expected {
            assert_eq!(rng.next_u64(), e);
        }
    }

    #[test]
    fn unit_values_stay_in_range_and_below_respects_bound() {
        let mut rng = SplitMix64::new(7);
        for _ in 0..10_000 {
            let x = rng.next_f32();
            assert!((0.0..1.0).contains(&x));
            assert!(rng.below(17) < 17);
        }
        assert_eq!(rng.below(1), 0);
        let h = hash_unit(1, 2, 3, 4);
        assert!((0.0..1.0).contains(&h));
        assert_eq!(h, hash_unit(1, 2, 3, 4));
        assert_ne!(h, hash_unit(1, 2, 3, 5));
    }
}

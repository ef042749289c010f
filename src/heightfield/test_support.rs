//! What the height field unit tests share: fields made from a function of the texel, and a seeded
//! random stream (SplitMix64, so every failure reproduces).

use super::rng::SplitMix64;
use super::Heightfield;

/// A `w` x `h` field whose texel `(i, j)` holds `f(i, j)`.
pub(crate) fn field(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Heightfield {
    let data = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| f(i, j))
        .collect();
    Heightfield::new(w, h, data).expect("a valid test field")
}

/// Seeded random numbers for test cases.
pub(crate) struct Rng(SplitMix64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Rng {
        Rng(SplitMix64::new(seed))
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in [0, 1), on a 2^-53 grid.
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in `0..n` (modulo bias is irrelevant for picking test cases).
    pub(crate) fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

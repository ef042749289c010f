//! The soak tests' side of `relief::bench::soak`: a sample that must be readable here (the
//! tests run where /proc is).

use relief::vk::Context;

// Not every test binary that includes `common` uses each of them.
#[allow(unused_imports)]
pub use relief::bench::soak::{growth, judge, Limits, Sample};

/// Takes a sample of `ctx` now.
pub fn sample(ctx: &Context, frame: u32) -> Sample {
    relief::bench::soak::sample(ctx, frame).expect("/proc/self/status is readable")
}

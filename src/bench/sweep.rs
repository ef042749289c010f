//! What `relief bench` measures: the sections of the sweep (error against run time, scaling with
//! map size, depth scale), each a small grid over the options, with defaults for a meaningful
//! full sweep and a `--quick` one small enough for CI on lavapipe.

use std::path::PathBuf;

use super::slow_down::SlowDown;
use crate::heightfield::{Address, Generator};
use crate::method::{Budget, Leaf, Method};
use crate::render::HeightFormat;

/// Where a height field comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum FieldSource {
    /// A generated field, made at each size asked for.
    Synthetic(Generator),
    /// A PNG height map, loaded from this path.
    File(PathBuf),
}

impl FieldSource {
    /// The name reports use.
    pub fn name(&self) -> String {
        match self {
            FieldSource::Synthetic(g) => g.name().to_owned(),
            FieldSource::File(p) => p
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
        }
    }
}

/// Every option of a bench run.
#[derive(Debug, Clone)]
pub struct SweepConfig {
    /// Methods to measure.
    pub methods: Vec<Method>,
    /// Height fields to measure them on.
    pub fields: Vec<FieldSource>,
    /// Map sides for the scaling section; the first is the size of every other section.
    pub sizes: Vec<u32>,
    /// View elevations above the surface plane, in degrees (90 = straight down).
    pub angles: Vec<f64>,
    /// View azimuths from +u toward +v, in degrees.
    pub azimuths: Vec<f64>,
    /// The first is the depth scale of every section but the depth-scale one.
    pub depth_scales: Vec<f64>,
    /// Iteration caps tried on the fixed-step methods besides their default budget.
    pub budgets: Vec<u32>,
    /// Rays per timed frame, as a (width, height) grid.
    pub resolution: (u32, u32),
    /// Timed frames per configuration.
    pub frames: u32,
    /// Untimed frames run before them, in every pass.
    pub warmup: u32,
    /// Timed passes over the sweep's runs: each configuration's frames are split over this many
    /// passes (see [`SweepConfig::frames_in_pass`]), so that a slow spell of the machine falls on
    /// part of every method's frames rather than on all of one method's.
    pub passes: u32,
    /// Rays per configuration for the error measurement.
    pub error_grid: (u32, u32),
    /// Addressing mode of every map.
    pub address: Address,
    /// Texel format the heights are uploaded in.
    pub format: HeightFormat,
    /// Seed of the synthetic generators.
    pub seed: u64,
    /// Run the stability matrix (stiff and extreme cases) too.
    pub stability: bool,
    /// Also run each method with a leaf choice with the paper's refinement (error vs time).
    pub paper_leaf: bool,
    /// The small CI variant: fewer and smaller cases.
    pub quick: bool,
    /// Methods slowed on purpose (`--slow-down`, for testing `bench compare`); empty to measure.
    pub slow_down: Vec<SlowDown>,
}

impl SweepConfig {
    /// The full default sweep.
    pub fn full() -> SweepConfig {
        SweepConfig {
            methods: Method::all().collect(),
            fields: vec![
                FieldSource::Synthetic(Generator::Fbm),
                FieldSource::Synthetic(Generator::Bricks),
            ],
            sizes: vec![1024, 256, 512, 2048, 4096],
            angles: vec![5.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0],
            azimuths: vec![30.0],
            depth_scales: vec![0.1, 0.02, 0.05, 0.2, 0.5, 1.0],
            // POM's quality tiers in engines (o3de: 16, 32, 64, 128 steps).
            budgets: vec![16, 32, 64, 128],
            resolution: (1024, 1024),
            frames: 10,
            warmup: 2,
            passes: 3,
            error_grid: (128, 128),
            address: Address::Repeat,
            format: HeightFormat::R16Unorm,
            seed: 1,
            stability: true,
            paper_leaf: true,
            quick: false,
            slow_down: Vec::new(),
        }
    }

    /// The CI sweep: every method, tiny maps and images, a few views.
    pub fn quick() -> SweepConfig {
        SweepConfig {
            fields: vec![FieldSource::Synthetic(Generator::Fbm)],
            sizes: vec![128, 64, 256],
            angles: vec![10.0, 30.0, 90.0],
            depth_scales: vec![0.1, 0.5],
            budgets: vec![16, 64],
            resolution: (128, 128),
            frames: 3,
            warmup: 1,
            passes: 3,
            error_grid: (32, 32),
            paper_leaf: false,
            quick: true,
            ..SweepConfig::full()
        }
    }

    /// Budgets to run `method` with: its default, for fixed-step methods each listed cap, and
    /// with `paper_leaf` the paper's refinement for methods with a leaf choice.
    pub fn budgets_for(&self, method: Method) -> Vec<Budget> {
        let default = method.info().default_budget;
        let mut list = vec![default];
        if self.paper_leaf && method.info().leaf_choice {
            list.push(Budget {
                leaf: Leaf::Paper,
                ..default
            });
        }
        if method.info().fixed_step {
            for &steps in &self.budgets {
                let b = Budget {
                    max_steps: steps,
                    ..default
                };
                if !list.contains(&b) {
                    list.push(b);
                }
            }
        }
        list
    }

    /// Trace dispatches per timed frame of `method`: 1, or its `--slow-down` factor.
    pub fn dispatches_per_frame(&self, method: Method) -> u32 {
        self.slow_down
            .iter()
            .find(|s| s.method == method)
            .map_or(1, |s| s.factor)
    }

    /// Timed frames of each configuration in pass `pass` (from 0): `frames` split as evenly as
    /// they go over the passes, the earlier passes taking the remainder; 0 past the last pass or
    /// beyond the frames.
    pub fn frames_in_pass(&self, pass: u32) -> u32 {
        let passes = self.effective_passes();
        if pass >= passes {
            return 0;
        }
        self.frames / passes + u32::from(pass < self.frames % passes)
    }

    /// Passes actually run: `passes`, but never more than the frames to split (at least 1).
    pub fn effective_passes(&self) -> u32 {
        self.passes.clamp(1, self.frames.max(1))
    }

    /// The map side of every section but scaling.
    pub fn main_size(&self) -> u32 {
        self.sizes.first().copied().unwrap_or(256)
    }

    /// The depth scale of every section but the depth-scale one.
    pub fn main_depth_scale(&self) -> f64 {
        self.depth_scales.first().copied().unwrap_or(0.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(frames: u32, passes: u32) -> Vec<u32> {
        let cfg = SweepConfig {
            frames,
            passes,
            ..SweepConfig::quick()
        };
        (0..cfg.effective_passes())
            .map(|p| cfg.frames_in_pass(p))
            .collect()
    }

    #[test]
    fn passes_share_the_frames_evenly_and_never_lose_one() {
        assert_eq!(split(10, 3), [4, 3, 3]);
        assert_eq!(split(9, 3), [3, 3, 3]);
        assert_eq!(split(2, 3), [1, 1], "no pass without a frame");
        assert_eq!(split(5, 0), [5], "zero passes is one");
        for frames in 1..40 {
            for passes in 0..8 {
                assert_eq!(split(frames, passes).iter().sum::<u32>(), frames);
            }
        }
    }
}

//! What `relief bench` records (DESIGN.md section 3): the device, one object per measured
//! configuration, the map build times and the stability matrix, written as `results.json`.

use serde::Serialize;

use super::ao::AoRun;
use super::shading::ShadowRun;
use super::shadow_stability::ShadowStabilityCell;
use super::subgroup_steps::TimedSteps;
use super::trace_stats::{Spread, StepStats};
use crate::method::Budget;
use crate::vk::DeviceInfo;

/// Median, minimum and maximum GPU time of the timed frames.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct GpuMs {
    pub median: f64,
    pub min: f64,
    pub max: f64,
}

impl GpuMs {
    /// Summarises frame times; empty input gives zeros.
    pub fn of(frames: &[f64]) -> GpuMs {
        let mut sorted = frames.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        if n == 0 {
            return GpuMs {
                median: 0.0,
                min: 0.0,
                max: 0.0,
            };
        }
        let median = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
        };
        GpuMs {
            median,
            min: sorted[0],
            max: sorted[n - 1],
        }
    }
}

/// One measured configuration: a method on a height field at one view, scale and budget.
#[derive(Debug, Clone, Serialize)]
pub struct Run {
    pub section: super::runner::Section,
    pub method: String,
    pub heightfield: String,
    pub size: [u32; 2],
    pub depth_scale: f64,
    pub angle_deg: f64,
    pub azimuth_deg: f64,
    pub address: String,
    pub budget: Budget,
    pub gpu_ms: GpuMs,
    pub frames: u32,
    pub resolution: [u32; 2],
    /// CPU wall time of the whole timed submission, for context.
    pub cpu_ms: f64,
    pub error_texels: Spread,
    pub depth_error_texels: Spread,
    pub gross_rate: f64,
    pub capped_rate: f64,
    pub nan_pixels: usize,
    /// Iterations of the error trace's rays.
    pub steps: StepStats,
    /// Iterations of the timed rays, and what their subgroups paid.
    pub timed_steps: TimedSteps,
}

/// Time to build one precomputed map.
#[derive(Debug, Clone, Serialize)]
pub struct MapBuild {
    pub kind: String,
    pub heightfield: String,
    pub size: [u32; 2],
    /// GPU ms for maps built on the GPU, CPU wall ms for those built on the CPU.
    pub ms: f64,
    /// Which builder built it: "gpu" or "cpu".
    pub on: &'static str,
}

/// One cell of the stability matrix: a method on a named stiff case.
#[derive(Debug, Clone, Serialize)]
pub struct StabilityCell {
    pub method: String,
    pub case: String,
    pub nan_pixels: usize,
    pub capped_rate: f64,
    pub gross_rate: f64,
    pub max_error_texels: f64,
    /// The trace's GPU time (the fastest timed dispatch), in ms.
    pub gpu_ms: Option<f64>,
    /// Why the case could not run for this method (an error), if it could not.
    pub failed: Option<String>,
}

/// The whole of `results.json`.
#[derive(Debug, Clone, Serialize)]
pub struct BenchResults {
    pub device: BenchDevice,
    pub command: String,
    pub runs: Vec<Run>,
    pub maps: Vec<MapBuild>,
    pub stability: Vec<StabilityCell>,
    /// The shading section: shadow modes against the exact visible fraction.
    pub shadows: Vec<ShadowRun>,
    /// Shadow modes under extreme lights on degenerate fields.
    pub shadow_stability: Vec<ShadowStabilityCell>,
    /// The AO modes' maps against the exact AO, with their build times.
    pub ao: Vec<AoRun>,
    /// The level-of-detail section (`None` when skipped, e.g. `--no-lod`).
    pub lod: Option<super::lod::LodSection>,
    /// The terrain-edit section (empty when skipped, e.g. `--no-edits`).
    pub edits: Vec<super::edits::EditCost>,
    /// The weight-painting costs beside it (empty when skipped, e.g. `--no-edits`).
    pub paint_edits: Vec<super::paint_edits::PaintCost>,
    /// The terrain-blending section (`None` when skipped, e.g. `--no-blending`).
    pub blending: Option<super::blending::BlendingSection>,
}

/// The device every number was measured on.
#[derive(Debug, Clone, Serialize)]
pub struct BenchDevice {
    pub name: String,
    pub driver: String,
    pub api: String,
    pub timestamp_period: f32,
}

impl From<&DeviceInfo> for BenchDevice {
    fn from(i: &DeviceInfo) -> Self {
        BenchDevice {
            name: i.name.clone(),
            driver: i.driver.trim().to_owned(),
            api: i.api.clone(),
            timestamp_period: i.timestamp_period_ns,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::GpuMs;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(
            GpuMs::of(&[3.0, 1.0, 2.0]),
            GpuMs {
                median: 2.0,
                min: 1.0,
                max: 3.0
            }
        );
        assert_eq!(GpuMs::of(&[4.0, 1.0, 2.0, 3.0]).median, 2.5);
        assert_eq!(GpuMs::of(&[]).max, 0.0);
    }
}

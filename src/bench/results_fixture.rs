//! Small, made-up results for the unit tests of the results file and of `bench compare`: one
//! device, one build, runs whose only measurement is their frame samples.

use super::provenance::{BenchDevice, ReliefBuild, SweepOptions};
use super::results::{BenchResults, GpuMs, Run, SCHEMA_VERSION};
use super::runner::Section;
use super::sweep::SweepConfig;
use super::trace_stats::Spread;
use crate::method::Method;

/// A lavapipe-like device.
pub(crate) fn device(name: &str) -> BenchDevice {
    BenchDevice {
        name: name.to_owned(),
        driver: "Mesa 25.0".into(),
        api: "1.4.305".into(),
        kind: "cpu".into(),
        vendor_id: 0x10005,
        device_id: 0,
        timestamp_period: 1.0,
        ray_query: true,
        acceleration_structure: true,
        device_uuid: String::new(),
        driver_uuid: String::new(),
    }
}

/// `method` in the error-vs-time section at `angle`, with these frame times and mean error.
pub(crate) fn run(method: &str, angle: f64, samples: &[f64], error: f64) -> Run {
    let m: Method = method.parse().expect("a known method");
    Run {
        section: Section::ErrorVsTime,
        method: method.to_owned(),
        heightfield: "fbm".into(),
        size: [64, 64],
        depth_scale: 0.1,
        angle_deg: angle,
        azimuth_deg: 30.0,
        address: "repeat".into(),
        budget: m.info().default_budget,
        gpu_ms: GpuMs::of(samples),
        frames: samples.len() as u32,
        resolution: [64, 64],
        cpu_ms: 1.0,
        error_texels: Spread {
            mean: error,
            p99: 2.0 * error,
            max: 3.0 * error,
        },
        depth_error_texels: Spread::default(),
        gross_rate: 0.0,
        capped_rate: 0.0,
        nan_pixels: 0,
        steps: Default::default(),
        timed_steps: Default::default(),
        fetches: Default::default(),
        compute_invocations: None,
    }
}

/// A whole file around `runs`, measured on `device`.
pub(crate) fn results(device: BenchDevice, runs: Vec<Run>) -> BenchResults {
    BenchResults {
        schema_version: SCHEMA_VERSION,
        relief: ReliefBuild::current(),
        date: "2026-12-04T17:00:00Z".into(),
        device,
        command: "relief bench --quick --out x".into(),
        argv: ["relief", "bench", "--quick", "--out", "x"]
            .map(str::to_owned)
            .to_vec(),
        options: SweepOptions::from(&SweepConfig::quick()),
        runs,
        maps: Vec::new(),
        stability: Vec::new(),
        shadows: Vec::new(),
        shadow_stability: Vec::new(),
        ao: Vec::new(),
        lod: None,
        edits: Vec::new(),
        paint_edits: Vec::new(),
        blending: None,
        scene_shadows: None,
        frame_features: None,
        silhouettes: None,
        frame_costs: None,
        shard: None,
        machine: None,
        sections: None,
        steps_maps: Vec::new(),
    }
}

//! The AO part of the shading section: every AO mode's map built on the GPU, its build time, and
//! its error against the exact AO (`heightfield::ambient_occlusion`) at every texel of a small
//! field (the reference is computed once per field and shared by the modes), plus the build time
//! alone at the bench's main map size, where the reference would take too long.

use serde::{Deserialize, Serialize};

use super::runner::Runner;
use super::sweep::FieldSource;
use super::trace_stats::Spread;
use crate::heightfield::ambient_occlusion::ao_reference;
use crate::heightfield::Heightfield;
use crate::render::AoMapPass;
use crate::scene::AoMode;

/// What the AO part measures.
#[derive(Debug, Clone)]
pub struct AoConfig {
    /// Side of the field compared texel by texel with the exact reference.
    pub error_size: u32,
    /// Azimuth slices of the exact reference.
    pub reference_azimuths: u32,
    /// Also time each build at the sweep's main map size.
    pub time_main_size: bool,
}

impl AoConfig {
    /// The full sweep's settings: a 128^2 error field against a 256-azimuth reference, builds also timed at
    /// the main map size.
    pub fn full() -> AoConfig {
        AoConfig {
            error_size: 128,
            reference_azimuths: 256,
            time_main_size: true,
        }
    }

    /// `--quick`'s settings: a 48^2 error field, a 64-azimuth reference, no timing at the main size.
    pub fn quick() -> AoConfig {
        AoConfig {
            error_size: 48,
            reference_azimuths: 64,
            time_main_size: false,
        }
    }
}

/// One AO mode on one field.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AoRun {
    /// The AO mode's name.
    pub mode: String,
    /// The height field's name.
    pub heightfield: String,
    /// Depth of height 0 below the top plane, in uv units.
    pub depth_scale: f64,
    /// The field compared with the reference.
    pub size: [u32; 2],
    /// Per texel `|ao - exact|`, AO being the unoccluded fraction in [0, 1]; texels counted in `bad_values`
    /// are left out.
    pub error: Spread,
    /// Texels whose value is NaN or outside [0, 1].
    pub bad_values: usize,
    /// GPU time of the build at `size`.
    pub build_ms: f64,
    /// GPU time of the build at `main_size`, when measured.
    pub main_size: Option<[u32; 2]>,
    /// GPU ms of the build at `main_size`; `None` when not measured (`--quick`).
    pub main_build_ms: Option<f64>,
}

fn modes() -> Vec<AoMode> {
    AoMode::all().into_iter().filter(|m| m.is_some()).collect()
}

/// Measures every AO mode on `field`; `note` hears what runs next.
pub fn measure_ao(
    runner: &mut Runner,
    cfg: &AoConfig,
    field: &FieldSource,
    note: &mut dyn FnMut(&str),
) -> anyhow::Result<Vec<AoRun>> {
    let sweep = runner.config().clone();
    let small = runner.field(field, cfg.error_size)?;
    let main = if cfg.time_main_size {
        Some(runner.field(field, sweep.main_size())?)
    } else {
        None
    };
    let s = sweep.main_depth_scale();
    note(&format!("AO: exact reference on {}", field.name()));
    let reference = ao_reference(&small, s, sweep.address, cfg.reference_azimuths)?;
    let ctx = runner.ctx().clone();
    let mut runs = Vec::new();
    for mode in modes() {
        note(&format!("AO: {mode} on {}", field.name()));
        let pass = AoMapPass::new(&ctx, mode)?;
        let (values, build_ms) = pass.build(&small, s, sweep.address)?;
        let main_build = match &main {
            Some(hf) => Some((size_of(hf), pass.build(hf, s, sweep.address)?.1)),
            None => None,
        };
        let bad_values = values.iter().filter(|v| !(0.0..=1.0).contains(*v)).count();
        let diffs: Vec<f64> = values
            .iter()
            .zip(&reference)
            .filter(|(v, _)| (0.0..=1.0).contains(*v))
            .map(|(v, r)| f64::from((v - r).abs()))
            .collect();
        runs.push(AoRun {
            mode: mode.to_string(),
            heightfield: field.name(),
            depth_scale: s,
            size: size_of(&small),
            error: Spread::of(diffs),
            bad_values,
            build_ms,
            main_size: main_build.map(|(size, _)| size),
            main_build_ms: main_build.map(|(_, ms)| ms),
        });
    }
    Ok(runs)
}

fn size_of(hf: &Heightfield) -> [u32; 2] {
    [hf.width(), hf.height()]
}

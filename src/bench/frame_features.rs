//! The bench's frame-feature section: what each of the frame's looks costs on the default scene
//! (tone mapping, 4x MSAA, 2x2 supersampling, the sky's image-based light and background, and
//! `relief render`'s default with all of them) against the frame the method sweep times (one
//! sample, flat ambient light, no tone mapping), and the environment maps' one-time build.

use std::fmt::Write as _;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::frame_timing::time_interleaved;
use crate::environment::{Background, EnvironmentSource};
use crate::render::{RenderError, RenderOptions, ToneMap, ToneMapping};
use crate::scene::{default_heightfield, default_scene, DEFAULT_SCENE_METHOD};
use crate::vk::Context;

/// One look of the default scene's frame.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FrameFeatureRow {
    /// What the frame adds to the baseline.
    pub feature: String,
    /// GPU ms per steady frame (median).
    pub gpu_ms: f64,
    /// Of that, the surface pass (tone mapping and background included).
    pub surface_ms: f64,
    /// `gpu_ms` over the baseline's.
    pub ratio: f64,
}

/// The whole section.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FrameFeatureSection {
    /// Frame size.
    pub size: [u32; 2],
    /// Frames timed per row (after one untimed frame).
    pub frames: u32,
    /// The baseline first, then each feature alone, then all of them.
    pub rows: Vec<FrameFeatureRow>,
    /// GPU ms of building the sky's irradiance, prefiltered specular and BRDF table, once per
    /// renderer (`None` without timestamps).
    pub environment_build_ms: Option<f64>,
    /// The surface pass's growth with the sky's light per frame, as a share of the baseline's
    /// surface pass.
    pub ibl_share_of_surface: f64,
}

/// The features timed, each as options over the baseline's.
fn looks(size: [u32; 2]) -> Vec<(&'static str, RenderOptions)> {
    let base = RenderOptions {
        width: size[0],
        height: size[1],
        ..RenderOptions::default()
    };
    let neutral = ToneMapping {
        curve: ToneMap::PbrNeutral,
        exposure_ev: 0.0,
    };
    vec![
        (
            "baseline: 1 sample, flat ambient, no tone mapping",
            base.clone(),
        ),
        (
            "tone mapping (PBR Neutral)",
            RenderOptions {
                tone_mapping: neutral,
                ..base.clone()
            },
        ),
        (
            "4x MSAA (relief traced once per pixel)",
            RenderOptions {
                msaa: 4,
                ..base.clone()
            },
        ),
        (
            "2x2 supersampling",
            RenderOptions {
                supersample: 2,
                ..base.clone()
            },
        ),
        (
            "sky light (image-based, per frame)",
            RenderOptions {
                environment: EnvironmentSource::Sky,
                background: Background::Colour,
                ..base.clone()
            },
        ),
        (
            "sky light and background",
            RenderOptions {
                environment: EnvironmentSource::Sky,
                background: Background::Environment,
                ..base.clone()
            },
        ),
        (
            "relief render's default: 4x MSAA, PBR Neutral, sky light and background",
            RenderOptions {
                msaa: 4,
                tone_mapping: neutral,
                environment: EnvironmentSource::Sky,
                background: Background::Environment,
                ..base
            },
        ),
    ]
}

/// Runs the section; `quick` times fewer frames on a smaller image.
pub fn run_frame_feature_section(
    ctx: &Arc<Context>,
    quick: bool,
    mut progress: impl FnMut(&str),
) -> Result<FrameFeatureSection, RenderError> {
    let (size, frames) = if quick {
        ([480, 270], 3)
    } else {
        ([960, 540], 10)
    };
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let heights = default_heightfield();
    let looks = looks(size);
    progress("frame features: every look, frames in turn");
    let options: Vec<RenderOptions> = looks.iter().map(|(_, o)| o.clone()).collect();
    let timed = time_interleaved(ctx, &scene, Some(&heights), &options, frames)?;
    let baseline = timed.first().map_or(1.0, |t| t.total_ms).max(1e-9);
    let mut environment_build_ms = None;
    let mut sky_surface_ms = None;
    let mut rows = Vec::new();
    for ((feature, opts), t) in looks.iter().zip(&timed) {
        let sky_alone =
            opts.environment == EnvironmentSource::Sky && opts.background == Background::Colour;
        if sky_alone {
            environment_build_ms = t
                .maps
                .iter()
                .find(|m| m.kind == "environment maps" && m.on == "gpu")
                .map(|m| m.ms);
            sky_surface_ms = Some(t.surface_ms);
        }
        rows.push(FrameFeatureRow {
            feature: (*feature).to_owned(),
            gpu_ms: t.total_ms,
            surface_ms: t.surface_ms,
            ratio: t.total_ms / baseline,
        });
    }
    let base_surface = rows.first().map_or(0.0, |r| r.surface_ms);
    let ibl_share_of_surface = sky_surface_ms.map_or(0.0, |s| s / base_surface.max(1e-9) - 1.0);
    Ok(FrameFeatureSection {
        size,
        frames,
        rows,
        environment_build_ms,
        ibl_share_of_surface,
    })
}

/// The section's table in `report.md`.
pub fn report(md: &mut String, s: &FrameFeatureSection) {
    let _ = writeln!(md, "\n## Frame features\n");
    let _ = writeln!(
        md,
        "The default scene at {}x{}, median of {} frames, each feature alone over the frame the \
         method sweep times, then `relief render`'s default look. The sky's light adds \
         **{:+.1}%** to the surface pass; its maps take {} GPU ms to build, once per renderer.\n",
        s.size[0],
        s.size[1],
        s.frames,
        100.0 * s.ibl_share_of_surface,
        s.environment_build_ms
            .map_or_else(|| "(untimed)".to_owned(), |ms| format!("{ms:.3}"))
    );
    let _ = writeln!(md, "| frame | GPU ms | surface ms | x baseline |");
    let _ = writeln!(md, "|---|---|---|---|");
    for r in &s.rows {
        let _ = writeln!(
            md,
            "| {} | {:.3} | {:.3} | {:.2} |",
            r.feature, r.gpu_ms, r.surface_ms, r.ratio
        );
    }
}

//! Tone mapping: the scene passes draw linear radiance into a half-float target, and one
//! full-frame pass scales it by the exposure, maps it into [0, 1] with the chosen curve and writes
//! the sRGB frame (encoded once, by the hardware on write). [`ToneMap::apply`] is the curves'
//! definition on the CPU, which `shaders/passes/tonemap.frag` mirrors and the tests compare with.

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

use ash::vk;
use serde::Serialize;

use crate::shaders;
use crate::vk::{
    graphics_pipeline, Bind, Context, DescriptorLayout, DescriptorPool, DescriptorSet,
    GraphicsDesc, ImageView, Pipeline, Recording, Sampler, SpecConstants, VkError, VkResult,
};

/// The scene passes' colour format: linear radiance, beyond 1 where lights are bright.
pub const HDR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// The largest finite half float: the radiance target holds nothing brighter.
const HALF_MAX: f32 = 65504.0;

/// How linear radiance becomes a displayable value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ToneMap {
    /// Clamped to [0, 1]: what relief drew before tone mapping, and what timing runs use.
    #[default]
    None,
    /// Khronos PBR Neutral: base colours under direct light up to about 0.76 pass unchanged,
    /// highlights roll off toward white keeping their hue.
    PbrNeutral,
    /// ACES filmic (Narkowicz's fit): more contrast, shifts hues.
    Aces,
}

impl ToneMap {
    fn shader_value(self) -> u32 {
        match self {
            ToneMap::None => 0,
            ToneMap::PbrNeutral => 1,
            ToneMap::Aces => 2,
        }
    }

    /// The curve applied to linear `rgb` (already scaled by the exposure).
    pub fn apply(self, rgb: [f32; 3]) -> [f32; 3] {
        // As the pass reads a half-float target: nothing beyond its largest finite value.
        let rgb = rgb.map(|c| {
            if c.is_nan() {
                0.0
            } else {
                c.clamp(0.0, HALF_MAX)
            }
        });
        let out = match self {
            ToneMap::None => rgb,
            ToneMap::PbrNeutral => pbr_neutral(rgb),
            ToneMap::Aces => rgb.map(|c| (c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14)),
        };
        out.map(|c| c.clamp(0.0, 1.0))
    }
}

fn pbr_neutral(mut c: [f32; 3]) -> [f32; 3] {
    const START: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let low = c[0].min(c[1]).min(c[2]);
    let offset = if low < 0.08 {
        low - 6.25 * low * low
    } else {
        0.04
    };
    c = c.map(|x| x - offset);
    let peak = c[0].max(c[1]).max(c[2]);
    if peak < START {
        return c;
    }
    let d = 1.0 - START;
    let mapped = 1.0 - d * d / (peak + d - START);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - mapped) + 1.0);
    c.map(|x| {
        let scaled = x * mapped / peak;
        scaled + (mapped - scaled) * g
    })
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ToneMap::None => "none",
            ToneMap::PbrNeutral => "pbr-neutral",
            ToneMap::Aces => "aces",
        })
    }
}

impl FromStr for ToneMap {
    type Err = String;

    fn from_str(s: &str) -> Result<ToneMap, String> {
        match s {
            "none" => Ok(ToneMap::None),
            "pbr-neutral" => Ok(ToneMap::PbrNeutral),
            "aces" => Ok(ToneMap::Aces),
            _ => Err(format!(
                "unknown tone map {s:?}: use pbr-neutral, aces or none"
            )),
        }
    }
}

/// The frame's tone mapping, for the plan and `--explain`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ToneMapping {
    /// The curve.
    pub curve: ToneMap,
    /// Exposure in stops: radiance is scaled by 2^EV before the curve.
    pub exposure_ev: f32,
}

impl ToneMapping {
    /// No curve, no exposure change: radiance clamped, as before tone mapping.
    pub const NONE: ToneMapping = ToneMapping {
        curve: ToneMap::None,
        exposure_ev: 0.0,
    };
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ToneMapPush {
    exposure: f32,
    curve: u32,
    scale: u32,
    samples: u32,
}

/// The full-frame pass: its pipeline, set layout and sampler; each target set owns its set.
pub struct ToneMapPass {
    pipeline: Pipeline,
    layout: DescriptorLayout,
    sampler: Sampler,
    /// Samples per texel of the radiance it reads.
    samples: u32,
}

impl ToneMapPass {
    /// The pass writing into `color_format` targets from a radiance of `samples` samples per
    /// texel: with more than one, the pass is also the resolve, tone mapping every sample before
    /// averaging them (`tonemap_resolve.frag`).
    pub fn new(
        ctx: &Arc<Context>,
        color_format: vk::Format,
        samples: u32,
    ) -> VkResult<ToneMapPass> {
        let missing = |k: &str| VkError::Invalid(format!("no compiled shader {k}"));
        let vertex = shaders::spirv("tonemap.vert").ok_or_else(|| missing("tonemap.vert"))?;
        let key = if samples > 1 {
            "tonemap_resolve.frag"
        } else {
            "tonemap.frag"
        };
        let fragment = shaders::spirv(key).ok_or_else(|| missing(key))?;
        let layout = DescriptorLayout::new(
            ctx,
            &[(0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER)],
            vk::ShaderStageFlags::FRAGMENT,
            "tone map layout",
        )?;
        let desc = GraphicsDesc {
            vertex,
            fragment,
            fragment_spec: &SpecConstants::default(),
            vertex_stride: 0,
            attributes: &[],
            color_format,
            extra_colors: &[],
            writes_extra: false,
            depth_format: vk::Format::UNDEFINED,
            cull: vk::CullModeFlags::NONE,
            set_layouts: &[&layout],
            push_bytes: std::mem::size_of::<ToneMapPush>() as u32,
            blend: false,
            samples: 1,
        };
        let pipeline = graphics_pipeline(ctx, &desc, "tone map")?;
        let sampler = Sampler::new(
            ctx,
            vk::Filter::NEAREST,
            vk::SamplerAddressMode::CLAMP_TO_EDGE,
            "tone map sampler",
        )?;
        Ok(ToneMapPass {
            pipeline,
            layout,
            sampler,
            samples,
        })
    }

    /// Samples per texel of the radiance the pass reads.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// A set reading `hdr` (in `SHADER_READ_ONLY_OPTIMAL` when the pass runs), from `pool`.
    pub fn set_for(&self, pool: &DescriptorPool, hdr: &ImageView) -> VkResult<DescriptorSet> {
        pool.allocate(&self.layout, &[Bind::Texture(0, hdr, &self.sampler)])
    }

    /// Draws the full-frame triangle with `set`, whose radiance is `scale` times the frame's
    /// size along each axis (supersampling); rendering into the frame must have begun.
    pub fn record(
        &self,
        rec: &Recording,
        set: &DescriptorSet,
        mapping: ToneMapping,
        scale: u32,
    ) -> VkResult<()> {
        let push = ToneMapPush {
            exposure: mapping.exposure_ev.exp2(),
            curve: mapping.curve.shader_value(),
            scale,
            samples: self.samples,
        };
        self.pipeline.bind(rec, Some(set));
        self.pipeline.push(rec, bytemuck::bytes_of(&push))?;
        rec.draw(3);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pbr_neutral_keeps_mid_tones_and_rolls_highlights_off() {
        // Above the toe and below the compression start: only the fixed 0.04 offset.
        let mid = ToneMap::PbrNeutral.apply([0.5, 0.3, 0.2]);
        for (out, x) in mid.iter().zip([0.46, 0.26, 0.16]) {
            assert!((out - x).abs() < 1e-6, "{mid:?}");
        }
        // Black stays black; the toe is continuous where it meets the offset.
        assert_eq!(ToneMap::PbrNeutral.apply([0.0; 3]), [0.0; 3]);
        let toe = 0.08f32 - 6.25 * 0.08 * 0.08;
        assert!((toe - 0.04).abs() < 1e-6);
        // Highlights: monotonic, below 1, and hue toward white as they grow.
        let mut last = 0.0;
        for x in [0.8f32, 1.0, 2.0, 10.0, 1e4] {
            let y = ToneMap::PbrNeutral.apply([x, x * 0.5, x * 0.25]);
            assert!(y[0] > last && y[0] <= 1.0, "{x}: {y:?}");
            last = y[0];
        }
        let sun = ToneMap::PbrNeutral.apply([1e4, 5e3, 2.5e3]);
        assert!(sun.iter().all(|c| c.is_finite() && *c > 0.99), "{sun:?}");
    }

    #[test]
    fn aces_and_none_are_bounded_and_nan_free() {
        for curve in [ToneMap::None, ToneMap::Aces, ToneMap::PbrNeutral] {
            for x in [f32::NAN, -1.0, 0.0, 0.18, 1.0, 1e4, f32::INFINITY] {
                let y = curve.apply([x; 3]);
                assert!(
                    y.iter().all(|c| (0.0..=1.0).contains(c)),
                    "{curve} {x}: {y:?}"
                );
            }
        }
        assert_eq!("pbr-neutral".parse::<ToneMap>(), Ok(ToneMap::PbrNeutral));
        assert!("filmic"
            .parse::<ToneMap>()
            .unwrap_err()
            .contains("pbr-neutral"));
    }
}

//! The shadow probe: one frame that writes a light's visibility terms instead of colours, read
//! back with its depth, so every pixel's surface point (the relief hit for relief materials) and
//! relief's verdict for it can be compared with an exact reference on the CPU.

use std::sync::Arc;

use glam::{Vec3, Vec4};

use crate::heightfield::Heightfield;
use crate::render::frame::renderer::{FrameRequest, Renderer};
use crate::render::frame::single_frame::RenderOptions;
use crate::render::kit::pass_timer::PassTiming;
use crate::render::kit::render_error::RenderError;
use crate::scene::{Camera, Scene};
use crate::vk::{Context, VkError};

/// What the probe saw at each pixel, rows top to bottom.
#[derive(Debug, Clone)]
pub struct ShadowProbe {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The world point each pixel shows; `None` for the background.
    pub world: Vec<Option<Vec3>>,
    /// The shadow maps' visible fraction of the light there.
    pub maps: Vec<f32>,
    /// The height field's own visible fraction (1 for surfaces without relief or self-shadows).
    pub own: Vec<f32>,
    /// Whether the surface faces the light there (else the light does not shade it).
    pub facing: Vec<bool>,
    /// Whether both terms were numbers there (the shader flags NaN and infinity).
    pub finite: Vec<bool>,
    /// The frame's GPU time per pass.
    pub timings: Vec<PassTiming>,
    /// World size of a shadow-map texel at each pixel's point (0 where no map covers it): the
    /// width of the band around shadow edges that a map cannot place exactly.
    pub texel_world: Vec<f32>,
}

impl ShadowProbe {
    /// Relief's visible fraction at each pixel: both terms multiplied, 0 where the surface
    /// faces away, -1 on the background.
    pub fn visibility(&self) -> Vec<f32> {
        (0..self.world.len())
            .map(|k| match (self.world[k], self.facing[k]) {
                (None, _) => -1.0,
                (Some(_), false) => 0.0,
                (Some(_), true) => self.maps[k] * self.own[k],
            })
            .collect()
    }
}

/// sRGB-encoded byte to linear.
fn srgb_to_linear(v: u8) -> f32 {
    crate::srgb::decode(f32::from(v) / 255.0)
}

/// Renders `scene` from `camera` (its own when `None`) with light `light` probed, and reads the
/// terms and the surface points back.
pub fn probe_shadows(
    ctx: &Arc<Context>,
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    opts: &RenderOptions,
    light: usize,
    camera: Option<Camera>,
) -> Result<ShadowProbe, RenderError> {
    let opts = RenderOptions {
        shadow_probe: Some(light),
        ..opts.clone()
    };
    let mut renderer = Renderer::new(ctx, scene, frame_heights, &opts)?;
    let camera = camera.unwrap_or_else(|| renderer.default_camera());
    let out = renderer.draw(&FrameRequest {
        camera,
        read_back: true,
    })?;
    let missing = || VkError::Invalid("the probe frame was not read back".into());
    let rgba = out.rgba.ok_or_else(missing)?;
    let depth = out.depth.ok_or_else(missing)?;
    let (w, h) = (out.width, out.height);
    let aspect = w as f32 / h as f32;
    let to_world = camera.view_projection(aspect).inverse();
    let world: Vec<Option<Vec3>> = depth
        .iter()
        .enumerate()
        .map(|(k, &d)| {
            if d >= 1.0 {
                return None;
            }
            let (x, y) = ((k as u32 % w) as f32, (k as u32 / w) as f32);
            let ndc = Vec4::new(
                (x + 0.5) / w as f32 * 2.0 - 1.0,
                (y + 0.5) / h as f32 * 2.0 - 1.0,
                d,
                1.0,
            );
            let p = to_world * ndc;
            Some(p.truncate() / p.w)
        })
        .collect();
    let term = |channel: usize| -> Vec<f32> {
        rgba.chunks_exact(4)
            .map(|px| srgb_to_linear(px[channel]))
            .collect()
    };
    let texel_world = renderer.shadow_texel_world(&camera, light, &world);
    Ok(ShadowProbe {
        width: w,
        height: h,
        maps: term(0),
        own: term(1),
        facing: rgba.chunks_exact(4).map(|px| px[2] > 127).collect(),
        finite: rgba.chunks_exact(4).map(|px| px[3] > 127).collect(),
        world,
        timings: out.timings,
        texel_world,
    })
}

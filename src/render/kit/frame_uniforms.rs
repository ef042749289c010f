//! The frame uniform block every pass that traces binds (set 0, binding 0): camera, ambient,
//! the height map's size, the punctual lights and the views of their shadow maps: what fills it
//! (its layout is `FrameUniforms` in `shader_interface`, which the shaders read too).

use glam::{Mat4, Vec3};

pub use crate::render::shader_interface::{FrameUniforms, LightUniform, ShadowTileUniform};
use crate::scene::{Camera, Light, LightKind, Projection, Scene};

/// Lights the shaders read; a scene with more is lit by its first ones (the plan says so).
pub const MAX_LIGHTS: usize = crate::render::shader_interface::MAX_LIGHTS as usize;

/// Shadow-map views the frame holds.
pub const MAX_SHADOW_TILES: usize = crate::render::shader_interface::MAX_SHADOW_TILES as usize;

/// Ambient radiance: a dim sky so unlit sides keep their shape.
const AMBIENT: [f32; 4] = [0.09, 0.1, 0.12, 0.0];

impl LightUniform {
    fn of(light: &Light) -> LightUniform {
        let r = light.radius;
        let (kind, cone) = match light.kind {
            LightKind::Directional => (0.0, [0.0, 0.0, r, 0.0]),
            LightKind::Point => (1.0, [0.0, 0.0, r, 0.0]),
            LightKind::Spot {
                inner_cone,
                outer_cone,
            } => (2.0, [outer_cone.cos(), inner_cone.cos(), r, 0.0]),
        };
        let p = light.position;
        let d = light.direction.normalize_or(Vec3::NEG_Y);
        let c = light.color;
        LightUniform {
            position: [p.x, p.y, p.z, kind],
            direction: [d.x, d.y, d.z, light.range.unwrap_or(0.0)],
            color: [c.x, c.y, c.z, f32::from(u8::from(light.casts_shadows))],
            cone,
        }
    }
}

/// The camera a frame uses: the scene's, or one framing its bounds.
pub fn frame_camera(scene: &Scene) -> Camera {
    scene.camera.unwrap_or_else(|| match scene.bounds() {
        Some((lo, hi)) => Camera::framing(lo, hi),
        None => Camera::look_at(Vec3::new(0.0, 1.0, 3.0), Vec3::ZERO, 0.8, 0.1, 100.0),
    })
}

impl FrameUniforms {
    /// The uniforms for `scene` seen with an image of `aspect` (width / height), lit by `lights`.
    pub fn for_scene(scene: &Scene, lights: &[Light], aspect: f32) -> FrameUniforms {
        Self::new(&frame_camera(scene), lights, aspect)
    }

    /// The uniforms for `camera` with an image of `aspect` (width / height), lit by `lights`.
    pub fn new(camera: &Camera, lights: &[Light], aspect: f32) -> FrameUniforms {
        let eye = camera.eye();
        // A right-handed view looks down its -z; a scaled view still measures world units.
        let row = -camera.view.row(2);
        let axis = row / row.truncate().length().max(f32::MIN_POSITIVE);
        let forward = axis.truncate();
        let orthographic = match camera.projection {
            Projection::Orthographic { .. } => 1.0,
            Projection::Perspective { .. } => 0.0,
        };
        let view_proj = camera.view_projection(aspect).to_cols_array_2d();
        let mut out = FrameUniforms {
            view_proj,
            eye: [eye.x, eye.y, eye.z, 1.0],
            ambient: AMBIENT,
            height_info: [0.0; 4],
            counts: [lights.len().min(MAX_LIGHTS) as i32, 0, 0, 0],
            lights: [LightUniform::default(); MAX_LIGHTS],
            light_shadows: [[0; 4]; MAX_LIGHTS],
            shadow_tiles: [ShadowTileUniform::default(); MAX_SHADOW_TILES],
            view_depth: axis.to_array(),
            previous_view_proj: view_proj,
            viewport: [0.0; 4],
            view_axis: [forward.x, forward.y, forward.z, orthographic],
        };
        for (slot, light) in out.lights.iter_mut().zip(lights) {
            *slot = LightUniform::of(light);
        }
        out
    }

    /// The view-projection matrix.
    pub fn view_projection(&self) -> Mat4 {
        Mat4::from_cols_array_2d(&self.view_proj)
    }
}

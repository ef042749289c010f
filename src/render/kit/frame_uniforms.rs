//! The frame uniform block every pass that traces binds (set 0, binding 0): camera, ambient,
//! the height map's size, the punctual lights and the views of their shadow maps. Mirrors `Frame` in `shaders/include/bindings.glsl`.

use glam::{Mat4, Vec3};

use crate::scene::{Camera, Light, LightKind, Projection, Scene};

/// Lights the shaders read; a scene with more is lit by its first ones (the plan says so).
pub const MAX_LIGHTS: usize = crate::render::shader_interface::MAX_LIGHTS as usize;

/// One light; mirrors `LightData` in `bindings.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LightUniform {
    /// xyz: world position (point, spot); w: kind, 0 directional, 1 point, 2 spot.
    pub position: [f32; 4],
    /// xyz: unit world direction the light travels (directional, spot); w: range, 0 for none.
    pub direction: [f32; 4],
    /// rgb: linear colour times intensity; w: 1 if relief traces self-shadow rays toward it.
    pub color: [f32; 4],
    /// x, y: cosines of the outer and inner cone angles (spot, else 0); z: the light's size
    /// ([`Light::radius`]: radians for directional, world units otherwise); w: unused.
    pub cone: [f32; 4],
}

/// Shadow-map views the frame holds.
pub const MAX_SHADOW_TILES: usize = crate::render::shader_interface::MAX_SHADOW_TILES as usize;

/// One shadow map's view (a cascade, a spot light's map or a cube face); mirrors `ShadowTile`
/// in `bindings.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShadowTileUniform {
    /// World to the view's clip space, column-major.
    pub view_proj: [[f32; 4]; 4],
    /// xy: the atlas texel of the tile's corner; z: its size in texels; w: 1 perspective, 0
    /// orthographic.
    pub rect: [f32; 4],
    /// x: near plane (perspective); y: far plane, or the depth range in world units
    /// (orthographic); z: world size of a texel (at unit distance when perspective); w: unused.
    pub depth: [f32; 4],
    /// xyz: the light's position (perspective) or the direction it travels (orthographic).
    pub origin: [f32; 4],
}

/// The frame uniform block.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameUniforms {
    /// World to clip space, column-major (glam's `to_cols_array_2d`).
    pub view_proj: [[f32; 4]; 4],
    /// xyz: camera position in world space; w: 1.
    pub eye: [f32; 4],
    /// rgb: flat ambient radiance, linear; w: with an environment, the prefiltered specular
    /// map's last level.
    pub ambient: [f32; 4],
    /// x: width and y: height in texels, z: mip levels, w: 1 for repeat addressing, 0 for clamp.
    /// Filled in per height map by `HeightResources`; zero until then.
    pub height_info: [f32; 4],
    /// x: lights in use (at most [`MAX_LIGHTS`]); y: 1 + the light whose visibility the frame
    /// writes instead of colours (the shadow probe, `relief shadows`), 0 to shade; z: 1 when the
    /// ambient light comes from the environment maps, 0 for the flat colour; w: unused.
    pub counts: [i32; 4],
    /// The first `counts[0]` are the frame's lights; the rest are zero.
    pub lights: [LightUniform; MAX_LIGHTS],
    /// Per light: x the first of its shadow tiles, y how many (0: no shadow map), z its
    /// `ShadowFilter` value; w: unused.
    pub light_shadows: [[i32; 4]; MAX_LIGHTS],
    /// The shadow maps' views.
    pub shadow_tiles: [ShadowTileUniform; MAX_SHADOW_TILES],
    /// The plane of linear view depth: `dot(xyz, p) + w` is world point p's distance along the
    /// camera's axis (the G-buffer's depth).
    pub view_depth: [f32; 4],
    /// The previous frame's world to clip space (the G-buffer's motion is measured against it);
    /// the frame's own when there is none.
    pub previous_view_proj: [[f32; 4]; 4],
    /// x, y: the frame's size in pixels; z, w: unused.
    pub viewport: [f32; 4],
    /// xyz: the camera's axis (unit, world space, looking forward); w: 1 for an orthographic
    /// camera, whose view rays all run along it, 0 for a perspective one.
    pub view_axis: [f32; 4],
}
const _: () =
    assert!(std::mem::size_of::<FrameUniforms>() == 240 + 80 * MAX_LIGHTS + 112 * MAX_SHADOW_TILES);

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

//! Scenes as plain Rust data: meshes with tangents, materials (with optional relief), images,
//! cameras and lights. No Vulkan types, so scenes are built and tested without a GPU.

mod builtin;
mod camera;
mod camera_path;
mod frustum;
mod gltf_accessor;
mod gltf_animation_check;
mod gltf_camera_path;
mod gltf_image;
mod gltf_load;
mod gltf_material;
mod gltf_mesh;
mod gltf_nodes;
mod gltf_prepass;
mod gltf_skin_check;
mod layer_extras;
mod layered;
mod light_extras;
mod lod;
mod material;
mod material_heights;
mod primitives;
mod relief_extras;
mod relief_stack;
mod shading;
mod shadow_scenes;
mod tangents;
mod terrain_scene;

pub use builtin::{default_heightfield, default_scene, DEFAULT_HEIGHTFIELD, DEFAULT_SCENE_METHOD};
pub use camera::{Camera, Projection};
pub use camera_path::{CameraPath, Interpolation, Keyed, Keyframe, NodeMotion, Track, TrackError};
pub use frustum::Frustum;
pub use gltf_load::{load_gltf, load_gltf_with_report, LoadReport, SceneError, SceneOptions};
pub use layered::{
    bake_vertex_color_weights, LayerWeights, Layers, LayersError, MaterialLayer,
    MAX_LAYERED_RESOLUTION,
};
pub use light_extras::{MAX_ANGULAR_RADIUS_DEG, SHADOW_CASCADES, SHADOW_MAP_SIZES};
pub use lod::Lod;
pub use material::{
    AlphaMode, Filter, HeightSource, Material, Relief, SamplerDesc, Silhouettes, TextureRef,
    TextureSlot, UvTransform, Wrap,
};
pub use material_heights::{HeightLookup, HeightUv, MaterialHeights, MaterialHeightsError};
pub use primitives::{box_mesh, cylinder_mesh, quad_mesh, sphere_mesh, torus_mesh};
pub use relief_stack::{relief_stack_scene, STACK_DEPTH_SCALE, STACK_QUAD_SIDE};
pub use shading::{AoMode, ShadowMode, ShadowSettings, AO_HORIZON_DIRECTIONS};
pub use shadow_scenes::{shadow_scene, sun, ShadowScene, SHADOW_SCENE_DEPTH};
pub use terrain_scene::{
    ground_rules, procedural_layers, rules_splat, terrain_scene, GroundLayer, TerrainOptions,
    TERRAIN_MESH,
};

pub use crate::geometry::{Mesh, Vertex};

use std::sync::Arc;

use glam::Vec3;

use crate::method::Method;

/// A decoded image a material's textures point at.
#[derive(Debug, Clone)]
pub struct SceneImage {
    /// Where it came from, for messages: a file name, `"embedded #3"`, ...
    pub name: String,
    /// The decoded pixels, shared by every texture that reads them.
    pub pixels: Arc<image::DynamicImage>,
}

/// What kind of punctual light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    /// Parallel rays along `Light::direction`.
    Directional,
    /// From `Light::position` in every direction.
    Point,
    /// From `Light::position` around `Light::direction`; angles in radians from the axis.
    Spot {
        /// Angle where the light starts to fall off.
        inner_cone: f32,
        /// Angle where it reaches 0.
        outer_cone: f32,
    },
}

/// A punctual light (KHR_lights_punctual semantics).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Directional, point or spot.
    pub kind: LightKind,
    /// World position (point and spot).
    pub position: Vec3,
    /// World direction the light travels (directional and spot), unit length.
    pub direction: Vec3,
    /// Linear RGB times intensity (lux for directional, candela for point and spot).
    pub color: Vec3,
    /// Distance where the light's influence ends, `None` for infinite.
    pub range: Option<f32>,
    /// Whether relief surfaces trace self-shadow rays toward this light.
    pub casts_shadows: bool,
    /// The light's size, 0 for a hard light: angular radius in radians for a directional light
    /// (the sun's is 0.27 degrees), the radius of its sphere in world units for point and spot.
    pub radius: f32,
    /// Texels per side of its shadow map (each cascade, each cube face); `None` takes the
    /// renderer's (`--shadow-map-size`).
    pub shadow_map_size: Option<u32>,
    /// Cascades of a directional light's shadow map; `None` takes the renderer's
    /// (`--shadow-cascades`).
    pub shadow_cascades: Option<u32>,
}

impl Light {
    /// The light a scene without lights gets: warm, from above and to the side. It fills in for
    /// missing lights and casts no shadows, so a scene with no light builds no shadow work.
    pub fn default_light() -> Light {
        Light {
            kind: LightKind::Directional,
            position: Vec3::ZERO,
            direction: -Vec3::new(-0.45, 0.8, 0.4).normalize(),
            color: Vec3::new(3.0, 2.85, 2.6),
            range: None,
            casts_shadows: false,
            radius: 0.0,
            shadow_map_size: None,
            shadow_cascades: None,
        }
    }
}

/// Everything a frame draws.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// Every mesh drawn, each naming its material by index.
    pub meshes: Vec<Mesh>,
    /// The materials meshes point at.
    pub materials: Vec<Material>,
    /// The images textures point at.
    pub images: Vec<SceneImage>,
    /// The camera to render with; `None` frames the scene's bounds.
    pub camera: Option<Camera>,
    /// The scene's own lights; empty means the renderer adds [`Light::default_light`].
    pub lights: Vec<Light>,
    /// How `camera` moves when the file animates it (or one of its ancestors); `None` when it
    /// stands still. `camera` itself is the rest pose, not the path's first sample.
    pub camera_path: Option<CameraPath>,
}

impl Scene {
    /// World-space bounds of every vertex, or `None` for an empty scene.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut points = self.meshes.iter().flat_map(|m| {
            m.vertices
                .iter()
                .map(move |v| m.transform.transform_point3(Vec3::from(v.position)))
        });
        let first = points.next()?;
        Some(points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }

    /// Whether any material carries relief.
    pub fn has_relief(&self) -> bool {
        self.materials.iter().any(|m| m.relief.is_some())
    }

    /// Gives relief from the frame's height map (`--heightmap`) to the materials `filter`
    /// selects: every material for `None`, else those named exactly so. Returns how many.
    pub fn apply_relief(
        &mut self,
        depth_scale: f32,
        method: Method,
        filter: Option<&str>,
    ) -> usize {
        let mut count = 0;
        for m in &mut self.materials {
            if filter.is_some_and(|name| name != m.name) {
                continue;
            }
            m.relief = Some(Relief::new(depth_scale, method));
            count += 1;
        }
        count
    }

    /// The lights the frame is lit by: the scene's, or the default light.
    pub fn effective_lights(&self) -> Vec<Light> {
        if self.lights.is_empty() {
            vec![Light::default_light()]
        } else {
            self.lights.clone()
        }
    }
}

//! A frame's shadow views: each planned map's views for this camera (cascades follow it; spot and
//! cube views stand still) written into the frame's uniforms, where the shadow pass's vertex
//! shader and the surface pass's lookups read them.

use glam::Vec3;

use super::light_views::{directional_cascades, point_views, spot_view, LightView};
use super::shadow_atlas::Tile;
use super::shadow_plan::ShadowMapPlan;
use crate::render::kit::frame_uniforms::{FrameUniforms, ShadowTileUniform};
use crate::scene::{Camera, Light, LightKind};

/// The views of `map` (its light `light`) for a frame seen by `camera` at `aspect`, over a scene
/// within `bounds`.
pub fn map_views(
    map: &ShadowMapPlan,
    light: &Light,
    camera: &Camera,
    aspect: f32,
    bounds: (Vec3, Vec3),
) -> Vec<LightView> {
    match light.kind {
        LightKind::Directional => {
            directional_cascades(light.direction, camera, aspect, bounds, map.tiles, map.size)
        }
        LightKind::Spot { outer_cone, .. } => vec![spot_view(
            light.position,
            light.direction,
            outer_cone,
            light.range,
            bounds,
            map.size,
        )],
        LightKind::Point => point_views(light.position, light.range, bounds, map.size).to_vec(),
    }
}

/// Writes every map's views into `uniforms` (tile `k` of the atlas is view `k`), and returns the
/// views in tile order.
pub fn write_shadow_views(
    uniforms: &mut FrameUniforms,
    maps: &[ShadowMapPlan],
    lights: &[Light],
    tiles: &[Tile],
    camera: &Camera,
    aspect: f32,
    bounds: (Vec3, Vec3),
) -> Vec<LightView> {
    let mut all = Vec::new();
    for map in maps {
        let light = &lights[map.light];
        let views = map_views(map, light, camera, aspect, bounds);
        uniforms.light_shadows[map.light] = [
            map.first_tile as i32,
            views.len() as i32,
            map.filter.shader_value() as i32,
            0,
        ];
        for (k, view) in views.iter().enumerate() {
            let index = map.first_tile as usize + k;
            let tile = tiles[index];
            let origin = if view.perspective {
                light.position
            } else {
                light.direction.normalize_or(Vec3::NEG_Y)
            };
            uniforms.shadow_tiles[index] = ShadowTileUniform {
                view_proj: view.view_proj.to_cols_array_2d(),
                rect: [
                    tile.x as f32,
                    tile.y as f32,
                    tile.size as f32,
                    f32::from(u8::from(view.perspective)),
                ],
                depth: [view.near, view.far, view.texel, 0.0],
                origin: [origin.x, origin.y, origin.z, 0.0],
            };
        }
        all.extend(views);
    }
    all
}

/// Texels a point keeps from a cascade's edge for the cascade to serve it (the shaders'
/// widest filter and one more: `shaders/include/scene_shadows.glsl`).
const CASCADE_MARGIN_TEXELS: f32 = 9.0;

/// World size of a texel of `light`'s map (its `views`) at `p`, as the surface pass picks the
/// view; 0 when no view holds `p`.
pub fn texel_world_at(views: &[LightView], light: &Light, size: u32, p: Vec3) -> f32 {
    let holds = |v: &LightView, margin: f32| {
        let c = v.view_proj * p.extend(1.0);
        if c.w <= 0.0 {
            return false;
        }
        let ndc = c.truncate() / c.w;
        let texel = (ndc.truncate() * 0.5 + 0.5) * size as f32;
        texel.min_element() >= margin
            && texel.max_element() <= size as f32 - margin
            && (0.0..=1.0).contains(&ndc.z)
    };
    let world = |v: &LightView| {
        if v.perspective {
            v.texel * p.distance(light.position)
        } else {
            v.texel
        }
    };
    match light.kind {
        LightKind::Directional => views
            .iter()
            .find(|v| holds(v, CASCADE_MARGIN_TEXELS))
            .map_or(0.0, world),
        LightKind::Spot { .. } => views.first().filter(|v| holds(v, 0.0)).map_or(0.0, world),
        LightKind::Point => {
            let d = p - light.position;
            let a = d.abs();
            let face = if a.x >= a.y && a.x >= a.z {
                usize::from(d.x < 0.0)
            } else if a.y >= a.z {
                2 + usize::from(d.y < 0.0)
            } else {
                4 + usize::from(d.z < 0.0)
            };
            views.get(face).map_or(0.0, world)
        }
    }
}

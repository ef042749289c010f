//! Which lights get a shadow map, of what kind and size, filtered how, and which draws cast into
//! it; the lights that get none are listed as skipped with the reason (`--explain`).

use std::fmt;
use std::str::FromStr;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::light_views::{point_views, spot_view};
use crate::render::kit::frame_uniforms::{MAX_LIGHTS, MAX_SHADOW_TILES};
use crate::render::kit::pass::Pass;
use crate::render::plan::frame_plan::Plan;
use crate::render::shader_interface::{SHADOW_FILTER_HARD, SHADOW_FILTER_PCF, SHADOW_FILTER_PCSS};
use crate::scene::{AlphaMode, Frustum, Light, LightKind, Mesh, Scene};

/// How a shadow map's depths become a visible fraction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ShadowFilter {
    /// One tap, the nearest texel: exact to the map's resolution, hard-edged.
    Hard,
    /// Percentage-closer filtering over a fixed footprint of a few texels.
    Pcf,
    /// Percentage-closer soft shadows: the blockers' mean depth and the light's size give the
    /// penumbra's width, which the filter then covers (sharp at contact, soft far away).
    Pcss,
}

impl ShadowFilter {
    /// Every filter, in the order the bench sweeps them.
    pub const ALL: [ShadowFilter; 3] = [ShadowFilter::Hard, ShadowFilter::Pcf, ShadowFilter::Pcss];

    /// The value the shaders branch on.
    pub fn shader_value(self) -> u32 {
        match self {
            ShadowFilter::Hard => SHADOW_FILTER_HARD,
            ShadowFilter::Pcf => SHADOW_FILTER_PCF,
            ShadowFilter::Pcss => SHADOW_FILTER_PCSS,
        }
    }

    /// The name the command line takes.
    pub fn id(self) -> &'static str {
        match self {
            ShadowFilter::Hard => "hard",
            ShadowFilter::Pcf => "pcf",
            ShadowFilter::Pcss => "pcss",
        }
    }
}

impl ShadowMapKind {
    /// The name `--explain` prints.
    pub fn id(self) -> &'static str {
        match self {
            ShadowMapKind::Cascades => "cascades",
            ShadowMapKind::Spot => "spot",
            ShadowMapKind::Cube => "cube",
        }
    }
}

impl fmt::Display for ShadowFilter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

impl FromStr for ShadowFilter {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ShadowFilter::ALL
            .into_iter()
            .find(|f| f.id() == s)
            .ok_or_else(|| format!("unknown shadow filter `{s}` (expected hard, pcf or pcss)"))
    }
}

/// The renderer's shadow-map settings; a light's `extras.relief` overrides size and cascades.
/// Built from [`ShadowOptions::DEFAULT`] (or `default()`) and the `with_*` setters.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct ShadowOptions {
    /// Build shadow maps at all (`--shadow-maps off` turns them off, for timing the surface alone).
    pub enabled: bool,
    /// Texels per side of each map (each cascade, each cube face).
    pub map_size: u32,
    /// Cascades of a directional light's map.
    pub cascades: u32,
    /// The filter of every map; `None` picks by the light: PCSS for a light with a size, hard
    /// for a point-like one.
    pub filter: Option<ShadowFilter>,
}

with_setters!(ShadowOptions {
    with_enabled => enabled: bool,
    with_map_size => map_size: u32,
    with_cascades => cascades: u32,
    with_filter => filter: Option<ShadowFilter>,
});

/// Default texels per side: on lavapipe a 1024 map of the default scene costs a fraction of its
/// frame (`relief bench --scene-shadows`), and its texels are finer than the slab's bricks.
pub const DEFAULT_SHADOW_MAP_SIZE: u32 = 1024;

/// Default cascades of a directional light: one, because on lavapipe each cascade is a full
/// pass over the casters (relief ones traced texel by texel: the default scene's second cascade,
/// filled by the slab, cost about 20 GPU ms at 1024^2), and one already places the default
/// scene's shadows within a texel on 99.9% of its pixels (`relief shadows`).
pub const DEFAULT_SHADOW_CASCADES: u32 = 1;

impl ShadowOptions {
    /// Maps on, default size and cascades, the filter picked by each light.
    pub const DEFAULT: ShadowOptions = ShadowOptions {
        enabled: true,
        map_size: DEFAULT_SHADOW_MAP_SIZE,
        cascades: DEFAULT_SHADOW_CASCADES,
        filter: None,
    };

    /// No shadow maps.
    pub const OFF: ShadowOptions = ShadowOptions {
        enabled: false,
        ..ShadowOptions::DEFAULT
    };
}

impl Default for ShadowOptions {
    fn default() -> Self {
        ShadowOptions::DEFAULT
    }
}

/// What kind of map a light gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ShadowMapKind {
    /// Orthographic cascades fitted to the view (directional lights).
    Cascades,
    /// One perspective map (spot lights).
    Spot,
    /// Six perspective faces (point lights).
    Cube,
}

/// One light's shadow map.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShadowMapPlan {
    /// Index into the plan's lights.
    pub light: usize,
    /// Cascades, one spot map or a cube.
    pub kind: ShadowMapKind,
    /// Its first view among the frame's shadow tiles.
    pub first_tile: u32,
    /// How many views (cascades, 1, or 6 faces).
    pub tiles: u32,
    /// Texels per side of each view.
    pub size: u32,
    /// How its depths are filtered.
    pub filter: ShadowFilter,
    /// The draws (indices into the plan's draws) that cast into it.
    pub casters: Vec<usize>,
    /// Their meshes' names, for `--explain`.
    pub caster_meshes: Vec<String>,
    /// Of those, how many trace their relief into the map (displaced casters).
    pub relief_casters: usize,
}

/// World-space bounds of a mesh, grown by `pad` on every side.
fn mesh_world_bounds(mesh: &Mesh, pad: f32) -> (Vec3, Vec3) {
    let init = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    let (lo, hi) = mesh.vertices.iter().fold(init, |(lo, hi), v| {
        let p = mesh.transform.transform_point3(Vec3::from(v.position));
        (lo.min(p), hi.max(p))
    });
    (lo - Vec3::splat(pad), hi + Vec3::splat(pad))
}

/// How far a caster's relief may reach below its polygons, in world units: its bounds grow by
/// this so that a displaced caster is never culled from a map it casts into.
pub(in crate::render) fn relief_pad(scene: &Scene) -> f32 {
    let diagonal = scene.bounds().map_or(1.0, |(lo, hi)| (hi - lo).length());
    let deepest = scene
        .materials
        .iter()
        .filter_map(|m| m.relief.map(|r| r.depth_scale))
        .fold(0.0f32, f32::max);
    // A depth scale is in uv units; a uv unit spans at most the scene.
    (deepest * diagonal).min(diagonal * 0.25)
}

/// The most capable filter any of `plan`'s shadow maps uses, as the shaders' `SPEC_SHADOW_FILTER`
/// (0 without maps: the lookups are compiled out).
pub(in crate::render) fn shadow_filter_max(plan: &Plan) -> u32 {
    plan.shadow_maps
        .iter()
        .map(|m| m.filter.shader_value())
        .max()
        .unwrap_or(0)
}

/// Adds the shadow maps of `scene`'s lights to `plan`, with the pass that renders them, or the
/// reasons there are none.
pub fn plan_shadow_maps(plan: &mut Plan, scene: &Scene, opts: &ShadowOptions) {
    if opts.enabled && plan.lights.iter().any(|l| l.casts_shadows) {
        plan.cast_cells_meshes(scene);
    }
    let casters = opaque_casters(plan, scene);
    let Some(bounds) = scene.bounds() else {
        return;
    };
    let pad = relief_pad(scene);
    let search = CasterSearch {
        scene,
        opts,
        casters: &casters,
        bounds: (bounds.0 - Vec3::splat(pad), bounds.1 + Vec3::splat(pad)),
        pad,
    };
    let mut next_tile = 0u32;
    for (index, light) in plan.lights.clone().iter().enumerate() {
        let what = format!("shadow map of light {index}");
        if index >= MAX_LIGHTS {
            break;
        }
        if !opts.enabled {
            plan.skip(what, "shadow maps are off (--shadow-maps off)");
            continue;
        }
        if !light.casts_shadows {
            plan.skip(what, "the light casts no shadows");
            continue;
        }
        match search.map_of_light(plan, index, light, next_tile) {
            Ok(map) => {
                next_tile += map.tiles;
                plan.shadow_maps.push(map);
            }
            Err(why) => plan.skip(what, why),
        }
    }
    if !plan.shadow_maps.is_empty() {
        insert_shadow_pass(plan);
    }
}

/// The draws that may cast shadows: every one not blended, by index into the plan's draws.
fn opaque_casters(plan: &Plan, scene: &Scene) -> Vec<usize> {
    plan.draws
        .iter()
        .enumerate()
        .filter(|(_, d)| scene.materials[d.material].alpha_mode != AlphaMode::Blend)
        .map(|(k, _)| k)
        .collect()
}

/// What a light's shadow map is planned from.
struct CasterSearch<'a> {
    scene: &'a Scene,
    opts: &'a ShadowOptions,
    /// The draws that may cast (`opaque_casters`).
    casters: &'a [usize],
    /// The scene's bounds, grown by `pad`.
    bounds: (Vec3, Vec3),
    /// How far relief may reach below a caster's polygons (`relief_pad`).
    pad: f32,
}

impl CasterSearch<'_> {
    /// The shadow map of `plan`'s light `index`, its views from tile `next_tile` on; or why it
    /// gets none (no caster in its view, or too many views).
    fn map_of_light(
        &self,
        plan: &Plan,
        index: usize,
        light: &Light,
        next_tile: u32,
    ) -> Result<ShadowMapPlan, String> {
        let size = light.shadow_map_size.unwrap_or(self.opts.map_size);
        let (kind, tiles) = map_kind(light, self.opts);
        let seen = self.casters_seen(plan, &light_frusta(light, self.bounds, size));
        if seen.is_empty() {
            return Err("no opaque or masked mesh lies in the light's view to cast".into());
        }
        if next_tile + tiles > MAX_SHADOW_TILES as u32 {
            return Err(format!(
                "its {tiles} view(s) would pass the frame's {MAX_SHADOW_TILES} shadow views"
            ));
        }
        let filter = self.opts.filter.unwrap_or(if light.radius > 0.0 {
            ShadowFilter::Pcss
        } else {
            ShadowFilter::Hard
        });
        let relief_casters = seen
            .iter()
            .filter(|&&k| plan.draws[k].heights.is_some())
            .count();
        let caster_meshes = seen
            .iter()
            .map(|&k| self.scene.meshes[plan.draws[k].mesh].name.clone())
            .collect();
        Ok(ShadowMapPlan {
            caster_meshes,
            light: index,
            kind,
            first_tile: next_tile,
            tiles,
            size,
            filter,
            casters: seen,
            relief_casters,
        })
    }

    /// The casters some of `frusta` may see (all of them when `frusta` is empty).
    fn casters_seen(&self, plan: &Plan, frusta: &[Frustum]) -> Vec<usize> {
        self.casters
            .iter()
            .copied()
            .filter(|&k| {
                let (lo, hi) = mesh_world_bounds(&self.scene.meshes[plan.draws[k].mesh], self.pad);
                frusta.is_empty() || frusta.iter().any(|f| f.may_see_box(lo, hi))
            })
            .collect()
    }
}

/// The kind of map `light` gets and its number of views.
fn map_kind(light: &Light, opts: &ShadowOptions) -> (ShadowMapKind, u32) {
    match light.kind {
        LightKind::Directional => (
            ShadowMapKind::Cascades,
            light.shadow_cascades.unwrap_or(opts.cascades).max(1),
        ),
        LightKind::Spot { .. } => (ShadowMapKind::Spot, 1),
        LightKind::Point => (ShadowMapKind::Cube, 6),
    }
}

/// The frusta of `light`'s views of `size` texels over `bounds`: a spot or point light sees a
/// fixed volume, so only casters inside it count; none for a directional light.
fn light_frusta(light: &Light, bounds: (Vec3, Vec3), size: u32) -> Vec<Frustum> {
    match light.kind {
        LightKind::Directional => Vec::new(),
        LightKind::Spot { outer_cone, .. } => {
            let v = spot_view(
                light.position,
                light.direction,
                outer_cone,
                light.range,
                bounds,
                size,
            );
            vec![Frustum::from_view_projection(v.view_proj)]
        }
        LightKind::Point => point_views(light.position, light.range, bounds, size)
            .iter()
            .map(|v| Frustum::from_view_projection(v.view_proj))
            .collect(),
    }
}

/// Inserts the shadow-map pass before the cells and surface passes, saying which maps it
/// renders.
fn insert_shadow_pass(plan: &mut Plan) {
    let maps: Vec<String> = plan
        .shadow_maps
        .iter()
        .map(|m| {
            format!(
                "light {} ({}, {} view(s) of {}^2, {}, {} caster(s), {} displaced)",
                m.light,
                m.kind.id(),
                m.tiles,
                m.size,
                m.filter,
                m.casters.len(),
                m.relief_casters
            )
        })
        .collect();
    plan.insert_before_scene(
        Pass::ShadowMaps,
        format!("shadow maps: {}", maps.join("; ")),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{default_scene, Light, DEFAULT_SCENE_METHOD};
    use glam::Vec3;

    fn planned(scene: &Scene, opts: &ShadowOptions) -> Plan {
        let heights = crate::scene::default_heightfield();
        let mut plan = Plan::derive(scene, Some(&heights)).unwrap();
        plan_shadow_maps(&mut plan, scene, opts);
        plan
    }

    fn skipped_why<'a>(plan: &'a Plan, what: &str) -> Option<&'a str> {
        plan.skipped
            .iter()
            .find(|s| s.what == what)
            .map(|s| s.why.as_str())
    }

    #[test]
    fn the_default_scene_gets_cascades_with_every_opaque_caster() {
        let scene = default_scene(DEFAULT_SCENE_METHOD);
        let plan = planned(&scene, &ShadowOptions::DEFAULT);
        assert_eq!(plan.shadow_maps.len(), 1);
        let m = &plan.shadow_maps[0];
        assert_eq!(
            (m.kind, m.tiles, m.size),
            (ShadowMapKind::Cascades, 1, 1024)
        );
        assert_eq!(m.filter, ShadowFilter::Pcss);
        assert_eq!((m.casters.len(), m.relief_casters), (4, 1));
        assert!(plan.passes.iter().any(|p| p.pass == Pass::ShadowMaps));
    }

    #[test]
    fn lights_without_shadows_and_options_off_build_no_map_and_say_why() {
        let mut scene = default_scene(DEFAULT_SCENE_METHOD);
        let plan = planned(&scene, &ShadowOptions::OFF);
        assert!(plan.shadow_maps.is_empty());
        assert!(skipped_why(&plan, "shadow map of light 0")
            .unwrap()
            .contains("off"));
        assert!(plan.passes.iter().all(|p| p.pass != Pass::ShadowMaps));
        scene.lights.clear();
        let plan = planned(&scene, &ShadowOptions::DEFAULT);
        assert!(plan.shadow_maps.is_empty());
        let why = skipped_why(&plan, "shadow map of light 0").unwrap();
        assert!(why.contains("casts no shadows"), "{why}");
    }

    #[test]
    fn spots_see_their_cone_and_points_get_six_faces() {
        let mut scene = default_scene(DEFAULT_SCENE_METHOD);
        let spot = |direction| Light {
            kind: LightKind::Spot {
                inner_cone: 0.2,
                outer_cone: 0.3,
            },
            position: Vec3::new(0.0, 3.0, 0.0),
            direction,
            casts_shadows: true,
            ..Light::default_light()
        };
        scene.lights = vec![
            spot(Vec3::NEG_Y),
            spot(Vec3::Y),
            Light {
                kind: LightKind::Point,
                position: Vec3::new(0.0, 2.0, 0.0),
                casts_shadows: true,
                shadow_map_size: Some(256),
                ..Light::default_light()
            },
        ];
        let plan = planned(&scene, &ShadowOptions::DEFAULT);
        let kinds: Vec<(usize, ShadowMapKind, u32, u32)> = plan
            .shadow_maps
            .iter()
            .map(|m| (m.light, m.kind, m.first_tile, m.tiles))
            .collect();
        assert_eq!(
            kinds,
            vec![
                (0, ShadowMapKind::Spot, 0, 1),
                (2, ShadowMapKind::Cube, 1, 6)
            ]
        );
        assert_eq!(plan.shadow_maps[1].size, 256);
        let why = skipped_why(&plan, "shadow map of light 1").unwrap();
        assert!(why.contains("no opaque or masked mesh"), "{why}");
    }

    #[test]
    fn views_beyond_the_frame_s_budget_are_refused_by_light() {
        let mut scene = default_scene(DEFAULT_SCENE_METHOD);
        let point = Light {
            kind: LightKind::Point,
            position: Vec3::new(0.0, 2.0, 0.0),
            casts_shadows: true,
            ..Light::default_light()
        };
        scene.lights = vec![point; 3];
        let plan = planned(&scene, &ShadowOptions::DEFAULT);
        assert_eq!(plan.shadow_maps.len(), 2);
        let why = skipped_why(&plan, "shadow map of light 2").unwrap();
        assert!(why.contains("16 shadow views"), "{why}");
    }
}

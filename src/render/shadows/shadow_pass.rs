//! The shadow pass: every planned map rendered into its tiles of the atlas, each map's casters
//! drawn with their caster pipelines (relief traced from the light) into each of its views, one
//! timestamp scope per map. The atlas is rendered again only when what it holds would change: a
//! view (the cascades follow the camera; spot and point views do not) or the casters (meshes
//! replaced, terrain edited or painted). A still sequence renders it once.

use std::sync::Arc;

use glam::Vec3;

use super::frame_views::{map_views, texel_world_at, write_shadow_views};
use super::light_views::LightView;
use super::shadow_atlas::ShadowAtlas;
use super::shadow_plan::relief_pad;
use crate::render::kit::caster_draws::CasterDraws;
use crate::render::kit::frame_uniforms::FrameUniforms;
use crate::render::kit::pass::Pass;
use crate::render::kit::pass_timer::{PassTimer, Scope};
use crate::render::plan::frame_plan::Plan;
use crate::scene::{Camera, Frustum, Scene};
use crate::vk::{Context, Recording, VkResult};

/// The atlas and what the frame needs to place the maps' views.
pub struct ShadowMaps {
    atlas: ShadowAtlas,
    /// The scene's bounds grown by the deepest relief: what the views must hold.
    bounds: (Vec3, Vec3),
    /// The views the atlas was last rendered with, in tile order; `None` before the first
    /// rendering and after the casters changed.
    rendered: Option<Vec<LightView>>,
}

impl ShadowMaps {
    /// The atlas for `plan`'s shadow maps (the stand-in when it has none).
    pub fn new(ctx: &Arc<Context>, scene: &Scene, plan: &Plan) -> VkResult<ShadowMaps> {
        let sizes: Vec<u32> = plan
            .shadow_maps
            .iter()
            .flat_map(|m| std::iter::repeat_n(m.size, m.tiles as usize))
            .collect();
        let pad = Vec3::splat(relief_pad(scene));
        let bounds = scene
            .bounds()
            .map_or((Vec3::splat(-1.0), Vec3::splat(1.0)), |(lo, hi)| {
                (lo - pad, hi + pad)
            });
        Ok(ShadowMaps {
            atlas: ShadowAtlas::new(ctx, &sizes)?,
            bounds,
            rendered: None,
        })
    }

    /// Whether a frame with these `views` must render the atlas: it has maps, and they were
    /// never rendered, the casters changed since, or a view moved.
    pub fn needs_render(&self, views: &[LightView]) -> bool {
        self.atlas.is_rendered() && self.rendered.as_deref() != Some(views)
    }

    /// Notes that a submitted frame rendered the atlas with `views`: later frames with the same
    /// views read it as it is (the single queue orders them after that frame).
    pub fn mark_rendered(&mut self, views: &[LightView]) {
        self.rendered = Some(views.to_vec());
    }

    /// The casters changed (a mesh replaced, a terrain edited or painted): the next frame
    /// renders every map again.
    pub fn invalidate(&mut self) {
        self.rendered = None;
    }

    /// The atlas every draw's set 0 binds.
    pub fn atlas(&self) -> &ShadowAtlas {
        &self.atlas
    }

    /// How many timestamp scopes a frame records (one per map).
    pub fn scopes(plan: &Plan) -> u32 {
        plan.shadow_maps.len() as u32
    }

    /// Writes the views of `plan`'s maps for a frame seen by `camera` at `aspect` into
    /// `uniforms`; returns them in tile order, for [`ShadowMaps::record`].
    pub fn write_views(
        &self,
        uniforms: &mut FrameUniforms,
        plan: &Plan,
        camera: &Camera,
        aspect: f32,
    ) -> Vec<LightView> {
        write_shadow_views(
            uniforms,
            &plan.shadow_maps,
            &plan.lights,
            self.atlas.tiles(),
            camera,
            aspect,
            self.bounds,
        )
    }

    /// World size of a shadow-map texel of light `light` at each of `points` for a frame seen by
    /// `camera` at `aspect`; 0 where its map does not hold the point or it has none.
    pub fn texel_world(
        &self,
        plan: &Plan,
        camera: &Camera,
        aspect: f32,
        light: usize,
        points: &[Option<Vec3>],
    ) -> Vec<f32> {
        let Some(map) = plan.shadow_maps.iter().find(|m| m.light == light) else {
            return vec![0.0; points.len()];
        };
        let l = &plan.lights[light];
        let views = map_views(map, l, camera, aspect, self.bounds);
        points
            .iter()
            .map(|p| p.map_or(0.0, |p| texel_world_at(&views, l, map.size, p)))
            .collect()
    }

    /// Records every map into the atlas for frame slot `slot`, with the frame's `views`; returns
    /// how many caster draws the views' frusta skipped. Records nothing without maps. The atlas's
    /// old contents are discarded: call it only when [`ShadowMaps::needs_render`] says so.
    pub fn record(
        &self,
        rec: &Recording,
        timer: &mut PassTimer,
        plan: &Plan,
        casters: &impl CasterDraws,
        slot: usize,
        views: &[LightView],
    ) -> VkResult<usize> {
        if !self.atlas.is_rendered() {
            return Ok(0);
        }
        self.atlas.begin(rec);
        let mut culled = 0;
        for (part, map) in plan.shadow_maps.iter().enumerate() {
            let scope = Scope {
                pass: Pass::ShadowMaps,
                part: Some(part),
            };
            culled += timer.scope(rec, scope, |rec| {
                let mut culled = 0;
                for k in 0..map.tiles {
                    let index = map.first_tile + k;
                    let tile = self.atlas.tiles()[index as usize];
                    rec.set_viewport(tile.x, tile.y, tile.size, tile.size);
                    let frustum = Frustum::from_view_projection(views[index as usize].view_proj);
                    culled += casters.record_casters(rec, slot, index, &map.casters, &frustum)?;
                }
                Ok(culled)
            })?;
        }
        self.atlas.end(rec);
        Ok(culled)
    }
}

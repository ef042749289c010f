//! The AO maps a scene's plan lists (`Plan::ao_maps`): one `AoMapPass` per mode in use, one job per
//! map, recorded once by the renderer's first frame after the pyramids (the fields are static) and
//! bound in the materials that read them from creation on (the image exists before it is written;
//! nothing samples it before the first frame's build, which precedes the draws in submission
//! order). A map planned with a bounded reach (`AoPlan::reach_texels`) can be rebuilt near a
//! change of its height map only ([`SceneAo::record_region`]), for fields edited live.

use std::sync::Arc;

use crate::render::heights::height_resources::HeightResources;
use crate::render::maps::ao_map_pass::{AoJob, AoMapPass};
use crate::render::plan::frame_plan::Plan;
use crate::scene::AoMode;
use crate::vk::{Context, ImageView, Recording, Sampler, VkError, VkResult};

/// The scene's AO passes and maps.
pub struct SceneAo {
    passes: Vec<AoMapPass>,
    /// By `Plan::ao_maps` index.
    jobs: Vec<MapJob>,
}

/// One map: its job, which pass builds it and from which height map (`Plan::heights` index), so
/// that an edit of a height map finds the maps to rebuild.
struct MapJob {
    job: AoJob,
    pass: usize,
    heights: usize,
}

impl SceneAo {
    /// Prepares every AO map of `plan` over the uploaded `heights` (by `Plan::heights` index).
    pub fn new(ctx: &Arc<Context>, plan: &Plan, heights: &[HeightResources]) -> VkResult<SceneAo> {
        let mut passes: Vec<AoMapPass> = Vec::new();
        let mut jobs = Vec::with_capacity(plan.ao_maps.len());
        for ao in &plan.ao_maps {
            let pass = match passes.iter().position(|p| p.mode() == ao.mode) {
                Some(k) => k,
                None => {
                    passes.push(AoMapPass::new(ctx, ao.mode)?);
                    passes.len() - 1
                }
            };
            let h = heights.get(ao.heights).ok_or_else(|| {
                VkError::Invalid(format!("AO map of height map {}, not uploaded", ao.heights))
            })?;
            if matches!(ao.mode, AoMode::Horizon { .. }) && !h.has_pyramid() {
                return Err(VkError::Invalid(
                    "horizon AO planned over a height map without its pyramid".into(),
                ));
            }
            let job = passes[pass].prepare_reaching(&h.heights, ao.depth_scale, ao.reach_texels)?;
            jobs.push(MapJob {
                job,
                pass,
                heights: ao.heights,
            });
        }
        Ok(SceneAo { passes, jobs })
    }

    /// How many maps there are.
    pub fn len(&self) -> usize {
        self.jobs.len()
    }

    /// Records the build of map `k` (after its height map's pyramid).
    pub fn record(&self, rec: &Recording, k: usize) -> VkResult<()> {
        let map = &self.jobs[k];
        self.passes[map.pass].record(rec, &map.job)
    }

    /// The maps (by `Plan::ao_maps` index) built from height map `heights` (`Plan::heights`
    /// index): those to rebuild after it changes.
    pub fn maps_of(&self, heights: usize) -> Vec<usize> {
        (0..self.jobs.len())
            .filter(|&k| self.jobs[k].heights == heights)
            .collect()
    }

    /// Records the rebuild of the texels of map `k` (already built) that a change of its height
    /// map's level 0 in `changed` (x0, y0, width, height) can alter, after the heights and their
    /// pyramid were updated (visible to compute shaders, in `SHADER_READ_ONLY_OPTIMAL`). Returns
    /// the rectangle rebuilt: the change's influence region under a bounded reach, the whole map
    /// (recorded as a full build) when the reach is unbounded, `None` (nothing recorded) when
    /// `changed` covers no texel.
    pub fn record_region(
        &self,
        rec: &Recording,
        k: usize,
        changed: [u32; 4],
    ) -> VkResult<Option<[u32; 4]>> {
        let map = self.jobs.get(k).ok_or_else(|| {
            VkError::Invalid(format!("AO map {k} of {}: no such map", self.jobs.len()))
        })?;
        let pass = &self.passes[map.pass];
        let d = map.job.map().image.desc();
        let touches =
            changed[2] > 0 && changed[3] > 0 && changed[0] < d.width && changed[1] < d.height;
        if !touches {
            return Ok(None);
        }
        match map.job.influence_region(changed) {
            Some(region) => {
                pass.record_region(rec, &map.job, region)?;
                Ok(Some(region))
            }
            None => {
                pass.record(rec, &map.job)?;
                Ok(Some([0, 0, d.width, d.height]))
            }
        }
    }

    /// Map `k`'s view and sampler, for a material's descriptor set.
    pub fn binding(&self, k: usize) -> Option<(ImageView, Sampler)> {
        self.jobs.get(k).map(|m| {
            (
                m.job.map().image.view().clone(),
                m.job.map().sampler.clone(),
            )
        })
    }
}

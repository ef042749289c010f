//! The AO maps a scene's plan lists (`Plan::ao_maps`): one `AoMapPass` per mode in use, one job per
//! map, recorded once by the renderer's first frame after the pyramids (the fields are static) and
//! bound in the materials that read them from creation on (the image exists before it is written;
//! nothing samples it before the first frame's build, which precedes the draws in submission
//! order).

use std::sync::Arc;

use ash::vk;

use super::ao_map_pass::{AoJob, AoMapPass};
use super::height_resources::HeightResources;
use super::plan::Plan;
use crate::scene::AoMode;
use crate::vk::{Context, Recording, VkError, VkResult};

/// The scene's AO passes and maps.
pub struct SceneAo {
    passes: Vec<AoMapPass>,
    /// By `Plan::ao_maps` index: the job, and which pass builds it.
    jobs: Vec<(AoJob, usize)>,
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
            jobs.push((passes[pass].prepare(&h.heights, ao.depth_scale)?, pass));
        }
        Ok(SceneAo { passes, jobs })
    }

    /// How many maps there are.
    pub fn len(&self) -> usize {
        self.jobs.len()
    }

    /// Records the build of map `k` (after its height map's pyramid).
    pub fn record(&self, rec: &Recording, k: usize) -> VkResult<()> {
        let (job, pass) = &self.jobs[k];
        self.passes[*pass].record(rec, job)
    }

    /// Map `k`'s view and sampler, for a material's descriptor set.
    pub fn binding(&self, k: usize) -> Option<(vk::ImageView, vk::Sampler)> {
        self.jobs
            .get(k)
            .map(|(job, _)| (job.map().image.view(), job.map().sampler.raw()))
    }
}

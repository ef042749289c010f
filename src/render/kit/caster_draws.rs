//! How the shadow pass has the scene's casters drawn without knowing the pass that owns their
//! meshes and pipelines (the surface pass, in `frame`).

use crate::scene::Frustum;
use crate::vk::{Recording, VkResult};

/// Something that draws shadow casters into the shadow view being recorded.
pub(in crate::render) trait CasterDraws {
    /// Records the casters `draws` (indices into the scene's draws) for frame slot `slot` into
    /// shadow view `tile`, skipping those outside `frustum`; returns how many it skipped.
    fn record_casters(
        &self,
        rec: &Recording,
        slot: usize,
        tile: u32,
        draws: &[usize],
        frustum: &Frustum,
    ) -> VkResult<usize>;
}

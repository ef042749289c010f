//! Recording one frame: the graph's passes in the graph's order, each from the renderer's part
//! that owns it. The background and the tone map run inside the surface pass's rendering (its
//! draws call the sky after the opaque surfaces; its end tone maps), so their nodes record
//! nothing of their own here.

use glam::{Mat4, Vec3};

use super::occluders::OccluderTargets;
use super::scene_ao::SceneAo;
use super::surface_pass::SurfacePass;
use super::targets::{FrameReadbacks, Targets};
use super::tonemap::ToneMapPass;
use super::work_counters::WorkCounterBuffer;
use crate::render::cells::cells_pass::CellsPass;
use crate::render::environment::BackgroundPass;
use crate::render::heights::height_resources::HeightResources;
use crate::render::kit::graph::FrameGraph;
use crate::render::kit::pass::Pass;
use crate::render::kit::pass_timer::{PassTimer, Scope};
use crate::render::kit::tone_curves::ToneMapping;
use crate::render::lighting::LightingPass;
use crate::render::plan::frame_plan::Plan;
use crate::render::shadows::light_views::LightView;
use crate::render::shadows::shadow_pass::ShadowMaps;
use crate::scene::Frustum;
use crate::vk::{Readback, Recording, VkError, VkResult};

/// The renderer's parts one frame records with.
pub(super) struct RecordingParts<'a> {
    pub graph: &'a FrameGraph,
    pub plan: &'a Plan,
    pub heights: &'a [HeightResources],
    pub ao: &'a SceneAo,
    pub shadows: &'a ShadowMaps,
    pub occluders: Option<&'a OccluderTargets>,
    pub cells: &'a CellsPass,
    pub surface: &'a SurfacePass,
    pub background: Option<&'a BackgroundPass>,
    pub targets: &'a Targets,
    pub tone_map: (&'a ToneMapPass, ToneMapping),
    /// The deferred frame's lighting pass, run as the scene's rendering ends.
    pub lighting: Option<&'a LightingPass>,
}

/// What this frame is: its slot, view, shadow views, the passes due at their own rate, and the
/// buffers it is read back into.
pub(super) struct FrameWork<'a> {
    pub slot: usize,
    pub eye: Vec3,
    pub view_proj: Mat4,
    pub views: &'a [LightView],
    /// The first frame: the pyramids and AO maps are built.
    pub build_maps: bool,
    /// A view moved or a caster changed: the shadow maps are rendered again.
    pub render_shadow_maps: bool,
    /// Where the work counters are copied, when the frame counts.
    pub work: Option<&'a Readback>,
    pub into: FrameReadbacks<'a>,
}

impl RecordingParts<'_> {
    /// Records `work`'s frame into `rec`, each timed pass in its scope of `timer`; returns how
    /// many surface draws the view could not see.
    pub fn record(
        &self,
        rec: &Recording,
        timer: &mut PassTimer,
        work: FrameWork,
    ) -> VkResult<usize> {
        let k = work.slot;
        let frustum = Frustum::from_view_projection(work.view_proj);
        // After the opaque draws, with the depth test: the sky is shaded only where nothing was
        // drawn.
        let sky = |rec: &Recording| match self.background {
            Some(b) => b.record(rec, work.view_proj),
            None => Ok(()),
        };
        let mut sky = Some(sky);
        let mut culled = 0;
        let mut rendering = false;
        let counters = self.record_counter_clear(rec)?;
        for pass in self.graph.passes() {
            match pass {
                Pass::Pyramid if work.build_maps => self.record_pyramids(rec, timer)?,
                Pass::AmbientOcclusion if work.build_maps => self.record_ao_maps(rec, timer)?,
                Pass::ShadowMaps if work.render_shadow_maps => {
                    self.shadows
                        .record(rec, timer, self.plan, self.surface, k, work.views)?;
                }
                Pass::Occluders => self.record_occluders(rec, timer, &work, &frustum)?,
                Pass::Cells => {
                    self.record_cells(rec, timer, &work)?;
                    rendering = true;
                }
                Pass::Surface => {
                    let view = SurfaceView {
                        work: &work,
                        frustum: &frustum,
                        rendering,
                    };
                    culled = self.record_surface(rec, timer, &view, &mut sky)?;
                }
                _ => {}
            }
        }
        if let (Some(counters), Some(into)) = (counters, work.work) {
            counters.record_copy(rec, into)?;
        }
        Ok(culled)
    }

    /// Records the clearing of the work counters when the frame counts, and returns them (the
    /// occluder bounds beside them are cleared too when no pass draws them).
    fn record_counter_clear(&self, rec: &Recording) -> VkResult<Option<&WorkCounterBuffer>> {
        let counters = self
            .occluders
            .map(OccluderTargets::counters)
            .filter(|c| c.counting());
        if let (Some(counters), Some(o)) = (counters, self.occluders) {
            counters.record_clear(rec)?;
            if !self.plan.occluders {
                // Bound beside the counters though never read: cleared, so it has a layout.
                o.begin(rec);
                o.end(rec);
            }
        }
        Ok(counters)
    }

    /// Records the build of each height map's pyramid, each in its own scope.
    fn record_pyramids(&self, rec: &Recording, timer: &mut PassTimer) -> VkResult<()> {
        let pass = Pass::Pyramid;
        for (part, h) in self.heights.iter().enumerate() {
            if h.builds_pyramid() {
                let part = Some(part);
                timer.scope(rec, Scope { pass, part }, |rec| h.record_pyramid(rec))?;
            }
        }
        Ok(())
    }

    /// Records the build of each AO map, each in its own scope.
    fn record_ao_maps(&self, rec: &Recording, timer: &mut PassTimer) -> VkResult<()> {
        for part in 0..self.ao.len() {
            let scope = Scope {
                pass: Pass::AmbientOcclusion,
                part: Some(part),
            };
            timer.scope(rec, scope, |rec| self.ao.record(rec, part))?;
        }
        Ok(())
    }

    /// Records the occluder pass's draws that `frustum` may see, when the frame has the pass's
    /// targets.
    fn record_occluders(
        &self,
        rec: &Recording,
        timer: &mut PassTimer,
        work: &FrameWork,
        frustum: &Frustum,
    ) -> VkResult<()> {
        if let Some(o) = self.occluders {
            timer.scope(rec, whole(Pass::Occluders), |rec| {
                o.begin(rec);
                self.surface
                    .record_occluders(rec, work.slot, work.eye, frustum)?;
                o.end(rec);
                Ok(())
            })?;
        }
        Ok(())
    }

    /// Begins the scene's rendering and records the cells pass's complexes into it.
    fn record_cells(
        &self,
        rec: &Recording,
        timer: &mut PassTimer,
        work: &FrameWork,
    ) -> VkResult<()> {
        // The complexes first (opaque), then the surface pass's draws, in one rendering that
        // this scope begins and the surface's ends: neither is counted, since a statistics
        // query may not span a rendering's begin or end.
        timer.scope_uncounted(rec, whole(Pass::Cells), |rec| {
            self.targets.begin(rec);
            let frame_set = self
                .surface
                .plain_set(work.slot)
                .ok_or_else(|| VkError::Invalid("no plain frame set".into()))?;
            let materials = |m| self.surface.material_set(m);
            self.cells.record(rec, frame_set, work.eye, materials)
        })
    }

    /// Records the surface pass's draws (with `sky` behind the opaque ones, the first time),
    /// beginning the rendering unless the cells pass did, then ends it (lighting and tone
    /// mapping); returns how many draws the view could not see.
    fn record_surface(
        &self,
        rec: &Recording,
        timer: &mut PassTimer,
        view: &SurfaceView,
        sky: &mut Option<impl FnOnce(&Recording) -> VkResult<()>>,
    ) -> VkResult<usize> {
        let (work, k) = (view.work, view.work.slot);
        let bounds = self.occluders.map(OccluderTargets::set);
        let record = |rec: &Recording| {
            if !view.rendering {
                self.targets.begin(rec);
            }
            let behind = |rec: &Recording| match sky.take() {
                Some(draw) => draw(rec),
                None => Ok(()),
            };
            let eye_view = (work.eye, view.frustum);
            let culled = self.surface.record_draws(rec, k, eye_view, bounds, behind);
            let frame_set =
                match self.lighting {
                    Some(_) => Some(self.surface.plain_set(k).ok_or_else(|| {
                        VkError::Invalid("no plain frame set to light with".into())
                    })?),
                    None => None,
                };
            let lighting = self.lighting.zip(frame_set.as_ref());
            self.targets.end(rec, self.tone_map, lighting, work.into)?;
            culled
        };
        if view.rendering {
            timer.scope_uncounted(rec, whole(Pass::Surface), record)
        } else {
            timer.scope(rec, whole(Pass::Surface), record)
        }
    }
}

/// What the surface pass records this frame from.
struct SurfaceView<'a> {
    work: &'a FrameWork<'a>,
    frustum: &'a Frustum,
    /// The cells pass has begun the rendering already.
    rendering: bool,
}

/// The scope of the whole of `pass`.
fn whole(pass: Pass) -> Scope {
    Scope { pass, part: None }
}

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
        let scope = |pass| Scope { pass, part: None };
        // After the opaque draws, with the depth test: the sky is shaded only where nothing was
        // drawn.
        let sky = |rec: &Recording| match self.background {
            Some(b) => b.record(rec, work.view_proj),
            None => Ok(()),
        };
        let mut sky = Some(sky);
        let mut culled = 0;
        let mut rendering = false;
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
        for pass in self.graph.passes() {
            match pass {
                Pass::Pyramid if work.build_maps => {
                    for (part, h) in self.heights.iter().enumerate() {
                        if h.builds_pyramid() {
                            let part = Some(part);
                            timer.scope(rec, Scope { pass, part }, |rec| h.record_pyramid(rec))?;
                        }
                    }
                }
                Pass::AmbientOcclusion if work.build_maps => {
                    for part in 0..self.ao.len() {
                        let scope = Scope {
                            pass,
                            part: Some(part),
                        };
                        timer.scope(rec, scope, |rec| self.ao.record(rec, part))?;
                    }
                }
                Pass::ShadowMaps if work.render_shadow_maps => {
                    self.shadows
                        .record(rec, timer, self.plan, self.surface, k, work.views)?;
                }
                Pass::Occluders => {
                    if let Some(o) = self.occluders {
                        timer.scope(rec, scope(pass), |rec| {
                            o.begin(rec);
                            self.surface.record_occluders(rec, k, work.eye, &frustum)?;
                            o.end(rec);
                            Ok(())
                        })?;
                    }
                }
                Pass::Cells => {
                    // The complexes first (opaque), then the surface pass's draws, in one
                    // rendering that this scope begins and the surface's ends: neither is
                    // counted, since a statistics query may not span a rendering's begin or end.
                    timer.scope_uncounted(rec, scope(pass), |rec| {
                        self.targets.begin(rec);
                        let frame_set = self
                            .surface
                            .plain_set(k)
                            .ok_or_else(|| VkError::Invalid("no plain frame set".into()))?;
                        let materials = |m| self.surface.material_set(m);
                        self.cells.record(rec, frame_set, work.eye, materials)
                    })?;
                    rendering = true;
                }
                Pass::Surface => {
                    let bounds = self.occluders.map(OccluderTargets::set);
                    let record = |rec: &Recording| {
                        if !rendering {
                            self.targets.begin(rec);
                        }
                        let behind = |rec: &Recording| match sky.take() {
                            Some(draw) => draw(rec),
                            None => Ok(()),
                        };
                        let view = (work.eye, &frustum);
                        let culled = self.surface.record_draws(rec, k, view, bounds, behind);
                        let frame_set = match self.lighting {
                            Some(_) => Some(self.surface.plain_set(k).ok_or_else(|| {
                                VkError::Invalid("no plain frame set to light with".into())
                            })?),
                            None => None,
                        };
                        let lighting = self.lighting.zip(frame_set.as_ref());
                        self.targets.end(rec, self.tone_map, lighting, work.into)?;
                        culled
                    };
                    culled = if rendering {
                        timer.scope_uncounted(rec, scope(pass), record)?
                    } else {
                        timer.scope(rec, scope(pass), record)?
                    };
                }
                _ => {}
            }
        }
        if let (Some(counters), Some(into)) = (counters, work.work) {
            counters.record_copy(rec, into)?;
        }
        Ok(culled)
    }
}

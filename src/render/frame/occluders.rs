//! The occluder pass's targets: per pixel of the scene, the farthest depth the nearest opaque
//! surface can reach (`shaders/passes/occluders.frag`), which the relief surface variants read
//! through set 3 before they trace (`shaders/include/occluders.glsl`). Made with the frame's
//! targets, at their size, and made again when they are.
//!
//! Why a pass of its own: a relief fragment writes its displaced depth, so neither lavapipe nor
//! most GPUs test its depth before running it, and a relief surface hidden behind another would
//! walk its whole height field for nothing. The bounds come from relief's own structure (a slab
//! of depth `depth_scale` under the polygon), so they hold on every driver.

use std::sync::Arc;

use ash::vk;

use super::work_counters::WorkCounterBuffer;
use crate::render::kit::depth_as_colour::{DepthAsColour, DEPTH_COLOUR_FORMAT};
use crate::render::kit::pass::Pass;
use crate::render::plan::frame_plan::{DrawPlan, DrawRole, PipelineKey, Plan};
use crate::render::shader_interface::{BINDING_OCCLUDER_BOUNDS, BINDING_WORK_COUNTS};
use crate::scene::{AlphaMode, Mesh, Scene};
use crate::vk::{
    Bind, Context, DescriptorLayout, DescriptorPool, DescriptorSet, Recording, Sampler, VkResult,
};
use glam::Vec3;

/// The bounds' format: one float depth per pixel, as the shadow atlas holds.
pub const BOUNDS_FORMAT: vk::Format = DEPTH_COLOUR_FORMAT;

/// Whether draw `d` (pipeline `key`) bounds what lies behind it in the occluder pass: it is
/// shaded and opaque, and nothing of it is cut away but where a clamp-addressed map ends (which
/// its occluder variant answers per fragment). Curved relief and prism shells cut their
/// silhouettes, so they only read the bounds.
pub fn occludes(scene: &Scene, d: &DrawPlan, key: &PipelineKey) -> bool {
    let opaque = matches!(scene.materials[d.material].alpha_mode, AlphaMode::Opaque);
    d.role == DrawRole::Surface && opaque && !key.blend && !key.curved && !key.shells
}

/// Adds the occluder pass to `plan` when `on` and it can spare a trace: some relief surface is
/// drawn and some draw occludes; otherwise says why it is left out.
pub fn plan_occluders(plan: &mut Plan, scene: &Scene, on: bool) {
    let surfaces = || plan.draws.iter().filter(|d| d.role == DrawRole::Surface);
    let relief = surfaces()
        .filter(|d| plan.pipelines[d.pipeline].method.is_some())
        .count();
    let occluding = surfaces()
        .filter(|d| occludes(scene, d, &plan.pipelines[d.pipeline]))
        .count();
    let lone_flat = {
        let mut drawn = surfaces();
        match (drawn.next(), drawn.next()) {
            (Some(d), None) => is_flat(&scene.meshes[d.mesh]),
            _ => false,
        }
    };
    let why = if !on {
        Some("--occluders off: every relief fragment is traced (the forward reference)")
    } else if relief == 0 {
        Some("no relief surface is drawn, so no trace can be skipped")
    } else if lone_flat {
        Some("one flat mesh is drawn, and it cannot hide any of itself")
    } else if occluding == 0 {
        Some("no opaque draw can occlude (every drawn material blends, masks or cuts its silhouette)")
    } else {
        None
    };
    plan.occluders = why.is_none();
    match why {
        Some(why) => plan.skip(Pass::Occluders.name(), why),
        None => {
            plan.insert_before_scene(
                Pass::Occluders,
                format!(
                    "{occluding} opaque draw(s) bound what lies behind them, so the {relief} relief draw(s) skip hidden fragments' traces"
                ),
            );
        }
    }
}

/// Whether every vertex normal of `mesh` is the same: a flat mesh, whose front faces never hide
/// one another.
fn is_flat(mesh: &Mesh) -> bool {
    let Some(first) = mesh.vertices.first() else {
        return true;
    };
    let n = Vec3::from(first.normal).normalize_or_zero();
    mesh.vertices
        .iter()
        .all(|v| Vec3::from(v.normal).normalize_or_zero().dot(n) > 1.0 - 1e-6)
}

/// How many bounds a relief fragment reads (`SPEC_OCCLUDER_TAPS`): its own pixel's with one
/// sample per pixel; with MSAA the nine around it too, since the bounds hold pixel centres and a
/// fragment's samples lie off them.
pub fn occluder_taps(samples: u32) -> u32 {
    if samples > 1 {
        9
    } else {
        1
    }
}

/// Set 3 of the relief surface variants: the bounds, one texture, and the work counters.
pub fn occluder_layout(ctx: &Arc<Context>) -> VkResult<DescriptorLayout> {
    DescriptorLayout::new(
        ctx,
        &[
            (
                BINDING_OCCLUDER_BOUNDS,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            ),
            (BINDING_WORK_COUNTS, vk::DescriptorType::STORAGE_BUFFER),
        ],
        vk::ShaderStageFlags::FRAGMENT,
        "occluder bounds layout",
    )
}

/// The bounds, the depth test that keeps the nearest, the work counters beside them, and the
/// set the surface pass binds.
pub struct OccluderTargets {
    bounds: DepthAsColour,
    counters: WorkCounterBuffer,
    set: DescriptorSet,
    _pool: DescriptorPool,
}

impl OccluderTargets {
    /// Targets of `width` x `height` pixels (the scene's drawing size, supersampling included),
    /// bound through a set of `layout` ([`occluder_layout`]), with per-pixel work counters when
    /// `counting`.
    pub fn new(
        ctx: &Arc<Context>,
        layout: &DescriptorLayout,
        (width, height): (u32, u32),
        counting: bool,
    ) -> VkResult<OccluderTargets> {
        let counters = WorkCounterBuffer::new(ctx, (width, height), counting)?;
        let bounds = DepthAsColour::new(ctx, width, height, "occluder bounds")?;
        let sampler = Sampler::new(
            ctx,
            vk::Filter::NEAREST,
            vk::SamplerAddressMode::CLAMP_TO_EDGE,
            "occluder bounds sampler",
        )?;
        let pool = DescriptorPool::new(ctx, 1, 1, "occluder bounds set")?;
        let binds = [
            Bind::Texture(BINDING_OCCLUDER_BOUNDS, bounds.depths.view(), &sampler),
            Bind::Storage(BINDING_WORK_COUNTS, counters.buffer()),
        ];
        let set = pool.allocate(layout, &binds)?;
        Ok(OccluderTargets {
            bounds,
            counters,
            set,
            _pool: pool,
        })
    }

    /// The per-pixel work counters (a stand-in unless the frame counts).
    pub fn counters(&self) -> &WorkCounterBuffer {
        &self.counters
    }

    /// The set the relief surface variants bind as set 3.
    pub fn set(&self) -> &DescriptorSet {
        &self.set
    }

    /// Begins rendering the bounds, cleared to the far plane (nothing hidden), after the
    /// previous frame's surface pass has read them.
    pub fn begin(&self, rec: &Recording) {
        self.bounds.begin(rec);
    }

    /// Ends the rendering and hands the bounds to the surface pass's fragment shaders.
    pub fn end(&self, rec: &Recording) {
        self.bounds.end(rec);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multisampled_fragments_read_the_pixels_around_them() {
        assert_eq!(occluder_taps(1), 1);
        for samples in [2, 4, 8] {
            assert_eq!(occluder_taps(samples), 9);
        }
    }
}

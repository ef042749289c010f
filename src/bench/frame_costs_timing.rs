//! The frame-cost section's timings: the looks of the default scene, the plain frame and the
//! look at other sizes, the stacks of relief quads and the still view's shadow maps, each
//! keeping its frames' timelines.

use std::sync::Arc;

use super::frame_costs::{look, plain, row, stack_scene, FrameCostRow, StackRow, STACK_QUADS};
use super::frame_timing::{
    time_interleaved, time_setups_interleaved, FrameSetup, MapRate, SteadyFrames,
};
use crate::heightfield::Heightfield;
use crate::render::{FrameTimeline, RenderError, RenderOptions};
use crate::scene::Scene;
use crate::vk::Context;

/// What every timing of a run shares, and the timelines it keeps.
pub(super) struct SectionRun<'a> {
    pub ctx: &'a Arc<Context>,
    pub frames: u32,
    pub timelines: Vec<(String, Vec<FrameTimeline>)>,
}

impl SectionRun<'_> {
    /// Keeps `t`'s frames' timelines under `label`.
    pub(super) fn keep(&mut self, label: String, t: &SteadyFrames) {
        self.timelines.push((label, t.timelines.clone()));
    }

    /// A row per look of `scene`, timed in turn.
    pub(super) fn time_looks(
        &mut self,
        scene: &Scene,
        heights: &Heightfield,
        looks: &[(&str, RenderOptions)],
    ) -> Result<Vec<FrameCostRow>, RenderError> {
        let options: Vec<RenderOptions> = looks.iter().map(|(_, o)| o.clone()).collect();
        let timed = time_interleaved(self.ctx, scene, Some(heights), &options, self.frames)?;
        let rows: Vec<FrameCostRow> = looks
            .iter()
            .zip(&timed)
            .map(|((name, opts), t)| row(name, opts, t))
            .collect();
        for (r, t) in rows.iter().zip(&timed) {
            self.keep(format!("{} {}x{}", r.frame, r.size[0], r.size[1]), t);
        }
        Ok(rows)
    }

    /// The rows of the plain frame and the look of `scene` at `size`, timed in turn.
    pub(super) fn time_plain_and_look(
        &mut self,
        scene: &Scene,
        heights: &Heightfield,
        size: [u32; 2],
    ) -> Result<[FrameCostRow; 2], RenderError> {
        let options = [plain(size), look(size)];
        let timed = time_interleaved(self.ctx, scene, Some(heights), &options, self.frames)?;
        self.keep(format!("plain {}x{}", size[0], size[1]), &timed[0]);
        self.keep(format!("look {}x{}", size[0], size[1]), &timed[1]);
        Ok([
            row("plain", &options[0], &timed[0]),
            row("look", &options[1], &timed[1]),
        ])
    }

    /// One quad against eight `spacing` apart in both orders, with and without the occluder
    /// pass, plain frame at `size`.
    pub(super) fn time_stack(
        &mut self,
        heights: &Heightfield,
        size: [u32; 2],
        spacing: f32,
    ) -> Result<StackRow, RenderError> {
        let culled = plain(size);
        let forward = RenderOptions {
            occluders: false,
            ..plain(size)
        };
        let scenes = [
            stack_scene(1, spacing, true),
            stack_scene(STACK_QUADS, spacing, true),
            stack_scene(STACK_QUADS, spacing, false),
        ];
        let setups: Vec<FrameSetup> = [&culled, &forward]
            .into_iter()
            .flat_map(|opts| {
                scenes.iter().map(move |scene| FrameSetup {
                    scene,
                    heights: Some(heights),
                    opts,
                })
            })
            .collect();
        let timed = time_setups_interleaved(self.ctx, &setups, self.frames, MapRate::AsNeeded)?;
        let kinds = ["one quad", "eight, nearest first", "eight, farthest first"];
        for (k, t) in timed.iter().enumerate() {
            let path = if k < 3 { "occluders" } else { "forward" };
            self.keep(
                format!("stack {spacing} apart: {}, {path}", kinds[k % 3]),
                t,
            );
        }
        Ok(StackRow {
            spacing,
            one_ms: timed[0].total_ms,
            nearest_first_ms: timed[1].total_ms,
            farthest_first_ms: timed[2].total_ms,
            forward: Some([timed[3].total_ms, timed[4].total_ms, timed[5].total_ms]),
            occluders_ms: [
                timed[0].occluders_ms,
                timed[1].occluders_ms,
                timed[2].occluders_ms,
            ],
        })
    }

    /// On the one-quad scene with the look at `size`: the steady frames' shadow-map pass over
    /// the rest of their frame.
    pub(super) fn still_shadow_share(
        &mut self,
        heights: &Heightfield,
        size: [u32; 2],
    ) -> Result<f64, RenderError> {
        let one_quad = stack_scene(1, 1.0, true);
        let look_opts = look(size);
        let t = time_interleaved(
            self.ctx,
            &one_quad,
            Some(heights),
            std::slice::from_ref(&look_opts),
            self.frames,
        )?;
        let still = &t[0];
        self.keep("one quad, look, still view".to_owned(), still);
        Ok(still.shadow_maps_ms / (still.total_ms - still.shadow_maps_ms).max(1e-9))
    }
}

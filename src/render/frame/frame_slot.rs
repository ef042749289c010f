//! One of the renderer's frames in flight: its command buffer, pass timer, read-back buffers and
//! what it submitted and has not yet retired. The buffers are made for every slot at the first
//! frame that reads back, so later frames create nothing, and dropped when the targets change.

use std::sync::Arc;

use super::gbuffer::GBufferChannels;
use super::targets::{average_blocks, Targets};
use crate::render::kit::frame_timeline::SubmittedTimeline;
use crate::render::kit::pass_timer::PassTimer;
use crate::vk::{half_floats_to_rgba, CommandSlot, Context, Readback, VkResult};

pub(super) struct FrameSlot {
    pub commands: CommandSlot,
    pub timer: PassTimer,
    pub readback: Option<Readback>,
    /// The depth's copy (shadow probes only).
    pub depth_readback: Option<Readback>,
    /// The radiance's copy (`RenderOptions::keep_radiance` only).
    pub radiance_readback: Option<Readback>,
    /// The G-buffer's channels (`RenderOptions::gbuffer` only).
    pub gbuffer_readback: Option<Vec<Readback>>,
    /// The frame submitted from this slot and not yet retired: (index, read back?, draws culled).
    pub pending: Option<(u64, bool, usize)>,
    /// That frame's host spans and clock calibration so far.
    pub timeline: Option<SubmittedTimeline>,
    /// The work counters' copy (`RenderOptions::count_work` only).
    pub work_readback: Option<Readback>,
}

/// What a retired frame read back.
pub(super) struct ReadPixels {
    pub rgba: Option<Vec<u8>>,
    pub depth: Option<Vec<f32>>,
    pub radiance: Option<Vec<[f32; 4]>>,
    pub gbuffer: Option<GBufferChannels>,
}

impl FrameSlot {
    /// Slot `k`, timing up to `scopes` scopes a frame, with no read-back buffers yet.
    pub fn new(ctx: &Arc<Context>, k: usize, scopes: u32) -> VkResult<FrameSlot> {
        Ok(FrameSlot {
            commands: CommandSlot::new(ctx, &format!("frame slot {k}"))?,
            timer: PassTimer::new(ctx, scopes, &format!("frame slot {k} timestamps"))?,
            readback: None,
            depth_readback: None,
            radiance_readback: None,
            gbuffer_readback: None,
            pending: None,
            timeline: None,
            work_readback: None,
        })
    }

    /// Makes slot `k`'s read-back buffers for `targets`: the colour always, the depth and the
    /// radiance when asked, the G-buffer's channels where the targets have them.
    pub fn make_readbacks(
        &mut self,
        ctx: &Arc<Context>,
        k: usize,
        targets: &Targets,
        (depth, radiance): (bool, bool),
    ) -> VkResult<()> {
        let name = format!("frame slot {k} readback");
        self.readback = Some(targets.readback_buffer(ctx, &name)?);
        if depth {
            let name = format!("frame slot {k} depth readback");
            self.depth_readback = Some(targets.readback_buffer(ctx, &name)?);
        }
        if radiance {
            let name = format!("frame slot {k} radiance readback");
            self.radiance_readback = Some(targets.radiance_buffer(ctx, &name)?);
        }
        if let Some(g) = targets.gbuffer.as_ref().filter(|g| g.kept()) {
            let name = format!("frame slot {k}");
            self.gbuffer_readback = Some(g.readbacks(ctx, &name)?);
        }
        Ok(())
    }

    /// Drops every read-back buffer (the targets they copy from changed).
    pub fn forget_readbacks(&mut self) {
        self.readback = None;
        self.depth_readback = None;
        self.radiance_readback = None;
        self.gbuffer_readback = None;
        self.work_readback = None;
    }

    /// The pixels the retired frame copied back, at `width` x `height` (`targets` says by how
    /// much the radiance was supersampled); all `None` when the frame was not read back.
    pub fn read_pixels(
        &self,
        targets: &Targets,
        (width, height): (u32, u32),
        read_back: bool,
    ) -> VkResult<ReadPixels> {
        let rgba = self
            .readback
            .as_ref()
            .filter(|_| read_back)
            .map(|b| b.bytes().map(<[u8]>::to_vec))
            .transpose()?;
        let depth = self
            .depth_readback
            .as_ref()
            .filter(|_| read_back)
            .map(|b| b.bytes().map(bytemuck::pod_collect_to_vec))
            .transpose()?;
        let radiance = match self.radiance_readback.as_ref().filter(|_| read_back) {
            Some(buffer) => {
                let scale = targets.scale();
                let texels = half_floats_to_rgba(buffer.bytes()?);
                Some(average_blocks(&texels, width * scale, scale))
            }
            None => None,
        };
        let gbuffer = match (&self.gbuffer_readback, read_back) {
            (Some(buffers), true) => {
                let bytes = buffers
                    .iter()
                    .map(Readback::bytes)
                    .collect::<VkResult<Vec<_>>>()?;
                Some(GBufferChannels::decode(width, height, &bytes))
            }
            _ => None,
        };
        Ok(ReadPixels {
            rgba,
            depth,
            radiance,
            gbuffer,
        })
    }
}

//! Puts a renderer's finished frames on the window: acquires a swapchain image, blits the colour
//! target into it, presents it; re-creates the swapchain when the window changes; and, when
//! asked, copies the presented image back to the host (the viewer's screenshot), so a screenshot
//! shows what went through the swapchain, not the offscreen target.
//!
//! The blit is its own submission after the renderer's frame on the same queue: queue order and
//! one barrier (colour attachment output to blit) order it after the frame's drawing, and the
//! renderer's next frame waits for transfers before it clears the target.

use std::sync::Arc;

use ash::vk;

use crate::render::FRAMES_IN_FLIGHT;
use crate::vk::{
    transition_images, whole_color_region, CommandSlot, Context, Image, ImageTransition,
    PresentMode, Readback, Recording, Semaphore, SubmitSync, Swapchain, SwapchainImage, VkResult,
};

/// A presented image read back: RGBA8 (sRGB), rows top to bottom.
#[derive(Debug, Clone)]
pub struct Screenshot {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, four bytes each.
    pub rgba: Vec<u8>,
}

/// What became of a frame handed to [`Presenter::present`].
#[derive(Debug)]
pub enum Presented {
    /// On screen (and read back, if asked).
    Shown(Option<Screenshot>),
    /// The window changed before an image could be acquired; the swapchain was re-created and
    /// the frame dropped.
    Dropped,
}

struct PresentSlot {
    commands: CommandSlot,
    /// Signalled when the slot's acquired image may be written.
    acquired: Semaphore,
}

/// The swapchain of a presenting context's window and the per-frame objects that feed it.
pub struct Presenter {
    ctx: Arc<Context>,
    mode: PresentMode,
    slots: Vec<PresentSlot>,
    next: usize,
    capture: Option<Readback>,
    /// Declared last: dropped after the slots, whose fences it relies on having waited.
    swapchain: Option<Swapchain>,
}

impl Presenter {
    /// A presenter for a window of `size` pixels.
    pub fn new(ctx: &Arc<Context>, size: (u32, u32), mode: PresentMode) -> VkResult<Presenter> {
        let slots = (0..FRAMES_IN_FLIGHT)
            .map(|k| {
                Ok(PresentSlot {
                    commands: CommandSlot::new(ctx, &format!("present slot {k}"))?,
                    acquired: Semaphore::new(ctx, &format!("present slot {k} acquired"))?,
                })
            })
            .collect::<VkResult<Vec<_>>>()?;
        let swapchain = Some(Swapchain::new(ctx, size, mode, None)?);
        Ok(Presenter {
            ctx: ctx.clone(),
            mode,
            slots,
            next: 0,
            capture: None,
            swapchain,
        })
    }

    /// The swapchain's size, which frames should be drawn at.
    pub fn extent(&self) -> (u32, u32) {
        self.swapchain
            .as_ref()
            .map_or((0, 0), |s| (s.extent().width, s.extent().height))
    }

    /// How presentation paces frames.
    pub fn mode(&self) -> PresentMode {
        self.mode
    }

    /// The present mode the surface gave.
    pub fn present_mode(&self) -> vk::PresentModeKHR {
        self.swapchain
            .as_ref()
            .map_or(vk::PresentModeKHR::FIFO, |s| s.present_mode())
    }

    /// Re-creates the swapchain for a window of `size` (a resize, or another present mode).
    pub fn rebuild(&mut self, size: (u32, u32), mode: PresentMode) -> VkResult<()> {
        for slot in &mut self.slots {
            slot.commands.wait()?;
        }
        self.ctx.wait_idle()?;
        let old = self.swapchain.take();
        self.swapchain = Some(Swapchain::new(&self.ctx, size, mode, old)?);
        self.mode = mode;
        self.capture = None;
        Ok(())
    }

    /// Shows `color` (the renderer's colour target, `COLOR_ATTACHMENT_OPTIMAL` after a frame
    /// submitted before this call) in the window, scaled to the swapchain's size; with `capture`,
    /// waits for it and returns the presented pixels. The swapchain is re-created when it no longer
    /// matches `window` (pixels).
    pub fn present(
        &mut self,
        color: &Image,
        window: (u32, u32),
        capture: bool,
    ) -> VkResult<Presented> {
        let k = self.next;
        self.slots[k].commands.wait()?;
        let chain = self
            .swapchain
            .as_ref()
            .expect("a swapchain between rebuilds");
        let acquired = match chain.acquire(&self.slots[k].acquired)? {
            Ok(acquired) => acquired,
            Err(_lost) => {
                self.rebuild(window, self.mode)?;
                return Ok(Presented::Dropped);
            }
        };
        let (extent, format) = (chain.extent(), chain.format());
        if capture && self.capture.is_none() {
            let bytes = u64::from(extent.width) * u64::from(extent.height) * 4;
            self.capture = Some(Readback::new(&self.ctx, bytes, "screenshot")?);
        }
        let target = chain.image(acquired.index);
        let readback = self.capture.as_ref().filter(|_| capture);
        let slot = &mut self.slots[k];
        let sync = SubmitSync {
            wait: Some((&slot.acquired, vk::PipelineStageFlags::TRANSFER)),
            signal: Some(chain.filled(acquired.index)),
        };
        slot.commands.submit_synced(sync, |rec| {
            to_transfer(rec, color, &target);
            rec.blit_whole(color, &target);
            finish_image(rec, target, extent, readback)
        })?;
        let current = chain.present(acquired.index)?;
        self.next = (k + 1) % self.slots.len();
        let screenshot = match readback {
            Some(buffer) => {
                self.slots[k].commands.wait()?;
                let mut rgba = buffer.bytes()?.to_vec();
                if format == vk::Format::B8G8R8A8_SRGB || format == vk::Format::B8G8R8A8_UNORM {
                    rgba.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
                }
                Some(Screenshot {
                    width: extent.width,
                    height: extent.height,
                    rgba,
                })
            }
            None => None,
        };
        let stale = (extent.width, extent.height) != window;
        if !current || acquired.suboptimal || stale {
            self.rebuild(window, self.mode)?;
        }
        Ok(Presented::Shown(screenshot))
    }
}

/// The colour target from drawing to blit source, the acquired image from nothing to blit target.
fn to_transfer(rec: &Recording, color: &Image, target: &SwapchainImage) {
    let blit = vk::PipelineStageFlags2::BLIT;
    transition_images(
        rec,
        &[
            ImageTransition::color(
                color,
                (
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                ),
                (
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
                (blit, vk::AccessFlags2::TRANSFER_READ),
            ),
            ImageTransition::color(
                target,
                (
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                ),
                // Chained to the acquire semaphore's wait, which is at the transfer stage.
                (
                    vk::PipelineStageFlags2::ALL_TRANSFER,
                    vk::AccessFlags2::NONE,
                ),
                (blit, vk::AccessFlags2::TRANSFER_WRITE),
            ),
        ],
    );
}

/// The blitted image to presentation, through a copy into `readback` when given.
fn finish_image(
    rec: &Recording,
    target: SwapchainImage,
    extent: vk::Extent2D,
    readback: Option<&Readback>,
) -> VkResult<()> {
    use vk::ImageLayout as L;
    let written = (
        vk::PipelineStageFlags2::BLIT,
        vk::AccessFlags2::TRANSFER_WRITE,
    );
    let presented = (
        vk::PipelineStageFlags2::BOTTOM_OF_PIPE,
        vk::AccessFlags2::NONE,
    );
    let step = |layouts, src, dst| {
        transition_images(rec, &[ImageTransition::color(&target, layouts, src, dst)]);
    };
    let Some(buffer) = readback else {
        step(
            (L::TRANSFER_DST_OPTIMAL, L::PRESENT_SRC_KHR),
            written,
            presented,
        );
        return Ok(());
    };
    let copied = (
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
    );
    step(
        (L::TRANSFER_DST_OPTIMAL, L::TRANSFER_SRC_OPTIMAL),
        written,
        copied,
    );
    let region = whole_color_region(extent.width, extent.height);
    buffer.record_copy_from_image(rec, &target, region)?;
    step(
        (L::TRANSFER_SRC_OPTIMAL, L::PRESENT_SRC_KHR),
        (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::NONE),
        presented,
    );
    Ok(())
}

//! The swapchain of a presenting context's window: creation (and re-creation after a resize or an
//! out-of-date answer), acquiring an image, presenting it. Its images are only ever transfer
//! targets (a finished frame is blitted in) and transfer sources (a screenshot), so they carry no
//! views.

use std::marker::PhantomData;
use std::sync::Arc;

use ash::{khr, vk};

use super::context::Context;
use super::deferred::Doomed;
use super::error::{Named, VkError, VkResult};
use super::image::{sealed, WholeImage};
use super::semaphore::Semaphore;

/// One image of a [`Swapchain`], borrowed from it: a target for
/// [`Recording::blit_whole`](super::Recording::blit_whole) and a source for screenshots.
#[derive(Debug, Clone, Copy)]
pub struct SwapchainImage<'s> {
    raw: vk::Image,
    format: vk::Format,
    extent: vk::Extent2D,
    _chain: PhantomData<&'s Swapchain>,
}

impl sealed::Sealed for SwapchainImage<'_> {}

impl WholeImage for SwapchainImage<'_> {
    fn whole_raw(&self) -> vk::Image {
        self.raw
    }

    fn whole_extent(&self) -> vk::Extent2D {
        self.extent
    }

    fn whole_format(&self) -> vk::Format {
        self.format
    }

    fn whole_levels(&self) -> u32 {
        1
    }

    fn whole_layers(&self) -> u32 {
        1
    }
}

/// How presentation paces frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PresentMode {
    /// Wait for the display's vertical blank (FIFO, always available).
    Vsync,
    /// Do not wait: immediate, else mailbox, else FIFO where the surface offers nothing else.
    Unpaced,
}

/// An image acquired for the next frame.
#[derive(Debug, Clone, Copy)]
pub struct Acquired {
    /// Which of the swapchain's images.
    pub index: u32,
    /// The swapchain still works but no longer matches the surface: re-create it after this frame.
    pub suboptimal: bool,
}

/// The surface changed under the swapchain (`VK_ERROR_OUT_OF_DATE_KHR`): re-create it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SwapchainLost;

/// A swapchain with its images and one presentation semaphore per image.
pub struct Swapchain {
    ctx: Arc<Context>,
    loader: khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    /// Signalled by the submission that fills image k and waited by its presentation; one per
    /// image because a presentation holds its semaphore until that image comes back.
    filled: Vec<Semaphore>,
    format: vk::Format,
    extent: vk::Extent2D,
    mode: vk::PresentModeKHR,
}

impl Swapchain {
    /// Creates a swapchain of about `size` (the surface's own extent wins where it has one),
    /// replacing `old`, whose work must have finished (`Context::wait_idle`).
    pub fn new(
        ctx: &Arc<Context>,
        size: (u32, u32),
        mode: PresentMode,
        old: Option<Swapchain>,
    ) -> VkResult<Swapchain> {
        let surface = ctx.present_surface().ok_or_else(|| {
            VkError::Invalid("a swapchain needs a context made with new_presenting".into())
        })?;
        let (pd, raw_surface) = (ctx.physical(), surface.raw);
        // SAFETY: plain queries on a valid physical device and surface.
        let (caps, formats, modes) = unsafe {
            (
                surface
                    .loader
                    .get_physical_device_surface_capabilities(pd, raw_surface)
                    .named("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?,
                surface
                    .loader
                    .get_physical_device_surface_formats(pd, raw_surface)
                    .named("vkGetPhysicalDeviceSurfaceFormatsKHR")?,
                surface
                    .loader
                    .get_physical_device_surface_present_modes(pd, raw_surface)
                    .named("vkGetPhysicalDeviceSurfacePresentModesKHR")?,
            )
        };
        let extent = choose_extent(&caps, size)?;
        let wanted_usage = vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::TRANSFER_SRC;
        if !caps.supported_usage_flags.contains(wanted_usage) {
            return Err(VkError::Unsupported(format!(
                "swapchain images that are transfer sources and targets (the surface offers {:?})",
                caps.supported_usage_flags
            )));
        }
        let format = choose_format(ctx, &formats)?;
        let present_mode = choose_present_mode(&modes, mode);
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count != 0 {
            count = count.min(caps.max_image_count);
        }
        let alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|&a| caps.supported_composite_alpha.contains(a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(raw_surface)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(wanted_usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(alpha)
            .present_mode(present_mode)
            .clipped(true)
            .old_swapchain(old.as_ref().map_or(vk::SwapchainKHR::null(), |o| o.raw));
        let loader = khr::swapchain::Device::new(ctx.instance(), ctx.device());
        // SAFETY: valid create info; the old swapchain, if any, is idle.
        let raw = unsafe { loader.create_swapchain(&info, None) }.named("vkCreateSwapchainKHR")?;
        drop(old);
        let mut chain = Swapchain {
            ctx: ctx.clone(),
            loader,
            raw,
            images: Vec::new(),
            filled: Vec::new(),
            format: format.format,
            extent,
            mode: present_mode,
        };
        // SAFETY: the swapchain was just created on this device.
        chain.images =
            unsafe { chain.loader.get_swapchain_images(raw) }.named("vkGetSwapchainImagesKHR")?;
        for (k, &image) in chain.images.iter().enumerate() {
            ctx.set_name(image, &format!("swapchain image {k}"));
            let semaphore = Semaphore::new(ctx, &format!("swapchain image {k} filled"))?;
            chain.filled.push(semaphore);
        }
        Ok(chain)
    }

    /// Acquires the next image; `ready` is signalled when the image may be written.
    pub fn acquire(&self, ready: &Semaphore) -> VkResult<Result<Acquired, SwapchainLost>> {
        let timeout = u64::try_from(self.ctx.gpu_timeout().as_nanos()).unwrap_or(u64::MAX);
        // SAFETY: valid swapchain; `ready` is unsignalled and not waited on (the caller's frame
        // slot that used it last has finished).
        let got = unsafe {
            self.loader
                .acquire_next_image(self.raw, timeout, ready.raw(), vk::Fence::null())
        };
        match got {
            Ok((index, suboptimal)) => Ok(Ok(Acquired { index, suboptimal })),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Err(SwapchainLost)),
            Err(vk::Result::TIMEOUT | vk::Result::NOT_READY) => Err(VkError::Hang {
                what: "acquiring a swapchain image".into(),
                seconds: self.ctx.gpu_timeout().as_secs_f64(),
            }),
            Err(e) => Err(e).named("vkAcquireNextImageKHR"),
        }
    }

    /// Presents image `index` once its [`Swapchain::filled`] semaphore is signalled. `Ok(false)`
    /// when the swapchain is out of date or suboptimal and should be re-created.
    pub fn present(&self, index: u32) -> VkResult<bool> {
        let chains = [self.raw];
        let indices = [index];
        let waits = [self.filled(index).raw()];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&chains)
            .image_indices(&indices);
        let queue = self
            .ctx
            .queue()
            .lock()
            .map_err(|_| VkError::Invalid("queue lock poisoned".into()))?;
        // SAFETY: the image was acquired and its filling submission signals the semaphore; the
        // queue is externally synchronised by the lock.
        match unsafe { self.loader.queue_present(*queue, &info) } {
            Ok(suboptimal) => Ok(!suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(e) => Err(e).named("vkQueuePresentKHR"),
        }
    }

    /// The semaphore the submission filling image `index` signals.
    pub fn filled(&self, index: u32) -> &Semaphore {
        &self.filled[index as usize]
    }

    /// Image `index`, owned by the swapchain (and never destroyed through the returned value).
    pub fn image(&self, index: u32) -> SwapchainImage<'_> {
        SwapchainImage {
            raw: self.images[index as usize],
            format: self.format,
            extent: self.extent,
            _chain: PhantomData,
        }
    }

    /// How many images the swapchain has.
    pub fn image_count(&self) -> usize {
        self.images.len()
    }

    /// The images' format.
    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// The images' size.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// The present mode chosen.
    pub fn present_mode(&self) -> vk::PresentModeKHR {
        self.mode
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // Presentation is not fenced: only an idle device proves its semaphore waits are over.
        let _ = self.ctx.wait_idle();
        self.filled.clear();
        // Destroyed at once unless a recording still open blits into one of its images.
        self.ctx
            .defer(Doomed::Swapchain(self.loader.clone(), self.raw));
    }
}

fn choose_extent(caps: &vk::SurfaceCapabilitiesKHR, size: (u32, u32)) -> VkResult<vk::Extent2D> {
    let extent = if caps.current_extent.width != u32::MAX {
        caps.current_extent
    } else {
        vk::Extent2D {
            width: size
                .0
                .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
            height: size
                .1
                .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
        }
    };
    if extent.width == 0 || extent.height == 0 {
        return Err(VkError::Invalid(
            "a swapchain for a window of zero size (minimised)".into(),
        ));
    }
    Ok(extent)
}

/// An 8-bit sRGB format the device can blit into, else any format it can blit into (colours then
/// pass through unencoded, which the log says).
fn choose_format(
    ctx: &Context,
    formats: &[vk::SurfaceFormatKHR],
) -> VkResult<vk::SurfaceFormatKHR> {
    let blittable = |f: &&vk::SurfaceFormatKHR| {
        ctx.format_features(f.format)
            .contains(vk::FormatFeatureFlags::BLIT_DST)
    };
    let srgb = [vk::Format::B8G8R8A8_SRGB, vk::Format::R8G8B8A8_SRGB];
    if let Some(f) = formats
        .iter()
        .filter(blittable)
        .find(|f| srgb.contains(&f.format) && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
    {
        return Ok(*f);
    }
    let any = formats.iter().find(blittable).copied().ok_or_else(|| {
        VkError::Unsupported(format!(
            "a swapchain format that can be blitted into (offered: {:?})",
            formats.iter().map(|f| f.format).collect::<Vec<_>>()
        ))
    })?;
    log::warn!(
        "the window offers no 8-bit sRGB format; presenting in {:?}, colours may look off",
        any.format
    );
    Ok(any)
}

fn choose_present_mode(modes: &[vk::PresentModeKHR], mode: PresentMode) -> vk::PresentModeKHR {
    let preferred: &[vk::PresentModeKHR] = match mode {
        PresentMode::Vsync => &[],
        PresentMode::Unpaced => &[vk::PresentModeKHR::IMMEDIATE, vk::PresentModeKHR::MAILBOX],
    };
    preferred
        .iter()
        .copied()
        .find(|m| modes.contains(m))
        .unwrap_or(vk::PresentModeKHR::FIFO)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unpaced_prefers_immediate_then_mailbox_and_vsync_is_fifo() {
        use vk::PresentModeKHR as M;
        let all = [M::FIFO, M::MAILBOX, M::IMMEDIATE];
        assert_eq!(choose_present_mode(&all, PresentMode::Vsync), M::FIFO);
        assert_eq!(
            choose_present_mode(&all, PresentMode::Unpaced),
            M::IMMEDIATE
        );
        let no_immediate = [M::FIFO, M::MAILBOX];
        assert_eq!(
            choose_present_mode(&no_immediate, PresentMode::Unpaced),
            M::MAILBOX
        );
        assert_eq!(
            choose_present_mode(&[M::FIFO], PresentMode::Unpaced),
            M::FIFO
        );
    }

    #[test]
    fn extent_follows_the_surface_else_the_window_clamped_and_never_zero() {
        let mut caps = vk::SurfaceCapabilitiesKHR {
            current_extent: vk::Extent2D {
                width: 640,
                height: 480,
            },
            min_image_extent: vk::Extent2D {
                width: 1,
                height: 1,
            },
            max_image_extent: vk::Extent2D {
                width: 4096,
                height: 4096,
            },
            ..Default::default()
        };
        let e = choose_extent(&caps, (100, 100)).unwrap();
        assert_eq!((e.width, e.height), (640, 480));
        caps.current_extent.width = u32::MAX;
        let e = choose_extent(&caps, (9000, 300)).unwrap();
        assert_eq!((e.width, e.height), (4096, 300));
        caps.current_extent = vk::Extent2D {
            width: 0,
            height: 0,
        };
        assert!(choose_extent(&caps, (10, 10)).is_err());
    }
}

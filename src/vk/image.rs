//! 2D images with memory and views, and samplers. A mip chain is uploaded level by level from one
//! staging buffer; per-level views serve compute passes that write one level at a time.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::context::Context;
use super::counters::Created;
use super::deferred::Doomed;
use super::error::{Named, VkError, VkResult};

/// What to create: size, format, mip count, usage, and the aspect its views see.
#[derive(Debug, Clone, Copy)]
pub struct ImageDesc {
    /// Width of mip level 0, in texels.
    pub width: u32,
    /// Height of mip level 0, in texels.
    pub height: u32,
    /// Texel format.
    pub format: vk::Format,
    /// Mip levels, at least 1.
    pub mip_levels: u32,
    /// How the image is used (sampled, storage, transfers, attachments).
    pub usage: vk::ImageUsageFlags,
    /// The aspect its views and transfers see (colour or depth).
    pub aspect: vk::ImageAspectFlags,
}

/// A 2D image, its allocation and a view over all its mip levels. Dropping it hands them to the
/// context, which destroys them once the GPU has finished every submission that may use them;
/// views (and so descriptor sets) of it keep the image alive as long as they live.
pub struct Image {
    inner: Arc<ImageInner>,
    view: ImageView,
}

/// What an [`Image`] shares with its views.
struct ImageInner {
    ctx: Arc<Context>,
    raw: vk::Image,
    allocation: Option<Allocation>,
    desc: ImageDesc,
    /// Array layers; views of array images are `TYPE_2D_ARRAY` even with one layer.
    layers: u32,
    array: bool,
    name: String,
}

impl Image {
    /// Creates the image in GPU memory, named `name`, with a view of every mip level.
    pub fn new(ctx: &Arc<Context>, desc: ImageDesc, name: &str) -> VkResult<Image> {
        Self::create(ctx, desc, None, 1, name)
    }

    /// An attachment with `samples` samples per pixel (1, 2, 4 or 8, at most the device's
    /// `max_samples`): a multisampled render target, resolved into a single-sample image.
    pub fn new_multisampled(
        ctx: &Arc<Context>,
        desc: ImageDesc,
        samples: u32,
        name: &str,
    ) -> VkResult<Image> {
        let most = ctx.info().max_samples;
        if !samples.is_power_of_two() || samples > most || desc.mip_levels != 1 {
            return Err(VkError::Invalid(format!(
                "image {name:?} of {samples} samples and {} mips (the device takes 1 to {most} samples, one mip)",
                desc.mip_levels
            )));
        }
        Self::create(ctx, desc, None, samples, name)
    }

    /// An array image of `layers` layers (read as `sampler2DArray`), its view over every layer
    /// and mip level.
    pub fn new_array(
        ctx: &Arc<Context>,
        desc: ImageDesc,
        layers: u32,
        name: &str,
    ) -> VkResult<Image> {
        // Vulkan's guaranteed minimum of maxImageArrayLayers.
        let limit = 256;
        if layers == 0 || layers > limit {
            return Err(VkError::Invalid(format!(
                "image {name:?} of {layers} layers (the device allows 1..={limit})"
            )));
        }
        Self::create(ctx, desc, Some(layers), 1, name)
    }

    fn create(
        ctx: &Arc<Context>,
        desc: ImageDesc,
        array: Option<u32>,
        samples: u32,
        name: &str,
    ) -> VkResult<Image> {
        let limit = ctx.info().max_image_dimension_2d;
        if desc.width == 0 || desc.height == 0 || desc.width > limit || desc.height > limit {
            return Err(VkError::Invalid(format!(
                "image {name:?} of {}x{} (the device allows 1..={limit} per side)",
                desc.width, desc.height
            )));
        }
        let device = ctx.device();
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(desc.mip_levels)
            .array_layers(array.unwrap_or(1))
            .samples(vk::SampleCountFlags::from_raw(samples))
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw = unsafe { device.create_image(&info, None) }
            .named("vkCreateImage")
            .map_err(|e| e.for_object("image", name))?;
        let mut inner = ImageInner {
            ctx: ctx.clone(),
            raw,
            allocation: None,
            desc,
            layers: array.unwrap_or(1),
            array: array.is_some(),
            name: name.to_owned(),
        };
        inner.bind_memory()?;
        let inner = Arc::new(inner);
        let view = ImageView::new(&inner, 0, desc.mip_levels)?;
        ctx.set_name(raw, name);
        ctx.set_name(view.raw(), &format!("{name} view"));
        Ok(Image { inner, view })
    }

    /// A view of one mip level, owned by the returned value.
    pub fn level_view(&self, level: u32) -> VkResult<ImageView> {
        if level >= self.desc().mip_levels {
            return Err(VkError::Invalid(format!(
                "mip {level} of image {:?}",
                self.name()
            )));
        }
        let view = ImageView::new(&self.inner, level, 1)?;
        self.inner
            .ctx
            .set_name(view.raw(), &format!("{} mip {level}", self.name()));
        Ok(view)
    }

    /// The raw handle, for the vk layer's own commands and an engine's (the shader-library
    /// example binds it in its own pipeline): this value still owns it and destroys it once the
    /// GPU is done with it, so a raw use must end before the last clone goes.
    pub fn raw(&self) -> vk::Image {
        self.inner.raw
    }

    /// The view over all mip levels and layers.
    pub fn view(&self) -> &ImageView {
        &self.view
    }

    /// What the image was created with.
    pub fn desc(&self) -> &ImageDesc {
        &self.inner.desc
    }

    /// Array layers (1 for plain images).
    pub fn layer_count(&self) -> u32 {
        self.inner.layers
    }

    /// The debug name.
    pub fn name(&self) -> &str {
        &self.inner.name
    }

    /// Width and height of mip `level`, by Vulkan's rule (halve, round down, at least 1).
    pub fn level_extent(&self, level: u32) -> (u32, u32) {
        let desc = self.desc();
        ((desc.width >> level).max(1), (desc.height >> level).max(1))
    }
}

/// A colour image recorded whole (blits, screenshots): an [`Image`] or a
/// [`SwapchainImage`](super::SwapchainImage). Sealed: only this layer's images implement it, so
/// no raw handle reaches a recording through it.
pub trait WholeImage: sealed::Sealed {
    /// The raw handle.
    #[doc(hidden)]
    fn whole_raw(&self) -> vk::Image;
    /// The size of mip level 0.
    fn whole_extent(&self) -> vk::Extent2D;
    /// The format.
    fn whole_format(&self) -> vk::Format;
    /// Mip levels.
    fn whole_levels(&self) -> u32;
    /// Array layers.
    fn whole_layers(&self) -> u32;
}

pub(crate) mod sealed {
    /// Keeps [`WholeImage`](super::WholeImage) to this layer's images.
    pub trait Sealed {}
}

impl sealed::Sealed for Image {}

impl WholeImage for Image {
    fn whole_raw(&self) -> vk::Image {
        self.raw()
    }

    fn whole_extent(&self) -> vk::Extent2D {
        vk::Extent2D {
            width: self.desc().width,
            height: self.desc().height,
        }
    }

    fn whole_format(&self) -> vk::Format {
        self.desc().format
    }

    fn whole_levels(&self) -> u32 {
        self.desc().mip_levels
    }

    fn whole_layers(&self) -> u32 {
        self.layer_count()
    }
}

impl ImageInner {
    fn bind_memory(&mut self) -> VkResult<()> {
        let device = self.ctx.device();
        // SAFETY: the image was created on this device.
        let requirements = unsafe { device.get_image_memory_requirements(self.raw) };
        self.ctx
            .faults()
            .allocation()
            .map_err(|e| e.for_object("image", &self.name))?;
        let allocation = self
            .ctx
            .allocator()
            .lock()
            .map_err(|_| VkError::Invalid("allocator lock poisoned".into()))?
            .allocate(&AllocationCreateDesc {
                name: &self.name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            })
            .map_err(|reason| VkError::Allocation {
                name: self.name.clone(),
                reason,
            })?;
        // The allocation's own size, which its destruction counts off again.
        self.ctx.count(Created::Image {
            bytes: allocation.size(),
        });
        // SAFETY: the allocation satisfies the image's requirements and is kept with the image.
        let bound =
            unsafe { device.bind_image_memory(self.raw, allocation.memory(), allocation.offset()) };
        self.allocation = Some(allocation);
        bound.named("vkBindImageMemory")
    }
}

impl Drop for ImageInner {
    fn drop(&mut self) {
        self.ctx
            .defer(Doomed::Image(self.raw, self.allocation.take()));
    }
}

/// An image view: the whole image's ([`Image::view`]) or one mip level's
/// ([`Image::level_view`]). Clones share the view; it keeps its image alive, and goes (after the
/// GPU is done with it) when the last clone, and every descriptor set written with it, is gone.
#[derive(Clone)]
pub struct ImageView {
    inner: Arc<ViewInner>,
}

struct ViewInner {
    raw: vk::ImageView,
    /// Dropped after the view is handed over, so the image is destroyed after it.
    image: Arc<ImageInner>,
}

impl ImageView {
    fn new(image: &Arc<ImageInner>, base_mip: u32, mip_count: u32) -> VkResult<ImageView> {
        let info = vk::ImageViewCreateInfo::default()
            .image(image.raw)
            .view_type(if image.array {
                vk::ImageViewType::TYPE_2D_ARRAY
            } else {
                vk::ImageViewType::TYPE_2D
            })
            .format(image.desc.format)
            .subresource_range(
                vk::ImageSubresourceRange::default()
                    .aspect_mask(image.desc.aspect)
                    .base_mip_level(base_mip)
                    .level_count(mip_count)
                    .layer_count(image.layers),
            );
        // SAFETY: the range lies within the image (callers check the level).
        let raw = unsafe { image.ctx.device().create_image_view(&info, None) }
            .named("vkCreateImageView")?;
        Ok(ImageView {
            inner: Arc::new(ViewInner {
                raw,
                image: image.clone(),
            }),
        })
    }

    /// The raw handle, for the vk layer's own commands and an engine's descriptor writes; owned
    /// as [`Image::raw`]'s is.
    pub fn raw(&self) -> vk::ImageView {
        self.inner.raw
    }

    /// What a descriptor set holds to keep the view (and its image) alive.
    pub(crate) fn keep_alive(&self) -> Arc<dyn Send + Sync> {
        self.inner.clone()
    }
}

impl Drop for ViewInner {
    fn drop(&mut self) {
        self.image.ctx.defer(Doomed::ImageView(self.raw));
    }
}

/// A sampler. Clones share it; it goes (after the GPU is done with it) when the last clone, and
/// every descriptor set written with it, is gone.
#[derive(Clone)]
pub struct Sampler {
    inner: Arc<SamplerInner>,
}

struct SamplerInner {
    ctx: Arc<Context>,
    raw: vk::Sampler,
}

impl Sampler {
    /// `filter` applies to magnification, minification and mip selection alike.
    pub fn new(
        ctx: &Arc<Context>,
        filter: vk::Filter,
        address: vk::SamplerAddressMode,
        name: &str,
    ) -> VkResult<Sampler> {
        let mip = if filter == vk::Filter::LINEAR {
            vk::SamplerMipmapMode::LINEAR
        } else {
            vk::SamplerMipmapMode::NEAREST
        };
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter)
            .min_filter(filter)
            .mipmap_mode(mip)
            .address_mode_u(address)
            .address_mode_v(address)
            .address_mode_w(address)
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device().create_sampler(&info, None) }.named("vkCreateSampler")?;
        ctx.count(Created::Sampler);
        ctx.set_name(raw, name);
        Ok(Sampler {
            inner: Arc::new(SamplerInner {
                ctx: ctx.clone(),
                raw,
            }),
        })
    }

    /// A sampler exactly as `info` describes it.
    pub fn from_info(
        ctx: &Arc<Context>,
        info: &vk::SamplerCreateInfo,
        name: &str,
    ) -> VkResult<Sampler> {
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device().create_sampler(info, None) }.named("vkCreateSampler")?;
        ctx.count(Created::Sampler);
        ctx.set_name(raw, name);
        Ok(Sampler {
            inner: Arc::new(SamplerInner {
                ctx: ctx.clone(),
                raw,
            }),
        })
    }

    /// The raw handle, for the vk layer's own descriptor writes and an engine's; owned as
    /// [`Image::raw`]'s is.
    pub fn raw(&self) -> vk::Sampler {
        self.inner.raw
    }

    /// What a descriptor set holds to keep the sampler alive.
    pub(crate) fn keep_alive(&self) -> Arc<dyn Send + Sync> {
        self.inner.clone()
    }
}

impl Drop for SamplerInner {
    fn drop(&mut self) {
        self.ctx.defer(Doomed::Sampler(self.raw));
    }
}

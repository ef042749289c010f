//! 2D images with memory and views, and samplers. A mip chain is uploaded level by level from one
//! staging buffer; per-level views serve compute passes that write one level at a time.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::context::Context;
use super::counters::Created;
use super::error::{Named, VkError, VkResult};

/// What to create: size, format, mip count, usage, and the aspect its views see.
#[derive(Debug, Clone, Copy)]
pub struct ImageDesc {
    pub width: u32,
    pub height: u32,
    pub format: vk::Format,
    pub mip_levels: u32,
    pub usage: vk::ImageUsageFlags,
    pub aspect: vk::ImageAspectFlags,
}

/// A 2D image, its allocation and a view over all its mip levels.
pub struct Image {
    ctx: Arc<Context>,
    raw: vk::Image,
    view: vk::ImageView,
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
        Self::create(ctx, desc, None, name)
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
        Self::create(ctx, desc, Some(layers), name)
    }

    fn create(
        ctx: &Arc<Context>,
        desc: ImageDesc,
        array: Option<u32>,
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
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw = unsafe { device.create_image(&info, None) }
            .named("vkCreateImage")
            .map_err(|e| e.for_object("image", name))?;
        let mut image = Image {
            ctx: ctx.clone(),
            raw,
            view: vk::ImageView::null(),
            allocation: None,
            desc,
            layers: array.unwrap_or(1),
            array: array.is_some(),
            name: name.to_owned(),
        };
        image.bind_memory()?;
        image.view = image.create_view(0, desc.mip_levels)?;
        ctx.set_name(raw, name);
        ctx.set_name(image.view, &format!("{name} view"));
        Ok(image)
    }

    fn bind_memory(&mut self) -> VkResult<()> {
        let device = self.ctx.device();
        // SAFETY: the image was created on this device.
        let requirements = unsafe { device.get_image_memory_requirements(self.raw) };
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
        self.ctx.count(Created::Image {
            bytes: requirements.size,
        });
        // SAFETY: the allocation satisfies the image's requirements.
        let bound =
            unsafe { device.bind_image_memory(self.raw, allocation.memory(), allocation.offset()) };
        self.allocation = Some(allocation);
        bound.named("vkBindImageMemory")
    }

    fn create_view(&self, base_mip: u32, mip_count: u32) -> VkResult<vk::ImageView> {
        let info = vk::ImageViewCreateInfo::default()
            .image(self.raw)
            .view_type(if self.array {
                vk::ImageViewType::TYPE_2D_ARRAY
            } else {
                vk::ImageViewType::TYPE_2D
            })
            .format(self.desc.format)
            .subresource_range(
                vk::ImageSubresourceRange::default()
                    .aspect_mask(self.desc.aspect)
                    .base_mip_level(base_mip)
                    .level_count(mip_count)
                    .layer_count(self.layers),
            );
        // SAFETY: the range lies within the image.
        unsafe { self.ctx.device().create_image_view(&info, None) }.named("vkCreateImageView")
    }

    /// A view of one mip level, owned by the returned value.
    pub fn level_view(&self, level: u32) -> VkResult<ImageView> {
        if level >= self.desc.mip_levels {
            return Err(VkError::Invalid(format!(
                "mip {level} of image {:?}",
                self.name
            )));
        }
        let raw = self.create_view(level, 1)?;
        self.ctx
            .set_name(raw, &format!("{} mip {level}", self.name));
        Ok(ImageView {
            ctx: self.ctx.clone(),
            raw,
        })
    }

    /// The raw handle.
    pub fn raw(&self) -> vk::Image {
        self.raw
    }

    /// The view over all mip levels.
    pub fn view(&self) -> vk::ImageView {
        self.view
    }

    /// What the image was created with.
    pub fn desc(&self) -> &ImageDesc {
        &self.desc
    }

    /// Array layers (1 for plain images).
    pub fn layer_count(&self) -> u32 {
        self.layers
    }

    /// The debug name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Width and height of mip `level`, by Vulkan's rule (halve, round down, at least 1).
    pub fn level_extent(&self, level: u32) -> (u32, u32) {
        (
            (self.desc.width >> level).max(1),
            (self.desc.height >> level).max(1),
        )
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        if self.ctx.is_hung() {
            // Hung work may still use the image: leave it (and its memory) to the process exit.
            return;
        }
        // SAFETY: users keep an Image alive until GPU work using it has completed.
        unsafe {
            self.ctx.device().destroy_image_view(self.view, None);
            self.ctx.device().destroy_image(self.raw, None);
        }
        if let (Some(a), Ok(mut alloc)) = (self.allocation.take(), self.ctx.allocator().lock()) {
            let _ = alloc.free(a);
        }
    }
}

/// An extra image view (e.g. one mip level); destroyed on drop.
pub struct ImageView {
    ctx: Arc<Context>,
    raw: vk::ImageView,
}

impl ImageView {
    /// The raw handle.
    pub fn raw(&self) -> vk::ImageView {
        self.raw
    }
}

impl Drop for ImageView {
    fn drop(&mut self) {
        // SAFETY: the view is not used by pending GPU work once its owner drops it.
        unsafe { self.ctx.device().destroy_image_view(self.raw, None) };
    }
}

/// A sampler; destroyed on drop.
pub struct Sampler {
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
            ctx: ctx.clone(),
            raw,
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
            ctx: ctx.clone(),
            raw,
        })
    }

    /// The raw handle.
    pub fn raw(&self) -> vk::Sampler {
        self.raw
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: no pending GPU work uses the sampler once its owner drops it.
        unsafe { self.ctx.device().destroy_sampler(self.raw, None) };
    }
}

//! Descriptor set layouts, a pool, and one way of writing sets: a list of `Bind`s.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::counters::Created;
use super::error::{Named, VkResult};

/// A descriptor set allocated and written by a [`DescriptorPool`]; only a pool makes one, so a
/// bound set is never null or foreign. It dies with its pool.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DescriptorSet(vk::DescriptorSet);

impl DescriptorSet {
    pub(crate) fn raw(self) -> vk::DescriptorSet {
        self.0
    }

    /// Rewrites `binds` into the set; no submitted work may be using it.
    pub fn rewrite(&self, ctx: &Context, binds: &[Bind]) {
        write_set(ctx.device(), self.0, binds);
    }
}

/// One resource bound at a binding number.
#[derive(Debug, Clone, Copy)]
pub enum Bind {
    /// A uniform buffer, whole.
    Uniform(u32, vk::Buffer),
    /// A storage buffer, whole.
    Storage(u32, vk::Buffer),
    /// An image view with its sampler, in `SHADER_READ_ONLY_OPTIMAL`.
    Texture(u32, vk::ImageView, vk::Sampler),
    /// A storage image view in `GENERAL` layout.
    StorageImage(u32, vk::ImageView),
}

impl Bind {
    fn binding(&self) -> u32 {
        match *self {
            Bind::Uniform(b, _)
            | Bind::Storage(b, _)
            | Bind::Texture(b, ..)
            | Bind::StorageImage(b, _) => b,
        }
    }

    fn kind(&self) -> vk::DescriptorType {
        match self {
            Bind::Uniform(..) => vk::DescriptorType::UNIFORM_BUFFER,
            Bind::Storage(..) => vk::DescriptorType::STORAGE_BUFFER,
            Bind::Texture(..) => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            Bind::StorageImage(..) => vk::DescriptorType::STORAGE_IMAGE,
        }
    }
}

/// A descriptor set layout; destroyed on drop.
pub struct DescriptorLayout {
    ctx: Arc<Context>,
    raw: vk::DescriptorSetLayout,
}

impl DescriptorLayout {
    /// Creates a layout from `(binding, type)` pairs visible to `stages`.
    pub fn new(
        ctx: &Arc<Context>,
        bindings: &[(u32, vk::DescriptorType)],
        stages: vk::ShaderStageFlags,
        name: &str,
    ) -> VkResult<DescriptorLayout> {
        let list: Vec<_> = bindings
            .iter()
            .map(|&(binding, kind)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(binding)
                    .descriptor_type(kind)
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&list);
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device().create_descriptor_set_layout(&info, None) }
            .named("vkCreateDescriptorSetLayout")?;
        ctx.set_name(raw, name);
        Ok(DescriptorLayout {
            ctx: ctx.clone(),
            raw,
        })
    }

    /// The raw handle.
    pub fn raw(&self) -> vk::DescriptorSetLayout {
        self.raw
    }
}

impl Drop for DescriptorLayout {
    fn drop(&mut self) {
        // SAFETY: no pipeline creation or set allocation is in flight with this layout.
        unsafe {
            self.ctx
                .device()
                .destroy_descriptor_set_layout(self.raw, None)
        };
    }
}

/// A descriptor pool sized for a known number of sets; its sets die with it.
pub struct DescriptorPool {
    ctx: Arc<Context>,
    raw: vk::DescriptorPool,
}

impl DescriptorPool {
    /// A pool for `max_sets` sets with up to `per_type` descriptors of each common type.
    pub fn new(
        ctx: &Arc<Context>,
        max_sets: u32,
        per_type: u32,
        name: &str,
    ) -> VkResult<DescriptorPool> {
        let sizes = [
            vk::DescriptorType::UNIFORM_BUFFER,
            vk::DescriptorType::STORAGE_BUFFER,
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            vk::DescriptorType::STORAGE_IMAGE,
        ]
        .map(|ty| vk::DescriptorPoolSize {
            ty,
            descriptor_count: per_type,
        });
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(max_sets)
            .pool_sizes(&sizes);
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device().create_descriptor_pool(&info, None) }
            .named("vkCreateDescriptorPool")?;
        ctx.set_name(raw, name);
        Ok(DescriptorPool {
            ctx: ctx.clone(),
            raw,
        })
    }

    /// Allocates one set of `layout` and writes `binds` into it.
    pub fn allocate(&self, layout: &DescriptorLayout, binds: &[Bind]) -> VkResult<DescriptorSet> {
        let layouts = [layout.raw()];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.raw)
            .set_layouts(&layouts);
        // SAFETY: the pool and layout belong to this device.
        let set = unsafe { self.ctx.device().allocate_descriptor_sets(&info) }
            .named("vkAllocateDescriptorSets")?[0];
        write_set(self.ctx.device(), set, binds);
        self.ctx.count(Created::DescriptorSet);
        Ok(DescriptorSet(set))
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        // SAFETY: no pending GPU work uses sets from this pool once its owner drops it.
        unsafe { self.ctx.device().destroy_descriptor_pool(self.raw, None) };
    }
}

/// Writes `binds` into `set`.
fn write_set(device: &ash::Device, set: vk::DescriptorSet, binds: &[Bind]) {
    let buffers: Vec<_> = binds
        .iter()
        .map(|b| match *b {
            Bind::Uniform(_, buf) | Bind::Storage(_, buf) => vk::DescriptorBufferInfo {
                buffer: buf,
                offset: 0,
                range: vk::WHOLE_SIZE,
            },
            _ => vk::DescriptorBufferInfo::default(),
        })
        .collect();
    let images: Vec<_> = binds
        .iter()
        .map(|b| match *b {
            Bind::Texture(_, view, sampler) => vk::DescriptorImageInfo {
                sampler,
                image_view: view,
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            },
            Bind::StorageImage(_, view) => vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: view,
                image_layout: vk::ImageLayout::GENERAL,
            },
            _ => vk::DescriptorImageInfo::default(),
        })
        .collect();
    let writes: Vec<_> = binds
        .iter()
        .enumerate()
        .map(|(k, b)| {
            let w = vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(b.binding())
                .descriptor_type(b.kind());
            match b {
                Bind::Uniform(..) | Bind::Storage(..) => w.buffer_info(&buffers[k..k + 1]),
                _ => w.image_info(&images[k..k + 1]),
            }
        })
        .collect();
    // SAFETY: every handle in `binds` is alive and belongs to this device.
    unsafe { device.update_descriptor_sets(&writes, &[]) };
}

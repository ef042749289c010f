//! Descriptor set layouts, a pool, and one way of writing sets: a list of `Bind`s.

use std::sync::{Arc, Mutex};

use ash::vk;

use super::acceleration_structure::AccelerationStructure;
use super::buffer::Buffer;
use super::context::Context;
use super::counters::Created;
use super::deferred::Doomed;
use super::error::{Named, VkError, VkResult};
use super::image::{ImageView, Sampler};

/// What a descriptor set holds so that nothing written into it is destroyed before it.
type KeepAlive = Arc<dyn Send + Sync>;

/// A descriptor set allocated and written by a [`DescriptorPool`]; only a pool makes one, so a
/// bound set is never null or foreign. Clones share the set. It keeps its pool, its layout and
/// every buffer, view and sampler written into it alive, so binding it never reaches a destroyed
/// object.
#[derive(Clone)]
pub struct DescriptorSet {
    inner: Arc<SetInner>,
}

struct SetInner {
    raw: vk::DescriptorSet,
    pool: Arc<PoolInner>,
    /// Kept because Vulkan forbids updating a set whose layout is destroyed; rewrites are checked
    /// against it.
    layout: Arc<LayoutInner>,
    held: Mutex<Vec<KeepAlive>>,
}

impl std::fmt::Debug for DescriptorSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("DescriptorSet")
            .field(&self.inner.raw)
            .finish()
    }
}

impl DescriptorSet {
    pub(crate) fn raw(&self) -> vk::DescriptorSet {
        self.inner.raw
    }

    /// Rewrites `binds` into the set, which then holds them (and lets go of what it held). A
    /// bind whose binding number or kind the set's layout lacks is an error, and nothing is
    /// written.
    ///
    /// # Safety
    /// No command buffer that binds the set may be pending or still recording: Vulkan forbids
    /// updating a set in use, and a recording that bound it would be invalidated. Waiting for the
    /// submissions that used it ([`CommandSlot::wait`](super::CommandSlot::wait), or a one-shot
    /// having returned) meets this. Safe code cannot call it:
    ///
    /// ```compile_fail,E0133
    /// fn rewrite(set: &relief::vk::DescriptorSet) {
    ///     set.rewrite(&[]);
    /// }
    /// ```
    pub unsafe fn rewrite(&self, binds: &[Bind]) -> VkResult<()> {
        self.inner.layout.check(binds)?;
        write_set(&self.inner.pool.ctx, self.inner.raw, binds);
        let mut held = self.inner.held.lock().unwrap_or_else(|p| p.into_inner());
        *held = binds.iter().map(Bind::keep_alive).collect();
        Ok(())
    }
}

/// One resource bound at a binding number. It borrows typed objects, so only live objects of
/// this layer can be written into a set; raw handles are refused:
///
/// ```compile_fail,E0308
/// use relief::vk::{raw, Bind};
/// let forged = Bind::Storage(0, raw::Buffer::null());
/// ```
///
/// ```compile_fail,E0308
/// use relief::vk::{raw, Bind, Sampler};
/// fn forge(sampler: &Sampler) -> Bind<'_> {
///     Bind::Texture(1, raw::ImageView::null(), sampler)
/// }
/// ```
///
/// while the typed objects themselves are accepted:
///
/// ```no_run
/// use relief::vk::{Bind, Buffer, Image, Sampler};
/// fn binds<'a>(buffer: &'a Buffer, image: &'a Image, sampler: &'a Sampler) -> [Bind<'a>; 2] {
///     [Bind::Uniform(0, buffer), Bind::Texture(1, image.view(), sampler)]
/// }
/// ```
#[derive(Clone, Copy)]
pub enum Bind<'a> {
    /// A uniform buffer, whole.
    Uniform(u32, &'a Buffer),
    /// A storage buffer, whole.
    Storage(u32, &'a Buffer),
    /// An image view with its sampler, in `SHADER_READ_ONLY_OPTIMAL`.
    Texture(u32, &'a ImageView, &'a Sampler),
    /// A storage image view in `GENERAL` layout.
    StorageImage(u32, &'a ImageView),
    /// A top-level acceleration structure, for ray queries.
    Structure(u32, &'a AccelerationStructure),
}

impl Bind<'_> {
    fn keep_alive(&self) -> KeepAlive {
        match *self {
            Bind::Uniform(_, b) | Bind::Storage(_, b) => b.keep_alive(),
            Bind::Texture(_, view, sampler) => Arc::new((view.keep_alive(), sampler.keep_alive())),
            Bind::StorageImage(_, view) => view.keep_alive(),
            Bind::Structure(_, s) => s.keep_alive(),
        }
    }

    fn binding(&self) -> u32 {
        match *self {
            Bind::Uniform(b, _)
            | Bind::Storage(b, _)
            | Bind::Texture(b, ..)
            | Bind::StorageImage(b, _)
            | Bind::Structure(b, _) => b,
        }
    }

    fn kind(&self) -> vk::DescriptorType {
        match self {
            Bind::Uniform(..) => vk::DescriptorType::UNIFORM_BUFFER,
            Bind::Storage(..) => vk::DescriptorType::STORAGE_BUFFER,
            Bind::Texture(..) => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            Bind::StorageImage(..) => vk::DescriptorType::STORAGE_IMAGE,
            Bind::Structure(..) => vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
        }
    }
}

/// A descriptor set layout; the sets allocated with it keep it alive, and it goes when the last
/// of them and this value are gone (after the GPU is done with them).
pub struct DescriptorLayout {
    inner: Arc<LayoutInner>,
}

struct LayoutInner {
    ctx: Arc<Context>,
    raw: vk::DescriptorSetLayout,
    bindings: Vec<(u32, vk::DescriptorType)>,
    name: String,
}

impl LayoutInner {
    /// Refuses binds the layout has no binding of that number and kind for: Vulkan leaves such
    /// writes undefined.
    fn check(&self, binds: &[Bind]) -> VkResult<()> {
        for b in binds {
            let wanted = (b.binding(), b.kind());
            if !self.bindings.contains(&wanted) {
                return Err(VkError::Invalid(format!(
                    "{:?} at binding {} of layout {:?}, which has {:?}",
                    wanted.1, wanted.0, self.name, self.bindings
                )));
            }
        }
        Ok(())
    }
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
            inner: Arc::new(LayoutInner {
                ctx: ctx.clone(),
                raw,
                bindings: bindings.to_vec(),
                name: name.to_owned(),
            }),
        })
    }

    /// The raw handle, for pipeline layouts.
    pub(crate) fn raw(&self) -> vk::DescriptorSetLayout {
        self.inner.raw
    }
}

impl Drop for LayoutInner {
    fn drop(&mut self) {
        self.ctx.defer(Doomed::DescriptorLayout(self.raw));
    }
}

/// A descriptor pool sized for a known number of sets. Its sets keep it alive; it goes when the
/// last of them and this value are gone (after the GPU is done with them).
pub struct DescriptorPool {
    inner: Arc<PoolInner>,
}

struct PoolInner {
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
        let mut types = vec![
            vk::DescriptorType::UNIFORM_BUFFER,
            vk::DescriptorType::STORAGE_BUFFER,
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            vk::DescriptorType::STORAGE_IMAGE,
        ];
        // A type of an extension the device has not enabled may not be named at all.
        if ctx.structures().is_some() {
            types.push(vk::DescriptorType::ACCELERATION_STRUCTURE_KHR);
        }
        let sizes: Vec<_> = types
            .into_iter()
            .map(|ty| vk::DescriptorPoolSize {
                ty,
                descriptor_count: per_type,
            })
            .collect();
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(max_sets)
            .pool_sizes(&sizes);
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device().create_descriptor_pool(&info, None) }
            .named("vkCreateDescriptorPool")?;
        ctx.set_name(raw, name);
        Ok(DescriptorPool {
            inner: Arc::new(PoolInner {
                ctx: ctx.clone(),
                raw,
            }),
        })
    }

    /// Allocates one set of `layout` and writes `binds` into it. A bind whose binding number or
    /// kind the layout lacks is an error.
    pub fn allocate(&self, layout: &DescriptorLayout, binds: &[Bind]) -> VkResult<DescriptorSet> {
        layout.inner.check(binds)?;
        let ctx = &self.inner.ctx;
        let layouts = [layout.raw()];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.inner.raw)
            .set_layouts(&layouts);
        // SAFETY: the pool and layout belong to this device; the pool is not used by another
        // thread (allocation takes `&self` of its one owner, and sets never free themselves).
        let set = unsafe { ctx.device().allocate_descriptor_sets(&info) }
            .named("vkAllocateDescriptorSets")?[0];
        write_set(ctx, set, binds);
        ctx.count(Created::DescriptorSet);
        Ok(DescriptorSet {
            inner: Arc::new(SetInner {
                raw: set,
                pool: self.inner.clone(),
                layout: layout.inner.clone(),
                held: Mutex::new(binds.iter().map(Bind::keep_alive).collect()),
            }),
        })
    }
}

impl Drop for SetInner {
    fn drop(&mut self) {
        // Sets are never freed one by one: the handle goes with its pool. It stops being alive
        // here, since nothing can use it any more.
        self.pool.ctx.count_destroyed(Created::DescriptorSet);
    }
}

impl Drop for PoolInner {
    fn drop(&mut self) {
        self.ctx.defer(Doomed::DescriptorPool(self.raw));
    }
}

/// Writes `binds` into `set`.
fn write_set(ctx: &Context, set: vk::DescriptorSet, binds: &[Bind]) {
    let buffers: Vec<_> = binds
        .iter()
        .map(|b| match *b {
            Bind::Uniform(_, buf) | Bind::Storage(_, buf) => vk::DescriptorBufferInfo {
                buffer: buf.raw(),
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
                sampler: sampler.raw(),
                image_view: view.raw(),
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            },
            Bind::StorageImage(_, view) => vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: view.raw(),
                image_layout: vk::ImageLayout::GENERAL,
            },
            _ => vk::DescriptorImageInfo::default(),
        })
        .collect();
    let structures: Vec<[vk::AccelerationStructureKHR; 1]> = binds
        .iter()
        .map(|b| match *b {
            Bind::Structure(_, s) => [s.raw()],
            _ => [vk::AccelerationStructureKHR::null()],
        })
        .collect();
    let mut structure_writes: Vec<_> = structures
        .iter()
        .map(|s| {
            vk::WriteDescriptorSetAccelerationStructureKHR::default().acceleration_structures(s)
        })
        .collect();
    let writes: Vec<_> = binds
        .iter()
        .zip(structure_writes.iter_mut())
        .enumerate()
        .map(|(k, (b, structure))| {
            let w = vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(b.binding())
                .descriptor_type(b.kind());
            match b {
                Bind::Uniform(..) | Bind::Storage(..) => w.buffer_info(&buffers[k..k + 1]),
                // The structure travels in the chained struct; the count is not implied.
                Bind::Structure(..) => w.descriptor_count(1).push_next(structure),
                _ => w.image_info(&images[k..k + 1]),
            }
        })
        .collect();
    // SAFETY: every object in `binds` is borrowed, so alive, and was made on this device.
    unsafe { ctx.device().update_descriptor_sets(&writes, &[]) };
}

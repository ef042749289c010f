//! Buffers with their memory: created, named, mapped for host access where asked, freed on drop.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::context::Context;
use super::counters::Created;
use super::deferred::Doomed;
use super::error::{Named, VkError, VkResult};

/// A buffer and its allocation, owned together. Dropping it hands both to the context, which
/// destroys them once the GPU has finished every submission that may read them; descriptor sets
/// written with it keep it alive as long as they live.
pub struct Buffer {
    inner: Arc<BufferInner>,
}

/// What a [`Buffer`] shares with the descriptor sets that reference it.
struct BufferInner {
    ctx: Arc<Context>,
    raw: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
    location: MemoryLocation,
    name: String,
}

impl Buffer {
    /// Creates a buffer of `size` bytes. `MemoryLocation::CpuToGpu`/`GpuToCpu` buffers are mapped.
    pub fn new(
        ctx: &Arc<Context>,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
        name: &str,
    ) -> VkResult<Buffer> {
        if size == 0 {
            return Err(VkError::Invalid(format!("buffer {name:?} of zero bytes")));
        }
        let device = ctx.device();
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info.
        let raw = unsafe { device.create_buffer(&info, None) }
            .named("vkCreateBuffer")
            .map_err(|e| e.for_object("buffer", name))?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        if let Err(e) = ctx.faults().allocation() {
            // SAFETY: the buffer has no memory bound and is unused.
            unsafe { device.destroy_buffer(raw, None) };
            return Err(e.for_object("buffer", name));
        }
        let allocation = ctx
            .allocator()
            .lock()
            .map_err(|_| VkError::Invalid("allocator lock poisoned".into()))?
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            });
        let allocation = match allocation {
            Ok(a) => {
                // The allocation's own size, which its destruction counts off again.
                ctx.count(Created::Buffer { bytes: a.size() });
                a
            }
            Err(source) => {
                // SAFETY: the buffer has no memory bound and is unused.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(VkError::Allocation {
                    name: name.to_owned(),
                    reason: source,
                });
            }
        };
        let buffer = Buffer {
            inner: Arc::new(BufferInner {
                ctx: ctx.clone(),
                raw,
                allocation: Some(allocation),
                size,
                location,
                name: name.to_owned(),
            }),
        };
        if let Some(a) = &buffer.inner.allocation {
            // SAFETY: memory and offset come from an allocation made for this buffer's
            // requirements, and stay allocated while the buffer lives.
            unsafe { device.bind_buffer_memory(raw, a.memory(), a.offset()) }
                .named("vkBindBufferMemory")?;
        }
        ctx.set_name(raw, name);
        Ok(buffer)
    }

    /// Creates a host-visible buffer filled with `bytes`.
    pub fn with_data(
        ctx: &Arc<Context>,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
        name: &str,
    ) -> VkResult<Buffer> {
        let mut buffer = Buffer::new(
            ctx,
            bytes.len() as u64,
            usage,
            MemoryLocation::CpuToGpu,
            name,
        )?;
        // SAFETY: the buffer was just made: no submission can read it yet.
        unsafe { buffer.write(0, bytes)? };
        Ok(buffer)
    }

    /// The context the buffer belongs to.
    pub(crate) fn context(&self) -> &Arc<Context> {
        &self.inner.ctx
    }

    /// The raw handle, for the vk layer's own commands.
    pub(crate) fn raw(&self) -> vk::Buffer {
        self.inner.raw
    }

    /// The buffer's device address; it must have been made with `SHADER_DEVICE_ADDRESS` usage
    /// on a device with buffer addresses (one with ray queries).
    pub(crate) fn device_address(&self) -> u64 {
        let info = vk::BufferDeviceAddressInfo::default().buffer(self.inner.raw);
        // SAFETY: valid buffer on this device, bound to memory since creation.
        unsafe { self.inner.ctx.device().get_buffer_device_address(&info) }
    }

    /// What a descriptor set holds to keep the buffer alive.
    pub(crate) fn keep_alive(&self) -> Arc<dyn Send + Sync> {
        self.inner.clone()
    }

    /// Size in bytes.
    pub fn size(&self) -> u64 {
        self.inner.size
    }

    /// Where the buffer's memory was asked to live (`GpuOnly`: device-local).
    pub fn location(&self) -> MemoryLocation {
        self.inner.location
    }

    /// The debug name.
    pub fn name(&self) -> &str {
        &self.inner.name
    }

    /// Checks that `size` bytes from `offset` lie inside the buffer; `what` names the use.
    pub(crate) fn check_range(&self, offset: u64, size: u64, what: &str) -> VkResult<()> {
        if offset
            .checked_add(size)
            .is_some_and(|end| end <= self.size())
        {
            return Ok(());
        }
        Err(VkError::Invalid(format!(
            "{what} of {size} bytes at {offset} in buffer {:?} of {} bytes",
            self.name(),
            self.size()
        )))
    }

    /// Copies `bytes` into a mapped buffer at `offset`.
    ///
    /// # Safety
    /// No submission that may read the buffer is pending or executing: the caller waited for
    /// every one that binds it (the fence of each frame slot whose descriptor sets point at
    /// it), or the buffer was never bound. Safe code cannot call it:
    ///
    /// ```compile_fail,E0133
    /// fn overwrite(buffer: &mut relief::vk::Buffer) {
    ///     buffer.write(0, &[0u8; 4]).unwrap();
    /// }
    /// ```
    pub unsafe fn write(&mut self, offset: usize, bytes: &[u8]) -> VkResult<()> {
        let name = self.name();
        let ptr = self
            .inner
            .allocation
            .as_ref()
            .and_then(|a| a.mapped_ptr())
            .ok_or_else(|| VkError::Invalid(format!("buffer {name:?} is not host-visible")))?;
        if offset
            .checked_add(bytes.len())
            .is_none_or(|end| end as u64 > self.size())
        {
            return Err(VkError::Invalid(format!(
                "write past the end of buffer {name:?}"
            )));
        }
        // SAFETY: the mapping covers the whole buffer and the range was checked above; `&mut
        // self` keeps `mapped`'s shared slices away, and the clones descriptor sets hold never
        // touch the mapping.
        unsafe {
            std::ptr::copy_nonoverlapping(
                bytes.as_ptr(),
                ptr.as_ptr().cast::<u8>().add(offset),
                bytes.len(),
            )
        };
        Ok(())
    }

    /// The mapped contents of a host-visible buffer, as the host last wrote them. Not public: what
    /// the GPU wrote is read through a [`Readback`](super::Readback), which records the host-read
    /// barrier and waits for nothing it cannot prove finished:
    ///
    /// ```compile_fail,E0624
    /// fn peek(buffer: &relief::vk::Buffer) -> usize {
    ///     buffer.mapped().map_or(0, |b| b.len())
    /// }
    /// ```
    pub(crate) fn mapped(&self) -> VkResult<&[u8]> {
        self.inner
            .allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .map(|s| &s[..self.size() as usize])
            .ok_or_else(|| {
                VkError::Invalid(format!("buffer {:?} is not host-visible", self.name()))
            })
    }
}

impl Drop for BufferInner {
    fn drop(&mut self) {
        self.ctx
            .defer(Doomed::Buffer(self.raw, self.allocation.take()));
    }
}

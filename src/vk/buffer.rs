//! Buffers with their memory: created, named, mapped for host access where asked, freed on drop.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::context::Context;
use super::counters::Created;
use super::error::{Named, VkError, VkResult};

/// A buffer and its allocation, owned together.
pub struct Buffer {
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
                ctx.count(Created::Buffer {
                    bytes: requirements.size,
                });
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
            ctx: ctx.clone(),
            raw,
            allocation: Some(allocation),
            size,
            location,
            name: name.to_owned(),
        };
        let a = buffer
            .allocation
            .as_ref()
            .ok_or(VkError::Invalid("no allocation".into()))?;
        // SAFETY: memory and offset come from an allocation made for this buffer's requirements.
        unsafe { device.bind_buffer_memory(raw, a.memory(), a.offset()) }
            .named("vkBindBufferMemory")?;
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
        buffer.write(0, bytes)?;
        Ok(buffer)
    }

    /// The raw handle.
    pub fn raw(&self) -> vk::Buffer {
        self.raw
    }

    /// Size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Where the buffer's memory was asked to live (`GpuOnly`: device-local).
    pub fn location(&self) -> MemoryLocation {
        self.location
    }

    /// The debug name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Copies `bytes` into a mapped buffer at `offset`.
    pub fn write(&mut self, offset: usize, bytes: &[u8]) -> VkResult<()> {
        let name = self.name.clone();
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| VkError::Invalid(format!("buffer {name:?} is not host-visible")))?;
        let end = offset + bytes.len();
        let dst = slice
            .get_mut(offset..end)
            .ok_or_else(|| VkError::Invalid(format!("write past the end of buffer {name:?}")))?;
        dst.copy_from_slice(bytes);
        Ok(())
    }

    /// The mapped contents of a host-visible buffer, as the host last wrote them. For what the GPU
    /// wrote, copy into a [`Readback`](super::Readback): it records the host-read barrier.
    pub fn mapped(&self) -> VkResult<&[u8]> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .map(|s| &s[..self.size as usize])
            .ok_or_else(|| VkError::Invalid(format!("buffer {:?} is not host-visible", self.name)))
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if self.ctx.is_hung() {
            // Hung work may still use the buffer: leave it (and its memory) to the process exit.
            return;
        }
        // SAFETY: users keep a Buffer alive until the GPU work that uses it has completed
        // (one-shot submissions wait on their fence).
        unsafe { self.ctx.device().destroy_buffer(self.raw, None) };
        if let (Some(a), Ok(mut alloc)) = (self.allocation.take(), self.ctx.allocator().lock()) {
            let _ = alloc.free(a);
        }
    }
}

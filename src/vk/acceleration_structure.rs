//! Acceleration structures for ray queries (`VK_KHR_acceleration_structure`): bottom levels over
//! opaque triangles or over boxes whose contents a shader decides, a top level over instances of
//! them. Each is built on the device in its own submission, timed with timestamps, and owned as
//! one value with its buffer; a top level keeps the bottom levels it instances alive.

use std::sync::{Arc, OnceLock};

use ash::vk;
use bytemuck::{Pod, Zeroable};
use gpu_allocator::MemoryLocation;

use super::buffer::Buffer;
use super::context::Context;
use super::deferred::Doomed;
use super::error::{Named, VkError, VkResult};
use super::query::TimestampPool;

/// What one bottom-level structure holds.
#[derive(Debug, Clone, Copy)]
pub enum Geometry<'a> {
    /// Opaque triangles: positions, and three indices into them per triangle. Rays commit the
    /// nearest without asking the shader.
    Triangles {
        /// Vertex positions.
        positions: &'a [[f32; 3]],
        /// Three per triangle.
        indices: &'a [u32],
    },
    /// Axis-aligned boxes, `[min x, min y, min z, max x, max y, max z]`: a ray query reports each
    /// box it enters as a candidate, and the shader decides whether and where it is hit.
    Boxes(&'a [[f32; 6]]),
}

impl Geometry<'_> {
    fn primitives(&self) -> usize {
        match self {
            Geometry::Triangles { indices, .. } => indices.len() / 3,
            Geometry::Boxes(boxes) => boxes.len(),
        }
    }
}

/// One placement of a bottom-level structure in a top level.
#[derive(Clone, Copy)]
pub struct Instance<'a> {
    /// What is placed.
    pub structure: &'a AccelerationStructure,
    /// Object to world, the upper three rows of the matrix, row by row.
    pub transform: [[f32; 4]; 3],
    /// What the shader reads as the instance's custom index (24 bits).
    pub custom_index: u32,
}

/// The identity placement.
pub const IDENTITY: [[f32; 4]; 3] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
];

/// `VkAccelerationStructureInstanceKHR` as bytes.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct InstanceRecord {
    transform: [[f32; 4]; 3],
    /// Custom index in the low 24 bits, visibility mask in the high 8.
    index_and_mask: u32,
    /// Shader binding table offset in the low 24 bits, instance flags in the high 8.
    offset_and_flags: u32,
    structure: u64,
}

/// A built acceleration structure. Dropping it hands it and its buffer to the context, which
/// destroys them once the GPU has finished every submission that may trace through them.
#[derive(Clone)]
pub struct AccelerationStructure {
    inner: Arc<StructureInner>,
}

struct StructureInner {
    ctx: Arc<Context>,
    raw: vk::AccelerationStructureKHR,
    /// The structure's storage: `Drop` queues the structure first, and the buffer follows as
    /// a field.
    buffer: Buffer,
    address: u64,
    primitives: usize,
    /// Set once, when the build's timestamps are read.
    build_ms: OnceLock<f64>,
    /// The bottom levels a top level instances, kept alive as long as it is.
    _instanced: Vec<AccelerationStructure>,
}

impl std::fmt::Debug for AccelerationStructure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AccelerationStructure")
            .field("name", &self.inner.buffer.name())
            .field("bytes", &self.bytes())
            .field("primitives", &self.inner.primitives)
            .finish()
    }
}

impl Drop for StructureInner {
    fn drop(&mut self) {
        if let Some(loader) = self.ctx.structures() {
            self.ctx
                .defer(Doomed::AccelerationStructure(loader.clone(), self.raw));
        }
    }
}

impl AccelerationStructure {
    /// Builds a bottom level over `geometry`. A device without ray queries, an empty geometry,
    /// or triangles whose indices are not whole triples or point past the positions are errors.
    pub fn bottom_level(
        ctx: &Arc<Context>,
        geometry: Geometry,
        name: &str,
    ) -> VkResult<AccelerationStructure> {
        let input_usage = vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
            | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        require_ray_queries(ctx, name)?;
        if let Geometry::Triangles { positions, indices } = geometry {
            if indices.len() % 3 != 0 || indices.iter().any(|&i| i as usize >= positions.len()) {
                return Err(VkError::Invalid(format!(
                    "acceleration structure {name:?}: {} indices over {} positions",
                    indices.len(),
                    positions.len()
                )));
            }
        }
        let count = geometry.primitives();
        if count == 0 {
            return Err(VkError::Invalid(format!(
                "acceleration structure {name:?} over nothing"
            )));
        }
        // The inputs live until the build below has completed.
        let (data, _inputs) = match geometry {
            Geometry::Triangles { positions, indices } => {
                let vertices = Buffer::with_data(
                    ctx,
                    bytemuck::cast_slice(positions),
                    input_usage,
                    &format!("{name} positions"),
                )?;
                let index_buffer = Buffer::with_data(
                    ctx,
                    bytemuck::cast_slice(indices),
                    input_usage,
                    &format!("{name} indices"),
                )?;
                let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
                    .vertex_format(vk::Format::R32G32B32_SFLOAT)
                    .vertex_data(vk::DeviceOrHostAddressConstKHR {
                        device_address: vertices.device_address(),
                    })
                    .vertex_stride(12)
                    .max_vertex(positions.len().saturating_sub(1) as u32)
                    .index_type(vk::IndexType::UINT32)
                    .index_data(vk::DeviceOrHostAddressConstKHR {
                        device_address: index_buffer.device_address(),
                    });
                let data = vk::AccelerationStructureGeometryKHR::default()
                    .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
                    .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
                    .flags(vk::GeometryFlagsKHR::OPAQUE);
                (data, vec![vertices, index_buffer])
            }
            Geometry::Boxes(boxes) => {
                let buffer = Buffer::with_data(
                    ctx,
                    bytemuck::cast_slice(boxes),
                    input_usage,
                    &format!("{name} boxes"),
                )?;
                let aabbs = vk::AccelerationStructureGeometryAabbsDataKHR::default()
                    .data(vk::DeviceOrHostAddressConstKHR {
                        device_address: buffer.device_address(),
                    })
                    .stride(24);
                let data = vk::AccelerationStructureGeometryKHR::default()
                    .geometry_type(vk::GeometryTypeKHR::AABBS)
                    .geometry(vk::AccelerationStructureGeometryDataKHR { aabbs });
                (data, vec![buffer])
            }
        };
        let kind = vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL;
        build(ctx, kind, data, count, Vec::new(), name)
    }

    /// Builds a top level over `instances` (none is allowed: nothing to hit). Every instance's
    /// ray sees triangles from both sides.
    pub fn top_level(
        ctx: &Arc<Context>,
        instances: &[Instance],
        name: &str,
    ) -> VkResult<AccelerationStructure> {
        require_ray_queries(ctx, name)?;
        let records: Vec<InstanceRecord> = instances
            .iter()
            .map(|i| InstanceRecord {
                transform: i.transform,
                index_and_mask: (i.custom_index & 0x00ff_ffff) | 0xff << 24,
                offset_and_flags: vk::GeometryInstanceFlagsKHR::TRIANGLE_FACING_CULL_DISABLE
                    .as_raw()
                    << 24,
                structure: i.structure.inner.address,
            })
            .collect();
        // One record even with no instances: a buffer has at least a byte, and the build reads
        // none of it.
        let bytes = if records.is_empty() {
            vec![0u8; std::mem::size_of::<InstanceRecord>()]
        } else {
            bytemuck::cast_slice(&records).to_vec()
        };
        let buffer = Buffer::with_data(
            ctx,
            &bytes,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR
                | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            &format!("{name} instances"),
        )?;
        let data = vk::AccelerationStructureGeometryKHR::default()
            .geometry_type(vk::GeometryTypeKHR::INSTANCES)
            .geometry(vk::AccelerationStructureGeometryDataKHR {
                instances: vk::AccelerationStructureGeometryInstancesDataKHR::default().data(
                    vk::DeviceOrHostAddressConstKHR {
                        device_address: buffer.device_address(),
                    },
                ),
            });
        let kept = instances.iter().map(|i| i.structure.clone()).collect();
        let built = build(
            ctx,
            vk::AccelerationStructureTypeKHR::TOP_LEVEL,
            data,
            instances.len(),
            kept,
            name,
        );
        drop(buffer);
        built
    }

    /// Bytes of device memory the structure occupies.
    pub fn bytes(&self) -> u64 {
        self.inner.buffer.size()
    }

    /// Triangles, boxes or instances it was built over.
    pub fn primitives(&self) -> usize {
        self.inner.primitives
    }

    /// GPU milliseconds its build took.
    pub fn build_ms(&self) -> f64 {
        self.inner.build_ms.get().copied().unwrap_or(0.0)
    }

    /// The raw handle, for descriptor writes.
    pub(crate) fn raw(&self) -> vk::AccelerationStructureKHR {
        self.inner.raw
    }

    /// What a descriptor set holds to keep the structure alive.
    pub(crate) fn keep_alive(&self) -> Arc<dyn Send + Sync> {
        self.inner.clone()
    }
}

/// Sizes, allocates and builds one structure of `kind` over `data` (`count` primitives), in a
/// submission of its own that is waited for, so its inputs may go when this returns.
fn build(
    ctx: &Arc<Context>,
    kind: vk::AccelerationStructureTypeKHR,
    data: vk::AccelerationStructureGeometryKHR,
    count: usize,
    instanced: Vec<AccelerationStructure>,
    name: &str,
) -> VkResult<AccelerationStructure> {
    let loader = require_ray_queries(ctx, name)?;
    let count = u32::try_from(count).map_err(|_| {
        VkError::Invalid(format!(
            "acceleration structure {name:?} over {count} primitives"
        ))
    })?;
    let geometries = [data];
    let mut info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
        .ty(kind)
        .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
        .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
        .geometries(&geometries);
    let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    // SAFETY: the device has the extension (the loader exists); `info` describes valid geometry.
    unsafe {
        loader.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            &info,
            &[count],
            &mut sizes,
        )
    };
    let buffer = Buffer::new(
        ctx,
        sizes.acceleration_structure_size.max(1),
        vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR
            | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        MemoryLocation::GpuOnly,
        name,
    )?;
    let align = scratch_alignment(ctx);
    let scratch = Buffer::new(
        ctx,
        sizes.build_scratch_size.max(1) + align,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        MemoryLocation::GpuOnly,
        &format!("{name} scratch"),
    )?;
    let create = vk::AccelerationStructureCreateInfoKHR::default()
        .buffer(buffer.raw())
        .size(sizes.acceleration_structure_size)
        .ty(kind);
    // SAFETY: the buffer is alive, made for acceleration-structure storage, and large enough.
    let raw = unsafe { loader.create_acceleration_structure(&create, None) }
        .named("vkCreateAccelerationStructureKHR")?;
    ctx.set_name(raw, name);
    // SAFETY: the structure was just created on this device.
    let address = unsafe {
        loader.get_acceleration_structure_device_address(
            &vk::AccelerationStructureDeviceAddressInfoKHR::default().acceleration_structure(raw),
        )
    };
    let structure = AccelerationStructure {
        inner: Arc::new(StructureInner {
            ctx: ctx.clone(),
            raw,
            buffer,
            address,
            primitives: count as usize,
            build_ms: OnceLock::new(),
            _instanced: instanced,
        }),
    };
    info = info
        .dst_acceleration_structure(raw)
        .scratch_data(vk::DeviceOrHostAddressKHR {
            device_address: scratch.device_address().next_multiple_of(align),
        });
    let range = vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(count);
    let timestamps = TimestampPool::new(ctx, 2, &format!("{name} build timestamps"))?;
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    ctx.one_shot(|rec| {
        timestamps.write(rec, all, 0)?;
        // SAFETY: `rec` is recording; the inputs, scratch and destination are alive until the
        // one-shot submission has completed (it is waited for).
        unsafe {
            loader.cmd_build_acceleration_structures(rec.raw(), &[info], &[&[range]]);
        }
        timestamps.write(rec, all, 1)
    })?;
    let ticks = timestamps.read_ticks(2)?;
    let _ = structure
        .inner
        .build_ms
        .set(timestamps.ticks_to_ms(ticks[0], ticks[1]));
    Ok(structure)
}

/// The extension's functions, or why there are none.
fn require_ray_queries<'c>(
    ctx: &'c Context,
    name: &str,
) -> VkResult<&'c ash::khr::acceleration_structure::Device> {
    ctx.structures().ok_or_else(|| {
        VkError::Invalid(format!(
            "acceleration structure {name:?}: {} has no ray queries",
            ctx.info().name
        ))
    })
}

/// The alignment the scratch address of a build must have.
fn scratch_alignment(ctx: &Context) -> u64 {
    let mut props = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut all = vk::PhysicalDeviceProperties2::default().push_next(&mut props);
    // SAFETY: valid physical device; the chained struct belongs to an extension it offers.
    unsafe {
        ctx.instance()
            .get_physical_device_properties2(ctx.physical(), &mut all)
    };
    u64::from(
        props
            .min_acceleration_structure_scratch_offset_alignment
            .max(1),
    )
}

//! Vulkan only: instance and validation, device choice, memory, buffers, images, samplers,
//! pipelines, descriptors, timestamps, transfers, and presentation to a window. Knows nothing of height fields or scenes.
//!
//! Ownership: every object holds an `Arc<Context>`; the context is destroyed last, in the one
//! order written out in its `Drop`. An engine's instance and device, wrapped by
//! [`Context::from_external`], outlive it: relief destroys only what it created on them.
//!
//! Lifetimes on the GPU (the model: deferred destruction retired by a timeline semaphore). Safe
//! code may drop a [`Buffer`], [`Image`], [`ImageView`], [`Sampler`], [`Pipeline`],
//! [`DescriptorPool`], [`DescriptorLayout`], [`TimestampPool`], [`Semaphore`] or [`Swapchain`]
//! while a submitted frame still uses it. Dropping hands the handles (and the memory) to the context, tagged with the last
//! submission; every submission signals the next value of the context's timeline semaphore, and
//! objects whose tag the semaphore has passed are destroyed at the next submit, wait or drop (all
//! that remain when the context drops, after a device wait). Objects dropped while a recording is
//! open wait until no recording is open, since that recording may use them. A
//! [`DescriptorSet`] keeps its pool, its layout and everything written into it alive, so a bound
//! set never names a destroyed object.
//!
//! No safe function takes a raw Vulkan handle: commands and descriptor writes borrow this
//! layer's objects ([`Bind`], [`ImageTransition`], [`Recording::blit_whole`]), so the [`raw`]
//! re-export is for flags, formats and enums only. Ranges that safe code can get wrong (fills,
//! copies, timestamps, push constants) are checked at runtime and refused with a [`VkError`].
//! What cannot be checked cheaply is an `unsafe fn` with its contract written out
//! ([`DescriptorSet::rewrite`], [`TimestampPool::reset`], [`Context::wait_fence`]).
//!
//! Left to the validation layer (it reports them, and the tests fail on any report): whether
//! the state a dispatch or draw needs is complete and compatible (pipeline, sets, push constants,
//! index range), image layouts, and reading a [`Readback`] or a mapped [`Buffer`] before the
//! submission writing it has finished (the values are then undefined).

mod acceleration_structure;
mod buffer;
mod command_slot;
mod commands;
mod context;
mod context_setup;
mod counters;
mod deferred;
mod descriptors;
mod error;
mod external_device;
mod faults;
mod fence;
mod image;
mod instance;
mod physical;
mod pipeline;
mod pipeline_cache;
mod query;
mod query_core;
mod readback;
mod recording;
mod semaphore;
mod statistics_query;
mod surface;
mod swapchain;
mod transfer;

pub use acceleration_structure::{AccelerationStructure, Geometry, Instance, IDENTITY};
pub use buffer::Buffer;
pub use command_slot::{CommandSlot, SubmitSync};
pub use commands::{memory_barrier, transition_images, whole_color_region, ImageTransition};
pub use context::{Context, ContextOptions, RAY_QUERIES_ENV};
pub use counters::{LiveObjects, ObjectCounts};
pub use descriptors::{Bind, DescriptorLayout, DescriptorPool, DescriptorSet};
pub use error::{VkError, VkResult};
pub use external_device::ExternalDevice;
pub use faults::{Faults, FAULTS_ENV};
pub use fence::{gpu_timeout_from, DEFAULT_GPU_TIMEOUT, GPU_TIMEOUT_ENV};
pub use image::{Image, ImageDesc, ImageView, Sampler, WholeImage};
pub use instance::{MessageCounts, Validation};
pub use physical::{list_devices, DeviceInfo};
pub use pipeline::{compute_pipeline, graphics_pipeline, GraphicsDesc, Pipeline, SpecConstants};
pub use pipeline_cache::{
    check_header as check_pipeline_cache_header, CacheIdentity, PipelineCache,
};
pub use query::{ClockPair, TimestampPool};
pub use readback::{host_read_barrier, Readback};
pub use recording::{ColorTarget, Recording};
pub use semaphore::Semaphore;
pub use statistics_query::{PipelineCounts, StatisticsPool};
#[cfg(feature = "window")]
pub use surface::WindowHandles;
pub use swapchain::{Acquired, PresentMode, Swapchain, SwapchainImage, SwapchainLost};
pub use transfer::{
    half_floats_to_rgba, read_mip, record_copy_regions, texel_size, upload_layers, upload_mips,
    RegionTexels, StagedRegions,
};

pub use ash::vk as raw;
pub use gpu_allocator::MemoryLocation;

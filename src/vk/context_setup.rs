//! How a [`Context`] comes to be: relief's own instance and device made, or an engine's taken
//! over (the foundation either way), the objects relief creates on the device, the settings read
//! from the options and the environment, and the instance's teardown when a constructor fails.

use std::sync::Mutex;
use std::time::Duration;

use ash::{ext, khr, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::{AllocationSizes, AllocatorDebugSettings};

use super::context::{ContextOptions, Ownership, RAY_QUERIES_ENV};
use super::deferred::Retirement;
use super::error::{Named, VkError, VkResult};
use super::faults::{FaultPlan, Faults};
use super::fence::gpu_timeout_from_env;
use super::instance::{create_instance, InstanceParts, MessageCounts, Validation};
use super::physical::{choose_physical_device, DeviceInfo};
use super::pipeline_cache::{CacheIdentity, PipelineCache};
use super::surface::{surface_extensions, WindowHandles, WindowSurface};

/// What the context creates on the device and owns until its `Drop`.
pub(super) struct DeviceOwned {
    pub(super) pool: vk::CommandPool,
    pub(super) allocator: Allocator,
    pub(super) cache: PipelineCache,
    pub(super) retirement: Retirement,
}

impl DeviceOwned {
    /// Creates the pool, the allocator and the pipeline cache, or destroys what it made and says
    /// why (the allocator's own reason is kept).
    pub(super) fn new(
        parts: &InstanceParts,
        (physical, info): (vk::PhysicalDevice, &DeviceInfo),
        device: &ash::Device,
        cache_data: Option<&[u8]>,
    ) -> VkResult<DeviceOwned> {
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(info.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info.
        let pool =
            unsafe { device.create_command_pool(&pool_info, None) }.named("vkCreateCommandPool")?;
        // SAFETY: (for the error paths) the pool is unused.
        let drop_pool = || unsafe { device.destroy_command_pool(pool, None) };
        let allocator = match Allocator::new(&AllocatorCreateDesc {
            instance: parts.instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: AllocatorDebugSettings::default(),
            // Acceleration structures are built from and into buffers named by address.
            buffer_device_address: info.ray_query,
            allocation_sizes: AllocationSizes::default(),
        }) {
            Ok(a) => a,
            Err(source) => {
                drop_pool();
                return Err(VkError::AllocatorSetup { reason: source });
            }
        };
        let cache = match PipelineCache::new(device, &CacheIdentity::of(info), cache_data) {
            Ok(cache) => cache,
            Err(e) => {
                drop(allocator);
                drop_pool();
                return Err(e);
            }
        };
        match Retirement::new(device) {
            Ok(retirement) => Ok(DeviceOwned {
                pool,
                allocator,
                cache,
                retirement,
            }),
            Err(e) => {
                drop(cache);
                drop(allocator);
                drop_pool();
                Err(e)
            }
        }
    }
}

/// Held while an instance and its device are created or destroyed. The loader, layers and
/// drivers keep process-wide state there, and not all of them guard it: the Khronos validation
/// layer of Debian 12 (1.3.239) was seen to crash in two threads that made and dropped contexts
/// at once (relief's tests do, one context per test). Relief serialises those calls; everything
/// else runs concurrently.
static LIFECYCLE: Mutex<()> = Mutex::new(());

pub(super) fn lifecycle() -> std::sync::MutexGuard<'static, ()> {
    LIFECYCLE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// What a context takes from its options besides the device, read before anything is created so
/// a malformed environment variable fails first.
pub(super) struct Settings {
    pub(super) gpu_timeout: Duration,
    pub(super) faults: FaultPlan,
}

impl Settings {
    pub(super) fn read(options: &ContextOptions) -> VkResult<Settings> {
        let gpu_timeout = match options.gpu_timeout {
            Some(t) => t,
            None => gpu_timeout_from_env()?,
        };
        let faults = match options.faults {
            Some(f) => f,
            None => Faults::from_env()?,
        };
        Ok(Settings {
            gpu_timeout,
            faults: FaultPlan::new(faults),
        })
    }
}

/// Whether the options or `RELIEF_RAY_QUERIES=0` leave ray queries off.
pub(super) fn ray_queries_off(options: &ContextOptions) -> bool {
    options.without_ray_queries || std::env::var(RAY_QUERIES_ENV).is_ok_and(|v| v == "0")
}

/// The instance and device a context is assembled on, and who owns them.
pub(super) struct Foundation {
    pub(super) parts: InstanceParts,
    pub(super) physical: vk::PhysicalDevice,
    pub(super) info: DeviceInfo,
    pub(super) device: ash::Device,
    pub(super) queue_index: u32,
    /// `VK_EXT_debug_utils` is enabled on the instance: objects get debug names.
    pub(super) names_objects: bool,
    pub(super) ownership: Ownership,
}

impl Foundation {
    /// Destroys the device and the instance's parts if relief owns them; an engine's are left
    /// to the engine.
    ///
    /// # Safety
    /// Nothing made from the device is alive, and the foundation is not used afterwards. For
    /// relief's own, the caller holds [`lifecycle`].
    pub(super) unsafe fn release(&self) {
        if self.ownership == Ownership::Relief {
            // SAFETY: the caller's contract: nothing made from the device is left.
            unsafe { self.device.destroy_device(None) };
            destroy_instance_parts(&self.parts);
        }
    }
}

/// Relief's own instance (with `window`'s surface) and device, on the best device the options
/// accept. The caller holds [`lifecycle`].
///
/// # Safety
/// As [`Context::new_presenting`] when `window` is given.
pub(super) unsafe fn create_foundation(
    options: &ContextOptions,
    window: Option<&WindowHandles>,
    counts: &MessageCounts,
) -> VkResult<Foundation> {
    let validation = options.validation.unwrap_or_else(Validation::from_env);
    let extensions = match window {
        Some(w) => surface_extensions(w)?,
        None => &[],
    };
    let mut parts = create_instance(validation, counts, extensions)?;
    if let Some(handles) = window {
        // SAFETY: the caller keeps the window alive; the instance has its extensions.
        match unsafe { WindowSurface::new(&parts.entry, &parts.instance, handles) } {
            Ok(surface) => parts.surface = Some(surface),
            Err(e) => {
                destroy_instance_parts(&parts);
                return Err(e);
            }
        }
    }
    let presents = |pd: vk::PhysicalDevice, info: &DeviceInfo| {
        parts
            .surface
            .as_ref()
            .is_none_or(|s| s.supports(pd, info.queue_family))
    };
    let chosen =
        choose_physical_device(&parts.instance, options.device_filter.as_deref(), &presents);
    let (physical, mut info) = match chosen {
        Ok(pair) => pair,
        Err(e) => {
            destroy_instance_parts(&parts);
            return Err(e);
        }
    };
    // Asked only where the extension is offered: its query is the extension's.
    info.calibrated_timestamps =
        info.calibrated_timestamps && device_time_domain(&parts.entry, &parts.instance, physical);
    info.ray_query &= !ray_queries_off(options);
    match create_device(&parts, physical, &info) {
        Ok(device) => Ok(Foundation {
            names_objects: parts.debug_utils.is_some(),
            parts,
            physical,
            info,
            device,
            queue_index: 0,
            ownership: Ownership::Relief,
        }),
        Err(e) => {
            destroy_instance_parts(&parts);
            Err(e)
        }
    }
}

pub(super) fn destroy_instance_parts(parts: &InstanceParts) {
    // SAFETY: called once, after every child object of the instance is destroyed.
    unsafe {
        if let Some(surface) = &parts.surface {
            surface.destroy();
        }
        if let Some((loader, messenger)) = &parts.debug_utils {
            loader.destroy_debug_utils_messenger(*messenger, None);
        }
        parts.instance.destroy_instance(None);
    }
}

/// Whether `physical`, which offers `VK_EXT_calibrated_timestamps`, calibrates its own time
/// domain (the one its timestamp queries count in).
pub(super) fn device_time_domain(
    entry: &ash::Entry,
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
) -> bool {
    let calibrated = ext::calibrated_timestamps::Instance::new(entry, instance);
    // SAFETY: valid physical device; the caller has seen it offer the extension.
    let domains = unsafe { calibrated.get_physical_device_calibrateable_time_domains(physical) };
    domains.is_ok_and(|d| d.contains(&vk::TimeDomainKHR::DEVICE))
}

fn create_device(
    parts: &InstanceParts,
    physical: vk::PhysicalDevice,
    info: &DeviceInfo,
) -> VkResult<ash::Device> {
    let queue_family = info.queue_family;
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(queue_family)
        .queue_priorities(&priorities)];
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default()
        .host_query_reset(true)
        // Retires dropped objects after the submissions that use them (see `deferred`).
        .timeline_semaphore(true)
        // Acceleration structures take their inputs by buffer address.
        .buffer_device_address(info.ray_query);
    let mut structures =
        vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default().acceleration_structure(true);
    let mut ray_query = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true)
        // glslang lowers `discard` (alpha masks) to demote-to-helper under SPIR-V 1.6.
        .shader_demote_to_helper_invocation(true);
    let features = vk::PhysicalDeviceFeatures::default()
        .shader_storage_image_extended_formats(info.storage_r16)
        // Passes count their invocations where the device can (PassTimer).
        .pipeline_statistics_query(info.pipeline_statistics)
        // Relief fragments count their work per pixel where asked (work counters).
        .fragment_stores_and_atomics(info.fragment_stores)
        // The G-buffer's attachments keep their own write masks beside the radiance's blend.
        .independent_blend(true);
    let mut extensions = Vec::new();
    if parts.surface.is_some() {
        extensions.push(khr::swapchain::NAME.as_ptr());
    }
    if info.calibrated_timestamps {
        extensions.push(ext::calibrated_timestamps::NAME.as_ptr());
    }
    if info.ray_query {
        extensions.extend([
            khr::acceleration_structure::NAME.as_ptr(),
            khr::deferred_host_operations::NAME.as_ptr(),
            khr::ray_query::NAME.as_ptr(),
        ]);
    }
    let mut create = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extensions)
        .enabled_features(&features)
        .push_next(&mut v12)
        .push_next(&mut v13);
    if info.ray_query {
        create = create.push_next(&mut structures).push_next(&mut ray_query);
    }
    let info = create;
    // SAFETY: the create info and everything it points to live until the call returns.
    let device =
        unsafe { parts.instance.create_device(physical, &info, None) }.named("vkCreateDevice")?;
    Ok(device)
}

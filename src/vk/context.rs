//! The device context: instance, chosen physical device, logical device, its one queue, the memory
//! allocator and a command pool. Every other Vulkan object holds an `Arc<Context>`, so the context
//! is dropped last, and its `Drop` is the one place where teardown order is written out.

use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

use ash::{ext, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::{AllocationSizes, AllocatorDebugSettings};

use super::counters::{Created, ObjectCounters, ObjectCounts};
use super::error::{Named, VkError, VkResult};
use super::instance::{create_instance, InstanceParts, MessageCounts, Validation};
use super::physical::{choose_physical_device, DeviceInfo};

/// What the caller wants from [`Context::new`].
#[derive(Debug, Clone, Default)]
pub struct ContextOptions {
    /// Case-insensitive substring of the device name to pick (`--device`).
    pub device_filter: Option<String>,
    /// Validation choice; `None` reads `RELIEF_VALIDATION` and the build profile.
    pub validation: Option<Validation>,
}

/// One Vulkan device, ready to record and submit work.
pub struct Context {
    parts: ManuallyDrop<InstanceParts>,
    counts: Box<MessageCounts>,
    physical: vk::PhysicalDevice,
    info: DeviceInfo,
    device: ash::Device,
    debug_device: Option<ext::debug_utils::Device>,
    queue: Mutex<vk::Queue>,
    queue_family: u32,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    command_pool: Mutex<vk::CommandPool>,
    created: ObjectCounters,
}

impl Context {
    /// Creates the instance, picks a device (discrete > integrated > virtual > CPU, or by name) and
    /// creates the logical device with the features relief uses.
    pub fn new(options: &ContextOptions) -> VkResult<Arc<Context>> {
        let counts = Box::<MessageCounts>::default();
        let validation = options.validation.unwrap_or_else(Validation::from_env);
        let parts = create_instance(validation, &counts)?;
        let chosen = choose_physical_device(&parts.instance, options.device_filter.as_deref());
        let (physical, info) = match chosen {
            Ok(pair) => pair,
            Err(e) => {
                destroy_instance_parts(&parts);
                return Err(e);
            }
        };
        match create_device(&parts, physical, &info) {
            Ok((device, queue_family)) => {
                Self::finish(parts, counts, physical, info, device, queue_family)
            }
            Err(e) => {
                destroy_instance_parts(&parts);
                Err(e)
            }
        }
    }

    fn finish(
        parts: InstanceParts,
        counts: Box<MessageCounts>,
        physical: vk::PhysicalDevice,
        info: DeviceInfo,
        device: ash::Device,
        queue_family: u32,
    ) -> VkResult<Arc<Context>> {
        // SAFETY: queue family index and queue 0 were requested at device creation.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: parts.instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: AllocatorDebugSettings::default(),
            buffer_device_address: false,
            allocation_sizes: AllocationSizes::default(),
        });
        // SAFETY: valid device and create info.
        let pool =
            unsafe { device.create_command_pool(&pool_info, None) }.named("vkCreateCommandPool");
        let (allocator, pool) = match (allocator, pool) {
            (Ok(a), Ok(p)) => (a, p),
            (a, p) => {
                // SAFETY: the device is idle and owns at most this pool.
                unsafe {
                    if let Ok(p) = p {
                        device.destroy_command_pool(p, None);
                    }
                    drop(a);
                    device.destroy_device(None);
                }
                destroy_instance_parts(&parts);
                return Err(VkError::Unsupported(
                    "a memory allocator or command pool".into(),
                ));
            }
        };
        let debug_device = parts
            .debug_utils
            .as_ref()
            .map(|_| ext::debug_utils::Device::new(&parts.instance, &device));
        Ok(Arc::new(Context {
            parts: ManuallyDrop::new(parts),
            counts,
            physical,
            info,
            device,
            debug_device,
            queue: Mutex::new(queue),
            queue_family,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            command_pool: Mutex::new(pool),
            created: ObjectCounters::default(),
        }))
    }

    /// The logical device.
    pub fn device(&self) -> &ash::Device {
        &self.device
    }

    /// The instance.
    pub fn instance(&self) -> &ash::Instance {
        &self.parts.instance
    }

    /// The chosen physical device.
    pub fn physical(&self) -> vk::PhysicalDevice {
        self.physical
    }

    /// Name, driver, API version, limits of the chosen device.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// Whether the Khronos validation layer is active.
    pub fn validation_enabled(&self) -> bool {
        self.parts.validation_enabled
    }

    /// What the validation layer has reported so far.
    pub fn messages(&self) -> &MessageCounts {
        &self.counts
    }

    /// How many objects and allocations this context has created so far.
    pub fn created(&self) -> ObjectCounts {
        self.created.snapshot()
    }

    pub(crate) fn count(&self, what: Created) {
        self.created.record(what);
    }

    /// The queue family of the single graphics + compute queue relief uses.
    pub fn queue_family(&self) -> u32 {
        self.queue_family
    }

    pub(crate) fn queue(&self) -> &Mutex<vk::Queue> {
        &self.queue
    }

    pub(crate) fn allocator(&self) -> &Mutex<Allocator> {
        &self.allocator
    }

    pub(crate) fn command_pool(&self) -> &Mutex<vk::CommandPool> {
        &self.command_pool
    }

    /// Format features of `format` with optimal tiling.
    pub fn format_features(&self, format: vk::Format) -> vk::FormatFeatureFlags {
        // SAFETY: plain query on a valid physical device.
        unsafe {
            self.parts
                .instance
                .get_physical_device_format_properties(self.physical, format)
        }
        .optimal_tiling_features
    }

    /// Gives a Vulkan object a debug name, so validation messages say what they are about.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(debug) = &self.debug_device else {
            return;
        };
        let Ok(cname) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&cname);
        // SAFETY: the handle belongs to this device; naming failures are harmless and ignored.
        let _ = unsafe { debug.set_debug_utils_object_name(&info) };
    }

    /// Waits for the device to finish all submitted work.
    pub fn wait_idle(&self) -> VkResult<()> {
        // SAFETY: valid device; the queue lock keeps submissions out while we wait.
        let _queue = self.queue.lock();
        unsafe { self.device.device_wait_idle() }.named("vkDeviceWaitIdle")
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: every object made from this device holds an Arc of this context, so all of them
        // are gone. Order: wait idle, allocator (frees its memory blocks), pools, device,
        // messenger, instance.
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            if let Ok(pool) = self.command_pool.lock() {
                self.device.destroy_command_pool(*pool, None);
            }
            self.device.destroy_device(None);
            destroy_instance_parts(&self.parts);
            ManuallyDrop::drop(&mut self.parts);
        }
    }
}

fn destroy_instance_parts(parts: &InstanceParts) {
    // SAFETY: called once, after every child object of the instance is destroyed.
    unsafe {
        if let Some((loader, messenger)) = &parts.debug_utils {
            loader.destroy_debug_utils_messenger(*messenger, None);
        }
        parts.instance.destroy_instance(None);
    }
}

fn create_device(
    parts: &InstanceParts,
    physical: vk::PhysicalDevice,
    info: &DeviceInfo,
) -> VkResult<(ash::Device, u32)> {
    let queue_family = info.queue_family;
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(queue_family)
        .queue_priorities(&priorities)];
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default().host_query_reset(true);
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true)
        // glslang lowers `discard` (alpha masks) to demote-to-helper under SPIR-V 1.6.
        .shader_demote_to_helper_invocation(true);
    let features = vk::PhysicalDeviceFeatures::default()
        .shader_storage_image_extended_formats(info.storage_r16);
    let info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_features(&features)
        .push_next(&mut v12)
        .push_next(&mut v13);
    // SAFETY: the create info and everything it points to live until the call returns.
    let device =
        unsafe { parts.instance.create_device(physical, &info, None) }.named("vkCreateDevice")?;
    Ok((device, queue_family))
}

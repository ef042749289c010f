//! An engine's own Vulkan instance and device, which a context can be built on instead of
//! creating its own ([`super::Context::from_external`]). The contract is written out there and
//! in `docs/engine-device.md`.

use std::fmt;

use ash::vk;

use super::error::{VkError, VkResult};
use super::physical::{describe_family, missing_requirements, DeviceInfo, QUEUE_FLAGS};

/// An engine's Vulkan instance, physical device, logical device and the queue relief is to
/// submit to, with what the engine enabled of what relief uses when present. Built by
/// [`ExternalDevice::new`] (every optional part off) and the `with_*` setters; see
/// [`super::Context::from_external`] for what the engine promises.
#[derive(Clone)]
#[non_exhaustive]
pub struct ExternalDevice {
    /// The loader the instance was created with; relief keeps a clone loaded while it lives.
    pub entry: ash::Entry,
    /// The engine's instance (Vulkan 1.3 or later requested at creation).
    pub instance: ash::Instance,
    /// The physical device the logical device was created on.
    pub physical: vk::PhysicalDevice,
    /// The engine's logical device.
    pub device: ash::Device,
    /// The queue family of the queue relief submits to: it must do graphics and compute.
    pub queue_family: u32,
    /// Which queue of that family relief submits to (created with the device, without flags).
    pub queue_index: u32,
    /// `VK_EXT_debug_utils` is enabled on the instance: relief names its objects, so the
    /// engine's validation messages say which of relief's objects they are about.
    pub debug_utils: bool,
    /// `VK_KHR_ray_query`, `VK_KHR_acceleration_structure` and
    /// `VK_KHR_deferred_host_operations` are enabled with the `rayQuery`,
    /// `accelerationStructure` and `bufferDeviceAddress` features: relief traces ray queries.
    pub ray_query: bool,
    /// `VK_EXT_calibrated_timestamps` is enabled: relief places GPU timestamps on the host's
    /// clock (where the device calibrates its own time domain).
    pub calibrated_timestamps: bool,
    /// The `pipelineStatisticsQuery` feature is enabled: passes count their invocations.
    pub pipeline_statistics: bool,
    /// The `fragmentStoresAndAtomics` feature is enabled: fragment shaders count their work.
    pub fragment_stores: bool,
    /// The `shaderStorageImageExtendedFormats` feature is enabled: storage images may be R16.
    pub storage_r16: bool,
}

with_setters!(ExternalDevice {
    with_debug_utils => debug_utils: bool,
    with_ray_query => ray_query: bool,
    with_calibrated_timestamps => calibrated_timestamps: bool,
    with_pipeline_statistics => pipeline_statistics: bool,
    with_fragment_stores => fragment_stores: bool,
    with_storage_r16 => storage_r16: bool,
});

impl ExternalDevice {
    /// The engine's objects and relief's queue (family and index), with every optional part
    /// off; the `with_*` setters say which the engine enabled.
    pub fn new(
        entry: ash::Entry,
        instance: ash::Instance,
        physical: vk::PhysicalDevice,
        device: ash::Device,
        queue_family: u32,
        queue_index: u32,
    ) -> ExternalDevice {
        ExternalDevice {
            entry,
            instance,
            physical,
            device,
            queue_family,
            queue_index,
            debug_utils: false,
            ray_query: false,
            calibrated_timestamps: false,
            pipeline_statistics: false,
            fragment_stores: false,
            storage_r16: false,
        }
    }

    /// What relief may use of this device: checks what Vulkan lets relief check (the physical
    /// device is the instance's, supports what relief requires, has the queue, offers what the
    /// optional flags claim) and describes the device with only the claimed optional parts on.
    /// The calibrated time domain is left to the caller, which needs the entry for it.
    pub(crate) fn device_info(&self) -> VkResult<DeviceInfo> {
        // SAFETY: the caller's contract: the instance is valid.
        let physicals = unsafe { self.instance.enumerate_physical_devices() }
            .map_err(|e| VkError::from_call("vkEnumeratePhysicalDevices", e))?;
        if !physicals.contains(&self.physical) {
            return Err(VkError::Invalid(
                "ExternalDevice::physical is not one of the instance's physical devices".into(),
            ));
        }
        let name = device_name(&self.instance, self.physical);
        let missing = missing_requirements(&self.instance, self.physical);
        if !missing.is_empty() {
            return Err(VkError::Unsupported(format!(
                "what relief requires of an engine's device ({name} lacks {}; see \
                 docs/engine-device.md)",
                missing.join(", ")
            )));
        }
        self.check_queue(&name)?;
        let (_, mut info) = describe_family(&self.instance, self.physical, self.queue_family);
        let claims = [
            ("ray_query", self.ray_query, info.ray_query),
            (
                "calibrated_timestamps",
                self.calibrated_timestamps,
                info.calibrated_timestamps,
            ),
            (
                "pipeline_statistics",
                self.pipeline_statistics,
                info.pipeline_statistics,
            ),
            (
                "fragment_stores",
                self.fragment_stores,
                info.fragment_stores,
            ),
            ("storage_r16", self.storage_r16, info.storage_r16),
        ];
        if let Some((field, ..)) = claims.iter().find(|(_, claimed, has)| *claimed && !has) {
            return Err(VkError::Invalid(format!(
                "ExternalDevice::{field} says it is enabled, but {name} does not offer it"
            )));
        }
        info.ray_query = self.ray_query;
        // Relief enables acceleration structures only with ray queries: the flag says what it
        // may use.
        info.acceleration_structure &= self.ray_query;
        info.calibrated_timestamps = self.calibrated_timestamps;
        info.pipeline_statistics = self.pipeline_statistics;
        info.fragment_stores = self.fragment_stores;
        info.storage_r16 = self.storage_r16;
        Ok(info)
    }

    /// Whether the queue family exists and does graphics and compute, and has the queue.
    fn check_queue(&self, name: &str) -> VkResult<()> {
        // SAFETY: plain query on a physical device of the instance (checked by the caller).
        let families = unsafe {
            self.instance
                .get_physical_device_queue_family_properties(self.physical)
        };
        let family = self.queue_family;
        let Some(props) = families.get(family as usize) else {
            return Err(VkError::Invalid(format!(
                "ExternalDevice::queue_family is {family}, but {name} has {} queue families",
                families.len()
            )));
        };
        if !props.queue_flags.contains(QUEUE_FLAGS) {
            return Err(VkError::Unsupported(format!(
                "graphics and compute on queue family {family} of {name} (it has {:?}); relief \
                 records both into one queue's command buffers",
                props.queue_flags
            )));
        }
        if self.queue_index >= props.queue_count {
            return Err(VkError::Invalid(format!(
                "ExternalDevice::queue_index is {}, but queue family {family} of {name} has {} \
                 queue(s)",
                self.queue_index, props.queue_count
            )));
        }
        Ok(())
    }
}

impl fmt::Debug for ExternalDevice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ExternalDevice")
            .field("instance", &self.instance.handle())
            .field("physical", &self.physical)
            .field("device", &self.device.handle())
            .field("queue_family", &self.queue_family)
            .field("queue_index", &self.queue_index)
            .field("debug_utils", &self.debug_utils)
            .field("ray_query", &self.ray_query)
            .field("calibrated_timestamps", &self.calibrated_timestamps)
            .field("pipeline_statistics", &self.pipeline_statistics)
            .field("fragment_stores", &self.fragment_stores)
            .field("storage_r16", &self.storage_r16)
            .finish_non_exhaustive()
    }
}

/// The device's name, for messages.
fn device_name(instance: &ash::Instance, physical: vk::PhysicalDevice) -> String {
    // SAFETY: plain query on a physical device of the instance.
    let props = unsafe { instance.get_physical_device_properties(physical) };
    props
        .device_name_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_else(|_| "the device".into())
}

//! Choosing the physical device: a queue family that does graphics and compute, Vulkan 1.3 with
//! dynamic rendering, synchronization2 and demote-to-helper; then discrete > integrated > virtual > CPU, or by name.

use std::ffi::CStr;

use ash::vk;
use serde::Serialize;

use super::error::{Named, VkError, VkResult};

/// What relief reports and checks about a device.
#[derive(Debug, Clone, Serialize)]
pub struct DeviceInfo {
    /// Device name, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    pub name: String,
    /// Driver name and info, e.g. "llvmpipe Mesa 22.3.6 (LLVM 15.0.6)".
    pub driver: String,
    /// Vulkan API version the device supports, "major.minor.patch".
    pub api: String,
    /// "discrete", "integrated", "virtual", "cpu" or "other".
    pub kind: &'static str,
    /// Largest 2D image side (`maxImageDimension2D`).
    pub max_image_dimension_2d: u32,
    /// Largest range of a storage buffer binding, in bytes (`maxStorageBufferRange`).
    pub max_storage_buffer_range: u32,
    /// Nanoseconds per timestamp tick.
    pub timestamp_period_ns: f32,
    /// Valid bits of timestamps on the chosen queue family (0: no timestamps).
    pub timestamp_valid_bits: u32,
    /// The queue family used for everything.
    pub queue_family: u32,
    /// Whether storage images may use R16 (`shaderStorageImageExtendedFormats`).
    pub storage_r16: bool,
    /// Invocations that run in lockstep (`subgroupSize`): 8 on llvmpipe with AVX2, 32 or 64 on
    /// GPUs. A loop costs such a group as many iterations as its slowest invocation needs.
    pub subgroup_size: u32,
    /// PCI vendor id (`vendorID`); with `device_id` and `pipeline_cache_uuid` it says which
    /// pipeline cache data this device accepts.
    #[serde(skip)]
    pub vendor_id: u32,
    /// Vendor-specific device id (`deviceID`).
    #[serde(skip)]
    pub device_id: u32,
    /// `pipelineCacheUUID`: changes with the driver build, so an old cache is not reused.
    #[serde(skip)]
    pub pipeline_cache_uuid: [u8; 16],
    /// The most samples per pixel (1, 2, 4 or 8) a colour and a depth attachment both take.
    #[serde(skip)]
    pub max_samples: u32,
}

/// The most samples of 1, 2, 4 and 8 that `counts` holds.
fn most_samples(counts: vk::SampleCountFlags) -> u32 {
    [8u32, 4, 2]
        .into_iter()
        .find(|&n| counts.contains(vk::SampleCountFlags::from_raw(n)))
        .unwrap_or(1)
}

fn kind_rank(kind: vk::PhysicalDeviceType) -> (u32, &'static str) {
    match kind {
        vk::PhysicalDeviceType::DISCRETE_GPU => (0, "discrete"),
        vk::PhysicalDeviceType::INTEGRATED_GPU => (1, "integrated"),
        vk::PhysicalDeviceType::VIRTUAL_GPU => (2, "virtual"),
        vk::PhysicalDeviceType::CPU => (3, "cpu"),
        _ => (4, "other"),
    }
}

fn version_string(v: u32) -> String {
    format!(
        "{}.{}.{}",
        vk::api_version_major(v),
        vk::api_version_minor(v),
        vk::api_version_patch(v)
    )
}

/// Describes a device, or `None` if relief cannot use it.
fn describe(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Option<(u32, DeviceInfo)> {
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut driver)
        .push_next(&mut subgroup);
    // SAFETY: valid physical device; the chained structs live across the call.
    unsafe { instance.get_physical_device_properties2(pd, &mut props2) };
    let props = props2.properties;
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut feats2 = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut v12)
        .push_next(&mut v13);
    // SAFETY: as above.
    unsafe { instance.get_physical_device_features2(pd, &mut feats2) };
    let storage_r16 = feats2.features.shader_storage_image_extended_formats == vk::TRUE;
    let usable = props.api_version >= vk::API_VERSION_1_3
        && v13.dynamic_rendering == vk::TRUE
        && v13.synchronization2 == vk::TRUE
        && v13.shader_demote_to_helper_invocation == vk::TRUE
        && v12.host_query_reset == vk::TRUE;
    if !usable {
        return None;
    }
    // SAFETY: plain query.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
    let (family, fprops) = families
        .iter()
        .enumerate()
        .find(|(_, f)| f.queue_flags.contains(wanted))?;
    let (rank, kind) = kind_rank(props.device_type);
    let text = |s: Result<&CStr, _>| {
        s.map(|c: &CStr| c.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let info = DeviceInfo {
        name: text(props.device_name_as_c_str()),
        driver: format!(
            "{} {}",
            text(driver.driver_name_as_c_str()),
            text(driver.driver_info_as_c_str())
        ),
        api: version_string(props.api_version),
        kind,
        max_image_dimension_2d: props.limits.max_image_dimension2_d,
        max_storage_buffer_range: props.limits.max_storage_buffer_range,
        timestamp_period_ns: props.limits.timestamp_period,
        timestamp_valid_bits: fprops.timestamp_valid_bits,
        queue_family: family as u32,
        subgroup_size: subgroup.subgroup_size.max(1),
        storage_r16,
        vendor_id: props.vendor_id,
        device_id: props.device_id,
        pipeline_cache_uuid: props.pipeline_cache_uuid,
        max_samples: most_samples(
            props.limits.framebuffer_color_sample_counts
                & props.limits.framebuffer_depth_sample_counts,
        ),
    };
    Some((rank, info))
}

/// Lists every device relief can use, best first.
pub fn list_devices(instance: &ash::Instance) -> VkResult<Vec<(vk::PhysicalDevice, DeviceInfo)>> {
    // SAFETY: valid instance.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.named("vkEnumeratePhysicalDevices")?;
    let mut usable: Vec<_> = devices
        .into_iter()
        .filter_map(|pd| describe(instance, pd).map(|(rank, info)| (rank, pd, info)))
        .collect();
    usable.sort_by_key(|(rank, _, _)| *rank);
    Ok(usable.into_iter().map(|(_, pd, info)| (pd, info)).collect())
}

/// Picks the best device that `accepts` (a window's presentation support), or the first whose
/// name contains `filter` (case-insensitive).
pub(crate) fn choose_physical_device(
    instance: &ash::Instance,
    filter: Option<&str>,
    accepts: &dyn Fn(vk::PhysicalDevice, &DeviceInfo) -> bool,
) -> VkResult<(vk::PhysicalDevice, DeviceInfo)> {
    let all = list_devices(instance)?;
    if all.is_empty() {
        return Err(VkError::NoDevice);
    }
    let devices: Vec<_> = all
        .iter()
        .filter(|(pd, info)| accepts(*pd, info))
        .cloned()
        .collect();
    if devices.is_empty() {
        let names: Vec<_> = all.iter().map(|(_, i)| i.name.as_str()).collect();
        return Err(VkError::Unsupported(format!(
            "presenting to this window from any device ({})",
            names.join(", ")
        )));
    }
    let Some(filter) = filter else {
        return devices.into_iter().next().ok_or(VkError::NoDevice);
    };
    let wanted = filter.to_lowercase();
    let names = devices
        .iter()
        .map(|(_, i)| i.name.clone())
        .collect::<Vec<_>>();
    devices
        .into_iter()
        .find(|(_, info)| info.name.to_lowercase().contains(&wanted))
        .ok_or_else(|| VkError::NoMatchingDevice {
            wanted: filter.to_owned(),
            available: names.join(", "),
        })
}

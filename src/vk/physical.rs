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
    /// `VK_KHR_ray_query` with its `rayQuery` feature: shaders may trace rays through
    /// acceleration structures.
    pub ray_query: bool,
    /// `VK_KHR_acceleration_structure` (with `VK_KHR_deferred_host_operations`, which it needs)
    /// and its `accelerationStructure` feature.
    pub acceleration_structure: bool,
    /// Why this driver is known to leak host memory every frame, where it is (see
    /// `known_frame_leak`): long sequences on it grow without bound.
    pub known_frame_leak: Option<String>,
    /// `pipelineStatisticsQuery`: passes can count their shader invocations and primitives.
    pub pipeline_statistics: bool,
    /// `fragmentStoresAndAtomics`: fragment shaders can count into storage buffers.
    pub fragment_stores: bool,
    /// `VK_EXT_calibrated_timestamps` with the device's time domain: GPU timestamps can be
    /// placed on the host's clock.
    pub calibrated_timestamps: bool,
    /// `deviceUUID` in hex: the same device across processes and APIs.
    pub device_uuid: String,
    /// `driverUUID` in hex: changes with the driver build.
    pub driver_uuid: String,
}

/// Sixteen bytes as 32 lowercase hex digits.
fn hex_uuid(bytes: &[u8; 16]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Whether `extensions` holds `name`.
fn offers(extensions: &[String], name: &CStr) -> bool {
    extensions.iter().any(|e| e.as_bytes() == name.to_bytes())
}

/// The first Mesa release whose lavapipe is not known to leak every frame. 22.3.6 (Debian 12)
/// leaks about 5 MB a frame in its queue thread; 25.0.7 holds memory flat.
const LAVAPIPE_FLAT_SINCE: (u32, u32) = (23, 0);

/// Why a driver is known to leak host memory every frame, from its `driverName` and
/// `driverInfo` (lavapipe's `driverVersion` does not carry Mesa's version): lavapipe
/// ("llvmpipe") of Mesa before 23.0.
pub fn known_frame_leak(driver_name: &str, driver_info: &str) -> Option<String> {
    if !driver_name.contains("llvmpipe") {
        return None;
    }
    let version = driver_info
        .split_whitespace()
        .skip_while(|w| *w != "Mesa")
        .nth(1)?;
    let mut parts = version.split(['.', '-']).map(|p| p.parse::<u32>().ok());
    let major = parts.next()??;
    let minor = parts.next().flatten().unwrap_or(0);
    ((major, minor) < LAVAPIPE_FLAT_SINCE).then(|| {
        format!(
            "lavapipe of Mesa {version} leaks host memory every frame (about 5 MB at relief's \
             default scene); Mesa {}.{} and later hold memory flat",
            LAVAPIPE_FLAT_SINCE.0, LAVAPIPE_FLAT_SINCE.1
        )
    })
}

/// The device extensions `pd` offers, by name.
fn device_extensions(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Vec<String> {
    // SAFETY: valid physical device.
    let props = unsafe { instance.enumerate_device_extension_properties(pd) }.unwrap_or_default();
    props
        .iter()
        .filter_map(|p| p.extension_name_as_c_str().ok())
        .map(|c| c.to_string_lossy().into_owned())
        .collect()
}

/// Whether `pd` can trace ray queries and build acceleration structures: (ray query,
/// acceleration structure). The feature structs are chained only where the extension is offered.
fn ray_tracing_support(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    extensions: &[String],
) -> (bool, bool) {
    let has = |name: &CStr| extensions.iter().any(|e| e.as_bytes() == name.to_bytes());
    let has_structures = has(ash::khr::acceleration_structure::NAME)
        && has(ash::khr::deferred_host_operations::NAME);
    let has_query = has_structures && has(ash::khr::ray_query::NAME);
    if !has_structures {
        return (false, false);
    }
    let mut structures = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut query = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut feats2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut structures);
    if has_query {
        feats2 = feats2.push_next(&mut query);
    }
    // SAFETY: valid physical device; the chained structs belong to extensions it offers and
    // live across the call.
    unsafe { instance.get_physical_device_features2(pd, &mut feats2) };
    let structures = structures.acceleration_structure == vk::TRUE;
    (structures && query.ray_query == vk::TRUE, structures)
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

/// The queue flags relief's one queue needs: it records draws and dispatches into the same
/// command buffers.
pub(crate) const QUEUE_FLAGS: vk::QueueFlags =
    vk::QueueFlags::from_raw(vk::QueueFlags::GRAPHICS.as_raw() | vk::QueueFlags::COMPUTE.as_raw());

/// What `pd` lacks of what relief enables on every device, by its Vulkan name (empty: nothing).
/// Only support can be asked; whether an engine's device enabled them cannot.
pub(crate) fn missing_requirements(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
) -> Vec<String> {
    // SAFETY: valid physical device.
    let api = unsafe { instance.get_physical_device_properties(pd) }.api_version;
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut feats2 = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut v12)
        .push_next(&mut v13);
    // SAFETY: valid physical device; the chained structs live across the call.
    unsafe { instance.get_physical_device_features2(pd, &mut feats2) };
    let mut missing = Vec::new();
    if api < vk::API_VERSION_1_3 {
        missing.push(format!("Vulkan 1.3 (it reports {})", version_string(api)));
    }
    // independentBlend: the G-buffer's attachments keep their own write masks (Vulkan's 2022
    // roadmap profile requires it; lavapipe has it).
    let features = [
        ("independentBlend", feats2.features.independent_blend),
        ("timelineSemaphore", v12.timeline_semaphore),
        ("hostQueryReset", v12.host_query_reset),
        ("dynamicRendering", v13.dynamic_rendering),
        ("synchronization2", v13.synchronization2),
        (
            "shaderDemoteToHelperInvocation",
            v13.shader_demote_to_helper_invocation,
        ),
    ];
    missing.extend(
        features
            .iter()
            .filter(|(_, has)| *has != vk::TRUE)
            .map(|(name, _)| (*name).to_owned()),
    );
    missing
}

/// Describes a device, or `None` if relief cannot use it.
fn describe(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Option<(u32, DeviceInfo)> {
    if !missing_requirements(instance, pd).is_empty() {
        return None;
    }
    // SAFETY: plain query.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    let family = families
        .iter()
        .position(|f| f.queue_flags.contains(QUEUE_FLAGS))?;
    Some(describe_family(instance, pd, family as u32))
}

/// What relief knows of `pd` used through queue family `family` (which must exist), with its rank
/// among device kinds. The optional flags say what the device offers, not what is enabled.
pub(crate) fn describe_family(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    family: u32,
) -> (u32, DeviceInfo) {
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
    let mut ids = vk::PhysicalDeviceIDProperties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut driver)
        .push_next(&mut subgroup)
        .push_next(&mut ids);
    // SAFETY: valid physical device; the chained structs live across the call.
    unsafe { instance.get_physical_device_properties2(pd, &mut props2) };
    let props = props2.properties;
    // SAFETY: as above.
    let features = unsafe { instance.get_physical_device_features(pd) };
    // SAFETY: plain query.
    let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
    let fprops = families[family as usize];
    let (rank, kind) = kind_rank(props.device_type);
    let text = |s: Result<&CStr, _>| {
        s.map(|c: &CStr| c.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let (driver_name, driver_info) = (
        text(driver.driver_name_as_c_str()),
        text(driver.driver_info_as_c_str()),
    );
    let extensions = device_extensions(instance, pd);
    let (ray_query, acceleration_structure) = ray_tracing_support(instance, pd, &extensions);
    let info = DeviceInfo {
        pipeline_statistics: features.pipeline_statistics_query == vk::TRUE,
        fragment_stores: features.fragment_stores_and_atomics == vk::TRUE,
        // The device time domain is checked when the device is made (it needs the entry).
        calibrated_timestamps: offers(&extensions, ash::ext::calibrated_timestamps::NAME),
        device_uuid: hex_uuid(&ids.device_uuid),
        driver_uuid: hex_uuid(&ids.driver_uuid),
        name: text(props.device_name_as_c_str()),
        known_frame_leak: known_frame_leak(&driver_name, &driver_info),
        driver: format!("{driver_name} {driver_info}"),
        ray_query,
        acceleration_structure,
        api: version_string(props.api_version),
        kind,
        max_image_dimension_2d: props.limits.max_image_dimension2_d,
        max_storage_buffer_range: props.limits.max_storage_buffer_range,
        timestamp_period_ns: props.limits.timestamp_period,
        timestamp_valid_bits: fprops.timestamp_valid_bits,
        queue_family: family,
        subgroup_size: subgroup.subgroup_size.max(1),
        storage_r16: features.shader_storage_image_extended_formats == vk::TRUE,
        vendor_id: props.vendor_id,
        device_id: props.device_id,
        pipeline_cache_uuid: props.pipeline_cache_uuid,
        max_samples: most_samples(
            props.limits.framebuffer_color_sample_counts
                & props.limits.framebuffer_depth_sample_counts,
        ),
    };
    (rank, info)
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

#[cfg(test)]
mod tests {
    use super::known_frame_leak;

    #[test]
    fn old_lavapipe_is_known_to_leak_and_new_is_not() {
        let old = known_frame_leak("llvmpipe", "Mesa 22.3.6 (LLVM 15.0.6)");
        assert!(old.is_some_and(|why| why.contains("22.3.6")));
        assert!(known_frame_leak("llvmpipe", "Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)").is_none());
        assert!(known_frame_leak("llvmpipe", "Mesa 23.0.0 (LLVM 15.0.6)").is_none());
        assert!(known_frame_leak("llvmpipe", "Mesa 22.0.1").is_some());
        // Other drivers, and info strings without a Mesa version, are not judged.
        assert!(known_frame_leak("NVIDIA", "550.54.14").is_none());
        assert!(known_frame_leak("llvmpipe", "a build of unknown origin").is_none());
    }
}

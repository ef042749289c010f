//! The pipeline cache: compiled pipelines kept across runs. Bytes from a file are checked against
//! this device's `VkPipelineCacheHeaderVersionOne` before Vulkan sees them, so a corrupt, truncated
//! or foreign file (another GPU, another driver build) only costs a warning and an empty cache.
//!
//! The cache is owned by the [`Context`](super::Context) (pipelines are created through it), so it
//! holds a clone of the device's function table rather than an `Arc<Context>`, which would be a
//! cycle; the context destroys it before the device.

use std::sync::PoisonError;

use ash::vk;

use super::context::Context;
use super::error::{Named, VkResult};
use super::physical::DeviceInfo;

/// Bytes in a `VkPipelineCacheHeaderVersionOne`: length, version, vendor, device, 16-byte UUID.
pub const HEADER_BYTES: usize = 32;

/// What a pipeline cache header must name to be accepted by a device.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CacheIdentity {
    /// `VkPhysicalDeviceProperties::vendorID`.
    pub vendor_id: u32,
    /// `VkPhysicalDeviceProperties::deviceID`.
    pub device_id: u32,
    /// `VkPhysicalDeviceProperties::pipelineCacheUUID`.
    pub uuid: [u8; 16],
}

impl CacheIdentity {
    /// The identity of the device `info` describes.
    pub fn of(info: &DeviceInfo) -> CacheIdentity {
        CacheIdentity {
            vendor_id: info.vendor_id,
            device_id: info.device_id,
            uuid: info.pipeline_cache_uuid,
        }
    }
}

fn le_u32(bytes: &[u8], at: usize) -> u32 {
    let mut word = [0u8; 4];
    word.copy_from_slice(&bytes[at..at + 4]);
    u32::from_le_bytes(word)
}

/// Checks that `bytes` start with a version-one header made by the device `expected` names; the
/// error says what is wrong. The header's words are little-endian whatever the host (spec 10.6).
pub fn check_header(bytes: &[u8], expected: &CacheIdentity) -> Result<(), String> {
    if bytes.len() < HEADER_BYTES {
        return Err(format!(
            "{} bytes, shorter than the {HEADER_BYTES}-byte header",
            bytes.len()
        ));
    }
    let length = le_u32(bytes, 0);
    let version = le_u32(bytes, 4);
    if length != HEADER_BYTES as u32 {
        return Err(format!("header length {length}, expected {HEADER_BYTES}"));
    }
    if version != vk::PipelineCacheHeaderVersion::ONE.as_raw() as u32 {
        return Err(format!("header version {version}, expected 1"));
    }
    let (vendor, device) = (le_u32(bytes, 8), le_u32(bytes, 12));
    if (vendor, device) != (expected.vendor_id, expected.device_id) {
        return Err(format!(
            "made for device {vendor:#06x}:{device:#06x}, this is {:#06x}:{:#06x}",
            expected.vendor_id, expected.device_id
        ));
    }
    if bytes[16..32] != expected.uuid {
        return Err("made by another driver build (pipelineCacheUUID differs)".into());
    }
    Ok(())
}

/// A `VkPipelineCache`, destroyed on drop.
pub struct PipelineCache {
    device: ash::Device,
    raw: vk::PipelineCache,
    seeded: bool,
}

impl PipelineCache {
    /// Creates a cache, seeded with `initial` when its header matches `identity`; bytes that do not
    /// match, or that the driver refuses, are logged with `log::warn!` and an empty cache is made.
    pub(crate) fn new(
        device: &ash::Device,
        identity: &CacheIdentity,
        initial: Option<&[u8]>,
    ) -> VkResult<PipelineCache> {
        let usable = initial.filter(|bytes| match check_header(bytes, identity) {
            Ok(()) => true,
            Err(why) => {
                log::warn!("ignoring the pipeline cache data ({why}); starting an empty cache");
                false
            }
        });
        if let Some(bytes) = usable {
            match create(device, bytes) {
                Ok(raw) => return Ok(Self::wrap(device, raw, true)),
                Err(e) => log::warn!(
                    "the driver refused the pipeline cache data ({e}); starting an empty cache"
                ),
            }
        }
        Ok(Self::wrap(device, create(device, &[])?, false))
    }

    fn wrap(device: &ash::Device, raw: vk::PipelineCache, seeded: bool) -> PipelineCache {
        PipelineCache {
            device: device.clone(),
            raw,
            seeded,
        }
    }

    /// The raw handle.
    pub fn raw(&self) -> vk::PipelineCache {
        self.raw
    }

    /// Whether the cache started from the given bytes (false: it started empty).
    pub fn seeded(&self) -> bool {
        self.seeded
    }

    /// The cache's contents, to be written to a file and passed back on a later run.
    pub fn data(&self) -> VkResult<Vec<u8>> {
        // SAFETY: the cache belongs to this device; reading it needs no external sync.
        unsafe { self.device.get_pipeline_cache_data(self.raw) }.named("vkGetPipelineCacheData")
    }
}

impl Context {
    /// Runs `f` with the context's pipeline cache, for `vkCreate*Pipelines`.
    pub(crate) fn with_pipeline_cache<R>(&self, f: impl FnOnce(vk::PipelineCache) -> R) -> R {
        let cache = self
            .pipeline_cache_lock()
            .read()
            .unwrap_or_else(PoisonError::into_inner);
        let started = std::time::Instant::now();
        let created = f(cache.raw());
        // What the cache saves shows here: the CPU time of pipeline creation.
        let micros = started.elapsed().as_micros() as u64;
        self.count(super::counters::Created::PipelineTime { micros });
        created
    }

    /// The pipeline cache's contents, to persist after rendering and pass back through
    /// [`ContextOptions::pipeline_cache`](super::ContextOptions) or
    /// [`Context::merge_pipeline_cache`] on a later run.
    pub fn pipeline_cache_data(&self) -> VkResult<Vec<u8>> {
        let cache = self
            .pipeline_cache_lock()
            .read()
            .unwrap_or_else(PoisonError::into_inner);
        cache.data()
    }

    /// Whether the pipeline cache holds data from an earlier run (given at creation or merged).
    pub fn pipeline_cache_seeded(&self) -> bool {
        let cache = self
            .pipeline_cache_lock()
            .read()
            .unwrap_or_else(PoisonError::into_inner);
        cache.seeded()
    }

    /// Adds pipeline cache data from an earlier run to the context's cache, for callers that only
    /// know which file to read once the device is chosen. Data made by another device or driver,
    /// or corrupt, is ignored with a warning: the answer is whether the data was used.
    pub fn merge_pipeline_cache(&self, bytes: &[u8]) -> VkResult<bool> {
        let loaded =
            PipelineCache::new(self.device(), &CacheIdentity::of(self.info()), Some(bytes))?;
        if !loaded.seeded() {
            return Ok(false);
        }
        let mut cache = self
            .pipeline_cache_lock()
            .write()
            .unwrap_or_else(PoisonError::into_inner);
        // SAFETY: both caches belong to this device; the write lock gives the target to this
        // thread alone, as vkMergePipelineCaches requires.
        unsafe {
            self.device()
                .merge_pipeline_caches(cache.raw(), &[loaded.raw()])
        }
        .named("vkMergePipelineCaches")?;
        cache.seeded = true;
        Ok(true)
    }
}

fn create(device: &ash::Device, bytes: &[u8]) -> VkResult<vk::PipelineCache> {
    let info = vk::PipelineCacheCreateInfo::default().initial_data(bytes);
    // SAFETY: valid device; `bytes` (empty or with a checked header) outlives the call.
    unsafe { device.create_pipeline_cache(&info, None) }.named("vkCreatePipelineCache")
}

impl Drop for PipelineCache {
    fn drop(&mut self) {
        // SAFETY: no pipeline creation uses the cache any more (its owner is being dropped).
        unsafe { self.device.destroy_pipeline_cache(self.raw, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ME: CacheIdentity = CacheIdentity {
        vendor_id: 0x10005,
        device_id: 0,
        uuid: [7; 16],
    };

    fn header(length: u32, version: u32, id: &CacheIdentity) -> Vec<u8> {
        let mut bytes = Vec::new();
        for word in [length, version, id.vendor_id, id.device_id] {
            bytes.extend_from_slice(&word.to_le_bytes());
        }
        bytes.extend_from_slice(&id.uuid);
        bytes.extend_from_slice(b"payload");
        bytes
    }

    #[test]
    fn own_header_is_accepted() {
        assert_eq!(check_header(&header(32, 1, &ME), &ME), Ok(()));
    }

    #[test]
    fn truncated_data_is_refused() {
        let full = header(32, 1, &ME);
        for len in [0, 4, 31] {
            let why = check_header(&full[..len], &ME).unwrap_err();
            assert!(why.contains("shorter"), "{why}");
        }
    }

    #[test]
    fn wrong_length_or_version_is_refused() {
        assert!(check_header(&header(16, 1, &ME), &ME).is_err());
        assert!(check_header(&header(32, 2, &ME), &ME).is_err());
    }

    #[test]
    fn foreign_device_or_driver_is_refused() {
        let other_vendor = CacheIdentity {
            vendor_id: 0x10de,
            ..ME
        };
        let other_device = CacheIdentity { device_id: 9, ..ME };
        let other_driver = CacheIdentity {
            uuid: [8; 16],
            ..ME
        };
        for other in [other_vendor, other_device] {
            let why = check_header(&header(32, 1, &other), &ME).unwrap_err();
            assert!(why.contains("made for device"), "{why}");
        }
        let why = check_header(&header(32, 1, &other_driver), &ME).unwrap_err();
        assert!(why.contains("pipelineCacheUUID"), "{why}");
    }

    #[test]
    fn garbage_is_refused() {
        let garbage: Vec<u8> = (0..200u32).map(|k| (k * 37 % 251) as u8).collect();
        assert!(check_header(&garbage, &ME).is_err());
    }
}

//! The device context: instance, chosen physical device, logical device, its one queue, the memory
//! allocator and a command pool. Every other Vulkan object holds an `Arc<Context>`, so the context
//! is dropped last, and its `Drop` is the one place where teardown order is written out.
//!
//! The instance and device are relief's own ([`Context::new`]) or an engine's
//! ([`Context::from_external`]); both constructors end in the same assembly, and the context
//! destroys the instance and device only when they are its own (`Ownership`).

use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, RwLock};
use std::time::{Duration, Instant};

use ash::{ext, khr, vk};
use gpu_allocator::vulkan::Allocator;

use super::context_setup::{
    create_foundation, destroy_instance_parts, device_time_domain, lifecycle, ray_queries_off,
    DeviceOwned, Foundation, Settings,
};
use super::counters::{Created, LiveObjects, ObjectCounters, ObjectCounts};
use super::deferred::Retirement;
use super::error::{Named, VkResult};
use super::external_device::ExternalDevice;
use super::faults::{FaultPlan, Faults};
use super::instance::{InstanceParts, MessageCounts, Validation};
use super::physical::DeviceInfo;
use super::pipeline_cache::PipelineCache;
use super::query::ClockPair;
use super::surface::{WindowHandles, WindowSurface};

/// What the caller wants from [`Context::new`]: `ContextOptions::default()` and the `with_*`
/// setters.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct ContextOptions {
    /// Case-insensitive substring of the device name to pick (`--device`).
    pub device_filter: Option<String>,
    /// Validation choice; `None` reads `RELIEF_VALIDATION` and the build profile.
    pub validation: Option<Validation>,
    /// How long one submission may take before it counts as a hang; `None` reads
    /// `RELIEF_GPU_TIMEOUT_S` (default 600 s).
    pub gpu_timeout: Option<Duration>,
    /// Pipeline cache data from an earlier run ([`Context::pipeline_cache_data`]); data made by
    /// another device or driver, or corrupt, is ignored with a warning.
    pub pipeline_cache: Option<Vec<u8>>,
    /// Leave ray queries off even where the device has them, as on a device without them (the
    /// paths that must do without; `RELIEF_RAY_QUERIES=0` does the same).
    pub without_ray_queries: bool,
    /// Faults to feign, for tests of the error paths ([`Faults`]); `None` reads `RELIEF_FAULTS`
    /// (none when unset).
    pub faults: Option<Faults>,
}

with_setters!(ContextOptions {
    with_device_filter => device_filter: Option<String>,
    with_validation => validation: Option<Validation>,
    with_gpu_timeout => gpu_timeout: Option<Duration>,
    with_pipeline_cache => pipeline_cache: Option<Vec<u8>>,
    with_without_ray_queries => without_ray_queries: bool,
    with_faults => faults: Option<Faults>,
});

/// The environment variable that, set to 0, leaves ray queries off ([`ContextOptions`]).
pub const RAY_QUERIES_ENV: &str = "RELIEF_RAY_QUERIES";

/// Who destroys a context's instance and device (and the messenger and surface relief made).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Ownership {
    /// Relief created them ([`Context::new`]): the context's `Drop` destroys them.
    Relief,
    /// An engine did ([`Context::from_external`]): relief destroys only what it created on the
    /// device, and the engine destroys its device and instance after the context is gone.
    Engine,
}

/// One Vulkan device, ready to record and submit work.
pub struct Context {
    parts: ManuallyDrop<InstanceParts>,
    ownership: Ownership,
    counts: Box<MessageCounts>,
    physical: vk::PhysicalDevice,
    info: DeviceInfo,
    device: ash::Device,
    debug_device: Option<ext::debug_utils::Device>,
    /// `VK_EXT_calibrated_timestamps`, where the device has it with its own time domain.
    calibration: Option<ext::calibrated_timestamps::Device>,
    /// `VK_KHR_acceleration_structure`'s functions, where the device traces ray queries.
    structures: Option<khr::acceleration_structure::Device>,
    queue: Mutex<vk::Queue>,
    queue_family: u32,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    command_pool: Mutex<vk::CommandPool>,
    /// Read-locked while pipelines are created (the cache is internally synchronised for that),
    /// write-locked to merge into it (`vkMergePipelineCaches` needs its target to itself).
    pipeline_cache: ManuallyDrop<RwLock<PipelineCache>>,
    /// The timeline semaphore every submission signals, and the objects waiting on it.
    retirement: Retirement,
    gpu_timeout: Duration,
    /// Set when a fence wait timed out: work may still be pending, so `Drop` must not wait for the
    /// device or destroy it.
    hung: AtomicBool,
    created: ObjectCounters,
    /// What [`ContextOptions::faults`] asked to feign.
    faults: FaultPlan,
}

impl Context {
    /// Creates the instance, picks a device (discrete > integrated > virtual > CPU, or by name) and
    /// creates the logical device with the features relief uses.
    pub fn new(options: &ContextOptions) -> VkResult<Arc<Context>> {
        // SAFETY: no window, so no handle to keep alive.
        unsafe { Self::create(options, None) }
    }

    /// As [`Context::new`], for a context that also presents to `window`: the instance gets the
    /// window system's surface extensions, the context owns the window's surface
    /// (`Context::present_surface`), the device chosen can present to it and has
    /// `VK_KHR_swapchain` enabled.
    ///
    /// # Safety
    /// The window behind `window` must outlive the returned context (and every clone of its `Arc`).
    #[cfg(feature = "window")]
    pub unsafe fn new_presenting(
        options: &ContextOptions,
        window: &WindowHandles,
    ) -> VkResult<Arc<Context>> {
        // SAFETY: the caller's contract.
        unsafe { Self::create(options, Some(window)) }
    }

    /// Wraps an engine's own instance and device: relief creates its allocator, command pool,
    /// pipeline cache and retirement timeline on the device and submits to the one queue named,
    /// and destroys only those when the last `Arc` of the context drops. `options` is read as for
    /// [`Context::new`], except `device_filter` and `validation`, which are the engine's choice.
    ///
    /// Checked here, with a [`VkError`](super::VkError) saying what is wrong: the physical device is one of the
    /// instance's and supports Vulkan 1.3 and every feature relief requires; the queue family
    /// exists, does graphics and compute and has the queue; the device offers each optional part
    /// `device` says is enabled. Formats are checked where relief uses them, as on its own device.
    ///
    /// Validation: relief has no debug messenger on an engine's instance, so
    /// [`Context::messages`] stays at zero and [`Context::validation_enabled`] is false; the
    /// engine's own messenger sees the messages about relief's work.
    ///
    /// # Safety
    /// The engine promises (Vulkan gives no way to ask an instance or device what was enabled):
    /// - `device.device` was created from `device.instance` (created with `apiVersion` 1.3 or
    ///   later, from `device.entry`) on `device.physical`, with queue `queue_index` of family
    ///   `queue_family` among its queues (no creation flags);
    /// - the device has the features relief requires enabled: `independentBlend`,
    ///   `timelineSemaphore`, `hostQueryReset`, `dynamicRendering`, `synchronization2` and
    ///   `shaderDemoteToHelperInvocation`;
    /// - each optional part that `device` says is enabled (`ray_query`, `calibrated_timestamps`,
    ///   `pipeline_statistics`, `fragment_stores`, `storage_r16`, `debug_utils`) is enabled, with
    ///   the extensions and features [`ExternalDevice`] lists for it;
    /// - the instance and device stay alive, and are not destroyed, until the context and
    ///   everything made from it (every clone of its `Arc`, renderers, buffers) have dropped;
    /// - relief's queue is used by relief alone, or the engine synchronises its own use of it
    ///   with relief's (relief holds its own lock for each submission and wait, which the engine
    ///   cannot take); and `vkDeviceWaitIdle`, which needs every queue of the device held, is not
    ///   called while relief may submit. Relief itself waits only on its queue, never on the
    ///   whole device.
    pub unsafe fn from_external(
        device: ExternalDevice,
        options: &ContextOptions,
    ) -> VkResult<Arc<Context>> {
        let settings = Settings::read(options)?;
        let mut info = device.device_info()?;
        info.calibrated_timestamps = info.calibrated_timestamps
            && device_time_domain(&device.entry, &device.instance, device.physical);
        info.ray_query &= !ray_queries_off(options);
        let foundation = Foundation {
            parts: InstanceParts {
                entry: device.entry,
                instance: device.instance,
                debug_utils: None,
                validation_enabled: false,
                surface: None,
            },
            physical: device.physical,
            info,
            device: device.device,
            queue_index: device.queue_index,
            names_objects: device.debug_utils,
            ownership: Ownership::Engine,
        };
        Self::build(
            foundation,
            Box::default(),
            settings,
            options.pipeline_cache.as_deref(),
        )
    }

    /// # Safety
    /// As [`Context::new_presenting`] when `window` is given.
    unsafe fn create(
        options: &ContextOptions,
        window: Option<&WindowHandles>,
    ) -> VkResult<Arc<Context>> {
        let settings = Settings::read(options)?;
        let counts = Box::<MessageCounts>::default();
        // Held until the context is whole: creating it, or on failure destroying it.
        let _lifecycle = lifecycle();
        // SAFETY: the caller's contract for the window.
        let foundation = unsafe { create_foundation(options, window, &counts) }?;
        let cache_data = options.pipeline_cache.as_deref();
        Self::build(foundation, counts, settings, cache_data)
    }

    /// The assembly both constructors end in: relief's own objects on the device, then the
    /// context. On failure the foundation is released as its ownership says (for relief's own,
    /// the caller holds [`lifecycle`]).
    fn build(
        foundation: Foundation,
        counts: Box<MessageCounts>,
        settings: Settings,
        cache_data: Option<&[u8]>,
    ) -> VkResult<Arc<Context>> {
        let f = &foundation;
        let owned = match DeviceOwned::new(&f.parts, (f.physical, &f.info), &f.device, cache_data) {
            Ok(owned) => owned,
            Err(e) => {
                // SAFETY: nothing made from the device is left, and nothing else holds it.
                unsafe { foundation.release() };
                return Err(e);
            }
        };
        let ctx = Self::assemble(foundation, counts, owned, settings);
        ctx.with_pipeline_cache(|raw| ctx.set_name(raw, "pipeline cache"));
        ctx.set_name(ctx.retirement.timeline(), "retirement timeline");
        Ok(ctx)
    }

    fn assemble(
        foundation: Foundation,
        counts: Box<MessageCounts>,
        owned: DeviceOwned,
        settings: Settings,
    ) -> Arc<Context> {
        let Foundation {
            parts,
            physical,
            info,
            device,
            queue_index,
            names_objects,
            ownership,
        } = foundation;
        let queue_family = info.queue_family;
        // SAFETY: the queue was requested at device creation (by relief, or as the engine
        // promised; the index is within the family's count, checked for an engine's device).
        let queue = unsafe { device.get_device_queue(queue_family, queue_index) };
        let debug_device =
            names_objects.then(|| ext::debug_utils::Device::new(&parts.instance, &device));
        let calibration = info
            .calibrated_timestamps
            .then(|| ext::calibrated_timestamps::Device::new(&parts.instance, &device));
        let structures = info
            .ray_query
            .then(|| khr::acceleration_structure::Device::new(&parts.instance, &device));
        Arc::new(Context {
            parts: ManuallyDrop::new(parts),
            ownership,
            counts,
            physical,
            info,
            device,
            debug_device,
            calibration,
            structures,
            queue: Mutex::new(queue),
            queue_family,
            allocator: ManuallyDrop::new(Mutex::new(owned.allocator)),
            command_pool: Mutex::new(owned.pool),
            pipeline_cache: ManuallyDrop::new(RwLock::new(owned.cache)),
            retirement: owned.retirement,
            gpu_timeout: settings.gpu_timeout,
            hung: AtomicBool::new(false),
            created: ObjectCounters::default(),
            faults: settings.faults,
        })
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

    /// One line for people: name (driver; Vulkan version; validation on, off, or the engine's
    /// on an engine's device).
    pub fn describe(&self) -> String {
        let i = &self.info;
        let validation = if self.is_external() {
            "the engine's"
        } else if self.validation_enabled() {
            "on"
        } else {
            "off"
        };
        format!(
            "{} ({}; Vulkan {}; validation {validation})",
            i.name,
            i.driver.trim(),
            i.api
        )
    }

    /// Whether relief loaded the Khronos validation layer and counts what it reports
    /// ([`Context::messages`]). False on an engine's device ([`Context::from_external`]): relief
    /// cannot ask which layers the engine's instance has, and has no messenger there.
    pub fn validation_enabled(&self) -> bool {
        self.parts.validation_enabled
    }

    /// What the validation layer has reported so far to relief's debug messenger. On an
    /// engine's device there is none and the counts stay at zero; the engine's own messenger
    /// sees the messages about relief's work.
    pub fn messages(&self) -> &MessageCounts {
        &self.counts
    }

    /// Whether the instance and device are an engine's ([`Context::from_external`]), which
    /// relief does not destroy.
    pub fn is_external(&self) -> bool {
        self.ownership == Ownership::Engine
    }

    /// How many objects and allocations this context has created so far.
    pub fn created(&self) -> ObjectCounts {
        self.created.snapshot()
    }

    /// Vulkan objects and allocations of this context alive now (created and not yet destroyed).
    pub fn alive(&self) -> LiveObjects {
        self.created.alive()
    }

    pub(crate) fn count(&self, what: Created) {
        self.created.record(what);
    }

    /// Counts the destruction of an object counted as `what` when it was created.
    pub(crate) fn count_destroyed(&self, what: Created) {
        self.created.release(what);
    }

    /// The queue family of the single graphics + compute queue relief uses.
    pub fn queue_family(&self) -> u32 {
        self.queue_family
    }

    /// The window surface of a context made by [`Context::new_presenting`].
    /// The acceleration-structure functions, where the device traces ray queries (the
    /// extensions and features are enabled exactly then).
    pub(crate) fn structures(&self) -> Option<&khr::acceleration_structure::Device> {
        self.structures.as_ref()
    }

    pub(crate) fn present_surface(&self) -> Option<&WindowSurface> {
        self.parts.surface.as_ref()
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

    pub(crate) fn retirement(&self) -> &Retirement {
        &self.retirement
    }

    pub(crate) fn pipeline_cache_lock(&self) -> &RwLock<PipelineCache> {
        &self.pipeline_cache
    }

    /// How long one submission may take before [`Context::wait_fence`] calls it a hang.
    pub fn gpu_timeout(&self) -> Duration {
        self.gpu_timeout
    }

    /// The faults this context feigns and its count of operations so far.
    pub(crate) fn faults(&self) -> &FaultPlan {
        &self.faults
    }

    pub(crate) fn mark_hung(&self) {
        self.hung.store(true, Ordering::Relaxed);
    }

    /// Whether a fence wait timed out: submitted work may never finish, so buffers, images and the
    /// device itself are left undestroyed from then on.
    pub fn is_hung(&self) -> bool {
        self.hung.load(Ordering::Relaxed)
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

    /// The device's timestamp counter read beside the host's clock, where the device calibrates
    /// its time domain (`VK_EXT_calibrated_timestamps`); `None` elsewhere.
    pub fn calibrate(&self) -> Option<ClockPair> {
        let calibration = self.calibration.as_ref()?;
        let domains =
            [vk::CalibratedTimestampInfoKHR::default().time_domain(vk::TimeDomainKHR::DEVICE)];
        let before = Instant::now();
        // SAFETY: the extension is enabled and the device domain is calibrateable (checked when
        // the device was made).
        let (ticks, _) = unsafe { calibration.get_calibrated_timestamps(&domains) }.ok()?;
        let after = Instant::now();
        let half = (after - before) / 2;
        let bits = self.info.timestamp_valid_bits;
        let mask = if bits >= 64 {
            u64::MAX
        } else {
            (1u64 << bits) - 1
        };
        Some(ClockPair {
            gpu_ticks: ticks[0] & mask,
            host: before + half,
            uncertainty: half,
        })
    }

    /// Gives a Vulkan object a debug name, so validation messages say what they are about.
    pub(crate) fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
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

    /// Waits for the device to finish all submitted work, then destroys the objects dropped
    /// while it ran.
    pub fn wait_idle(&self) -> VkResult<()> {
        let waited = self.wait_for_gpu();
        self.retire();
        waited
    }

    /// Waits until the GPU has finished relief's submissions: the whole device where it is
    /// relief's, only relief's queue on an engine's device (`vkDeviceWaitIdle` needs every queue
    /// of the device held, and the engine's are not relief's to hold).
    fn wait_for_gpu(&self) -> VkResult<()> {
        let queue = self
            .queue
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        match self.ownership {
            Ownership::Relief => {
                // SAFETY: valid device, and relief's is its only queue; the lock keeps
                // submissions out while we wait.
                unsafe { self.device.device_wait_idle() }.named("vkDeviceWaitIdle")
            }
            Ownership::Engine => {
                // SAFETY: valid queue, held by the lock (the engine promised not to use it
                // concurrently).
                unsafe { self.device.queue_wait_idle(*queue) }.named("vkQueueWaitIdle")
            }
        }
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        if self.is_hung() {
            // Waiting would block forever and destroying objects still in use is undefined;
            // leave the device (an engine's: relief's objects on it) to the process exit.
            log::warn!("the GPU hung: leaving the Vulkan device undestroyed");
            return;
        }
        let _ = self.wait_for_gpu();
        // SAFETY: every object made from this device holds an Arc of this context, so all of them
        // are gone, and relief's queue is idle. Order: objects still waiting for retirement
        // (their memory goes back to the allocator), allocator (frees its memory blocks),
        // pipeline cache, pools; then, only where relief made them, device, messenger, surface
        // and instance. An engine's are its own to destroy.
        unsafe {
            self.retirement.drain(self);
            ManuallyDrop::drop(&mut self.allocator);
            ManuallyDrop::drop(&mut self.pipeline_cache);
            if let Ok(pool) = self.command_pool.lock() {
                self.device.destroy_command_pool(*pool, None);
            }
            if self.ownership == Ownership::Relief {
                let _lifecycle = lifecycle();
                self.device.destroy_device(None);
                destroy_instance_parts(&self.parts);
            }
            // Only the loader's handle and the function tables: nothing is destroyed here.
            ManuallyDrop::drop(&mut self.parts);
        }
    }
}

//! An engine's own Vulkan instance and device, made here with raw `ash` as an engine would,
//! wrapped by `Context::from_external`: relief renders on it the same picture as on its own
//! device, destroys only what it created (the engine's device is alive and usable afterwards, and
//! destroying it reports no object relief left behind), and refuses a queue it cannot have with
//! an error that says why. The engine's own debug messenger counts the validation errors.

mod common;

use std::ffi::{c_void, CStr};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use ash::{ext, khr, vk};
use relief::render::{FrameRequest, RenderOptions, Renderer};
use relief::scene::{default_heightfield, default_scene, DEFAULT_SCENE_METHOD};
use relief::vk::{Context, ContextOptions, ExternalDevice, VkError};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Held for each whole test: the engine's instance and device are made and destroyed outside
/// relief's own lock around those calls, which some layers need serialised.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// What the engine's messenger saw: errors counted, their first texts kept.
#[derive(Default)]
struct ErrorLog {
    errors: AtomicU32,
    kept: Mutex<Vec<String>>,
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if !severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        || data.is_null()
        || user.is_null()
    {
        return vk::FALSE;
    }
    // SAFETY: the layer passes valid callback data for the call; `user` is the engine's boxed
    // `ErrorLog`, which outlives the messenger.
    let (data, log) = unsafe { (&*data, &*(user as *const ErrorLog)) };
    // SAFETY: a NUL-terminated string when non-null, valid during the callback.
    let text = unsafe { data.message_as_c_str() }
        .map(|m| m.to_string_lossy().into_owned())
        .unwrap_or_default();
    log.errors.fetch_add(1, Ordering::Relaxed);
    if let Ok(mut kept) = log.kept.lock() {
        if kept.len() < 8 {
            kept.push(text);
        }
    }
    vk::FALSE
}

/// What the engine found its device offers of relief's optional parts, and enabled.
#[derive(Debug, Clone, Copy, Default)]
struct Optional {
    ray_query: bool,
    calibrated_timestamps: bool,
    pipeline_statistics: bool,
    fragment_stores: bool,
    storage_r16: bool,
}

/// The engine: its instance (validated when the layer is installed, with its own messenger),
/// one physical device and a device with one graphics and compute queue.
struct Engine {
    entry: ash::Entry,
    instance: ash::Instance,
    validation: bool,
    messenger: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    log: Box<ErrorLog>,
    physical: vk::PhysicalDevice,
    name: String,
    family: u32,
    optional: Optional,
    device: Option<ash::Device>,
}

impl Engine {
    /// The engine's Vulkan, or `None` (the test says it skipped) where there is none and none is
    /// required.
    fn new(test: &str) -> Option<Engine> {
        let skip = |why: &str| {
            assert!(!common::device_required(), "{test}: {why}");
            eprintln!("SKIPPED: no Vulkan device ({test}): {why}");
        };
        // SAFETY: loading the system loader runs its initialisers; nothing else is shared yet.
        let entry = match unsafe { ash::Entry::load() } {
            Ok(entry) => entry,
            Err(e) => {
                skip(&format!("no loader: {e}"));
                return None;
            }
        };
        let validation = validation_wanted(&entry);
        common::validation_check(common::under_ci(), validation)
            .unwrap_or_else(|why| panic!("{why}"));
        let log = Box::<ErrorLog>::default();
        let instance = match create_instance(&entry, validation) {
            Some(instance) => instance,
            None => {
                skip("the loader found no driver");
                return None;
            }
        };
        let messenger = create_messenger(&entry, &instance, &log);
        let mut engine = Engine {
            entry,
            instance,
            validation,
            messenger: Some(messenger),
            log,
            physical: vk::PhysicalDevice::null(),
            name: String::new(),
            family: 0,
            optional: Optional::default(),
            device: None,
        };
        let Some((physical, family)) = choose_physical(&engine.instance) else {
            skip("no device with Vulkan 1.3 and what relief requires");
            return None;
        };
        engine.physical = physical;
        engine.family = family;
        engine.name = device_name(&engine.instance, physical);
        engine.optional = optional_support(&engine.instance, physical);
        engine.device = Some(create_device(
            &engine.instance,
            physical,
            family,
            engine.optional,
        ));
        Some(engine)
    }

    fn device(&self) -> &ash::Device {
        self.device.as_ref().expect("the engine's device is alive")
    }

    /// The engine's objects as relief takes them, with `queue` as relief's queue.
    fn external(&self, family: u32, queue: u32) -> ExternalDevice {
        let o = self.optional;
        ExternalDevice::new(
            self.entry.clone(),
            self.instance.clone(),
            self.physical,
            self.device().clone(),
            family,
            queue,
        )
        .with_debug_utils(true)
        .with_ray_query(o.ray_query)
        .with_calibrated_timestamps(o.calibrated_timestamps)
        .with_pipeline_statistics(o.pipeline_statistics)
        .with_fragment_stores(o.fragment_stores)
        .with_storage_r16(o.storage_r16)
    }

    /// Proves the device still works after relief is gone: it idles, and makes and destroys a
    /// buffer.
    fn use_device(&self) {
        let device = self.device();
        // SAFETY: the engine's device; no queue of it is in use on another thread.
        unsafe { device.device_wait_idle() }.expect("the engine's device idles after relief");
        let info = vk::BufferCreateInfo::default()
            .size(256)
            .usage(vk::BufferUsageFlags::TRANSFER_DST)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info; the buffer is destroyed at once, never bound.
        unsafe {
            let buffer = device
                .create_buffer(&info, None)
                .expect("the engine's device makes a buffer after relief");
            device.destroy_buffer(buffer, None);
        }
    }

    /// Destroys the device (where the layer reports any object relief left on it), then the
    /// messenger and the instance; returns the validation errors counted through all of it.
    fn finish(mut self) -> Vec<String> {
        if let Some(device) = self.device.take() {
            // SAFETY: nothing of the device is in use: relief's context has dropped.
            unsafe { device.destroy_device(None) };
        }
        let errors = self.log.errors.load(Ordering::Relaxed);
        let mut kept = self.log.kept.lock().map(|k| k.clone()).unwrap_or_default();
        kept.insert(0, format!("{errors} error(s), the first of them:"));
        drop(self);
        if errors == 0 {
            kept.clear();
        }
        kept
    }
}

impl Drop for Engine {
    fn drop(&mut self) {
        // SAFETY: children first (device, messenger), then the instance; each exactly once.
        unsafe {
            if let Some(device) = self.device.take() {
                let _ = device.device_wait_idle();
                device.destroy_device(None);
            }
            if let Some((loader, messenger)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// The layer when installed, as relief's own tests load it (`RELIEF_VALIDATION=0` turns it off).
fn validation_wanted(entry: &ash::Entry) -> bool {
    if std::env::var("RELIEF_VALIDATION").is_ok_and(|v| v == "0") {
        return false;
    }
    // SAFETY: plain enumeration on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }.unwrap_or_default();
    layers
        .iter()
        .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER))
}

/// A Vulkan 1.3 instance with debug utils, and the layer where wanted; `None` where the loader
/// finds no driver.
fn create_instance(entry: &ash::Entry, validation: bool) -> Option<ash::Instance> {
    let app = vk::ApplicationInfo::default()
        .application_name(c"an engine")
        .api_version(vk::API_VERSION_1_3);
    let layers = if validation {
        vec![VALIDATION_LAYER.as_ptr()]
    } else {
        vec![]
    };
    let extensions = [ext::debug_utils::NAME.as_ptr()];
    let info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    // SAFETY: the create info and its arrays live across the call.
    match unsafe { entry.create_instance(&info, None) } {
        Ok(instance) => Some(instance),
        Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => None,
        Err(e) => panic!("vkCreateInstance failed: {e}"),
    }
}

fn create_messenger(
    entry: &ash::Entry,
    instance: &ash::Instance,
    log: &ErrorLog,
) -> (ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT) {
    let loader = ext::debug_utils::Instance::new(entry, instance);
    let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(log as *const ErrorLog as *mut c_void);
    // SAFETY: `log` is boxed by the engine and outlives the messenger, destroyed first.
    let messenger = unsafe { loader.create_debug_utils_messenger(&info, None) }
        .expect("vkCreateDebugUtilsMessengerEXT");
    (loader, messenger)
}

/// The features relief requires, as supported by `pd`.
fn has_requirements(instance: &ash::Instance, pd: vk::PhysicalDevice) -> bool {
    // SAFETY: valid physical device.
    let api = unsafe { instance.get_physical_device_properties(pd) }.api_version;
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut v12)
        .push_next(&mut v13);
    // SAFETY: valid physical device; the chained structs live across the call.
    unsafe { instance.get_physical_device_features2(pd, &mut features) };
    api >= vk::API_VERSION_1_3
        && features.features.independent_blend == vk::TRUE
        && v12.timeline_semaphore == vk::TRUE
        && v12.host_query_reset == vk::TRUE
        && v13.dynamic_rendering == vk::TRUE
        && v13.synchronization2 == vk::TRUE
        && v13.shader_demote_to_helper_invocation == vk::TRUE
}

/// The first device with relief's requirements and a graphics and compute family.
fn choose_physical(instance: &ash::Instance) -> Option<(vk::PhysicalDevice, u32)> {
    // SAFETY: valid instance.
    let devices = unsafe { instance.enumerate_physical_devices() }.unwrap_or_default();
    let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
    devices.into_iter().find_map(|pd| {
        if !has_requirements(instance, pd) {
            return None;
        }
        // SAFETY: plain query.
        let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
        let family = families
            .iter()
            .position(|f| f.queue_flags.contains(wanted))?;
        Some((pd, family as u32))
    })
}

fn device_name(instance: &ash::Instance, pd: vk::PhysicalDevice) -> String {
    // SAFETY: plain query.
    let props = unsafe { instance.get_physical_device_properties(pd) };
    props
        .device_name_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// What `pd` offers of relief's optional parts: the engine enables all of it, so relief uses on
/// it what it uses on its own device.
fn optional_support(instance: &ash::Instance, pd: vk::PhysicalDevice) -> Optional {
    // SAFETY: valid physical device.
    let extensions =
        unsafe { instance.enumerate_device_extension_properties(pd) }.unwrap_or_default();
    let offers = |name: &CStr| {
        extensions
            .iter()
            .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
    };
    let mut structures = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut query = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default();
    let rays_offered = offers(khr::ray_query::NAME)
        && offers(khr::acceleration_structure::NAME)
        && offers(khr::deferred_host_operations::NAME);
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut v12);
    if rays_offered {
        features = features.push_next(&mut structures).push_next(&mut query);
    }
    // SAFETY: valid physical device; the chained structs are of offered extensions and live
    // across the call.
    unsafe { instance.get_physical_device_features2(pd, &mut features) };
    let core = features.features;
    Optional {
        ray_query: rays_offered
            && structures.acceleration_structure == vk::TRUE
            && query.ray_query == vk::TRUE
            && v12.buffer_device_address == vk::TRUE,
        calibrated_timestamps: offers(ext::calibrated_timestamps::NAME),
        pipeline_statistics: core.pipeline_statistics_query == vk::TRUE,
        fragment_stores: core.fragment_stores_and_atomics == vk::TRUE,
        storage_r16: core.shader_storage_image_extended_formats == vk::TRUE,
    }
}

/// The engine's device: one queue of `family`, relief's required features, and every optional
/// part `optional` says the device offers.
fn create_device(
    instance: &ash::Instance,
    pd: vk::PhysicalDevice,
    family: u32,
    optional: Optional,
) -> ash::Device {
    let priorities = [1.0f32];
    let queues = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(family)
        .queue_priorities(&priorities)];
    let core = vk::PhysicalDeviceFeatures::default()
        .independent_blend(true)
        .pipeline_statistics_query(optional.pipeline_statistics)
        .fragment_stores_and_atomics(optional.fragment_stores)
        .shader_storage_image_extended_formats(optional.storage_r16);
    let mut v12 = vk::PhysicalDeviceVulkan12Features::default()
        .timeline_semaphore(true)
        .host_query_reset(true)
        .buffer_device_address(optional.ray_query);
    let mut v13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true)
        .shader_demote_to_helper_invocation(true);
    let mut structures =
        vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default().acceleration_structure(true);
    let mut query = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
    let mut extensions = Vec::new();
    if optional.calibrated_timestamps {
        extensions.push(ext::calibrated_timestamps::NAME.as_ptr());
    }
    if optional.ray_query {
        extensions.extend([
            khr::ray_query::NAME.as_ptr(),
            khr::acceleration_structure::NAME.as_ptr(),
            khr::deferred_host_operations::NAME.as_ptr(),
        ]);
    }
    let mut info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queues)
        .enabled_extension_names(&extensions)
        .enabled_features(&core)
        .push_next(&mut v12)
        .push_next(&mut v13);
    if optional.ray_query {
        info = info.push_next(&mut structures).push_next(&mut query);
    }
    // SAFETY: the create info and everything it points to live across the call.
    unsafe { instance.create_device(pd, &info, None) }.expect("the engine's vkCreateDevice")
}

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;

/// One frame of the default scene from its default camera, read back.
fn default_frame(ctx: &Arc<Context>) -> Vec<u8> {
    let opts = RenderOptions::default().with_size(WIDTH, HEIGHT);
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let hf = default_heightfield();
    let mut renderer = Renderer::new(ctx, &scene, Some(&hf), &opts).expect("prepares");
    let frame = renderer
        .draw(&FrameRequest::new(renderer.default_camera()))
        .expect("draws");
    frame.rgba.expect("read back")
}

#[test]
fn relief_renders_on_an_engines_device_and_leaves_it_alive() {
    let _serial = one_at_a_time();
    let test = "relief_renders_on_an_engines_device";
    let Some(engine) = Engine::new(test) else {
        return;
    };
    // SAFETY: the engine enabled what relief requires and what `external` says it enabled; its
    // instance and device outlive the context (dropped below, before `finish`), and nothing
    // else uses the queue.
    let ctx = unsafe {
        Context::from_external(
            engine.external(engine.family, 0),
            &ContextOptions::default(),
        )
    }
    .expect("relief takes the engine's device");
    assert!(ctx.is_external());
    assert!(
        !ctx.validation_enabled(),
        "relief has no messenger of its own here"
    );
    assert_eq!(ctx.info().ray_query, engine.optional.ray_query);
    let external = default_frame(&ctx);
    assert_eq!(ctx.messages().errors(), 0);
    assert_eq!(
        Arc::strong_count(&ctx),
        1,
        "the renderer let go of the context"
    );
    drop(ctx);
    engine.use_device();

    let own =
        Context::new(&ContextOptions::default().with_device_filter(Some(engine.name.clone())))
            .expect("relief's own context on the same device");
    let reference = default_frame(&own);
    common::assert_no_validation_errors(&own);
    drop(own);

    assert_eq!(external.len(), (WIDTH * HEIGHT * 4) as usize);
    let first = &external[..4];
    assert!(
        external.chunks_exact(4).any(|p| p != first),
        "the frame on the engine's device is one flat colour"
    );
    let (mean, max, _) = common::golden::compare(&external, &reference);
    assert!(
        mean < 0.5,
        "the engine's device and relief's own drew different frames (mean {mean:.3}, max {max})"
    );
    let validation = engine.validation;
    let errors = engine.finish();
    assert!(
        errors.is_empty(),
        "the engine's messenger counted validation errors (validation {validation}):\n{}",
        errors.join("\n")
    );
}

#[test]
fn a_queue_or_physical_device_the_engine_lacks_is_a_clear_error() {
    let _serial = one_at_a_time();
    let Some(engine) = Engine::new("a_queue_or_physical_device_the_engine_lacks") else {
        return;
    };
    let cases = [
        (engine.family + 40, 0, "queue_family is"),
        (engine.family, 40, "queue_index is 40"),
    ];
    for (family, queue, said) in cases {
        // SAFETY: as the test above, but relief refuses before it uses the device.
        let made = unsafe {
            Context::from_external(engine.external(family, queue), &ContextOptions::default())
        };
        match made {
            Err(VkError::Invalid(why)) => assert!(why.contains(said), "{why}"),
            Err(e) => panic!("family {family}, queue {queue}: another error: {e}"),
            Ok(_) => panic!("family {family}, queue {queue}: relief took a queue the device lacks"),
        }
    }
    let mut stranger = engine.external(engine.family, 0);
    stranger.physical = vk::PhysicalDevice::null();
    // SAFETY: as above; relief asks the instance for its devices and stops there.
    let made = unsafe { Context::from_external(stranger, &ContextOptions::default()) };
    match made {
        Err(VkError::Invalid(why)) => assert!(why.contains("physical"), "{why}"),
        Err(e) => panic!("a physical device not of the instance: another error: {e}"),
        Ok(_) => panic!("relief took a physical device not of the instance"),
    }
    engine.use_device();
    let errors = engine.finish();
    assert!(
        errors.is_empty(),
        "validation errors:\n{}",
        errors.join("\n")
    );
}

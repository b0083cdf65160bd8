//! Vulkan instance, device, queue and memory allocator, owned together.
//!
//! Every [`crate::Renderer`] and viewer owns its own [`Context`]; nothing is
//! global, so any number of them can live in parallel threads.

use std::ffi::{CStr, CString, c_char, c_void};
use std::mem::ManuallyDrop;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use ash::{ext, khr, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::error::{Result, VkError, VkResultExt};

/// Environment variable that turns the Khronos validation layer on (`1`).
pub const VALIDATION_ENV: &str = "SUBDIV_VK_VALIDATION";
/// When `1`, [`Validation::IfAvailable`] requires the layer: a test harness that has made sure
/// the layer is installed (`cargo xtask test`) sets it, so that no test runs unvalidated.
pub const REQUIRE_VALIDATION_ENV: &str = "SUBDIV_VK_REQUIRE_VALIDATION";
/// Environment variable with a substring of the device name to prefer.
pub const DEVICE_ENV: &str = "SUBDIV_VK_DEVICE";

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// When to enable the Khronos validation layer (`VK_LAYER_KHRONOS_validation`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Validation {
    /// Never.
    Off,
    /// When the environment variable [`VALIDATION_ENV`] is `1`; then the layer must be installed.
    #[default]
    FromEnv,
    /// Whenever the layer is installed (what the crate's tests use); with the environment
    /// variable [`REQUIRE_VALIDATION_ENV`] set to `1`, as [`Validation::Required`].
    IfAvailable,
    /// Always; an error if the layer is missing.
    Required,
}

/// How to set up Vulkan for a [`crate::Renderer`] or the [`crate::viewer`].
#[derive(Clone, Debug, Default)]
pub struct ContextOptions {
    /// Validation layer policy.
    pub validation: Validation,
    /// Open this Vulkan loader library instead of the system's `libvulkan.so.1`.
    pub library_path: Option<PathBuf>,
}

/// Messages reported by the validation layer (warnings and errors), shared
/// with the debug messenger callback. Clone it to inspect the messages after
/// the renderer has been dropped (destruction can report leaks, too).
#[derive(Clone, Debug, Default)]
pub struct ValidationLog(Arc<Mutex<Vec<String>>>);

impl ValidationLog {
    /// A copy of all messages so far.
    pub fn messages(&self) -> Vec<String> {
        match self.0.lock() {
            Ok(v) => v.clone(),
            Err(poisoned) => poisoned.into_inner().clone(),
        }
    }

    /// Removes and returns all messages so far.
    pub fn take(&self) -> Vec<String> {
        match self.0.lock() {
            Ok(mut v) => std::mem::take(&mut *v),
            Err(poisoned) => std::mem::take(&mut *poisoned.into_inner()),
        }
    }
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user.is_null() {
        return vk::FALSE;
    }
    // SAFETY: `user` is the `Mutex<Vec<String>>` inside the context's
    // `ValidationLog` Arc, which outlives the messenger; `data` comes from the layer.
    let (log, message) = unsafe {
        let log = &*(user as *const Mutex<Vec<String>>);
        let message = if (*data).p_message.is_null() {
            String::from("(no message)")
        } else {
            CStr::from_ptr((*data).p_message)
                .to_string_lossy()
                .into_owned()
        };
        (log, message)
    };
    let text = format!("[{severity:?} {types:?}] {message}");
    // Printed by the program's logger (the CLI: `warning: subdiv-vk validation: ...`).
    log::warn!("subdiv-vk validation: {text}");
    match log.lock() {
        Ok(mut v) => v.push(text),
        Err(poisoned) => poisoned.into_inner().push(text),
    }
    vk::FALSE
}

/// A surface to present to, created from the instance (viewer only).
pub(crate) type SurfaceFactory<'a> =
    &'a dyn Fn(&ash::Entry, &ash::Instance) -> Result<vk::SurfaceKHR>;

/// Instance + device + queue + allocator. Destroyed in the right order on drop.
pub(crate) struct Context {
    pub(crate) entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    debug: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    log: ValidationLog,
    pub(crate) surface: Option<(khr::surface::Instance, vk::SurfaceKHR)>,
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) device: ash::Device,
    pub(crate) queue: vk::Queue,
    pub(crate) queue_family: u32,
    allocator: ManuallyDrop<Allocator>,
    pub(crate) device_name: String,
    pub(crate) limits: vk::PhysicalDeviceLimits,
    pub(crate) wide_lines: bool,
    pub(crate) depth_format: vk::Format,
    /// Sample counts the colour and the depth targets both support.
    pub(crate) sample_counts: vk::SampleCountFlags,
}

fn layer_available(entry: &ash::Entry, name: &CStr) -> Result<bool> {
    // SAFETY: `entry` holds a loaded Vulkan library; enumerating layers needs no
    // instance and has no other preconditions.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }
        .call("vkEnumerateInstanceLayerProperties")?;
    Ok(layers
        .iter()
        .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == name)))
}

impl Context {
    /// Loads Vulkan, creates an instance and a device with a graphics queue.
    ///
    /// `instance_extensions` are added to the instance (surface extensions for
    /// the viewer); `surface` creates a surface the chosen queue must present to.
    pub(crate) fn new(
        options: &ContextOptions,
        instance_extensions: &[*const c_char],
        surface: Option<SurfaceFactory<'_>>,
    ) -> Result<Self> {
        let entry = load_entry(options)?;
        let want_validation = validation_wanted(&entry, options.validation)?;
        let log = ValidationLog::default();
        let mut messenger_info = messenger_info(&log);
        let instance = create_instance(
            &entry,
            instance_extensions,
            want_validation,
            &mut messenger_info,
        )?;

        // From here on, a partially built context is cleaned up by `Partial`.
        let mut partial = Partial::default();
        partial.instance = Some(instance.clone());
        if want_validation {
            let du = ext::debug_utils::Instance::new(&entry, &instance);
            // SAFETY: the instance is live and was created with debug_utils
            // enabled; the callback's user data is the log's mutex, kept alive
            // by `log`, which the context owns until after the messenger is gone.
            let messenger = unsafe { du.create_debug_utils_messenger(&messenger_info, None) }
                .call("vkCreateDebugUtilsMessengerEXT")?;
            partial.debug = Some((du, messenger));
        }
        if let Some(factory) = surface {
            let raw = factory(&entry, &instance)?;
            partial.surface = Some((khr::surface::Instance::new(&entry, &instance), raw));
        }

        let chosen = pick_device(&instance, partial.surface.as_ref())?;
        let device = create_device(&instance, &chosen, partial.surface.is_some())?;
        partial.device = Some(device.clone());
        // SAFETY: the device was created with one queue of `chosen.queue_family`,
        // so queue index 0 of that family exists.
        let queue = unsafe { device.get_device_queue(chosen.queue_family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device: chosen.physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })?;
        let depth_format = pick_depth_format(&instance, chosen.physical);
        // Success: hand the objects over to the context instead of destroying them.
        let debug = partial.debug.take();
        let surface = partial.surface.take();
        partial.device = None;
        partial.instance = None;
        drop(partial);
        log::debug!(
            "Vulkan device {} (validation {})",
            chosen.name,
            if debug.is_some() { "on" } else { "off" }
        );
        Ok(Context {
            entry,
            instance,
            debug,
            log,
            surface,
            physical: chosen.physical,
            device,
            queue,
            queue_family: chosen.queue_family,
            allocator: ManuallyDrop::new(allocator),
            device_name: chosen.name,
            limits: chosen.limits,
            wide_lines: chosen.wide_lines,
            depth_format,
            sample_counts: chosen.limits.framebuffer_color_sample_counts
                & chosen.limits.framebuffer_depth_sample_counts,
        })
    }

    /// The memory allocator.
    pub(crate) fn allocator(&mut self) -> &mut Allocator {
        &mut self.allocator
    }

    /// The validation messages collected so far (empty when validation is off).
    pub fn validation_log(&self) -> ValidationLog {
        self.log.clone()
    }

    /// Whether the validation layer is active.
    pub fn validation_enabled(&self) -> bool {
        self.debug.is_some()
    }

    /// Name of the physical device, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub fn device_name(&self) -> &str {
        &self.device_name
    }
}

/// Opens the Vulkan loader library (the system's, or `options.library_path`).
fn load_entry(options: &ContextOptions) -> Result<ash::Entry> {
    // SAFETY: loading runs the library's initialisers and trusts it to be a
    // conforming Vulkan loader: the system's `libvulkan.so.1` is one, and
    // `library_path` is documented as a Vulkan loader to open instead.
    unsafe {
        match &options.library_path {
            Some(path) => ash::Entry::load_from(path),
            None => ash::Entry::load(),
        }
    }
    .map_err(|e| VkError::LoaderMissing {
        detail: e.to_string(),
    })
}

/// Whether to enable the validation layer under `policy`; an error when the
/// policy requires a layer that is not installed.
fn validation_wanted(entry: &ash::Entry, policy: Validation) -> Result<bool> {
    Ok(match policy {
        Validation::Off => false,
        Validation::FromEnv => {
            let on = std::env::var(VALIDATION_ENV).is_ok_and(|v| v == "1");
            if on && !layer_available(entry, VALIDATION_LAYER)? {
                return Err(VkError::ValidationLayerMissing);
            }
            on
        }
        Validation::IfAvailable if std::env::var(REQUIRE_VALIDATION_ENV).as_deref() != Ok("1") => {
            layer_available(entry, VALIDATION_LAYER)?
        }
        Validation::IfAvailable | Validation::Required => {
            if !layer_available(entry, VALIDATION_LAYER)? {
                return Err(VkError::ValidationLayerMissing);
            }
            true
        }
    })
}

/// The debug messenger (warnings and errors into `log`), also chained into
/// instance creation so that creation itself is validated.
fn messenger_info(log: &ValidationLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    let user_data = Arc::as_ptr(&log.0) as *mut c_void;
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(debug_callback))
        .user_data(user_data)
}

/// A Vulkan 1.3 instance with `instance_extensions`, plus debug_utils and the
/// validation layer when `validation`.
fn create_instance(
    entry: &ash::Entry,
    instance_extensions: &[*const c_char],
    validation: bool,
    messenger_info: &mut vk::DebugUtilsMessengerCreateInfoEXT<'static>,
) -> Result<ash::Instance> {
    let app_name = CString::from(c"subdiv");
    let app_info = vk::ApplicationInfo::default()
        .application_name(&app_name)
        .application_version(1)
        .engine_name(&app_name)
        .engine_version(1)
        .api_version(vk::API_VERSION_1_3);
    let mut extensions: Vec<*const c_char> = instance_extensions.to_vec();
    let mut layers: Vec<*const c_char> = Vec::new();
    if validation {
        extensions.push(ext::debug_utils::NAME.as_ptr());
        layers.push(VALIDATION_LAYER.as_ptr());
    }
    let mut create_info = vk::InstanceCreateInfo::default()
        .application_info(&app_info)
        .enabled_extension_names(&extensions)
        .enabled_layer_names(&layers);
    if validation {
        create_info = create_info.push_next(messenger_info);
    }
    // SAFETY: every pointer in `create_info` (names, extension and layer
    // strings, the chained messenger info) lives until the call returns; the
    // extension names are NUL-terminated static strings.
    unsafe { entry.create_instance(&create_info, None) }.map_err(|result| match result {
        vk::Result::ERROR_INCOMPATIBLE_DRIVER | vk::Result::ERROR_INITIALIZATION_FAILED => {
            VkError::NoDriver {
                detail: format!("vkCreateInstance: {result}"),
            }
        }
        result => VkError::Vulkan {
            call: "vkCreateInstance",
            result,
        },
    })
}

/// A device with one queue of `chosen.queue_family`, dynamic rendering and
/// synchronization2, and the swapchain extension when presenting.
fn create_device(instance: &ash::Instance, chosen: &Chosen, present: bool) -> Result<ash::Device> {
    let priorities = [1.0f32];
    let queue_infos = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(chosen.queue_family)
        .queue_priorities(&priorities)];
    let features = vk::PhysicalDeviceFeatures::default()
        .wide_lines(chosen.wide_lines)
        .independent_blend(true);
    let mut features13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true);
    let mut device_extensions: Vec<*const c_char> = Vec::new();
    if present {
        device_extensions.push(khr::swapchain::NAME.as_ptr());
    }
    let device_info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_infos)
        .enabled_features(&features)
        .enabled_extension_names(&device_extensions)
        .push_next(&mut features13);
    // SAFETY: `chosen.physical` was enumerated from this instance and supports
    // every requested feature (checked by `pick_device`); the create info and
    // its chain live through the call.
    unsafe { instance.create_device(chosen.physical, &device_info, None) }.call("vkCreateDevice")
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: everything created from this device has been destroyed by its
        // owners before the context (they hold the context by value and destroy
        // their objects in their own Drop first); the allocator goes before the device.
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((loader, surface)) = self.surface.take() {
                loader.destroy_surface(surface, None);
            }
            if let Some((du, messenger)) = self.debug.take() {
                du.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
        // Keep the loader library loaded until after the instance is gone.
        let _ = &self.entry;
    }
}

/// Cleans up a half-constructed context when `Context::new` fails midway.
#[derive(Default)]
struct Partial {
    instance: Option<ash::Instance>,
    debug: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    surface: Option<(khr::surface::Instance, vk::SurfaceKHR)>,
    device: Option<ash::Device>,
}

impl Drop for Partial {
    fn drop(&mut self) {
        // SAFETY: each object was created from the handles stored next to it and
        // is owned by this guard alone (nothing was submitted to the device yet);
        // children go before parents: device, surface, messenger, instance.
        unsafe {
            if let Some(device) = self.device.take() {
                device.destroy_device(None);
            }
            if let Some((loader, surface)) = self.surface.take() {
                loader.destroy_surface(surface, None);
            }
            if let Some((du, messenger)) = self.debug.take() {
                du.destroy_debug_utils_messenger(messenger, None);
            }
            if let Some(instance) = self.instance.take() {
                instance.destroy_instance(None);
            }
        }
    }
}

struct Chosen {
    physical: vk::PhysicalDevice,
    queue_family: u32,
    name: String,
    limits: vk::PhysicalDeviceLimits,
    wide_lines: bool,
}

fn pick_device(
    instance: &ash::Instance,
    surface: Option<&(khr::surface::Instance, vk::SurfaceKHR)>,
) -> Result<Chosen> {
    // SAFETY: the instance is live; enumeration has no other preconditions.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.map_err(|result| match result {
            vk::Result::ERROR_INITIALIZATION_FAILED => VkError::NoDriver {
                detail: format!("vkEnumeratePhysicalDevices: {result}"),
            },
            result => VkError::Vulkan {
                call: "vkEnumeratePhysicalDevices",
                result,
            },
        })?;
    if devices.is_empty() {
        return Err(VkError::NoDriver {
            detail: "no physical devices".into(),
        });
    }
    let preferred = std::env::var(DEVICE_ENV).ok().filter(|s| !s.is_empty());
    let mut found = Vec::new();
    let mut best: Option<(u32, Chosen)> = None;
    for physical in devices {
        // SAFETY: `physical` was just enumerated from this live instance.
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let name = props
            .device_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|_| String::from("(unnamed)"));
        let version = props.api_version;
        found.push(format!(
            "{name} (Vulkan {}.{}.{})",
            vk::api_version_major(version),
            vk::api_version_minor(version),
            vk::api_version_patch(version)
        ));
        let Some((queue_family, wide_lines)) = suitable(instance, physical, version, surface)?
        else {
            continue;
        };
        let mut score = match props.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => 4,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 3,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            _ => 1,
        };
        if preferred.as_deref().is_some_and(|p| name.contains(p)) {
            score += 100;
        }
        if best.as_ref().is_none_or(|(s, _)| score > *s) {
            best = Some((
                score,
                Chosen {
                    physical,
                    queue_family,
                    name,
                    limits: props.limits,
                    wide_lines,
                },
            ));
        }
    }
    best.map(|(_, c)| c)
        .ok_or_else(|| VkError::NoSuitableDevice {
            found: found.join(", "),
        })
}

/// `Some((queue family, wide lines))` if `physical` has Vulkan 1.3 with
/// dynamic rendering, synchronization2 and independent blend, and a graphics
/// queue family (that can present to `surface`, if given).
fn suitable(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    version: u32,
    surface: Option<&(khr::surface::Instance, vk::SurfaceKHR)>,
) -> Result<Option<(u32, bool)>> {
    if vk::api_version_major(version) < 1
        || (vk::api_version_major(version) == 1 && vk::api_version_minor(version) < 3)
    {
        return Ok(None);
    }
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f13);
    // SAFETY: `physical` comes from this live instance, which supports Vulkan
    // 1.3 (so vkGetPhysicalDeviceFeatures2 exists); the chain lives through the call.
    unsafe { instance.get_physical_device_features2(physical, &mut f2) };
    let wide_lines = f2.features.wide_lines == vk::TRUE;
    let independent_blend = f2.features.independent_blend == vk::TRUE;
    if f13.dynamic_rendering != vk::TRUE || f13.synchronization2 != vk::TRUE || !independent_blend {
        return Ok(None);
    }
    Ok(queue_family(instance, physical, surface)?.map(|family| (family, wide_lines)))
}

/// The first graphics queue family of `physical` (that can present to
/// `surface`, if given).
fn queue_family(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    surface: Option<&(khr::surface::Instance, vk::SurfaceKHR)>,
) -> Result<Option<u32>> {
    // SAFETY: `physical` comes from this live instance.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    for (i, f) in families.iter().enumerate() {
        let Ok(i) = u32::try_from(i) else { continue };
        if !f.queue_flags.contains(vk::QueueFlags::GRAPHICS) {
            continue;
        }
        if let Some((loader, raw)) = surface {
            // SAFETY: the surface and the physical device both come from this
            // live instance, and `i` is one of the device's queue families.
            let ok = unsafe { loader.get_physical_device_surface_support(physical, i, *raw) }
                .call("vkGetPhysicalDeviceSurfaceSupportKHR")?;
            if !ok {
                continue;
            }
        }
        return Ok(Some(i));
    }
    Ok(None)
}

fn pick_depth_format(instance: &ash::Instance, physical: vk::PhysicalDevice) -> vk::Format {
    for format in [vk::Format::D32_SFLOAT, vk::Format::X8_D24_UNORM_PACK32] {
        // SAFETY: `physical` was enumerated from this live instance; querying
        // format properties has no other preconditions.
        let props = unsafe { instance.get_physical_device_format_properties(physical, format) };
        if props
            .optimal_tiling_features
            .contains(vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT)
        {
            return format;
        }
    }
    // Mandatory for every Vulkan implementation.
    vk::Format::D16_UNORM
}

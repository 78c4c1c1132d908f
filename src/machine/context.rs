//! Instance, device choice, validation and the memory allocator: the Vulkan objects
//! every other machine object depends on. Shared through an `Arc` so that images and
//! buffers can destroy themselves in `Drop`.

use crate::memory::Gather;
use std::{
    ffi::{c_void, CStr},
    mem::ManuallyDrop,
    path::PathBuf,
    sync::{Mutex, OnceLock},
};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::profile::Profiler;
use crate::error::{Error, Result, VkContext};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How the machine picks its device.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum DeviceChoice {
    /// A GPU if one is present, otherwise lavapipe.
    #[default]
    Auto,
    /// Mesa's software Vulkan device, lavapipe (`lavapipe`, `llvmpipe`).
    Lavapipe,
    /// `cpu`: no Vulkan device; algorithms with a path on the host run it, and
    /// a machine refuses it.
    Cpu,
    /// A hardware GPU; an error if there is none.
    Gpu,
    /// The device with this index in enumeration order.
    Index(usize),
    /// The first device whose name contains this text (case-insensitive).
    Name(String),
}

/// Whether the machine shows a GPU to Vulkan drivers: a DRM render node
/// (Mesa's and AMD's drivers), NVIDIA's device files, or WSL's. Without one,
/// the only Vulkan device is a software rasterizer.
pub fn has_gpu() -> bool {
    let render_node = std::fs::read_dir("/dev/dri").is_ok_and(|entries| {
        entries
            .flatten()
            .any(|e| e.file_name().to_string_lossy().starts_with("renderD"))
    });
    render_node
        || ["/dev/nvidia0", "/dev/nvidiactl", "/dev/dxg"]
            .iter()
            .any(|p| std::path::Path::new(p).exists())
}

/// The choice as the user wrote it: `gpu`, `2`, `NVIDIA`, ...
impl std::fmt::Display for DeviceChoice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Auto => f.write_str("auto"),
            Self::Lavapipe => f.write_str("lavapipe"),
            Self::Cpu => f.write_str("cpu"),
            Self::Gpu => f.write_str("gpu"),
            Self::Index(i) => write!(f, "{i}"),
            Self::Name(name) => f.write_str(name),
        }
    }
}

impl DeviceChoice {
    /// Reads `PIXGEO_DEVICE`: `auto`, `lavapipe`, `gpu`, an index, or part of a
    /// device name (or `cpu`, which names no Vulkan device).
    pub fn from_env() -> Self {
        match std::env::var("PIXGEO_DEVICE") {
            Ok(v) => Self::parse(&v),
            Err(_) => Self::Auto,
        }
    }

    /// Parses the same forms as `PIXGEO_DEVICE`.
    pub fn parse(text: &str) -> Self {
        let t = text.trim();
        match t.to_ascii_lowercase().as_str() {
            "" | "auto" => Self::Auto,
            "lavapipe" | "llvmpipe" => Self::Lavapipe,
            "cpu" => Self::Cpu,
            "gpu" => Self::Gpu,
            _ => t
                .parse()
                .map(Self::Index)
                .unwrap_or_else(|_| Self::Name(t.to_string())),
        }
    }
}

/// Options for creating a machine.
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct MachineOptions {
    pub device: DeviceChoice,
    /// Enable the Khronos validation layer; every message becomes an error.
    pub validation: bool,
    /// The folder that keeps compiled pipelines between processes; `None`
    /// keeps them for this machine's life only.
    pub pipeline_cache: Option<PathBuf>,
    /// Times every pass on the device and every run on the host into this
    /// profiler's timeline; `None` times nothing (passes are labelled always).
    pub profiler: Option<Profiler>,
    /// Enable none of the optional device features (logic ops, float64,
    /// fragment stores, 64-bit atomics), as on a device that lacks them: the
    /// programs needing them are refused and the algorithms take their other
    /// routes.
    pub core_features_only: bool,
}

impl MachineOptions {
    /// `PIXGEO_DEVICE`, `PIXGEO_VALIDATION=1` and `PIXGEO_CACHE_DIR` from the
    /// environment; without `PIXGEO_CACHE_DIR` pipelines are kept in
    /// `$XDG_CACHE_HOME/pixgeo` or `~/.cache/pixgeo`, and an empty one keeps none.
    pub fn from_env() -> Self {
        Self {
            device: DeviceChoice::from_env(),
            validation: std::env::var("PIXGEO_VALIDATION").is_ok_and(|v| v == "1"),
            pipeline_cache: user_cache_dir(),
            profiler: None,
            core_features_only: false,
        }
    }

    pub fn device(self, device: DeviceChoice) -> Self {
        Self { device, ..self }
    }

    pub fn validation(self, validation: bool) -> Self {
        Self { validation, ..self }
    }

    pub fn pipeline_cache(self, folder: Option<PathBuf>) -> Self {
        Self {
            pipeline_cache: folder,
            ..self
        }
    }

    pub fn profiler(self, profiler: Option<Profiler>) -> Self {
        Self { profiler, ..self }
    }

    pub fn core_features_only(self, core_features_only: bool) -> Self {
        Self {
            core_features_only,
            ..self
        }
    }
}

/// `PIXGEO_CACHE_DIR`, else the user's cache folder; `None` when it is set
/// empty or no home is known.
fn user_cache_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("PIXGEO_CACHE_DIR") {
        return (!dir.is_empty()).then(|| PathBuf::from(dir));
    }
    let base = std::env::var_os("XDG_CACHE_HOME")
        .filter(|d| !d.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("pixgeo"))
}

/// The shared Vulkan context. Dropped last: after every image, buffer and pipeline.
pub(crate) struct Context {
    pub instance: ash::Instance,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Boxed so its address is stable for the messenger's user-data pointer.
    messages: Box<Mutex<Vec<String>>>,
    /// Labels and object names, where the loader offers debug utils.
    debug_utils: Option<ash::ext::debug_utils::Device>,
    /// Nanoseconds per timestamp tick of the queue; `None` where its queue
    /// writes no timestamps.
    pub timestamp_period: Option<f32>,
    /// The valid bits of a timestamp.
    pub timestamp_mask: u64,
    pub device: ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub properties: vk::PhysicalDeviceProperties,
    pub device_name: String,
    /// Fragment shaders may write storage buffers.
    pub fragment_stores: bool,
    /// Fragment shaders may do 64-bit atomics on storage buffers.
    pub fragment_atomics64: bool,
    /// Shaders may compute in double precision (the area programs need it).
    pub float64: bool,
    /// Colour targets may be combined with logic operations.
    pub logic_op: bool,
    /// Shaders' buffer accesses are kept within the bound ranges.
    pub robust_buffer_access: bool,
    pub allocator: ManuallyDrop<Mutex<Allocator>>,
}

impl Context {
    pub fn new(options: &MachineOptions) -> Result<Self> {
        let entry = vulkan_loader()?;

        let mut layers = Vec::new();
        let mut extensions = Vec::new();
        if options.validation {
            // SAFETY: plain enumeration call on a valid entry.
            let available = unsafe { entry.enumerate_instance_layer_properties() }
                .vk("vkEnumerateInstanceLayerProperties")?;
            let found = available
                .iter()
                .any(|l| l.layer_name_as_c_str().ok() == Some(VALIDATION_LAYER));
            if !found {
                return Err(Error::NoVulkan(
                    "PIXGEO_VALIDATION=1 needs the Khronos validation layer (Debian package vulkan-validationlayers)".into(),
                ));
            }
            layers.push(VALIDATION_LAYER.as_ptr());
        }
        // Labels and object names for debuggers and profilers, and the
        // validation layer's messages: the loader or the layer offers them.
        // SAFETY: plain enumeration call on a valid entry.
        let debug_utils = options.validation
            || unsafe { entry.enumerate_instance_extension_properties(None) }
                .vk("vkEnumerateInstanceExtensionProperties")?
                .iter()
                .any(|e| e.extension_name_as_c_str().ok() == Some(ash::ext::debug_utils::NAME));
        if debug_utils {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
        }

        let app = vk::ApplicationInfo::default()
            .application_name(c"pixgeo")
            .engine_name(c"pixgeo")
            .api_version(vk::API_VERSION_1_3);
        let create = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        // SAFETY: the create info and the strings it points to outlive the call.
        let instance = unsafe { entry.create_instance(&create, None) }.map_err(|e| match e {
            vk::Result::ERROR_INCOMPATIBLE_DRIVER => {
                Error::NoVulkan("the loader found no Vulkan 1.3 driver".into())
            }
            result => Error::vulkan("vkCreateInstance", result),
        })?;
        keep_loaded(entry, &create, options.validation);
        // From here on, `partial` destroys the instance if a later step fails.
        let mut partial = Partial {
            instance: Some(&instance),
            debug: None,
            device: None,
        };

        let messages: Box<Mutex<Vec<String>>> = Box::default();
        let debug = if options.validation {
            let loader = ash::ext::debug_utils::Instance::new(entry, &instance);
            let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(
                    vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                        | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
                )
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                        | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                )
                .pfn_user_callback(Some(collect_message))
                .user_data(&*messages as *const Mutex<Vec<String>> as *mut c_void);
            // SAFETY: `messages` is boxed and lives in the context as long as the
            // messenger, which is destroyed first in `Drop`.
            let messenger = unsafe { loader.create_debug_utils_messenger(&info, None) }
                .vk("vkCreateDebugUtilsMessengerEXT")?;
            partial.debug = Some((loader.clone(), messenger));
            Some((loader, messenger))
        } else {
            None
        };

        let (physical_device, properties) = choose_device(&instance, &options.device)?;
        let device_name = properties
            .device_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();

        // SAFETY: valid physical device from this instance.
        let families =
            unsafe { instance.get_physical_device_queue_family_properties(physical_device) };
        let queue_family = families
            .iter()
            .position(|f| {
                f.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            })
            .ok_or_else(|| {
                Error::NoDevice(format!("{device_name} has no graphics+compute queue"))
            })? as u32;
        let timestamp_bits = families[queue_family as usize].timestamp_valid_bits;
        let timestamp_period = (timestamp_bits > 0 && properties.limits.timestamp_period > 0.0)
            .then_some(properties.limits.timestamp_period);
        let timestamp_mask = u64::MAX >> (64 - timestamp_bits.clamp(1, 64));

        let mut supported13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut supported12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut supported = vk::PhysicalDeviceFeatures2::default()
            .push_next(&mut supported13)
            .push_next(&mut supported12);
        // SAFETY: valid physical device; the chained struct outlives the call.
        unsafe { instance.get_physical_device_features2(physical_device, &mut supported) };
        // The optional features, unless the options ask for the core alone.
        let optional = !options.core_features_only;
        let logic_op = optional && supported.features.logic_op == vk::TRUE;
        let float64 = optional && supported.features.shader_float64 == vk::TRUE;
        // Per-pixel lists: fragments store them in storage buffers, and some
        // insert 64-bit keys with atomic min.
        let fragment_stores =
            optional && supported.features.fragment_stores_and_atomics == vk::TRUE;
        // A shader's reach past a buffer's end stays inside it (reads give
        // zeros or values of the buffer, writes are dropped), so that no
        // draw or dispatch from safe code touches memory it was not given;
        // not optional, but where the device offers it.
        let robust_buffer_access = supported.features.robust_buffer_access == vk::TRUE;
        let fragment_atomics64 = fragment_stores
            && supported.features.shader_int64 == vk::TRUE
            && supported12.shader_buffer_int64_atomics == vk::TRUE;
        if supported13.dynamic_rendering == vk::FALSE
            || supported13.synchronization2 == vk::FALSE
            || supported13.maintenance4 == vk::FALSE
        {
            return Err(Error::NoDevice(format!(
                "{device_name} lacks dynamic rendering, synchronization2 or maintenance4"
            )));
        }

        let priorities = [1.0f32];
        let queue_info = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let features = vk::PhysicalDeviceFeatures::default()
            .robust_buffer_access(robust_buffer_access)
            .logic_op(logic_op)
            .independent_blend(true)
            .fragment_stores_and_atomics(fragment_stores)
            .shader_int64(fragment_atomics64)
            .shader_float64(float64);
        let mut features12 = vk::PhysicalDeviceVulkan12Features::default()
            .shader_buffer_int64_atomics(fragment_atomics64);
        // maintenance4 relaxes interface matching: a fragment shader may ignore
        // an output its vertex shader passes to other fragment shaders.
        let mut features13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true)
            .maintenance4(true);
        let create = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_features(&features)
            .push_next(&mut features13)
            .push_next(&mut features12);
        // SAFETY: the create info and its chain outlive the call.
        let device = unsafe { instance.create_device(physical_device, &create, None) }
            .vk("vkCreateDevice")?;
        partial.device = Some(device.clone());
        // SAFETY: queue 0 of a family requested above.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };

        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        })
        .map_err(Error::memory)?;

        let debug_utils =
            debug_utils.then(|| ash::ext::debug_utils::Device::new(&instance, &device));
        std::mem::forget(partial);
        let context = Self {
            instance,
            debug,
            messages,
            debug_utils,
            timestamp_period,
            timestamp_mask,

            device,
            queue,
            queue_family,
            properties,
            device_name,
            fragment_stores,
            fragment_atomics64,
            float64,
            logic_op,
            robust_buffer_access,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
        };
        context.check_validation()?;
        Ok(context)
    }

    /// Returns the validation messages collected since the last check as an error.
    pub(crate) fn check_validation(&self) -> Result<()> {
        let mut messages = self.messages.lock().unwrap_or_else(|e| e.into_inner());
        if messages.is_empty() {
            Ok(())
        } else {
            Err(Error::Validation(std::mem::take(&mut *messages)))
        }
    }

    /// Names `handle` for debuggers and the validation layer's messages.
    pub(crate) fn name_object<H: vk::Handle>(&self, handle: H, name: &str) {
        let (Some(utils), Ok(name)) = (&self.debug_utils, std::ffi::CString::new(name)) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&name);
        // SAFETY: `handle` is a live object of this device; a name that cannot
        // be set only loses a debugging aid.
        let _ = unsafe { utils.set_debug_utils_object_name(&info) };
    }

    /// Opens a labelled region of `cmd` (closed by [`Context::end_label`]).
    pub(crate) fn begin_label(&self, cmd: vk::CommandBuffer, label: &str) {
        if let (Some(utils), Ok(label)) = (&self.debug_utils, std::ffi::CString::new(label)) {
            let info = vk::DebugUtilsLabelEXT::default().label_name(&label);
            // SAFETY: `cmd` is recording; the label outlives the call.
            unsafe { utils.cmd_begin_debug_utils_label(cmd, &info) };
        }
    }

    pub(crate) fn end_label(&self, cmd: vk::CommandBuffer) {
        if let Some(utils) = &self.debug_utils {
            // SAFETY: `cmd` is recording and has a region open (`begin_label`).
            unsafe { utils.cmd_end_debug_utils_label(cmd) };
        }
    }

    /// Marks one command of `cmd` with `label`.
    pub(crate) fn insert_label(&self, cmd: vk::CommandBuffer, label: &str) {
        if let (Some(utils), Ok(label)) = (&self.debug_utils, std::ffi::CString::new(label)) {
            let info = vk::DebugUtilsLabelEXT::default().label_name(&label);
            // SAFETY: `cmd` is recording; the label outlives the call.
            unsafe { utils.cmd_insert_debug_utils_label(cmd, &info) };
        }
    }

    pub(crate) fn allocator(&self) -> std::sync::MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: every object created from this device has been destroyed (they hold
        // an `Arc<Context>`); the allocator frees its memory before the device goes.
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((loader, messenger)) = self.debug.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

/// The Vulkan loader, loaded once and kept for the process's life: NVIDIA's driver
/// refuses new instances (ERROR_INCOMPATIBLE_DRIVER) after being unloaded and
/// loaded again many times, as a loader per machine did.
fn vulkan_loader() -> Result<&'static ash::Entry> {
    static LOADER: OnceLock<std::result::Result<ash::Entry, String>> = OnceLock::new();
    // SAFETY: loading the system's Vulkan loader library; its entry points are
    // only called through ash's typed wrappers, and it is never unloaded.
    LOADER
        .get_or_init(|| unsafe { ash::Entry::load() }.map_err(|e| e.to_string()))
        .as_ref()
        .map_err(|e| Error::NoVulkan(format!("cannot load libvulkan ({e})")))
}

/// Creates, once per process and layer set, an instance that is never destroyed,
/// so the driver's and the layers' libraries stay loaded: NVIDIA's driver with the
/// validation layer refuses new instances (ERROR_INCOMPATIBLE_DRIVER) once they
/// have been unloaded and loaded again a few dozen times.
fn keep_loaded(entry: &ash::Entry, create: &vk::InstanceCreateInfo, validation: bool) {
    static KEPT: [OnceLock<Option<ash::Instance>>; 2] = [OnceLock::new(), OnceLock::new()];
    KEPT[usize::from(validation)].get_or_init(|| {
        // SAFETY: the create info and the strings it points to outlive the call; the
        // instance is kept, unused, until the process ends.
        unsafe { entry.create_instance(create, None) }.ok()
    });
}

/// Destroys what `Context::new` created so far if a later step fails.
struct Partial<'a> {
    instance: Option<&'a ash::Instance>,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    device: Option<ash::Device>,
}

impl Drop for Partial<'_> {
    fn drop(&mut self) {
        // SAFETY: these objects were created in `Context::new` and nothing else uses
        // them once construction has failed.
        unsafe {
            if let Some(device) = self.device.take() {
                device.destroy_device(None);
            }
            if let Some((loader, messenger)) = self.debug.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            if let Some(instance) = self.instance.take() {
                instance.destroy_instance(None);
            }
        }
    }
}

#[expect(clippy::disallowed_methods, reason = "the devices' names")]
fn choose_device(
    instance: &ash::Instance,
    choice: &DeviceChoice,
) -> Result<(vk::PhysicalDevice, vk::PhysicalDeviceProperties)> {
    // SAFETY: valid instance.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    let all: Vec<_> = devices
        .into_iter()
        .map(|d| {
            // SAFETY: `d` was just enumerated from this instance.
            let props = unsafe { instance.get_physical_device_properties(d) };
            (d, props)
        })
        .gather("props")?;
    let name = |p: &vk::PhysicalDeviceProperties| {
        p.device_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let (candidates, older): (Vec<_>, Vec<_>) = all
        .into_iter()
        .partition(|(_, p)| p.api_version >= vk::API_VERSION_1_3);
    if candidates.is_empty() {
        // Drivers too old (Debian 11's lavapipe offers Vulkan 1.0) are named.
        let found: Vec<String> = older
            .iter()
            .map(|(_, p)| {
                let v = p.api_version;
                let (major, minor) = (vk::api_version_major(v), vk::api_version_minor(v));
                format!("{} (Vulkan {major}.{minor})", name(p))
            })
            .gather("device names")?;
        return Err(Error::NoVulkan(if found.is_empty() {
            "no device supports Vulkan 1.3 (install mesa-vulkan-drivers for lavapipe)".into()
        } else {
            format!(
                "no device supports Vulkan 1.3: found only {}; lavapipe needs Mesa 22 or newer, \
                 or use a GPU's driver",
                found.join(", ")
            )
        }));
    }
    let rank = |t: vk::PhysicalDeviceType| match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    };
    let is_gpu = |t: vk::PhysicalDeviceType| rank(t) <= 2;
    let found = match choice {
        DeviceChoice::Auto => candidates.iter().min_by_key(|(_, p)| rank(p.device_type)),
        DeviceChoice::Lavapipe => candidates
            .iter()
            .find(|(_, p)| p.device_type == vk::PhysicalDeviceType::CPU),
        DeviceChoice::Cpu => {
            return Err(Error::NoDevice(
                "device `cpu` names the CPU pixel algorithms, not a Vulkan device, and \
                 only some problems have them; for Mesa's software Vulkan device say \
                 `lavapipe`"
                    .into(),
            ))
        }
        DeviceChoice::Gpu => candidates
            .iter()
            .filter(|(_, p)| is_gpu(p.device_type))
            .min_by_key(|(_, p)| rank(p.device_type)),
        DeviceChoice::Index(i) => candidates.get(*i),
        DeviceChoice::Name(n) => candidates
            .iter()
            .find(|(_, p)| name(p).to_lowercase().contains(&n.to_lowercase())),
    };
    found.copied().ok_or_else(|| {
        let names: Vec<String> = candidates.iter().map(|(_, p)| name(p)).collect();
        Error::NoDevice(format!(
            "device `{choice}` matches none of: {}",
            names.join(", ")
        ))
    })
}

/// Debug-utils callback: stores each message for `Context::check_validation`.
unsafe extern "system" fn collect_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data; `user` is the boxed mutex that
    // the context keeps alive while the messenger exists.
    unsafe {
        let text = if data.is_null() || (*data).p_message.is_null() {
            "(no message)".to_string()
        } else {
            CStr::from_ptr((*data).p_message)
                .to_string_lossy()
                .into_owned()
        };
        if let Some(messages) = (user as *const Mutex<Vec<String>>).as_ref() {
            if let Ok(mut m) = messages.lock() {
                m.push(format!("{severity:?}: {text}"));
            }
        }
    }
    vk::FALSE
}

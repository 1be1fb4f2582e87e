//! Vulkan instance and logical device, with the Khronos validation layer on request (every
//! message it emits is recorded so that tests can fail on any).

use std::ffi::{c_void, CStr, CString, OsString};
use std::sync::{Arc, Mutex, OnceLock};

use ash::vk;

use crate::device_info::{DeviceInfo, DeviceMemory};
use crate::{Error, Result, Traversal, VkContext};

pub(crate) struct Context {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub info: DeviceInfo,
    pub properties: vk::PhysicalDeviceProperties,
    pub timestamp_bits: u32,
    /// With ray queries enabled: the alignment of an acceleration structure build's scratch
    /// memory (`minAccelerationStructureScratchOffsetAlignment`); None without them.
    pub scratch_alignment: Option<u64>,
    debug: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    pub validation_messages: Arc<Mutex<Vec<String>>>,
}

unsafe extern "system" fn on_validation_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if severity.intersects(
        vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
            | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
    ) {
        let messages = &*(user as *const Mutex<Vec<String>>);
        let text = if data.is_null() || (*data).p_message.is_null() {
            "(no message)".to_string()
        } else {
            CStr::from_ptr((*data).p_message)
                .to_string_lossy()
                .into_owned()
        };
        if let Ok(mut m) = messages.lock() {
            m.push(text);
        }
    }
    vk::FALSE
}

fn load_entry() -> Result<ash::Entry> {
    unsafe { ash::Entry::load() }.map_err(|e| Error::Loader(e.to_string()))
}

fn create_instance(entry: &ash::Entry, validation: bool) -> Result<ash::Instance> {
    let app_name = CString::new("platoon").unwrap();
    let app = vk::ApplicationInfo::default()
        .application_name(&app_name)
        .api_version(vk::API_VERSION_1_2);
    let layer = CString::new("VK_LAYER_KHRONOS_validation").unwrap();
    let layers = if validation {
        vec![layer.as_ptr()]
    } else {
        vec![]
    };
    let extensions = if validation {
        vec![ash::ext::debug_utils::NAME.as_ptr()]
    } else {
        vec![]
    };
    if validation {
        let available =
            unsafe { entry.enumerate_instance_layer_properties() }.ctx("enumerating layers")?;
        let found = available.iter().any(|l| {
            l.layer_name_as_c_str()
                .map(|n| n == layer.as_c_str())
                .unwrap_or(false)
        });
        if !found {
            return Err(Error::Loader("validation requested but VK_LAYER_KHRONOS_validation is not installed (vulkan-validationlayers)".into()));
        }
    }
    let info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    unsafe { entry.create_instance(&info, None) }.ctx("creating the Vulkan instance")
}

fn describe(instance: &ash::Instance, index: usize, pd: vk::PhysicalDevice) -> DeviceInfo {
    let api = unsafe { instance.get_physical_device_properties(pd) }.api_version;
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut maintenance3 = vk::PhysicalDeviceMaintenance3Properties::default();
    let mut maintenance4 = vk::PhysicalDeviceMaintenance4Properties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default()
        .push_next(&mut driver)
        .push_next(&mut maintenance3);
    // maxBufferSize is core from Vulkan 1.3; an older device's chain must not name it.
    let has_maintenance4 = api >= vk::API_VERSION_1_3;
    if has_maintenance4 {
        props2 = props2.push_next(&mut maintenance4);
    }
    unsafe { instance.get_physical_device_properties2(pd, &mut props2) };
    let p = props2.properties;
    let heaps = unsafe { instance.get_physical_device_memory_properties(pd) };
    let memory = DeviceMemory::of(
        &heaps,
        maintenance3.max_memory_allocation_size,
        has_maintenance4.then_some(maintenance4.max_buffer_size),
    );
    let name = p
        .device_name_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default();
    let driver_name = driver
        .driver_name_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default();
    let driver_info = driver
        .driver_info_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default();
    let device_type = match p.device_type {
        vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
        vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
        vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
        vk::PhysicalDeviceType::CPU => "CPU",
        _ => "other",
    };
    let v = p.api_version;
    let mesa = mesa_release(&driver_info);
    DeviceInfo {
        index,
        max_storage_buffer_range: p.limits.max_storage_buffer_range as u64,
        max_texel_buffer_elements: p.limits.max_texel_buffer_elements as u64,
        cpu: p.device_type == vk::PhysicalDeviceType::CPU,
        mesa,
        memory,
        ray_queries: crate::ray_query::offered(instance, pd),
        name,
        device_type: device_type.into(),
        driver: format!("{driver_name} {driver_info}").trim().to_string(),
        api_version: format!(
            "{}.{}.{}",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        ),
    }
}

/// The release in a Mesa driver's driverInfo ("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"):
/// lavapipe's driverVersion is 1 whatever the release.
fn mesa_release(driver_info: &str) -> Option<(u32, u32)> {
    let version = driver_info
        .split_whitespace()
        .skip_while(|w| *w != "Mesa")
        .nth(1)?;
    let mut parts = version.split(|c: char| !c.is_ascii_digit());
    Some((parts.next()?.parse().ok()?, parts.next()?.parse().ok()?))
}

/// Every Vulkan device of the machine, in the order `--device` indexes them.
pub fn list_devices() -> Result<Vec<DeviceInfo>> {
    // The loader reads the environment while it creates the instance (see CREATION).
    let _guard = CREATION.lock().unwrap_or_else(|e| e.into_inner());
    let entry = load_entry()?;
    let instance = create_instance(&entry, false)?;
    let pds = unsafe { instance.enumerate_physical_devices() }.ctx("enumerating devices");
    let out = pds.map(|pds| {
        pds.iter()
            .enumerate()
            .map(|(i, &pd)| describe(&instance, i, pd))
            .collect()
    });
    unsafe { instance.destroy_instance(None) };
    out
}

/// Serialises instance and device creation with changes of the environment: LP_NUM_THREADS is
/// process-wide and lavapipe reads it when a device is created, so it is set and read under this
/// lock; and the Vulkan loader reads the environment with C's getenv while it creates an
/// instance, which a setenv on another thread can crash (a test binary's tracers created on
/// five threads at once segfaulted in getenv about one run in ten).
static CREATION: Mutex<()> = Mutex::new(());

/// LP_NUM_THREADS as the process had it before platoon's first device: what a device made
/// without a thread count of its own gets.
static ORIGINAL_THREADS: OnceLock<Option<OsString>> = OnceLock::new();

/// Sets environment variables under the lock instance and device creation hold, so that no
/// other thread's Vulkan loader reads the environment meanwhile (what tests and embedders set
/// before their tracers: VK_DRIVER_FILES...).
pub fn set_environment(vars: &[(&str, &std::ffi::OsStr)]) {
    let _guard = CREATION.lock().unwrap_or_else(|e| e.into_inner());
    for (key, value) in vars {
        // SAFETY: under CREATION, which every creation of an instance or device holds; platoon
        // reads no environment through C meanwhile.
        unsafe { std::env::set_var(key, value) };
    }
}

impl Context {
    /// Whether the device's ray queries are enabled (the context was made for them).
    pub fn ray_queries(&self) -> bool {
        self.scratch_alignment.is_some()
    }

    /// `lavapipe_threads`: llvmpipe worker threads of this context's own thread pool.
    /// `traversal`: the device's ray queries enabled where it resolves to them on the device
    /// for a scene of `triangles` (refused where it asks for them and the device has none).
    pub fn new(
        device_index: usize,
        validation: bool,
        lavapipe_threads: Option<u32>,
        traversal: Traversal,
        triangles: u64,
    ) -> Result<Context> {
        let _guard = CREATION.lock().unwrap_or_else(|e| e.into_inner());
        let original = ORIGINAL_THREADS.get_or_init(|| std::env::var_os("LP_NUM_THREADS"));
        let wanted = match lavapipe_threads {
            Some(t) => Some(OsString::from(t.to_string())),
            None => original.clone(),
        };
        // Changed only where it differs, and left as this creation wants it (the next creation
        // sets its own): a setenv reallocates `environ` under whatever C code of another thread
        // reads it outside this lock (Mesa reads some options lazily), so tracers of one thread
        // count change it once in a process rather than twice per device.
        if std::env::var_os("LP_NUM_THREADS") != wanted {
            // SAFETY: creation is serialised by CREATION; platoon reads no environment meanwhile.
            unsafe {
                match &wanted {
                    Some(v) => std::env::set_var("LP_NUM_THREADS", v),
                    None => std::env::remove_var("LP_NUM_THREADS"),
                }
            }
        }
        Context::create(device_index, validation, traversal, triangles)
    }

    fn create(
        device_index: usize,
        validation: bool,
        traversal: Traversal,
        triangles: u64,
    ) -> Result<Context> {
        let entry = load_entry()?;
        let instance = create_instance(&entry, validation)?;
        let messages = Arc::new(Mutex::new(Vec::new()));
        let debug = if validation {
            let loader = ash::ext::debug_utils::Instance::new(&entry, &instance);
            let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(
                    vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                        | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
                )
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                        | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                        | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                )
                .pfn_user_callback(Some(on_validation_message))
                .user_data(Arc::as_ptr(&messages) as *mut c_void);
            let messenger = unsafe { loader.create_debug_utils_messenger(&info, None) }
                .ctx("creating the debug messenger")?;
            Some((loader, messenger))
        } else {
            None
        };
        let pds = unsafe { instance.enumerate_physical_devices() }.ctx("enumerating devices")?;
        let Some(&physical) = pds.get(device_index) else {
            return Err(Error::NoDevice {
                index: device_index,
                count: pds.len(),
            });
        };
        let info = describe(&instance, device_index, physical);
        let ray_queries = traversal.resolved(&info, triangles) == Traversal::RayQuery;
        let properties = unsafe { instance.get_physical_device_properties(physical) };
        let unsupported = |message: &str| Error::Unsupported {
            device: info.name.clone(),
            message: message.into(),
        };
        if properties.api_version < vk::API_VERSION_1_2 {
            return Err(unsupported("Vulkan 1.2 or newer is required"));
        }
        let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f12);
        unsafe { instance.get_physical_device_features2(physical, &mut f2) };
        let int64 = f2.features.shader_int64;
        if f12.buffer_device_address == vk::FALSE || int64 == vk::FALSE {
            return Err(unsupported(
                "bufferDeviceAddress and shaderInt64 are required",
            ));
        }
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let Some(queue_family) = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
        else {
            return Err(unsupported("no compute queue"));
        };
        let timestamp_bits = families[queue_family].timestamp_valid_bits;
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family as u32)
            .queue_priorities(&priorities)];
        let mut enable12 =
            vk::PhysicalDeviceVulkan12Features::default().buffer_device_address(true);
        let features = vk::PhysicalDeviceFeatures::default().shader_int64(true);
        if ray_queries && !info.ray_queries {
            return Err(unsupported(crate::ray_query::NOT_OFFERED));
        }
        let extensions: Vec<*const std::ffi::c_char> = if ray_queries {
            crate::ray_query::EXTENSIONS
                .iter()
                .map(|n| n.as_ptr())
                .collect()
        } else {
            Vec::new()
        };
        let mut structures = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default()
            .acceleration_structure(true);
        let mut queries = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
        let mut create = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_features(&features)
            .enabled_extension_names(&extensions)
            .push_next(&mut enable12);
        if ray_queries {
            create = create.push_next(&mut structures).push_next(&mut queries);
        }
        let device = unsafe { instance.create_device(physical, &create, None) }
            .ctx("creating the logical device")?;
        let queue = unsafe { device.get_device_queue(queue_family as u32, 0) };
        let scratch_alignment =
            ray_queries.then(|| crate::ray_query::scratch_alignment(&instance, physical));
        Ok(Context {
            scratch_alignment,
            entry,
            instance,
            physical,
            device,
            queue,
            queue_family: queue_family as u32,
            info,
            properties,
            timestamp_bits,
            debug,
            validation_messages: messages,
        })
    }
}

impl Drop for Context {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_device(None);
            if let Some((loader, messenger)) = self.debug.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
        let _ = &self.entry;
    }
}

#[cfg(test)]
mod tests {
    use super::mesa_release;

    #[test]
    fn mesa_releases_are_read_from_the_driver_info() {
        assert_eq!(mesa_release("Mesa 22.3.6 (LLVM 15.0.6)"), Some((22, 3)));
        assert_eq!(
            mesa_release("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"),
            Some((25, 0))
        );
        assert_eq!(
            mesa_release("Mesa 24.2.0-devel (git-1a2b3c)"),
            Some((24, 2))
        );
        assert_eq!(mesa_release("580.159.04"), None);
        assert_eq!(mesa_release("Mesa"), None);
    }
}

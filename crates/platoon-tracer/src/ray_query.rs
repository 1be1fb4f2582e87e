//! The device's own ray tracing (issue 61): whether a device offers ray queries over
//! acceleration structures, which compute kernels can trace with in place of platoon's own
//! traversal. Lavapipe offers them from Mesa 24.1 on (Debian 12's 22.3 does not;
//! `tools/mesa25.sh` fetches bookworm-backports' 25 beside it), GPUs with ray-tracing hardware
//! and their drivers mostly do.

use std::ffi::CStr;

use ash::vk;

/// The device extensions ray queries need on a Vulkan 1.2 device: the queries, the structures
/// they traverse and the deferred host operations the structures' extension requires to be
/// enabled with it.
pub(crate) const EXTENSIONS: [&CStr; 3] = [
    ash::khr::ray_query::NAME,
    ash::khr::acceleration_structure::NAME,
    ash::khr::deferred_host_operations::NAME,
];

/// Whether `pd` offers ray queries: the extensions, and the features `rayQuery` and
/// `accelerationStructure` (an extension may be listed with its feature off).
pub(crate) fn offered(instance: &ash::Instance, pd: vk::PhysicalDevice) -> bool {
    let Ok(listed) = (unsafe { instance.enumerate_device_extension_properties(pd) }) else {
        return false;
    };
    let has = |name: &CStr| {
        listed
            .iter()
            .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
    };
    if !EXTENSIONS.iter().all(|n| has(n)) {
        return false;
    }
    // The features' structures are asked for only where their extensions are listed.
    let mut structures = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut queries = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut features = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut structures)
        .push_next(&mut queries);
    unsafe { instance.get_physical_device_features2(pd, &mut features) };
    structures.acceleration_structure == vk::TRUE && queries.ray_query == vk::TRUE
}

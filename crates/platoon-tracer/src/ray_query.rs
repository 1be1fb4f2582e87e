//! The device's own ray tracing (issue 61): whether a device offers ray queries over
//! acceleration structures, which compute kernels can trace with in place of platoon's own
//! traversal. Lavapipe offers them from Mesa 24.1 on (Debian 12's 22.3 does not;
//! `tools/mesa25.sh` fetches bookworm-backports' 25 beside it), GPUs with ray-tracing hardware
//! and their drivers mostly do.

use std::ffi::CStr;

use ash::vk;

use crate::device_info::DeviceInfo;

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

/// A custom index holds 24 bits: the ray-query traversal takes scenes of fewer triangles (an
/// instance's custom index is its mesh's first triangle).
pub(crate) const MAX_TRIANGLES: u64 = 1 << 24;

/// The kernels' define of the ray-query traversal (`shaders/common/trace.glsl`).
pub(crate) const DEFINE: &str = "TRAVERSAL_RAY_QUERY";

/// Why a device refuses the ray-query traversal.
pub(crate) const NOT_OFFERED: &str = "no ray queries (VK_KHR_ray_query over \
    VK_KHR_acceleration_structure; lavapipe offers them from Mesa 24.1 on, tools/mesa25.sh \
    fetches one beside Debian 12's 22.3): use --traversal own";

/// `minAccelerationStructureScratchOffsetAlignment` of `pd` (at least 1).
pub(crate) fn scratch_alignment(instance: &ash::Instance, pd: vk::PhysicalDevice) -> u64 {
    let mut structures = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut properties = vk::PhysicalDeviceProperties2::default().push_next(&mut structures);
    unsafe { instance.get_physical_device_properties2(pd, &mut properties) };
    (structures.min_acceleration_structure_scratch_offset_alignment as u64).max(1)
}

/// How a tracer's kernels find what a ray hits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Traversal {
    /// The device's choice (`resolved`): platoon's own on CPU devices, where it was measured
    /// faster, and on devices without ray queries; the ray queries on a GPU that offers them.
    #[default]
    Auto,
    /// platoon's own traversal of its BVHs (every device).
    Own,
    /// The device's ray queries over acceleration structures built on it (a device that offers
    /// them; `DeviceInfo::ray_queries`).
    RayQuery,
}

impl Traversal {
    pub const NAMES: [&'static str; 3] = ["auto", "own", "ray-query"];

    pub fn by_name(name: &str) -> Option<Traversal> {
        match name {
            "auto" => Some(Traversal::Auto),
            "own" => Some(Traversal::Own),
            "ray-query" => Some(Traversal::RayQuery),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Traversal::Auto => "auto",
            Traversal::Own => "own",
            Traversal::RayQuery => "ray-query",
        }
    }

    /// What this choice stands for on `device` for a scene of `triangles`. `Auto` takes the
    /// own traversal on a CPU device: lavapipe 25's ray queries were 0.7-60x its time on the
    /// bench scenes (docs/PERFORMANCE.md); and the ray queries on a GPU that offers them, as
    /// every GPU renderer with ray-tracing hardware does (Cycles' OptiX, Falcor, bevy_solari),
    /// unless the scene is over what they take (`MAX_TRIANGLES`).
    pub fn resolved(self, device: &DeviceInfo, triangles: u64) -> Traversal {
        match self {
            Traversal::Auto if device.ray_queries && !device.cpu && triangles < MAX_TRIANGLES => {
                Traversal::RayQuery
            }
            Traversal::Auto => Traversal::Own,
            t => t,
        }
    }

    /// As an image's metadata and `platoon info` say it: `auto` with what it stands for.
    pub fn label(self) -> String {
        match self {
            Traversal::Auto => "auto (own on CPU devices and devices without ray queries, \
                                ray-query on GPUs that offer them)"
                .into(),
            t => t.name().into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn device(cpu: bool, ray_queries: bool) -> DeviceInfo {
        DeviceInfo {
            ray_queries,
            ..DeviceInfo::for_tests(cpu)
        }
    }

    #[test]
    fn auto_takes_the_ray_queries_on_a_gpu_that_offers_them_and_the_own_traversal_elsewhere() {
        use Traversal::*;
        let resolved = |cpu, queries, triangles| Auto.resolved(&device(cpu, queries), triangles);
        assert_eq!(resolved(false, true, 1000), RayQuery);
        assert_eq!(
            resolved(true, true, 1000),
            Own,
            "lavapipe 25 measured slower"
        );
        assert_eq!(resolved(false, false, 1000), Own);
        assert_eq!(
            resolved(false, true, MAX_TRIANGLES),
            Own,
            "over the custom index"
        );
        // A choice named is kept (and refused by the device where it cannot be).
        for t in [Own, RayQuery] {
            assert_eq!(t.resolved(&device(true, false), 1000), t);
        }
        assert!(Auto.label().starts_with("auto (own on CPU devices"));
    }
}

//! What platoon knows of a physical device (`platoon devices`): its kind, driver, limits,
//! memory and whether it offers ray queries; read by `context.rs` from the device.

use ash::vk;

/// One physical device as `platoon devices` lists it.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    pub index: usize,
    pub name: String,
    pub device_type: String,
    pub driver: String,
    pub api_version: String,
    /// `maxStorageBufferRange`: scene arrays up to this size can be storage buffers.
    pub max_storage_buffer_range: u64,
    /// `maxTexelBufferElements`: scene arrays of up to this many texels can be texel buffers.
    pub max_texel_buffer_elements: u64,
    /// A CPU implementation (lavapipe).
    pub cpu: bool,
    /// The Mesa release (major, minor) of a Mesa driver (lavapipe, RADV, ANV...), read from its
    /// driverInfo; `None` for other drivers.
    pub mesa: Option<(u32, u32)>,
    /// What the device's memory holds: its heaps and the largest allocation and buffer.
    pub memory: DeviceMemory,
    /// Whether it offers ray queries over acceleration structures (`ray_query.rs`).
    pub ray_queries: bool,
}

impl DeviceInfo {
    /// What the choice of memory paths depends on.
    pub fn memory_limits(&self) -> crate::memory::MemoryLimits {
        crate::memory::MemoryLimits {
            max_storage_buffer_range: self.max_storage_buffer_range,
            max_texel_buffer_elements: self.max_texel_buffer_elements,
            texel_fastest: crate::memory::texel_fastest(self.cpu, self.mesa),
        }
    }
}

#[cfg(test)]
impl DeviceInfo {
    /// A device of 2 GiB, storage buffers and texel buffers of 2^27, no ray queries.
    pub(crate) fn for_tests(cpu: bool) -> DeviceInfo {
        DeviceInfo {
            index: 1,
            name: "test device".into(),
            device_type: String::new(),
            driver: String::new(),
            api_version: "1.3.0".into(),
            max_storage_buffer_range: 1 << 27,
            max_texel_buffer_elements: 1 << 27,
            cpu,
            mesa: None,
            memory: DeviceMemory {
                device_local: 2 << 30,
                max_allocation: 1 << 30,
                max_buffer: Some(4 << 30),
            },
            ray_queries: false,
        }
    }
}

/// What a device's memory can hold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeviceMemory {
    /// The largest device-local heap in bytes: where a GPU's scene arrays live.
    pub device_local: u64,
    /// `maxMemoryAllocationSize` (Vulkan 1.1): the largest single allocation.
    pub max_allocation: u64,
    /// `maxBufferSize` (Vulkan 1.3); None on older devices, which state no such limit.
    pub max_buffer: Option<u64>,
}

impl DeviceMemory {
    pub fn of(
        heaps: &vk::PhysicalDeviceMemoryProperties,
        max_allocation: u64,
        max_buffer: Option<u64>,
    ) -> DeviceMemory {
        let device_local = heaps.memory_heaps[..heaps.memory_heap_count as usize]
            .iter()
            .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|h| h.size)
            .max()
            .unwrap_or(0);
        DeviceMemory {
            device_local,
            max_allocation,
            max_buffer,
        }
    }

    /// The largest one array can be: one buffer in one allocation.
    pub fn largest_array(&self) -> u64 {
        self.max_buffer
            .map_or(self.max_allocation, |b| b.min(self.max_allocation))
    }
}

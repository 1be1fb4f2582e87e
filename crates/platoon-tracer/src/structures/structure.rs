//! One acceleration structure in a buffer of its own: made, addressed, freed.

use ash::khr::acceleration_structure::Device as Loader;
use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::buffer::GpuBuffer;
use crate::gpu::Gpu;
use crate::{Result, VkContext};

/// One acceleration structure and the buffer it lives in.
pub(super) struct Structure {
    pub(super) handle: vk::AccelerationStructureKHR,
    pub(super) buffer: GpuBuffer,
}

/// The sizes of a structure of `ty` built with `flags` over `geometry` of `count` primitives,
/// and of its build's and update's scratch.
pub(super) fn build_sizes(
    loader: &Loader,
    ty: vk::AccelerationStructureTypeKHR,
    flags: vk::BuildAccelerationStructureFlagsKHR,
    geometry: vk::AccelerationStructureGeometryKHR,
    count: u32,
) -> vk::AccelerationStructureBuildSizesInfoKHR<'static> {
    let geometries = [geometry];
    let info = vk::AccelerationStructureBuildGeometryInfoKHR::default()
        .ty(ty)
        .flags(flags)
        .geometries(&geometries);
    let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    unsafe {
        loader.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            &info,
            &[count],
            &mut sizes,
        )
    };
    sizes
}

impl Structure {
    /// No structure (a null handle, an empty buffer).
    pub(super) fn none() -> Structure {
        Structure {
            handle: vk::AccelerationStructureKHR::null(),
            buffer: GpuBuffer::empty(),
        }
    }

    /// A structure of `ty` and `size` bytes in a buffer of its own (nothing built in it yet).
    pub(super) fn create(
        loader: &Loader,
        gpu: &mut Gpu,
        ty: vk::AccelerationStructureTypeKHR,
        size: u64,
    ) -> Result<Structure> {
        let mut buffer = gpu.buffer(
            "acceleration structure",
            size,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR,
            MemoryLocation::GpuOnly,
        )?;
        let create = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(buffer.buffer)
            .size(size)
            .ty(ty);
        match unsafe { loader.create_acceleration_structure(&create, None) } {
            Ok(handle) => Ok(Structure { handle, buffer }),
            Err(e) => {
                gpu.destroy_buffer(&mut buffer);
                Err(e).ctx("creating an acceleration structure")
            }
        }
    }

    /// Its device address, which a top level's instance records name.
    pub(super) fn address(&self, loader: &Loader) -> u64 {
        let info = vk::AccelerationStructureDeviceAddressInfoKHR::default()
            .acceleration_structure(self.handle);
        unsafe { loader.get_acceleration_structure_device_address(&info) }
    }

    /// Frees the structure and its buffer (none after).
    pub(super) fn free(&mut self, loader: &Loader, gpu: &mut Gpu) {
        if self.handle != vk::AccelerationStructureKHR::null() {
            unsafe { loader.destroy_acceleration_structure(self.handle, None) };
            self.handle = vk::AccelerationStructureKHR::null();
        }
        gpu.destroy_buffer(&mut self.buffer);
    }
}

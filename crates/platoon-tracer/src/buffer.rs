//! Buffers with device addresses, allocated through gpu-allocator. Scene data is uploaded once
//! through a staging buffer into device-local memory.

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme, Allocator};
use gpu_allocator::MemoryLocation;

use crate::{Result, VkContext};

pub struct GpuBuffer {
    pub buffer: vk::Buffer,
    pub allocation: Option<Allocation>,
    pub address: u64,
    pub size: u64,
}

impl GpuBuffer {
    pub fn new(
        device: &ash::Device,
        allocator: &mut Allocator,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<GpuBuffer> {
        // Empty arrays still get a valid address: the kernel never reads them.
        let size = size.max(16);
        let usage = usage | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let buffer = unsafe { device.create_buffer(&info, None) }.ctx("creating a buffer")?;
        let requirements = unsafe { device.get_buffer_memory_requirements(buffer) };
        let allocation = allocator.allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })?;
        unsafe { device.bind_buffer_memory(buffer, allocation.memory(), allocation.offset()) }
            .ctx("binding buffer memory")?;
        let address = unsafe {
            device.get_buffer_device_address(&vk::BufferDeviceAddressInfo::default().buffer(buffer))
        };
        Ok(GpuBuffer {
            buffer,
            allocation: Some(allocation),
            address,
            size,
        })
    }

    /// No buffer (what a holder keeps before it makes one); destroying it does nothing.
    pub fn empty() -> GpuBuffer {
        GpuBuffer {
            buffer: vk::Buffer::null(),
            allocation: None,
            address: 0,
            size: 0,
        }
    }

    /// The buffer's bytes when its memory is mapped (host-visible).
    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        let size = self.size as usize;
        self.allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .map(|s| &mut s[..size])
    }

    pub fn mapped(&mut self) -> &mut [u8] {
        let size = self.size as usize;
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .expect("host-visible buffer");
        &mut slice[..size]
    }

    /// Frees the buffer and its memory; it is empty after (a second destroy does nothing).
    pub fn destroy(&mut self, device: &ash::Device, allocator: &mut Allocator) {
        let buffer = std::mem::replace(&mut self.buffer, vk::Buffer::null());
        if buffer != vk::Buffer::null() {
            unsafe { device.destroy_buffer(buffer, None) };
        }
        if let Some(a) = self.allocation.take() {
            let _ = allocator.free(a);
        }
    }
}

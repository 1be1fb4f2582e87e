//! A command buffer of a pool of its own and the fence its submissions signal: what the
//! tracer's waited work (`Gpu::submit`) and the structures' builds behind the host
//! (`structures/behind.rs`) each record and submit through.

use ash::vk;

use crate::{Result, VkContext};

pub(crate) struct Submission {
    pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
}

impl Submission {
    /// A resettable command buffer on `queue_family` and an unsignalled fence.
    pub(crate) fn new(device: &ash::Device, queue_family: u32) -> Result<Submission> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let pool =
            unsafe { device.create_command_pool(&info, None) }.ctx("creating a command pool")?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .command_buffer_count(1);
        let made = unsafe { device.allocate_command_buffers(&alloc) }
            .ctx("allocating a command buffer")
            .and_then(|cbs| {
                let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
                    .ctx("creating a fence")?;
                Ok((cbs[0], fence))
            });
        match made {
            Ok((command_buffer, fence)) => Ok(Submission {
                pool,
                command_buffer,
                fence,
            }),
            Err(e) => {
                unsafe { device.destroy_command_pool(pool, None) };
                Err(e)
            }
        }
    }

    /// Records `record` into the command buffer (reset first) and submits it to `queue`, the
    /// fence signalled when it is done; does not wait (the last submission waited for).
    pub(crate) fn submit(
        &self,
        device: &ash::Device,
        queue: vk::Queue,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<()> {
        let cb = self.command_buffer;
        unsafe {
            device
                .reset_command_buffer(cb, vk::CommandBufferResetFlags::empty())
                .ctx("resetting a command buffer")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(cb, &begin)
                .ctx("beginning a command buffer")?;
            record(device, cb);
            device
                .end_command_buffer(cb)
                .ctx("ending a command buffer")?;
            let cbs = [cb];
            let submit = vk::SubmitInfo::default().command_buffers(&cbs);
            device
                .queue_submit(queue, &[submit], self.fence)
                .ctx("submitting work")
        }
    }

    /// Waits for the last submission and resets the fence for the next.
    pub(crate) fn wait(&self, device: &ash::Device) -> Result<()> {
        unsafe {
            device
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .ctx("waiting for the device")?;
            device.reset_fences(&[self.fence]).ctx("resetting a fence")
        }
    }

    /// Frees the fence and the pool with its command buffer (no submission in flight).
    pub(crate) fn destroy(&self, device: &ash::Device) {
        unsafe {
            device.destroy_fence(self.fence, None);
            device.destroy_command_pool(self.pool, None);
        }
    }
}

//! Builds submitted behind the host: a living scene's refits and top level go to the queue
//! without the host waiting for them (the frame after them is ordered behind them on the same
//! queue, and their last barrier makes what they wrote visible to its kernels), so applying a
//! commit costs the host the recording, not the builds. Their scratch is freed when the next
//! builds come or the structures go.

use ash::vk;

use crate::buffer::GpuBuffer;
use crate::gpu::Gpu;
use crate::{Result, VkContext};

/// A command buffer and fence of the structures' own, and what the work in flight uses.
pub(super) struct Behind {
    pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
    /// Work submitted and not yet waited for.
    pending: bool,
    /// Buffers the work in flight reads or writes (its scratch).
    used: Vec<GpuBuffer>,
}

impl Behind {
    pub(super) fn new(gpu: &Gpu) -> Result<Behind> {
        let device = gpu.device();
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(gpu.ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let pool = unsafe { device.create_command_pool(&info, None) }
            .ctx("creating the structures' command pool")?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .command_buffer_count(1);
        let made = unsafe { device.allocate_command_buffers(&alloc) }
            .ctx("allocating the structures' command buffer")
            .and_then(|cbs| {
                let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
                    .ctx("creating the structures' fence")?;
                Ok((cbs[0], fence))
            });
        match made {
            Ok((command_buffer, fence)) => Ok(Behind {
                pool,
                command_buffer,
                fence,
                pending: false,
                used: Vec::new(),
            }),
            Err(e) => {
                unsafe { device.destroy_command_pool(pool, None) };
                Err(e)
            }
        }
    }

    /// Waits for the work in flight, if any, and frees what it used.
    pub(super) fn settle(&mut self, gpu: &mut Gpu) -> Result<()> {
        if self.pending {
            let device = gpu.device();
            unsafe { device.wait_for_fences(&[self.fence], true, u64::MAX) }
                .ctx("waiting for the structures' builds")?;
            unsafe { device.reset_fences(&[self.fence]) }.ctx("resetting a fence")?;
            self.pending = false;
        }
        for mut b in self.used.drain(..) {
            gpu.destroy_buffer(&mut b);
        }
        Ok(())
    }

    /// Keeps `buffer` until the work in flight is done.
    pub(super) fn keep(&mut self, buffer: GpuBuffer) {
        self.used.push(buffer);
    }

    /// Records `record` and submits it without waiting (after `settle`: the command buffer
    /// free).
    pub(super) fn submit(
        &mut self,
        gpu: &mut Gpu,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<()> {
        debug_assert!(!self.pending, "builds submitted behind unsettled ones");
        let device = gpu.device();
        crate::gpu::record_and_submit(
            device,
            gpu.ctx.queue,
            self.command_buffer,
            self.fence,
            record,
        )?;
        self.pending = true;
        Ok(())
    }

    /// Waits for the work in flight and frees the command buffer, fence and buffers.
    pub(super) fn destroy(&mut self, gpu: &mut Gpu) {
        let _ = self.settle(gpu);
        unsafe {
            gpu.device().destroy_fence(self.fence, None);
            gpu.device().destroy_command_pool(self.pool, None);
        }
    }
}

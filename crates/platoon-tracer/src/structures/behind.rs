//! Builds submitted behind the host: a living scene's refits and top level go to the queue
//! without the host waiting for them (the frame after them is ordered behind them on the same
//! queue, and their last barrier makes what they wrote visible to its kernels), so applying a
//! commit costs the host the recording, not the builds. Their scratch is freed when the next
//! builds come or the structures go.

use ash::vk;

use crate::buffer::GpuBuffer;
use crate::gpu::Gpu;
use crate::submission::Submission;
use crate::Result;

/// A command buffer and fence of the structures' own, and what the work in flight uses.
pub(super) struct Behind {
    submission: Submission,
    /// Work submitted and not yet waited for.
    pending: bool,
    /// Buffers the work in flight reads or writes (its scratch).
    used: Vec<GpuBuffer>,
}

impl Behind {
    pub(super) fn new(gpu: &Gpu) -> Result<Behind> {
        Ok(Behind {
            submission: Submission::new(gpu.device(), gpu.ctx.queue_family)?,
            pending: false,
            used: Vec::new(),
        })
    }

    /// Waits for the work in flight, if any, and frees what it used.
    pub(super) fn settle(&mut self, gpu: &mut Gpu) -> Result<()> {
        if self.pending {
            self.submission.wait(gpu.device())?;
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
        self.submission
            .submit(gpu.device(), gpu.ctx.queue, record)?;
        self.pending = true;
        Ok(())
    }

    /// Waits for the work in flight and frees the command buffer, fence and buffers.
    pub(super) fn destroy(&mut self, gpu: &mut Gpu) {
        let _ = self.settle(gpu);
        self.submission.destroy(gpu.device());
    }
}

//! Recording compute dispatches: a kernel with its scene set and push constants, after a barrier
//! that makes the previous dispatch's writes visible, and the timestamps around them.

use ash::vk;

use crate::globals::Push;

/// A kernel variant ready to dispatch: its pipeline, layout and scene descriptor set.
pub type Dispatchable = (vk::Pipeline, vk::PipelineLayout, vk::DescriptorSet);

/// Records a barrier after earlier compute writes, then the dispatch of `kernel`.
///
/// # Safety
/// `cb` is recording and `kernel`'s handles are alive.
pub(crate) unsafe fn record_dispatch(
    d: &ash::Device,
    cb: vk::CommandBuffer,
    (pipeline, layout, set): Dispatchable,
    push: &Push,
    groups: (u32, u32),
) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE)
        .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE);
    d.cmd_pipeline_barrier(
        cb,
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::DependencyFlags::empty(),
        &[barrier],
        &[],
        &[],
    );
    d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, pipeline);
    d.cmd_bind_descriptor_sets(cb, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]);
    d.cmd_push_constants(
        cb,
        layout,
        vk::ShaderStageFlags::COMPUTE,
        0,
        bytemuck::bytes_of(push),
    );
    d.cmd_dispatch(cb, groups.0, groups.1, 1);
}

/// Records a barrier after earlier compute writes (to memory and to dispatch sizes), then the
/// dispatch of `kernel` with the workgroup count at `offset` of `args`
/// (VkDispatchIndirectCommand).
///
/// # Safety
/// `cb` is recording and `kernel`'s handles and `args` are alive.
pub(crate) unsafe fn record_dispatch_indirect(
    d: &ash::Device,
    cb: vk::CommandBuffer,
    (pipeline, layout, set): Dispatchable,
    push: &Push,
    args: vk::Buffer,
    offset: u64,
) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE)
        .dst_access_mask(
            vk::AccessFlags::SHADER_READ
                | vk::AccessFlags::SHADER_WRITE
                | vk::AccessFlags::INDIRECT_COMMAND_READ,
        );
    d.cmd_pipeline_barrier(
        cb,
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::PipelineStageFlags::COMPUTE_SHADER | vk::PipelineStageFlags::DRAW_INDIRECT,
        vk::DependencyFlags::empty(),
        &[barrier],
        &[],
        &[],
    );
    d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, pipeline);
    d.cmd_bind_descriptor_sets(cb, vk::PipelineBindPoint::COMPUTE, layout, 0, &[set], &[]);
    d.cmd_push_constants(
        cb,
        layout,
        vk::ShaderStageFlags::COMPUTE,
        0,
        bytemuck::bytes_of(push),
    );
    d.cmd_dispatch_indirect(cb, args, offset);
}

/// Records timestamp `which` (0: before, resetting the pool; 1: after) when the device has them.
///
/// # Safety
/// `cb` is recording.
pub(crate) unsafe fn timestamp(
    d: &ash::Device,
    cb: vk::CommandBuffer,
    pool: Option<vk::QueryPool>,
    which: u32,
) {
    let Some(q) = pool else { return };
    if which == 0 {
        d.cmd_reset_query_pool(cb, q, 0, 2);
        d.cmd_write_timestamp(cb, vk::PipelineStageFlags::TOP_OF_PIPE, q, 0);
    } else {
        d.cmd_write_timestamp(cb, vk::PipelineStageFlags::BOTTOM_OF_PIPE, q, 1);
    }
}

/// Records a barrier that makes earlier compute writes visible to the host (counters read
/// between submissions).
///
/// # Safety
/// `cb` is recording.
pub(crate) unsafe fn record_to_host(d: &ash::Device, cb: vk::CommandBuffer) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ);
    d.cmd_pipeline_barrier(
        cb,
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::PipelineStageFlags::HOST,
        vk::DependencyFlags::empty(),
        &[barrier],
        &[],
        &[],
    );
}

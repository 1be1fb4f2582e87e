//! One device's means of work: its memory, the command buffer, fence and timestamp queries a
//! tracer submits through, and its compiled kernels. What the tracer and its rendering methods
//! (`method/`) share; each owns the buffers it makes here.

use std::collections::HashMap;
use std::mem::ManuallyDrop;
use std::time::Duration;

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::MemoryLocation;

use crate::buffer::GpuBuffer;
use crate::context::Context;
use crate::dispatch::{timestamp, Dispatchable};
use crate::kernel::{Kernel, PipelineCache};
use crate::memory::SceneDescriptors;
use crate::submission::Submission;
use crate::{Result, VkContext};

/// A kernel variant: its entry file (shaders/, `kernel::SOURCES`) and its defines.
pub(crate) type KernelKey = (&'static str, Vec<&'static str>);

/// One device's memory, submissions, timestamps and compiled kernels: what a method's device
/// half allocates its buffers from (`buffer`, `device::ensure`) and submits its own commands with.
pub struct Gpu {
    pub(crate) ctx: ManuallyDrop<Context>,
    pub(crate) allocator: ManuallyDrop<Allocator>,
    submission: Submission,
    query_pool: Option<vk::QueryPool>,
    pipeline_cache: PipelineCache,
    kernels: HashMap<KernelKey, Kernel>,
    pipelines_built: u32,
    /// Set 1 of every kernel: storage buffers a rendering method binds for its own kernels
    /// (`METHOD_BINDINGS` of them; the streaming path tracer's stream).
    pub(crate) method_layout: vk::DescriptorSetLayout,
    /// `TracerOptions::stream_slots`.
    pub(crate) stream_slots: Option<u32>,
}

/// Storage-buffer bindings of the method set (set 1).
pub(crate) const METHOD_BINDINGS: u32 = 6;

impl Gpu {
    pub(crate) fn new(ctx: Context) -> Result<Gpu> {
        let device = ctx.device.clone();
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: ctx.instance.clone(),
            device: device.clone(),
            physical_device: ctx.physical,
            debug_settings: Default::default(),
            buffer_device_address: true,
            allocation_sizes: Default::default(),
        })?;
        let submission = Submission::new(&device, ctx.queue_family)?;
        let query_pool = if ctx.timestamp_bits > 0 {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(2);
            Some(unsafe { device.create_query_pool(&info, None) }.ctx("creating a query pool")?)
        } else {
            None
        };
        let pipeline_cache = PipelineCache::open(&device, &ctx.properties)?;
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = (0..METHOD_BINDINGS)
            .map(|i| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let method_layout = unsafe {
            device.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                None,
            )
        }
        .ctx("creating the method descriptor set layout")?;
        Ok(Gpu {
            ctx: ManuallyDrop::new(ctx),
            allocator: ManuallyDrop::new(allocator),
            submission,
            query_pool,
            pipeline_cache,
            kernels: HashMap::new(),
            pipelines_built: 0,
            method_layout,
            stream_slots: None,
        })
    }

    pub fn device(&self) -> &ash::Device {
        &self.ctx.device
    }

    pub fn wait_idle(&self) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.ctx("waiting for the device")
    }

    /// Submits `record` on the command buffer and waits for it.
    pub fn submit(&mut self, record: impl FnOnce(&ash::Device, vk::CommandBuffer)) -> Result<()> {
        let device = &self.ctx.device;
        self.submission.submit(device, self.ctx.queue, record)?;
        self.submission.wait(device)
    }

    /// Submits `record` between two timestamps; returns the device time between them (zero on
    /// a device without timestamps).
    pub fn timed(
        &mut self,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<Duration> {
        let pool = self.query_pool;
        self.submit(|d, cb| unsafe {
            timestamp(d, cb, pool, 0);
            record(d, cb);
            timestamp(d, cb, pool, 1);
        })?;
        let Some(q) = self.query_pool else {
            return Ok(Duration::ZERO);
        };
        let mut ts = [0u64; 2];
        unsafe {
            self.ctx
                .device
                .get_query_pool_results(q, 0, &mut ts, vk::QueryResultFlags::TYPE_64)
        }
        .ctx("reading timestamps")?;
        let period = self.ctx.properties.limits.timestamp_period as f64;
        Ok(Duration::from_nanos(
            (ts[1].saturating_sub(ts[0]) as f64 * period) as u64,
        ))
    }

    pub fn buffer(
        &mut self,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<GpuBuffer> {
        GpuBuffer::new(
            &self.ctx.device,
            &mut self.allocator,
            name,
            size,
            usage,
            location,
        )
    }

    pub fn destroy_buffer(&mut self, buffer: &mut GpuBuffer) {
        buffer.destroy(&self.ctx.device, &mut self.allocator);
    }

    /// Copies `(buffer, offset, bytes)` writes into device-local buffers through one staging
    /// buffer and one submission.
    pub fn write_buffers(&mut self, writes: &[(vk::Buffer, u64, &[u8])]) -> Result<()> {
        let total: usize = writes.iter().map(|w| w.2.len()).sum();
        if total == 0 {
            return Ok(());
        }
        let mut staging = self.buffer(
            "staging",
            total as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        let mut copies: Vec<(vk::Buffer, vk::BufferCopy)> = Vec::with_capacity(writes.len());
        let mut at = 0usize;
        let mapped = staging.mapped();
        for &(dst, offset, bytes) in writes {
            mapped[at..at + bytes.len()].copy_from_slice(bytes);
            let region = vk::BufferCopy::default()
                .src_offset(at as u64)
                .dst_offset(offset)
                .size(bytes.len() as u64);
            copies.push((dst, region));
            at += bytes.len();
        }
        let src = staging.buffer;
        let result = self.submit(|d, cb| unsafe {
            for (dst, region) in &copies {
                d.cmd_copy_buffer(cb, src, *dst, std::slice::from_ref(region));
            }
        });
        self.destroy_buffer(&mut staging);
        result
    }

    /// `size` bytes of `buffer` from `offset`, through a staging buffer (what tests compare
    /// with the CPU's; `buffer` was made with TRANSFER_SRC).
    pub fn read_buffer(&mut self, buffer: vk::Buffer, offset: u64, size: u64) -> Result<Vec<u8>> {
        if size == 0 {
            return Ok(Vec::new());
        }
        let mut staging = self.buffer(
            "readback",
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let dst = staging.buffer;
        let result =
            self.submit(|d, cb| unsafe { record_copy_to_host(d, cb, buffer, offset, dst, size) });
        let bytes = staging.mapped().to_vec();
        self.destroy_buffer(&mut staging);
        result.map(|_| bytes)
    }

    /// The kernel `key`, reading the scene arrays through `scene`'s set, built on first use.
    pub(crate) fn kernel(
        &mut self,
        key: KernelKey,
        scene: &SceneDescriptors,
    ) -> Result<Dispatchable> {
        use std::collections::hash_map::Entry;
        let k = match self.kernels.entry(key) {
            Entry::Occupied(e) => e.into_mut(),
            Entry::Vacant(e) => {
                let (entry, defines) = e.key();
                let k = Kernel::new(
                    &self.ctx.device,
                    &self.pipeline_cache,
                    entry,
                    defines,
                    &[scene.layout, self.method_layout],
                )?;
                self.pipelines_built += 1;
                e.insert(k)
            }
        };
        Ok((k.pipeline, k.layout, scene.set))
    }

    /// Destroys every kernel (the scene's bindings changed: they are built again on use).
    pub(crate) fn drop_kernels(&mut self) {
        for k in self.kernels.values() {
            k.destroy(&self.ctx.device);
        }
        self.kernels.clear();
    }

    /// A descriptor set of the method layout (set 1) binding `buffers` in order, from a pool of
    /// its own (destroy the pool to free it).
    pub(crate) fn method_set(
        &mut self,
        buffers: &[vk::Buffer],
    ) -> Result<(vk::DescriptorPool, vk::DescriptorSet)> {
        let device = &self.ctx.device;
        let sizes = [vk::DescriptorPoolSize::default()
            .ty(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(METHOD_BINDINGS)];
        let pool = unsafe {
            device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(&sizes),
                None,
            )
        }
        .ctx("creating a method descriptor pool")?;
        let layouts = [self.method_layout];
        let set = unsafe {
            device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(pool)
                    .set_layouts(&layouts),
            )
        }
        .ctx("allocating a method descriptor set")?[0];
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
            .iter()
            .map(|&b| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(b)
                    .offset(0)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let writes: Vec<vk::WriteDescriptorSet> = infos
            .iter()
            .enumerate()
            .map(|(i, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(i as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        Ok((pool, set))
    }

    /// Compute pipelines built so far.
    pub(crate) fn pipelines_built(&self) -> u32 {
        self.pipelines_built
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        let device = self.ctx.device.clone();
        unsafe {
            let _ = device.device_wait_idle();
        }
        self.drop_kernels();
        unsafe {
            self.pipeline_cache.save(&device);
            device.destroy_pipeline_cache(self.pipeline_cache.cache, None);
            if let Some(q) = self.query_pool {
                device.destroy_query_pool(q, None);
            }
            device.destroy_descriptor_set_layout(self.method_layout, None);
            self.submission.destroy(&device);
            ManuallyDrop::drop(&mut self.allocator);
            ManuallyDrop::drop(&mut self.ctx);
        }
    }
}

/// Records, after the compute writes before it, the copy of `size` bytes of `src` from `offset`
/// into host-visible `dst`, and makes the copy and those compute writes (to host-visible
/// buffers too) visible to the host.
///
/// # Safety
/// `cb` is recording and both buffers are alive.
pub(crate) unsafe fn record_copy_to_host(
    d: &ash::Device,
    cb: vk::CommandBuffer,
    src: vk::Buffer,
    offset: u64,
    dst: vk::Buffer,
    size: u64,
) {
    let barrier = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::SHADER_WRITE)
        .dst_access_mask(vk::AccessFlags::TRANSFER_READ);
    d.cmd_pipeline_barrier(
        cb,
        vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::PipelineStageFlags::TRANSFER,
        vk::DependencyFlags::empty(),
        &[barrier],
        &[],
        &[],
    );
    let region = vk::BufferCopy::default()
        .src_offset(offset)
        .dst_offset(0)
        .size(size);
    d.cmd_copy_buffer(cb, src, dst, &[region]);
    let host = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE | vk::AccessFlags::SHADER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ);
    d.cmd_pipeline_barrier(
        cb,
        vk::PipelineStageFlags::TRANSFER | vk::PipelineStageFlags::COMPUTE_SHADER,
        vk::PipelineStageFlags::HOST,
        vk::DependencyFlags::empty(),
        &[host],
        &[],
        &[],
    );
}

//! A tracer: one Vulkan device holding a copy of the scene, rendering bands of lines.

use std::collections::HashMap;
use std::mem::ManuallyDrop;
use std::time::Duration;

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::MemoryLocation;
use platoon_core::flatten::commit::SceneHeader;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::FrameParams;
use platoon_core::FeatureSet;

use crate::buffer::GpuBuffer;
use crate::context::{Context, DeviceInfo};
use crate::globals::Globals;
use crate::kernel::{self, Kernel, PipelineCache, Sampling};
use crate::memory::{self, ArrayPath, MemoryPath, SceneDescriptors, SCENE_ARRAYS};
use crate::{Result, VkContext};

#[derive(Clone, Debug, Default)]
pub struct TracerOptions {
    /// Index into `list_devices()`.
    pub device: usize,
    /// Enable VK_LAYER_KHRONOS_validation and record its messages.
    pub validation: bool,
    pub sampling: Sampling,
    /// For lavapipe: worker threads of this tracer's own llvmpipe thread pool (LP_NUM_THREADS).
    pub lavapipe_threads: Option<u32>,
    /// How the kernel reads the scene arrays (per device kind, by default).
    pub memory: MemoryPath,
}

pub(crate) struct SceneBuffers {
    /// The scene arrays in `SCENE_ARRAYS` order.
    pub(crate) list: Vec<GpuBuffer>,
    pub(crate) globals: Globals,
    /// Per array: how the kernel reads it.
    pub(crate) paths: Vec<ArrayPath>,
    pub(crate) descriptors: Option<SceneDescriptors>,
}

pub struct Tracer {
    pub(crate) ctx: ManuallyDrop<Context>,
    pub(crate) allocator: ManuallyDrop<Allocator>,
    pub(crate) scene: SceneBuffers,
    pub(crate) globals_buffer: GpuBuffer,
    pub(crate) frame_buffers: Option<(u32, u32, GpuBuffer, GpuBuffer, GpuBuffer)>,
    pub(crate) igi: crate::igi::IgiBuffers,
    pub(crate) kernels: HashMap<Vec<&'static str>, Kernel>,
    pub(crate) pipelines_built: u32,
    pub(crate) pipeline_cache: PipelineCache,
    pub(crate) command_pool: vk::CommandPool,
    pub(crate) command_buffer: vk::CommandBuffer,
    pub(crate) fence: vk::Fence,
    pub(crate) query_pool: Option<vk::QueryPool>,
    pub(crate) features: FeatureSet,
    pub(crate) sampling: Sampling,
    pub(crate) memory: MemoryPath,
}

// Vulkan handles are used from one thread at a time; the tracer moves to its own thread.
unsafe impl Send for Tracer {}

impl Tracer {
    /// The time between the two timestamps of the last submission (zero without timestamps).
    pub(crate) fn timestamps(&self) -> Result<Duration> {
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

    pub fn new(options: &TracerOptions, scene: &GpuScene) -> Result<Tracer> {
        let ctx = Context::new(options.device, options.validation, options.lavapipe_threads)?;
        let device = ctx.device.clone();
        let mut allocator = Allocator::new(&AllocatorCreateDesc {
            instance: ctx.instance.clone(),
            device: device.clone(),
            physical_device: ctx.physical,
            debug_settings: Default::default(),
            buffer_device_address: true,
            allocation_sizes: Default::default(),
        })?;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let command_pool = unsafe { device.create_command_pool(&pool_info, None) }
            .ctx("creating a command pool")?;
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(command_pool)
            .command_buffer_count(1);
        let command_buffer = unsafe { device.allocate_command_buffers(&alloc) }
            .ctx("allocating a command buffer")?[0];
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .ctx("creating a fence")?;
        let query_pool = if ctx.timestamp_bits > 0 {
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::TIMESTAMP)
                .query_count(2);
            Some(unsafe { device.create_query_pool(&info, None) }.ctx("creating a query pool")?)
        } else {
            None
        };
        let globals_buffer = GpuBuffer::new(
            &device,
            &mut allocator,
            "globals",
            std::mem::size_of::<Globals>() as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let pipeline_cache = PipelineCache::open(&device, &ctx.properties)?;
        let mut tracer = Tracer {
            ctx: ManuallyDrop::new(ctx),
            allocator: ManuallyDrop::new(allocator),
            scene: SceneBuffers {
                list: Vec::new(),
                globals: Globals::default(),
                paths: Vec::new(),
                descriptors: None,
            },
            globals_buffer,
            frame_buffers: None,
            igi: Default::default(),
            kernels: HashMap::new(),
            pipelines_built: 0,
            pipeline_cache,
            command_pool,
            command_buffer,
            fence,
            query_pool,
            features: scene.features,
            sampling: options.sampling,
            memory: options.memory,
        };
        tracer.upload_scene(scene)?;
        tracer.bind_scene_arrays()?;
        Ok(tracer)
    }

    pub(crate) fn wait_idle(&self) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle() }.ctx("waiting for the device")
    }

    /// Chooses each scene array's memory path from its buffer's size and binds the arrays.
    /// Called again after a buffer was replaced: while every array keeps its path the bindings
    /// are rewritten in place and the kernels stay (a game adding an instance must not wait for
    /// a recompile); a changed path makes a new set and new kernels.
    pub(crate) fn bind_scene_arrays(&mut self) -> Result<()> {
        let device = self.ctx.device.clone();
        let sizes: Vec<u64> = self.scene.list.iter().map(|b| b.size).collect();
        let limits = self.ctx.info.memory_limits();
        let paths = memory::choose(&sizes, &limits, self.memory);
        let buffers: Vec<vk::Buffer> = self.scene.list.iter().map(|b| b.buffer).collect();
        self.wait_idle()?;
        if let Some(d) = self.scene.descriptors.as_mut() {
            if paths == self.scene.paths {
                return d.write(&device, &buffers, &paths);
            }
        }
        if let Some(d) = self.scene.descriptors.take() {
            for k in self.kernels.values() {
                k.destroy(&device);
            }
            self.kernels.clear();
            d.destroy(&device);
        }
        self.scene.paths = paths;
        self.scene.descriptors = Some(SceneDescriptors::new(&device, &buffers, &self.scene.paths)?);
        Ok(())
    }

    /// Compute pipelines built so far (a kernel variant compiled by the driver, or compiled
    /// again after its bindings changed).
    pub fn pipelines_built(&self) -> u32 {
        self.pipelines_built
    }

    pub fn device_info(&self) -> &DeviceInfo {
        &self.ctx.info
    }

    /// Warnings and errors reported by the validation layer so far (empty without validation).
    pub fn validation_messages(&self) -> Vec<String> {
        self.ctx
            .validation_messages
            .lock()
            .map(|m| m.clone())
            .unwrap_or_default()
    }

    /// Defines of the kernel this tracer runs for `params` (feature set, estimator and the
    /// memory path of each scene array).
    pub fn kernel_defines(&self, params: &FrameParams) -> Vec<&'static str> {
        let features = self.features.with_render_options(params);
        let mut d = kernel::defines(features, self.sampling);
        d.extend(memory::defines(&self.scene.paths));
        d
    }

    /// Submits `record` on the tracer's command buffer and waits for it.
    pub(crate) fn submit(
        &mut self,
        record: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<()> {
        let device = &self.ctx.device;
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
                .queue_submit(self.ctx.queue, &[submit], self.fence)
                .ctx("submitting work")?;
            device
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .ctx("waiting for the device")?;
            device
                .reset_fences(&[self.fence])
                .ctx("resetting a fence")?;
        }
        Ok(())
    }

    /// A device-local buffer for a scene array of `capacity` bytes.
    /// On a CPU device (lavapipe) all memory is the host's: the arrays live in mapped memory
    /// and are written in place, with no staging copy and no transfer to wait for.
    pub(crate) fn array_buffer(&mut self, name: &str, capacity: u64) -> Result<GpuBuffer> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST;
        let location = if self.ctx.info.cpu {
            MemoryLocation::CpuToGpu
        } else {
            MemoryLocation::GpuOnly
        };
        GpuBuffer::new(
            &self.ctx.device,
            &mut self.allocator,
            name,
            capacity,
            usage,
            location,
        )
    }

    /// Writes `(array, offset, bytes)` into the scene arrays: in place where the array's memory
    /// is mapped, through one staging buffer and one submission otherwise. Between frames only.
    pub(crate) fn write_arrays(&mut self, writes: &[(usize, u64, &[u8])]) -> Result<()> {
        let mut staged: Vec<(vk::Buffer, u64, &[u8])> = Vec::new();
        for &(array, offset, bytes) in writes {
            let buffer = &mut self.scene.list[array];
            match buffer.mapped_mut() {
                Some(memory) => {
                    memory[offset as usize..offset as usize + bytes.len()].copy_from_slice(bytes)
                }
                None => staged.push((buffer.buffer, offset, bytes)),
            }
        }
        self.write_buffers(&staged)
    }

    /// Copies `(buffer, offset, bytes)` writes into device-local buffers through one staging
    /// buffer and one submission.
    pub(crate) fn write_buffers(&mut self, writes: &[(vk::Buffer, u64, &[u8])]) -> Result<()> {
        let total: usize = writes.iter().map(|w| w.2.len()).sum();
        if total == 0 {
            return Ok(());
        }
        let device = self.ctx.device.clone();
        let mut staging = GpuBuffer::new(
            &device,
            &mut self.allocator,
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
        staging.destroy(&device, &mut self.allocator);
        result
    }

    fn upload_scene(&mut self, s: &GpuScene) -> Result<()> {
        let arrays = memory::scene_array_bytes(s);
        for (i, data) in arrays.iter().enumerate() {
            let buffer = self.array_buffer(SCENE_ARRAYS[i].name, data.len() as u64)?;
            self.scene.list.push(buffer);
        }
        let writes: Vec<(usize, u64, &[u8])> = arrays
            .iter()
            .enumerate()
            .filter(|(_, d)| !d.is_empty())
            .map(|(i, d)| (i, 0, *d))
            .collect();
        self.write_arrays(&writes)?;
        self.refresh_globals(&s.header());
        Ok(())
    }

    /// The Globals fields that come from the scene: array addresses, counts, environment.
    pub(crate) fn refresh_globals(&mut self, h: &SceneHeader) {
        let mut g = Globals::default();
        for (info, buffer) in SCENE_ARRAYS.iter().zip(&self.scene.list) {
            *g.address_mut(info.array) = buffer.address;
        }
        g.env_color = [
            h.env_color[0],
            h.env_color[1],
            h.env_color[2],
            h.env_integral,
        ];
        g.dims[2] = h.env_size[0];
        g.dims[3] = h.env_size[1];
        g.counts = [h.lights, h.instances, h.tlas_root, h.env_kind];
        g.scene_sphere = h.scene_sphere;
        self.scene.globals = g;
        self.features = h.features;
    }

    /// Accumulation, stats and readback buffers for a frame size, reused while it stays.
    pub(crate) fn ensure_frame_buffers(&mut self, width: u32, height: u32) -> Result<()> {
        if matches!(&self.frame_buffers, Some((w, h, ..)) if *w == width && *h == height) {
            return Ok(());
        }
        self.destroy_frame_buffers();
        let device = self.ctx.device.clone();
        let pixels = width as u64 * height as u64 * 16;
        let accum = GpuBuffer::new(
            &device,
            &mut self.allocator,
            "accumulation",
            pixels,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let stats = GpuBuffer::new(
            &device,
            &mut self.allocator,
            "stats",
            (4 + height as u64) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let readback = GpuBuffer::new(
            &device,
            &mut self.allocator,
            "readback",
            pixels,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.frame_buffers = Some((width, height, accum, stats, readback));
        Ok(())
    }

    fn destroy_frame_buffers(&mut self) {
        if let Some((_, _, mut a, mut s, mut r)) = self.frame_buffers.take() {
            let device = self.ctx.device.clone();
            for b in [&mut a, &mut s, &mut r] {
                b.destroy(&device, &mut self.allocator);
            }
        }
    }

    /// The pipeline and layout of a kernel variant, and the scene descriptor set it binds.
    pub(crate) fn kernel(
        &mut self,
        defines: Vec<&'static str>,
    ) -> Result<(vk::Pipeline, vk::PipelineLayout, vk::DescriptorSet)> {
        let scene = self
            .scene
            .descriptors
            .as_ref()
            .expect("created with the tracer");
        if !self.kernels.contains_key(&defines) {
            let k = Kernel::new(
                &self.ctx.device,
                &self.pipeline_cache,
                &defines,
                scene.layout,
            )?;
            self.kernels.insert(defines.clone(), k);
            self.pipelines_built += 1;
        }
        let k = &self.kernels[&defines];
        Ok((k.pipeline, k.layout, scene.set))
    }
}

impl Drop for Tracer {
    fn drop(&mut self) {
        let device = self.ctx.device.clone();
        unsafe {
            let _ = device.device_wait_idle();
        }
        self.destroy_frame_buffers();
        self.igi.destroy(&device, &mut self.allocator);
        let mut list = std::mem::take(&mut self.scene.list);
        for b in &mut list {
            b.destroy(&device, &mut self.allocator);
        }
        self.globals_buffer.destroy(&device, &mut self.allocator);
        for k in self.kernels.values() {
            k.destroy(&device);
        }
        if let Some(d) = self.scene.descriptors.take() {
            d.destroy(&device);
        }
        unsafe {
            self.pipeline_cache.save(&device);
            device.destroy_pipeline_cache(self.pipeline_cache.cache, None);
            if let Some(q) = self.query_pool {
                device.destroy_query_pool(q, None);
            }
            device.destroy_fence(self.fence, None);
            device.destroy_command_pool(self.command_pool, None);
            ManuallyDrop::drop(&mut self.allocator);
            ManuallyDrop::drop(&mut self.ctx);
        }
    }
}

//! A tracer: one Vulkan device holding a copy of the scene, rendering bands of lines.

use std::collections::HashMap;
use std::mem::ManuallyDrop;
use std::time::{Duration, Instant};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::MemoryLocation;
use platoon_core::frame::{Band, BandTracer, FrameParams, TracerError};
use platoon_core::gpu_scene::{GpuLight, GpuScene};
use platoon_core::FeatureSet;

use crate::buffer::GpuBuffer;
use crate::context::{Context, DeviceInfo};
use crate::globals::{Globals, Push};
use crate::kernel::{self, Kernel, PipelineCache, Sampling};
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
}

struct SceneBuffers {
    list: Vec<GpuBuffer>,
    globals: Globals,
}

pub struct Tracer {
    ctx: ManuallyDrop<Context>,
    allocator: ManuallyDrop<Allocator>,
    scene: SceneBuffers,
    globals_buffer: GpuBuffer,
    frame_buffers: Option<(u32, u32, GpuBuffer, GpuBuffer, GpuBuffer)>,
    kernels: HashMap<Vec<&'static str>, Kernel>,
    pipeline_cache: PipelineCache,
    command_pool: vk::CommandPool,
    command_buffer: vk::CommandBuffer,
    fence: vk::Fence,
    query_pool: Option<vk::QueryPool>,
    features: FeatureSet,
    sampling: Sampling,
    light_count: u32,
    instance_count: u32,
    tlas_nodes: u32,
    env_kind: u32,
}

// Vulkan handles are used from one thread at a time; the tracer moves to its own thread.
unsafe impl Send for Tracer {}

fn bytes<T: bytemuck::Pod>(v: &[T]) -> &[u8] {
    bytemuck::cast_slice(v)
}

impl Tracer {
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
            },
            globals_buffer,
            frame_buffers: None,
            kernels: HashMap::new(),
            pipeline_cache,
            command_pool,
            command_buffer,
            fence,
            query_pool,
            features: scene.features,
            sampling: options.sampling,
            light_count: scene.lights.len() as u32,
            instance_count: scene.instances.len() as u32,
            tlas_nodes: scene.tlas_nodes.len() as u32,
            env_kind: scene.env.kind,
        };
        tracer.upload_scene(scene)?;
        Ok(tracer)
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

    /// Defines of the kernel this tracer runs for `params` (feature set + estimator).
    pub fn kernel_defines(&self, params: &FrameParams) -> Vec<&'static str> {
        let mut features = self.features;
        features.thin_lens = params.camera.aperture_radius > 0.0;
        kernel::defines(features, self.sampling)
    }

    /// Submits `record` on the tracer's command buffer and waits for it.
    fn submit(&mut self, record: impl FnOnce(&ash::Device, vk::CommandBuffer)) -> Result<()> {
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

    /// Uploads one array into device-local memory through a staging buffer.
    fn upload(&mut self, name: &str, data: &[u8]) -> Result<u64> {
        let device = self.ctx.device.clone();
        let size = data.len() as u64;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let buffer = GpuBuffer::new(
            &device,
            &mut self.allocator,
            name,
            size,
            usage,
            MemoryLocation::GpuOnly,
        )?;
        let address = buffer.address;
        if !data.is_empty() {
            let mut staging = GpuBuffer::new(
                &device,
                &mut self.allocator,
                "staging",
                size,
                vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::CpuToGpu,
            )?;
            staging.mapped()[..data.len()].copy_from_slice(data);
            let (src, dst) = (staging.buffer, buffer.buffer);
            let result = self.submit(|d, cb| unsafe {
                d.cmd_copy_buffer(cb, src, dst, &[vk::BufferCopy::default().size(size)]);
            });
            staging.destroy(&device, &mut self.allocator);
            result?;
        }
        self.scene.list.push(buffer);
        Ok(address)
    }

    fn upload_scene(&mut self, s: &GpuScene) -> Result<()> {
        let mut g = Globals {
            vertices: self.upload("vertices", bytes(&s.vertices))?,
            tri_pos: self.upload("triangle positions", bytes(&s.triangle_positions))?,
            triangles: self.upload("triangles", bytes(&s.triangles))?,
            tri_lights: self.upload("triangle lights", bytes(&s.triangle_lights))?,
            blas: self.upload("blas", bytes(&s.blas_nodes))?,
            tlas: self.upload("tlas", bytes(&s.tlas_nodes))?,
            instances: self.upload("instances", bytes(&s.instances))?,
            materials: self.upload("materials", bytes(&s.materials))?,
            textures: self.upload("textures", bytes(&s.textures))?,
            texels: self.upload("texels", bytes(&s.texels))?,
            lights: self.upload("lights", bytes::<GpuLight>(&s.lights))?,
            light_cdf: self.upload("light cdf", bytes(&s.light_cdf))?,
            env_texels: self.upload("environment", bytes(&s.env.texels))?,
            env_marginal: self.upload("environment marginal", bytes(&s.env.marginal_cdf))?,
            env_conditional: self
                .upload("environment conditional", bytes(&s.env.conditional_cdf))?,
            ..Default::default()
        };
        g.env_color = [
            s.env.color[0],
            s.env.color[1],
            s.env.color[2],
            s.env.integral,
        ];
        g.dims[2] = s.env.width;
        g.dims[3] = s.env.height;
        g.counts = [
            self.light_count,
            self.instance_count,
            self.tlas_nodes,
            self.env_kind,
        ];
        self.scene.globals = g;
        Ok(())
    }

    /// Accumulation, stats and readback buffers for a frame size, reused while it stays.
    fn ensure_frame_buffers(&mut self, width: u32, height: u32) -> Result<()> {
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

    fn kernel(&mut self, defines: Vec<&'static str>) -> Result<(vk::Pipeline, vk::PipelineLayout)> {
        if !self.kernels.contains_key(&defines) {
            let k = Kernel::new(&self.ctx.device, &self.pipeline_cache, &defines)?;
            self.kernels.insert(defines.clone(), k);
        }
        let k = &self.kernels[&defines];
        Ok((k.pipeline, k.layout))
    }

    /// Renders lines [y0, y1) of the frame at `params.spp` samples per pixel.
    pub fn render(
        &mut self,
        params: &FrameParams,
        y0: u32,
        y1: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band> {
        self.render_strided(params, y0, y1, 1, progress)
    }

    /// Renders lines y0, y0 + stride, ... below y1 (interleaved lines). The band's sums cover
    /// [y0, y1) with the lines not rendered left at zero.
    pub fn render_strided(
        &mut self,
        params: &FrameParams,
        y0: u32,
        y1: u32,
        stride: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band> {
        let stride = stride.max(1);
        let (width, height) = (params.width, params.height);
        let y1 = y1.min(height);
        let y0 = y0.min(y1);
        self.ensure_frame_buffers(width, height)?;
        // Compiling a kernel variant happens once; it is not part of the band's time.
        let (pipeline, layout) = self.kernel(self.kernel_defines(params))?;
        let wall = Instant::now();
        let (accum, stats, readback) = match &self.frame_buffers {
            Some((_, _, a, s, r)) => ((a.buffer, a.address), (s.buffer, s.address), r.buffer),
            None => unreachable!("frame buffers were just created"),
        };

        // Per-render parameters.
        let mut g = self.scene.globals;
        g.accum = accum.1;
        g.stats = stats.1;
        let cam = &params.camera;
        let m = cam.camera_to_world;
        let (right, up, forward) = (
            m.x_axis.truncate().normalize(),
            m.y_axis.truncate().normalize(),
            -m.z_axis.truncate().normalize(),
        );
        let tan_half = (cam.yfov * 0.5).tan();
        let aspect = width as f32 / height.max(1) as f32;
        let origin = m.w_axis.truncate();
        g.cam_origin = [origin.x, origin.y, origin.z, cam.aperture_radius];
        g.cam_right = [right.x, right.y, right.z, tan_half * aspect];
        g.cam_up = [up.x, up.y, up.z, tan_half];
        g.cam_forward = [forward.x, forward.y, forward.z, cam.focus_distance];
        g.dims[0] = width;
        g.dims[1] = height;
        g.params = [
            params.max_depth.max(1),
            params.frame,
            params.seed,
            params.rr_depth,
        ];
        self.globals_buffer.mapped()[..std::mem::size_of::<Globals>()]
            .copy_from_slice(bytemuck::bytes_of(&g));
        let globals_address = self.globals_buffer.address;

        let row_bytes = width as u64 * 16;
        let band_offset = y0 as u64 * row_bytes;
        let band_size = (y1 - y0) as u64 * row_bytes;
        let mut band = Band {
            y0,
            y1,
            ..Default::default()
        };
        if band_size == 0 {
            return Ok(band);
        }
        let compute_barrier = |d: &ash::Device,
                               cb: vk::CommandBuffer,
                               src: vk::PipelineStageFlags,
                               src_access: vk::AccessFlags| unsafe {
            let barrier = vk::MemoryBarrier::default()
                .src_access_mask(src_access)
                .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE);
            d.cmd_pipeline_barrier(
                cb,
                src,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::DependencyFlags::empty(),
                &[barrier],
                &[],
                &[],
            );
        };
        self.submit(|d, cb| unsafe {
            d.cmd_fill_buffer(cb, accum.0, band_offset, band_size, 0);
            d.cmd_fill_buffer(cb, stats.0, 0, vk::WHOLE_SIZE, 0);
            compute_barrier(
                d,
                cb,
                vk::PipelineStageFlags::TRANSFER,
                vk::AccessFlags::TRANSFER_WRITE,
            );
        })?;

        let spp = params.spp;
        let per_pass = params.samples_per_pass.max(1);
        let groups = (width.div_ceil(8), (y1 - y0).div_ceil(stride).div_ceil(8));
        let query_pool = self.query_pool;
        let period = self.ctx.properties.limits.timestamp_period as f64;
        let mut begin = 0;
        while begin < spp {
            let end = (begin + per_pass).min(spp);
            let push = Push {
                globals: globals_address,
                y0,
                y1,
                sample_begin: begin,
                sample_end: end,
                stride,
                _pad: 0,
            };
            self.submit(|d, cb| unsafe {
                // Earlier passes wrote the accumulation buffer.
                compute_barrier(
                    d,
                    cb,
                    vk::PipelineStageFlags::COMPUTE_SHADER,
                    vk::AccessFlags::SHADER_WRITE,
                );
                if let Some(q) = query_pool {
                    d.cmd_reset_query_pool(cb, q, 0, 2);
                    d.cmd_write_timestamp(cb, vk::PipelineStageFlags::TOP_OF_PIPE, q, 0);
                }
                d.cmd_bind_pipeline(cb, vk::PipelineBindPoint::COMPUTE, pipeline);
                d.cmd_push_constants(
                    cb,
                    layout,
                    vk::ShaderStageFlags::COMPUTE,
                    0,
                    bytemuck::bytes_of(&push),
                );
                d.cmd_dispatch(cb, groups.0, groups.1, 1);
                if let Some(q) = query_pool {
                    d.cmd_write_timestamp(cb, vk::PipelineStageFlags::BOTTOM_OF_PIPE, q, 1);
                }
            })?;
            if let Some(q) = query_pool {
                let mut ts = [0u64; 2];
                unsafe {
                    self.ctx.device.get_query_pool_results(
                        q,
                        0,
                        &mut ts,
                        vk::QueryResultFlags::TYPE_64,
                    )
                }
                .ctx("reading timestamps")?;
                band.gpu_time +=
                    Duration::from_nanos((ts[1].saturating_sub(ts[0]) as f64 * period) as u64);
            }
            begin = end;
            progress(end);
        }

        self.submit(|d, cb| unsafe {
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
                .src_offset(band_offset)
                .dst_offset(0)
                .size(band_size);
            d.cmd_copy_buffer(cb, accum.0, readback, &[region]);
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
        })?;

        let Some((_, _, _, stats_buf, readback_buf)) = self.frame_buffers.as_mut() else {
            unreachable!()
        };
        let data: &[[f32; 4]] = bytemuck::cast_slice(&readback_buf.mapped()[..band_size as usize]);
        band.sums = data.iter().map(|p| [p[0], p[1], p[2]]).collect();
        let counters: &[u32] = bytemuck::cast_slice(stats_buf.mapped());
        band.rejected_samples = counters[0] as u64;
        band.line_rays = counters[4 + y0 as usize..4 + y1 as usize]
            .iter()
            .map(|&r| r as u64)
            .collect();
        band.rays = band.line_rays.iter().sum();
        band.wall_time = wall.elapsed();
        Ok(band)
    }
}

impl BandTracer for Tracer {
    fn render_band(
        &mut self,
        params: &FrameParams,
        y0: u32,
        y1: u32,
        progress: &mut dyn FnMut(u32),
    ) -> std::result::Result<Band, TracerError> {
        self.render(params, y0, y1, progress)
            .map_err(|e| Box::new(e) as TracerError)
    }
}

impl Drop for Tracer {
    fn drop(&mut self) {
        let device = self.ctx.device.clone();
        unsafe {
            let _ = device.device_wait_idle();
        }
        self.destroy_frame_buffers();
        let mut list = std::mem::take(&mut self.scene.list);
        for b in &mut list {
            b.destroy(&device, &mut self.allocator);
        }
        self.globals_buffer.destroy(&device, &mut self.allocator);
        for k in self.kernels.values() {
            k.destroy(&device);
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

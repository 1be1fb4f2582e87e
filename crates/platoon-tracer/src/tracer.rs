//! A tracer: one Vulkan device holding a copy of the scene, rendering bands of lines.

use std::collections::HashMap;

use ash::vk;
use gpu_allocator::MemoryLocation;
use platoon_core::flatten::arrays::SceneArray;
use platoon_core::flatten::commit::{Commit, SceneHeader};
use platoon_core::flatten::GpuScene;
use platoon_core::frame::FrameParams;
use platoon_core::{KernelVariant, SceneFeatures};

use crate::buffer::GpuBuffer;
use crate::context::Context;
use crate::device_info::DeviceInfo;
use crate::globals::Globals;
use crate::gpu::Gpu;
use crate::kernel::Sampling;
use crate::memory::{self, ArrayPath, MemoryPath, SceneDescriptors, SCENE_ARRAYS};
use crate::memory_budget;
use crate::method::MethodPasses;
use crate::ray_query::Traversal;
use crate::structures::{SceneShape, Structures};
use crate::Result;

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
    /// Paths the streaming path tracer keeps in flight (`PathKernel::Streaming`); by default
    /// a number for the kind of device. Fewer than a band's pixels make slots take pixel after
    /// pixel.
    pub stream_slots: Option<u32>,
    /// Device memory the scene's arrays may take, in bytes (below what the device has): a
    /// scene over it is refused before upload (`memory_budget`).
    pub memory_limit: Option<u64>,
    /// How the kernels find what a ray hits: platoon's own traversal or the device's ray
    /// queries (`ray_query.rs`; refused on a device that offers none).
    pub traversal: Traversal,
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
    pub(crate) gpu: Gpu,
    pub(crate) scene: SceneBuffers,
    pub(crate) globals_buffer: GpuBuffer,
    pub(crate) frame_buffers: Option<(u32, u32, GpuBuffer, GpuBuffer, GpuBuffer)>,
    /// The device side of each rendering method used so far, by name (`method::passes_of`).
    pub(crate) methods: HashMap<&'static str, Box<dyn MethodPasses>>,
    pub(crate) features: SceneFeatures,
    pub(crate) sampling: Sampling,
    pub(crate) memory: MemoryPath,
    /// The device denoiser's planes (filter.rs), made on its first frame.
    pub(crate) filter_planes: Option<GpuBuffer>,
    /// The scene's acceleration structures, where the kernels trace with ray queries.
    pub(crate) structures: Option<Structures>,
}

// Vulkan handles are used from one thread at a time; the tracer moves to its own thread.
unsafe impl Send for Tracer {}

impl Tracer {
    pub fn new(options: &TracerOptions, scene: &GpuScene) -> Result<Tracer> {
        let mut tracer = Tracer::without_arrays(options, scene)?;
        let arrays = memory::scene_array_bytes(scene);
        let writes: Vec<(usize, u64, &[u8])> = arrays
            .iter()
            .enumerate()
            .filter(|(_, d)| !d.is_empty())
            .map(|(i, d)| (i, 0, *d))
            .collect();
        tracer.write_arrays(&writes)?;
        if tracer.gpu.ctx.ray_queries() {
            tracer.build_structures(SceneShape::of(scene))?;
        }
        tracer.bind_scene_arrays()?;
        Ok(tracer)
    }

    /// The device address of this tracer's triangle positions: what the structures are
    /// built from.
    fn positions(&self) -> u64 {
        self.scene.list[SceneArray::TrianglePositions.index()].address
    }

    /// The scene's acceleration structures, from the triangle positions this tracer holds.
    fn build_structures(&mut self, shape: SceneShape) -> Result<()> {
        let positions = self.positions();
        self.structures = Some(Structures::build(&mut self.gpu, shape, positions)?);
        Ok(())
    }

    /// The structures brought to the scene after `commit` (its arrays written and bound), the
    /// descriptor set naming a new top level.
    pub(crate) fn follow_with_structures(&mut self, commit: &Commit) -> Result<()> {
        let positions = self.positions();
        let Some(structures) = self.structures.as_mut() else {
            return Ok(());
        };
        if structures.follow(&mut self.gpu, commit, positions)? {
            let top = structures.top();
            if let Some(d) = &self.scene.descriptors {
                d.write_structure(self.gpu.device(), top);
            }
        }
        Ok(())
    }

    /// Tracers for `options`, each holding `scene`, which gives up its host copy of each large
    /// array (`GpuScene::release`) once every tracer has it: the host never holds the scene's
    /// arrays and a device's copy of them whole at once (on a CPU device the device's memory is
    /// the host's). For a render that reads the scene on its devices only (a still of the path
    /// tracer): the released arrays are empty after.
    pub fn new_releasing(options: &[TracerOptions], scene: &mut GpuScene) -> Result<Vec<Tracer>> {
        let mut tracers = options
            .iter()
            .map(|o| Tracer::without_arrays(o, scene))
            .collect::<Result<Vec<_>>>()?;
        // What the structures are built from, kept past the release of the arrays.
        let shape = tracers
            .iter()
            .any(|t| t.gpu.ctx.ray_queries())
            .then(|| SceneShape::of(scene));
        for (i, info) in SCENE_ARRAYS.iter().enumerate() {
            let bytes = scene.bytes_of(info.array);
            if !bytes.is_empty() {
                for t in &mut tracers {
                    t.write_arrays(&[(i, 0, bytes)])?;
                }
            }
            scene.release(info.array);
        }
        for t in &mut tracers {
            if let (Some(shape), true) = (&shape, t.gpu.ctx.ray_queries()) {
                t.build_structures(shape.clone())?;
            }
            t.bind_scene_arrays()?;
        }
        Ok(tracers)
    }

    /// A tracer with `scene`'s arrays made (their memory checked and allocated, nothing
    /// written yet) and its header read.
    fn without_arrays(options: &TracerOptions, scene: &GpuScene) -> Result<Tracer> {
        let ctx = Context::new(
            options.device,
            options.validation,
            options.lavapipe_threads,
            options.traversal,
            scene.triangle_count as u64,
        )?;
        let mut gpu = Gpu::new(ctx)?;
        gpu.stream_slots = options.stream_slots;
        let globals_buffer = gpu.buffer(
            "globals",
            std::mem::size_of::<Globals>() as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let mut tracer = Tracer {
            gpu,
            scene: SceneBuffers {
                list: Vec::new(),
                globals: Globals::default(),
                paths: Vec::new(),
                descriptors: None,
            },
            globals_buffer,
            frame_buffers: None,
            methods: HashMap::new(),
            features: scene.features,
            sampling: options.sampling,
            memory: options.memory,
            filter_planes: None,
            structures: None,
        };
        tracer.check_memory(scene, options.memory_limit)?;
        for (info, data) in SCENE_ARRAYS.iter().zip(memory::scene_array_bytes(scene)) {
            let buffer = tracer.array_buffer(info.name, data.len() as u64)?;
            tracer.scene.list.push(buffer);
        }
        tracer.refresh_globals(&scene.header());
        Ok(tracer)
    }

    /// Chooses each scene array's memory path from its buffer's size and binds the arrays.
    /// Called again after a buffer was replaced: while every array keeps its path the bindings
    /// are rewritten in place and the kernels stay (a game adding an instance must not wait for
    /// a recompile); a changed path makes a new set and new kernels.
    pub(crate) fn bind_scene_arrays(&mut self) -> Result<()> {
        let device = self.gpu.device().clone();
        let sizes: Vec<u64> = self.scene.list.iter().map(|b| b.size).collect();
        let limits = self.gpu.ctx.info.memory_limits();
        let paths = memory::choose(&sizes, &limits, self.memory);
        let buffers: Vec<vk::Buffer> = self.scene.list.iter().map(|b| b.buffer).collect();
        self.gpu.wait_idle()?;
        if let Some(d) = self.scene.descriptors.as_mut() {
            if paths == self.scene.paths {
                return d.write(&device, &buffers, &paths);
            }
        }
        if let Some(d) = self.scene.descriptors.take() {
            self.gpu.drop_kernels();
            d.destroy(&device);
        }
        self.scene.paths = paths;
        self.scene.descriptors = Some(SceneDescriptors::new(
            &device,
            &buffers,
            &self.scene.paths,
            self.globals_buffer.buffer,
            self.structures.as_ref().map(Structures::top),
        )?);
        Ok(())
    }

    /// The buffers method `name` (its `RenderMethod::name`) left after its last band, for tests
    /// to compare with the CPU's (`MethodPasses::read_back`); empty when it has not rendered.
    pub fn method_buffers(&mut self, name: &str) -> Result<Vec<Vec<u8>>> {
        match self.methods.get_mut(name) {
            Some(passes) => passes.read_back(&mut self.gpu),
            None => Ok(Vec::new()),
        }
    }

    /// Compute pipelines built so far (a kernel variant compiled by the driver, or compiled
    /// again after its bindings changed).
    pub fn pipelines_built(&self) -> u32 {
        self.gpu.pipelines_built()
    }

    pub fn device_info(&self) -> &DeviceInfo {
        &self.gpu.ctx.info
    }

    /// What this tracer's acceleration structures went through (None without ray queries).
    pub fn structure_counts(&self) -> Option<crate::StructureCounts> {
        self.structures.as_ref().map(|s| s.counts())
    }

    /// How this tracer's kernels find what a ray hits (its options' choice as the device
    /// resolved it).
    pub fn traversal(&self) -> Traversal {
        match self.gpu.ctx.ray_queries() {
            true => Traversal::RayQuery,
            false => Traversal::Own,
        }
    }

    /// Warnings and errors reported by the validation layer so far (empty without validation).
    pub fn validation_messages(&self) -> Vec<String> {
        self.gpu
            .ctx
            .validation_messages
            .lock()
            .map(|m| m.clone())
            .unwrap_or_default()
    }

    /// Defines of the kernels this tracer runs for `params` (the kernel variant, the estimator
    /// and the memory path of each scene array).
    pub fn kernel_defines(&self, params: &FrameParams) -> Vec<&'static str> {
        let mut d = KernelVariant::new(self.features, params).defines();
        d.extend(self.sampling.define());
        d.extend(memory::defines(&self.scene.paths));
        if self.structures.is_some() {
            d.push(crate::ray_query::DEFINE);
        }
        d
    }

    /// A device-local buffer for a scene array of `capacity` bytes.
    /// On a CPU device (lavapipe) all memory is the host's: the arrays live in mapped memory
    /// and are written in place, with no staging copy and no transfer to wait for.
    pub(crate) fn array_buffer(&mut self, name: &str, capacity: u64) -> Result<GpuBuffer> {
        let mut usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER
            | vk::BufferUsageFlags::TRANSFER_DST;
        if self.gpu.ctx.ray_queries() {
            // With ray queries the triangle positions are what the structures are built from.
            usage |= vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR;
        }
        let location = if self.gpu.ctx.info.cpu {
            MemoryLocation::CpuToGpu
        } else {
            MemoryLocation::GpuOnly
        };
        self.gpu.buffer(name, capacity, usage, location)
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
        self.gpu.write_buffers(&staged)
    }

    /// Refuses `s` when its arrays do not fit this device (or `limit`), before any is made.
    fn check_memory(&self, s: &GpuScene, limit: Option<u64>) -> Result<()> {
        let arrays: Vec<(&str, u64)> = SCENE_ARRAYS
            .iter()
            .zip(memory::scene_array_bytes(s))
            .map(|(a, bytes)| (a.name, bytes.len() as u64))
            .collect();
        let info = &self.gpu.ctx.info;
        let budget = memory_budget::budget(info, limit, memory_budget::host_memory());
        memory_budget::check(info, &arrays, budget, limit.is_some_and(|l| l <= budget))
    }

    /// Device memory this tracer's buffers take, in bytes (scene arrays, frame buffers, method
    /// buffers; the allocator reserves it in blocks of 64 MiB and more).
    pub fn device_bytes(&self) -> u64 {
        self.gpu.allocator.generate_report().total_allocated_bytes
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
        let pixels = width as u64 * height as u64 * 16;
        let accum = self.gpu.buffer(
            "accumulation",
            pixels,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let stats = self.gpu.buffer(
            "stats",
            (4 + height as u64) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let readback = self.gpu.buffer(
            "readback",
            pixels,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        self.frame_buffers = Some((width, height, accum, stats, readback));
        Ok(())
    }

    fn destroy_frame_buffers(&mut self) {
        if let Some((_, _, a, s, r)) = self.frame_buffers.take() {
            for mut b in [a, s, r] {
                self.gpu.destroy_buffer(&mut b);
            }
        }
    }
}

impl Drop for Tracer {
    fn drop(&mut self) {
        let _ = self.gpu.wait_idle();
        self.destroy_frame_buffers();
        if let Some(mut b) = self.filter_planes.take() {
            self.gpu.destroy_buffer(&mut b);
        }
        for m in self.methods.values_mut() {
            m.destroy(&mut self.gpu);
        }
        if let Some(mut s) = self.structures.take() {
            s.destroy(&mut self.gpu);
        }
        for b in &mut self.scene.list {
            self.gpu.destroy_buffer(b);
        }
        self.gpu.destroy_buffer(&mut self.globals_buffer);
        // Pipelines before the descriptor set layout their layouts were made from; the device
        // itself goes with `gpu`, dropped after this.
        self.gpu.drop_kernels();
        if let Some(d) = self.scene.descriptors.take() {
            d.destroy(self.gpu.device());
        }
    }
}

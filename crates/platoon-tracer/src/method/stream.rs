//! The streaming path tracer on one device (`PathKernel::Streaming`; shaders/path/stream/): a
//! stream of path slots, each following one pixel's samples in order, advanced by iterations of
//! regenerate, extend, shade and connect over queues that atomic counters compact, the sizes
//! of the dispatches read by the device itself (indirect dispatch). A pass records iterations
//! in growing batches until one finds no live slot.

use std::time::Duration;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use gpu_allocator::MemoryLocation;
use platoon_core::frame::FrameParams;

use super::Recorder;
use crate::buffer::GpuBuffer;
use crate::dispatch::{record_dispatch, record_dispatch_indirect, record_to_host};
use crate::globals::Push;
use crate::gpu::Gpu;
use crate::Result;

pub(crate) const REGENERATE: &str = "path/stream/regenerate.comp";
pub(crate) const COMPACT: &str = "path/stream/compact.comp";
pub(crate) const QUEUE: &str = "path/stream/queue.comp";
pub(crate) const EXTEND: &str = "path/stream/extend.comp";
pub(crate) const SHADE: &str = "path/stream/shade.comp";
pub(crate) const CONNECT: &str = "path/stream/connect.comp";
pub(crate) const LISTED: &str = "path/stream/listed.comp";
pub(crate) const KERNELS: [&str; 6] = [REGENERATE, COMPACT, QUEUE, EXTEND, SHADE, CONNECT];

/// SptSlot, SptHit and SptShadow of shaders/path/stream/stream.glsl ("Must match GPU side"):
/// here for their sizes. A slot is allocated at its largest (a medium and a light pass's
/// share); the kernels' stride is what their variant holds.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct StreamSlot([[u32; 4]; 7]);
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct StreamHit([[u32; 4]; 2]);
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct StreamShadow([[u32; 4]; 3]);
/// SptControl: three dispatch sizes (x, y, z, pad), the queues' counters and lengths.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct StreamControl {
    extend_args: [u32; 4],
    connect_args: [u32; 4],
    regenerate_args: [u32; 4],
    live_appended: u32,
    ended_appended: u32,
    shadow_appended: u32,
    live_count: u32,
    ended_count: u32,
    shadow_count: u32,
    next_cell: u32,
    iterations: u32,
    listed: u32,
    _pad: [u32; 3],
}
const _: () = assert!(std::mem::size_of::<StreamSlot>() == 112);
const _: () = assert!(std::mem::size_of::<StreamHit>() == 32);
const _: () = assert!(std::mem::size_of::<StreamShadow>() == 48);
const _: () = assert!(std::mem::size_of::<StreamControl>() == 96);
/// Offsets of the dispatch sizes in the control buffer.
const EXTEND_ARGS: u64 = 0;
const CONNECT_ARGS: u64 = 16;
const REGENERATE_ARGS: u64 = 32;

/// The dispatches of one iteration, in order.
const STAGES: [&str; 7] = [
    "regenerate",
    "compact",
    "queue",
    "extend",
    "shade",
    "queue",
    "connect",
];

/// Workgroup size of the stream kernels (STREAM_GROUP in stream.glsl).
const GROUP: u32 = 64;

/// Push words (stream.glsl): slots, cells, the queue step, whether regeneration takes every
/// slot, whether the cells are the listed pixels.
const SLOTS: usize = 0;
const CELLS: usize = 1;
const STEP: usize = 2;
const ALL: usize = 3;
const LIST: usize = 4;

/// Paths in flight on a device: `TracerOptions::stream_slots`, else `PLATOON_STREAM_SLOTS`
/// (measurements), else enough full SIMD groups for every core of a CPU, enough threads for a
/// GPU.
fn max_slots(gpu: &Gpu) -> u32 {
    let set = gpu.stream_slots.or_else(|| {
        std::env::var("PLATOON_STREAM_SLOTS")
            .ok()
            .and_then(|v| v.parse::<u32>().ok())
    });
    if let Some(n) = set {
        return n.max(1);
    }
    if gpu.ctx.info.cpu {
        1 << 14
    } else {
        1 << 20
    }
}

struct StreamBuffers {
    capacity: u32,
    /// Pixels the listed-pixel buffer holds.
    list_capacity: u32,
    /// Slots, hits, shadow rays, the queues (live, ended), the control block, the listed
    /// pixels (binding order).
    buffers: [GpuBuffer; 6],
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
}

impl StreamBuffers {
    fn new(gpu: &mut Gpu, capacity: u32, list_capacity: u32) -> Result<StreamBuffers> {
        let n = capacity as u64;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let sized = |size: usize| n * size as u64;
        let buffers = [
            gpu.buffer(
                "stream slots",
                sized(std::mem::size_of::<StreamSlot>()),
                storage,
                MemoryLocation::GpuOnly,
            )?,
            gpu.buffer(
                "stream hits",
                sized(std::mem::size_of::<StreamHit>()),
                storage,
                MemoryLocation::GpuOnly,
            )?,
            gpu.buffer(
                "stream shadow rays",
                sized(std::mem::size_of::<StreamShadow>()),
                storage,
                MemoryLocation::GpuOnly,
            )?,
            gpu.buffer(
                "stream queues",
                sized(2 * 4),
                storage,
                MemoryLocation::GpuOnly,
            )?,
            // Read by the host after each batch (how many iterations found live slots).
            gpu.buffer(
                "stream control",
                std::mem::size_of::<StreamControl>() as u64,
                storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
                MemoryLocation::GpuToCpu,
            )?,
            gpu.buffer(
                "stream listed pixels",
                list_capacity as u64 * 4,
                storage,
                MemoryLocation::GpuOnly,
            )?,
        ];
        let handles = buffers.each_ref().map(|b| b.buffer);
        let (pool, set) = gpu.method_set(&handles)?;
        Ok(StreamBuffers {
            capacity,
            list_capacity,
            buffers,
            pool,
            set,
        })
    }

    fn destroy(mut self, gpu: &mut Gpu) {
        unsafe { gpu.device().destroy_descriptor_pool(self.pool, None) };
        for b in &mut self.buffers {
            gpu.destroy_buffer(b);
        }
    }

    fn control(&mut self) -> StreamControl {
        let bytes = &self.buffers[4].mapped()[..std::mem::size_of::<StreamControl>()];
        bytemuck::pod_read_unaligned(bytes)
    }
}

/// The stream of one device, kept from pass to pass (grown when a band needs more slots).
#[derive(Default)]
pub(crate) struct StreamPasses {
    buffers: Option<StreamBuffers>,
}

impl StreamPasses {
    /// The samples [push.sample_begin, push.sample_end) of every pixel of the band.
    pub fn pass(&mut self, rec: &mut Recorder, push: &Push) -> Result<Duration> {
        let cells = band_cells(rec.params, push);
        self.run(rec, push, cells, None)
    }

    /// The same for the band's pixels the megakernel flagged (`flagged` of them): listed by
    /// listed.comp first, then streamed alone.
    pub fn pass_listed(
        &mut self,
        rec: &mut Recorder,
        push: &Push,
        flagged: u32,
    ) -> Result<Duration> {
        let cells = band_cells(rec.params, push);
        self.run(rec, push, flagged, Some(cells))
    }

    /// Streams `cells` cells: the band's (`band` None), or the pixels listed from the band's
    /// `band` cells.
    fn run(
        &mut self,
        rec: &mut Recorder,
        push: &Push,
        cells: u32,
        band: Option<u32>,
    ) -> Result<Duration> {
        if cells == 0 {
            return Ok(Duration::ZERO);
        }
        let slots = cells.min(max_slots(rec.gpu));
        let list = band.unwrap_or(0);
        if self
            .buffers
            .as_ref()
            .is_none_or(|b| b.capacity < slots || b.list_capacity < list)
        {
            rec.gpu.wait_idle()?;
            let (mut capacity, mut list_capacity) = (slots, list.max(1));
            if let Some(old) = self.buffers.take() {
                capacity = capacity.max(old.capacity);
                list_capacity = list_capacity.max(old.list_capacity);
                old.destroy(rec.gpu);
            }
            self.buffers = Some(StreamBuffers::new(rec.gpu, capacity, list_capacity)?);
        }
        let buffers = self.buffers.as_mut().expect("made above");
        let (slot_buffer, control, set) = (
            buffers.buffers[0].buffer,
            buffers.buffers[4].buffer,
            buffers.set,
        );
        let (regenerate, compact, queue) = (
            rec.kernel(REGENERATE)?,
            rec.kernel(COMPACT)?,
            rec.kernel(QUEUE)?,
        );
        let (extend, shade, connect) = (
            rec.kernel(EXTEND)?,
            rec.kernel(SHADE)?,
            rec.kernel(CONNECT)?,
        );
        let listed = match band {
            Some(_) => Some(rec.kernel(LISTED)?),
            None => None,
        };
        let mut words = *push;
        words.method[SLOTS] = slots;
        words.method[CELLS] = cells;
        words.method[LIST] = band.is_some() as u32;
        // The push words of iteration j's dispatches: the kernels share them; the queue steps
        // add theirs.
        let iteration = |j: u32| {
            let mut w = words;
            w.method[ALL] = (j == 0) as u32;
            let (mut step0, mut step1) = (w, w);
            step0.method[STEP] = 0;
            step1.method[STEP] = 1;
            (w, step0, step1)
        };
        let every_slot = (slots.div_ceil(GROUP), 1);
        // Stage j of iteration `it`: STAGES.
        let record = |d: &ash::Device, cb: vk::CommandBuffer, it: u32, stage: usize| unsafe {
            let (w, step0, step1) = iteration(it);
            match stage {
                0 if it == 0 => record_dispatch(d, cb, regenerate, &w, every_slot),
                0 => record_dispatch_indirect(d, cb, regenerate, &w, control, REGENERATE_ARGS),
                1 => record_dispatch(d, cb, compact, &w, every_slot),
                2 => record_dispatch(d, cb, queue, &step0, (1, 1)),
                3 => record_dispatch_indirect(d, cb, extend, &w, control, EXTEND_ARGS),
                4 => record_dispatch_indirect(d, cb, shade, &w, control, EXTEND_ARGS),
                5 => record_dispatch(d, cb, queue, &step1, (1, 1)),
                _ => record_dispatch_indirect(d, cb, connect, &w, control, CONNECT_ARGS),
            }
        };
        let bind = |d: &ash::Device, cb: vk::CommandBuffer| unsafe {
            d.cmd_bind_descriptor_sets(
                cb,
                vk::PipelineBindPoint::COMPUTE,
                regenerate.1,
                1,
                &[set],
                &[],
            );
        };
        // Every slot fresh, every counter zero; a listed pass lists its pixels first (over the
        // band's cells, in range mode).
        let mut list_words = words;
        list_words.method[CELLS] = list;
        list_words.method[LIST] = 0;
        let mut time = rec.gpu.timed(|d, cb| unsafe {
            // Whole slots whatever the variant's stride (80 bytes, 96 with a medium, 112 with a
            // light pass's share): a slot left as a pass ended must not seem to hold a path.
            d.cmd_fill_buffer(cb, slot_buffer, 0, vk::WHOLE_SIZE, 0);
            d.cmd_fill_buffer(cb, control, 0, vk::WHOLE_SIZE, 0);
            let barrier = vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::SHADER_READ | vk::AccessFlags::SHADER_WRITE);
            d.cmd_pipeline_barrier(
                cb,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::COMPUTE_SHADER,
                vk::DependencyFlags::empty(),
                &[barrier],
                &[],
                &[],
            );
            if let Some(listed) = listed {
                bind(d, cb);
                record_dispatch(d, cb, listed, &list_words, (list.div_ceil(GROUP), 1));
            }
        })?;

        if std::env::var_os("PLATOON_STREAM_PROFILE").is_some() {
            // Experiment: every dispatch in a submission of its own, device time per stage.
            let mut stage = [Duration::ZERO; STAGES.len()];
            let mut it = 0u32;
            loop {
                for (k, st) in stage.iter_mut().enumerate() {
                    *st += rec.gpu.timed(|d, cb| {
                        bind(d, cb);
                        record(d, cb, it, k);
                        unsafe { record_to_host(d, cb) };
                    })?;
                }
                it += 1;
                if buffers.control().iterations < it {
                    break;
                }
            }
            eprint!("stream pass: {it} iterations;");
            for (n, t) in STAGES.iter().zip(&stage) {
                eprint!(" {n} {:.1} ms", t.as_secs_f64() * 1e3);
            }
            eprintln!();
            return Ok(stage.iter().sum());
        }

        let mut recorded = 0u32;
        let mut batch = 8u32;
        loop {
            time += rec.gpu.timed(|d, cb| {
                bind(d, cb);
                for it in recorded..recorded + batch {
                    for stage in 0..STAGES.len() {
                        record(d, cb, it, stage);
                    }
                }
                unsafe { record_to_host(d, cb) };
            })?;
            recorded += batch;
            // An iteration that found no live slot ends the pass: every pixel has its samples.
            if buffers.control().iterations < recorded {
                return Ok(time);
            }
            batch = (batch * 2).min(128);
        }
    }

    pub fn destroy(&mut self, gpu: &mut Gpu) {
        if let Some(b) = self.buffers.take() {
            b.destroy(gpu);
        }
    }
}

/// The band's cells: its pixels in range mode, whole lines of `width` in interleaved mode
/// (stream.glsl's band_cell_pixel).
fn band_cells(params: &FrameParams, push: &Push) -> u32 {
    if push.stride <= 1 {
        push.pixel_end - push.pixel_begin
    } else {
        params.width * (push.y1 - push.y0).div_ceil(push.stride)
    }
}

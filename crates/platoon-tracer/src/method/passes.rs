//! What every method's device side implements (`MethodPasses`), what a band's passes record
//! with (`Recorder`), and the buffers they grow on demand (`ensure`): the public device-method
//! API (`platoon_tracer::device`), which the built-in methods use as a method from outside does.

use std::time::Duration;

use ash::vk;
use gpu_allocator::MemoryLocation;
use platoon_core::frame::{FrameParams, MethodReport, PixelData, Span};

use crate::buffer::GpuBuffer;
use crate::dispatch::{record_dispatch, Dispatchable};
use crate::globals::{Globals, Push, METHOD_WORDS};
use crate::gpu::Gpu;
use crate::memory::SceneDescriptors;
use crate::Result;

/// What a band's passes record with: the frame, the device, and the method's kernels in the
/// render's variant, resolved once for the band (by entry file); a kernel of the variant not
/// resolved is built when first asked for (a fallback's). The band's counters (`Stats` of
/// shaders/common/scene.glsl), host-visible between submissions.
pub struct Recorder<'a> {
    pub params: &'a FrameParams,
    pub gpu: &'a mut Gpu,
    pub(crate) kernels: Vec<(&'static str, Dispatchable)>,
    pub(crate) defines: Vec<&'static str>,
    pub(crate) scene: &'a SceneDescriptors,
    pub(crate) stats: &'a mut GpuBuffer,
    /// Passes a method could not finish in its own kernel and finished another way (the
    /// megakernel past the device's loop limit): `Band::kernel_fallbacks`.
    pub fallbacks: u32,
    /// The frame's root block (`Globals`), mapped, and what it holds.
    pub(crate) globals: &'a mut GpuBuffer,
    pub(crate) globals_block: Globals,
}

impl Recorder<'_> {
    /// The kernel of the entry file `entry` in the render's variant.
    pub fn kernel(&mut self, entry: &'static str) -> Result<Dispatchable> {
        if let Some(k) = self.kernels.iter().find(|k| k.0 == entry) {
            return Ok(k.1);
        }
        let k = self.gpu.kernel((entry, self.defines.clone()), self.scene)?;
        self.kernels.push((entry, k));
        Ok(k)
    }

    /// Whether the device is a CPU (lavapipe): a method may choose its kernels by it.
    pub fn cpu(&self) -> bool {
        self.gpu.ctx.info.cpu
    }

    /// Dispatches the kernel of `entry` over `groups` workgroups with `push`, after the writes
    /// of the passes before it; its device time.
    pub fn dispatch(
        &mut self,
        entry: &'static str,
        push: &Push,
        groups: (u32, u32),
    ) -> Result<Duration> {
        let kernel = self.kernel(entry)?;
        self.gpu
            .timed(|d, cb| unsafe { record_dispatch(d, cb, kernel, push, groups) })
    }

    /// Workgroups of 8 x 8 invocations covering the band of `push` (its lines, every
    /// `stride`-th, across the frame's width): what `band_pixel` of shaders/common/scene.glsl
    /// reads a pixel from.
    pub fn band_groups(&self, push: &Push) -> (u32, u32) {
        let lines = (push.y1 - push.y0).div_ceil(push.stride.max(1));
        (self.params.width.div_ceil(8), lines.div_ceil(8))
    }

    /// Word `i` of the band's counters (read after the submission that wrote it).
    pub fn stat(&mut self, i: usize) -> u32 {
        bytemuck::cast_slice::<u8, u32>(self.stats.mapped())[i]
    }

    /// Sets word `i` of the band's counters (before the next submission).
    pub fn set_stat(&mut self, i: usize, value: u32) {
        bytemuck::cast_slice_mut::<u8, u32>(self.stats.mapped())[i] = value;
    }

    /// Points the next submissions' method buffers at `buffers` (a method that grew one while
    /// recording: layered hit buffers' queue and lists).
    pub fn set_method_buffers(&mut self, buffers: [u64; 4]) {
        self.globals_block.method_buffers = buffers;
        self.globals.mapped()[..std::mem::size_of::<Globals>()]
            .copy_from_slice(bytemuck::bytes_of(&self.globals_block));
    }
}

/// A rendering method on one device. The band (band.rs) clears the accumulation and the
/// method's `clears`, calls `begin_band`, then `pass` until the samples are in, then
/// `end_band`, and reads back the sums and `per_pixel`.
pub trait MethodPasses {
    /// The entry files of its kernels (shaders/, or the sources it registered) for `params` on
    /// a CPU device (`cpu`) or a GPU, built before the band's clock starts.
    fn kernels(&self, params: &FrameParams, cpu: bool) -> Vec<&'static str>;
    /// Makes or grows the buffers its kernels read for `params`; returns their addresses
    /// (Globals' method buffers; 0 where unused).
    fn prepare(&mut self, _gpu: &mut Gpu, _params: &FrameParams) -> Result<[u64; 4]> {
        Ok([0; 4])
    }
    /// Its push-constant words for `params`.
    fn push_words(&self, _params: &FrameParams) -> [u32; METHOD_WORDS] {
        [0; METHOD_WORDS]
    }
    /// Ranges of its buffers (buffer, offset, size) the band clears before its first pass.
    fn clears(&self, _params: &FrameParams, _span: Span) -> Vec<(vk::Buffer, u64, u64)> {
        Vec::new()
    }
    /// Samples one pass adds per pixel.
    fn samples_per_pass(&self, params: &FrameParams) -> u32 {
        params.samples_per_pass.max(1)
    }
    /// Work before the band's first pass; returns its device time.
    fn begin_band(&mut self, _rec: &mut Recorder, _push: &Push) -> Result<Duration> {
        Ok(Duration::ZERO)
    }
    /// One pass: the samples [push.sample_begin, push.sample_end) of the band's pixels, over
    /// `groups` workgroups of 8 x 8; returns its device time.
    fn pass(&mut self, rec: &mut Recorder, push: &Push, groups: (u32, u32)) -> Result<Duration>;
    /// Work after the band's last pass, on the sums its passes left (`push`'s samples are all
    /// the band took); returns its device time.
    fn end_band(&mut self, _rec: &mut Recorder, _push: &Push) -> Result<Duration> {
        Ok(Duration::ZERO)
    }
    /// What its passes report of the band (`Band::method_report`, of the method's own type),
    /// given the band's counters after its last pass.
    fn report(&mut self, _counters: &[u32]) -> MethodReport {
        MethodReport::default()
    }
    /// What the span leaves for the method's work after assembly (`Band::per_pixel`): records
    /// of the method's types.
    fn per_pixel(&mut self, _params: &FrameParams, _span: Span) -> PixelData {
        PixelData::default()
    }
    /// Its buffers as the last band left them, for tests to compare with the CPU's (layered
    /// hit buffers: the work words of every texel, the layers); empty for most methods.
    fn read_back(&mut self, _gpu: &mut Gpu) -> Result<Vec<Vec<u8>>> {
        Ok(Vec::new())
    }
    /// Frees its buffers.
    fn destroy(&mut self, _gpu: &mut Gpu) {}
}

/// The buffer in `slot` of at least `size` bytes, replaced when too small; its address.
pub fn ensure(
    gpu: &mut Gpu,
    slot: &mut Option<GpuBuffer>,
    name: &str,
    size: u64,
    location: MemoryLocation,
) -> Result<u64> {
    if let Some(b) = slot.as_ref() {
        if b.size >= size {
            return Ok(b.address);
        }
    }
    gpu.wait_idle()?;
    if let Some(mut old) = slot.take() {
        gpu.destroy_buffer(&mut old);
    }
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER
        | vk::BufferUsageFlags::TRANSFER_DST
        | vk::BufferUsageFlags::TRANSFER_SRC;
    let b = gpu.buffer(name, size, usage, location)?;
    let address = b.address;
    *slot = Some(b);
    Ok(address)
}

//! Layered hit buffers on one device (platoon_core::method::lhb): the tables (uploaded once per
//! scene), the work words (per texel a count or an offset, the prefix sum's partial sums, the
//! queue of large triangles' blocks), the layers; the build at the start of every band (each
//! tracer builds the same buffers: they are a pure function of the scene and the options;
//! `build`) with, in a living scene, the layers of what did not move kept between frames
//! (`kept`), and the image passes that look rays up in them (shaders/lhb/).

use std::sync::Arc;
use std::time::Duration;

use gpu_allocator::MemoryLocation;
use platoon_core::frame::{FrameParams, MethodReport};
use platoon_core::method::lhb::{LhbBuild, RasterVariant};

mod build;
mod kept;
mod state;

pub(crate) use state::LhbPasses;
use state::{
    lhb, queue_at, tables, BLOCKS, CAMERA, CAMERA_SAMPLES_PER_PASS, PREFIX, PROBE, RASTER,
    STAT_QUEUED,
};

use super::{ensure, MethodPasses, Recorder};
use crate::buffer::GpuBuffer;
use crate::globals::{Push, METHOD_WORDS};
use crate::gpu::Gpu;
use crate::Result;

impl LhbPasses {
    fn addresses(&self) -> [u64; 4] {
        let a = |b: &Option<GpuBuffer>| b.as_ref().map_or(0, |b| b.address);
        [a(&self.tables), a(&self.work), a(&self.layers), 0]
    }

    /// The work words with room for the queue.
    fn ensure_work(&mut self, gpu: &mut Gpu, params: &FrameParams) -> Result<()> {
        let o = &lhb(params).options;
        let words = queue_at(o.directions.count() as u64, o.resolution as u64)
            + 4 * self.queue_capacity as u64;
        ensure(
            gpu,
            &mut self.work,
            "lhb work",
            words * 4,
            MemoryLocation::GpuOnly,
        )?;
        Ok(())
    }

    fn ensure_layers(&mut self, gpu: &mut Gpu, layers: u64) -> Result<()> {
        ensure(
            gpu,
            &mut self.layers,
            "lhb layers",
            (layers * 8).max(16),
            MemoryLocation::GpuOnly,
        )?;
        Ok(())
    }
}

impl MethodPasses for LhbPasses {
    fn kernels(&self, params: &FrameParams, _cpu: bool) -> Vec<&'static str> {
        match (lhb(params).options.variant, tables(params).probes()) {
            (RasterVariant::Capacity, false) => vec![RASTER, BLOCKS, CAMERA],
            (RasterVariant::Exact, false) => vec![RASTER, BLOCKS, PREFIX, CAMERA],
            (RasterVariant::Capacity, true) => vec![RASTER, BLOCKS, PROBE],
            (RasterVariant::Exact, true) => vec![RASTER, BLOCKS, PREFIX, PROBE],
        }
    }

    /// The tables (uploaded when the frame names others); work and layers are the build's.
    fn prepare(&mut self, gpu: &mut Gpu, params: &FrameParams) -> Result<[u64; 4]> {
        let t = tables(params);
        if !self.uploaded.as_ref().is_some_and(|u| Arc::ptr_eq(u, t)) {
            let bytes: &[u8] = bytemuck::cast_slice(&t.words);
            ensure(
                gpu,
                &mut self.tables,
                "lhb tables",
                bytes.len() as u64,
                MemoryLocation::GpuOnly,
            )?;
            let buffer = self.tables.as_ref().expect("just ensured").buffer;
            gpu.write_buffers(&[(buffer, 0, bytes)])?;
            self.uploaded = Some(t.clone());
        }
        Ok(self.addresses())
    }

    /// Image passes: the lookup bounces.
    fn push_words(&self, params: &FrameParams) -> [u32; METHOD_WORDS] {
        let mut words = [0; METHOD_WORDS];
        words[0] = lhb(params).options.bounces;
        words
    }

    fn samples_per_pass(&self, params: &FrameParams) -> u32 {
        params.samples_per_pass.clamp(1, CAMERA_SAMPLES_PER_PASS)
    }

    /// The frame's buffers.
    fn begin_band(&mut self, rec: &mut Recorder, push: &Push) -> Result<Duration> {
        self.build(rec, push)?;
        Ok(self.build.time)
    }

    fn pass(&mut self, rec: &mut Recorder, push: &Push, groups: (u32, u32)) -> Result<Duration> {
        // A probe's tables carry queries (tests): its pass answers them instead.
        let entry = if tables(rec.params).probes() {
            PROBE
        } else {
            CAMERA
        };
        rec.dispatch(entry, push, groups)
    }

    /// What the build made and cost on this device; lookups of the image passes.
    fn report(&mut self, counters: &[u32]) -> MethodReport {
        let b = &self.build;
        MethodReport::of(&LhbBuild {
            layers: b.layers,
            exact: b.exact,
            lost: b.lost,
            blocks: b.blocks,
            bytes: b.bytes,
            seconds: b.time.as_secs_f64(),
            attempts: b.attempts,
            kept: b.kept,
            lookups: counters[STAT_QUEUED],
        })
    }

    /// Every texel's word (count, or with the exact variant the end of its layers) and the
    /// layers.
    fn read_back(&mut self, gpu: &mut Gpu) -> Result<Vec<Vec<u8>>> {
        let (Some(t), Some(work), Some(layers)) = (&self.uploaded, &self.work, &self.layers) else {
            return Ok(Vec::new());
        };
        let texels = t.words[0] as u64 * t.words[1] as u64 * t.words[1] as u64;
        let (work, layers, size) = (work.buffer, layers.buffer, layers.size);
        Ok(vec![
            gpu.read_buffer(work, 0, texels * 4)?,
            gpu.read_buffer(layers, 0, size)?,
        ])
    }

    fn destroy(&mut self, gpu: &mut Gpu) {
        let kept = self.statics.take().and_then(|s| s.counts);
        for mut b in [
            self.tables.take(),
            self.work.take(),
            self.layers.take(),
            kept,
        ]
        .into_iter()
        .flatten()
        {
            gpu.destroy_buffer(&mut b);
        }
        self.uploaded = None;
    }
}

//! The world cache on one device (`platoon_core::method::path::world_cache`): the frame's table
//! uploaded once (method buffer 0, read by the path kernels with WORLD_CACHE), and the band's
//! training paths (shaders/path/world_cache_train.comp) before its beauty passes, whose
//! records (method buffer 1, a vec4 per pixel) the band leaves per pixel.

use std::sync::Arc;
use std::time::Duration;

use gpu_allocator::MemoryLocation;
use platoon_core::frame::{FrameParams, Output, PixelData, Span};
use platoon_core::method::path::world_cache::{CacheTable, TrainingRecord};

use super::{ensure, Recorder};
use crate::buffer::GpuBuffer;
use crate::globals::Push;
use crate::gpu::Gpu;
use crate::Result;

pub(crate) const TRAIN: &str = "path/world_cache_train.comp";

#[derive(Default)]
pub(crate) struct WorldCachePasses {
    table: Option<GpuBuffer>,
    records: Option<GpuBuffer>,
    /// The table the buffer holds (uploaded once a frame: the frame's bands share it).
    uploaded: Option<Arc<CacheTable>>,
}

/// Whether the frame's paths train the cache: the beauty's (AOV and light passes only read it).
pub(crate) fn trains(params: &FrameParams) -> bool {
    params.method.path().world_cache.is_some() && params.output == Output::Radiance
}

impl WorldCachePasses {
    /// Uploads the frame's table and sizes the records; the method buffers' addresses.
    pub fn prepare(&mut self, gpu: &mut Gpu, params: &FrameParams) -> Result<[u64; 4]> {
        let Some(table) = &params.method.path().world_cache else {
            return Ok([0; 4]);
        };
        let bytes: &[u8] = bytemuck::cast_slice(&table.slots);
        let fresh = !self
            .uploaded
            .as_ref()
            .is_some_and(|t| Arc::ptr_eq(t, table));
        let grew = self
            .table
            .as_ref()
            .is_none_or(|b| b.size < bytes.len() as u64);
        let table_address = ensure(
            gpu,
            &mut self.table,
            "world cache",
            bytes.len() as u64,
            MemoryLocation::CpuToGpu,
        )?;
        if fresh || grew {
            let b = self.table.as_mut().expect("ensured just above");
            b.mapped()[..bytes.len()].copy_from_slice(bytes);
            self.uploaded = Some(Arc::clone(table));
        }
        let pixels = params.width as u64 * params.height as u64;
        let records = ensure(
            gpu,
            &mut self.records,
            "world cache records",
            pixels.max(1) * 16,
            MemoryLocation::GpuToCpu,
        )?;
        Ok([table_address, records, 0, 0])
    }

    /// The kernels' push words 2-4 (world_cache.glsl).
    pub fn push_words(params: &FrameParams, words: &mut [u32]) {
        if let Some(t) = &params.method.path().world_cache {
            words[2] = t.cell_size.to_bits();
            words[3] = t.slot_mask();
            words[4] = t.train_stride.max(1);
        }
    }

    /// The band's training paths, over its pixels; their device time.
    pub fn train(&mut self, rec: &mut Recorder, push: &Push) -> Result<Duration> {
        if !trains(rec.params) {
            return Ok(Duration::ZERO);
        }
        // One training path a training pixel: a sample range of one, so band_pixel runs it.
        let push = Push {
            sample_begin: 0,
            sample_end: 1,
            ..*push
        };
        let groups = rec.band_groups(&push);
        rec.dispatch(TRAIN, &push, groups)
    }

    /// The span's records (after the band's last submission).
    pub fn records(&mut self, params: &FrameParams, span: Span) -> PixelData {
        if !trains(params) {
            return PixelData::default();
        }
        let Some(b) = self.records.as_mut() else {
            return PixelData::default();
        };
        PixelData::of_span::<TrainingRecord>(b.mapped(), span)
    }

    pub fn destroy(&mut self, gpu: &mut Gpu) {
        for mut b in [self.table.take(), self.records.take()]
            .into_iter()
            .flatten()
        {
            gpu.destroy_buffer(&mut b);
        }
        self.uploaded = None;
    }
}

//! Building the buffers on one device: the rasterizing passes over ranges of placed triangles
//! and the queue of large triangles' blocks, the capacity variant in one pass, the exact one's
//! count, prefix sum and fill.

use ash::vk;

use super::state::{
    lhb, tables, Build, LhbPasses, APPEND, BLOCKS, COUNT, DIRECTIONS_PER_DISPATCH, FILL,
    MAX_GROUPS_X, PREFIX, RASTER, STAT_LAYERS, STAT_QUEUED,
};
use crate::dispatch::record_dispatch;
use crate::globals::{method_words, Push};
use crate::method::Recorder;
use crate::Result;
use platoon_core::method::lhb::RasterVariant;

impl LhbPasses {
    /// One rasterizing pass (`pass`) of the placed triangles in `ranges` ([first, end) each):
    /// every (triangle, direction), then the queued blocks (read back between the two). False
    /// when the queue overflowed (grown: build again).
    pub(super) fn raster_pass(
        &mut self,
        rec: &mut Recorder,
        push: &Push,
        pass: u32,
        ranges: &[[u32; 2]],
    ) -> Result<bool> {
        let directions = tables(rec.params).views.len() as u32;
        let (raster, blocks) = (rec.kernel(RASTER)?, rec.kernel(BLOCKS)?);
        let capacity = self.queue_capacity;
        let with = |first: u32, [begin, end]: [u32; 2]| {
            let mut p = *push;
            p.method = method_words(&[pass, first, capacity, begin, end]);
            p
        };
        if pass != FILL {
            rec.set_stat(STAT_QUEUED, 0);
        }
        if ranges.iter().any(|r| r[1] > r[0]) {
            self.build.time += rec.gpu.timed(|d, cb| unsafe {
                for &range in ranges.iter().filter(|r| r[1] > r[0]) {
                    let groups = (range[1] - range[0]).div_ceil(64);
                    let mut first = 0;
                    while first < directions {
                        let n = (directions - first).min(DIRECTIONS_PER_DISPATCH);
                        record_dispatch(d, cb, raster, &with(first, range), (groups, n));
                        first += n;
                    }
                }
            })?;
        }
        let queued = rec.stat(STAT_QUEUED);
        if queued > capacity {
            self.queue_capacity = queued.next_power_of_two();
            return Ok(false);
        }
        self.build.blocks = queued as u64;
        if queued > 0 {
            let rows = queued.div_ceil(MAX_GROUPS_X);
            let width = queued.min(MAX_GROUPS_X);
            self.build.time += rec.gpu.timed(|d, cb| unsafe {
                record_dispatch(d, cb, blocks, &with(0, [0, 0]), (width, rows))
            })?;
        }
        Ok(true)
    }

    /// Builds every direction's buffer: the capacity variant in one pass (or, while the layers
    /// of what did not move are kept, a pass over what moved); the exact one counts, sums and
    /// fills.
    pub(super) fn build(&mut self, rec: &mut Recorder, push: &Push) -> Result<()> {
        let o = lhb(rec.params).options;
        let t = tables(rec.params).clone();
        let texels = o.texels();
        self.build = Build {
            exact: o.variant == RasterVariant::Exact,
            ..Build::default()
        };
        let all = [[0, t.placed.len() as u32]];
        loop {
            self.build.attempts += 1;
            self.ensure_work(rec.gpu, rec.params)?;
            if o.variant == RasterVariant::Capacity {
                self.ensure_layers(rec.gpu, texels * o.layers as u64)?;
            }
            rec.set_method_buffers(self.addresses());
            if o.variant == RasterVariant::Capacity && !o.rebuild {
                if !self.build_kept(rec, push, &t, &o)? {
                    continue;
                }
                break;
            }
            self.statics = None;
            self.clear_counts(rec, texels)?;
            let first = if o.variant == RasterVariant::Exact {
                COUNT
            } else {
                APPEND
            };
            if !self.raster_pass(rec, push, first, &all)? {
                continue;
            }
            if o.variant == RasterVariant::Capacity {
                self.build.lost = rec.stat(STAT_LAYERS) as u64;
                self.build.layers = texels * o.layers as u64;
                break;
            }
            let prefix = rec.kernel(PREFIX)?;
            let rows = (o.directions.count() as u32 * o.resolution).div_ceil(64);
            let dirs = (o.directions.count() as u32).div_ceil(64);
            self.build.time += rec.gpu.timed(|d, cb| unsafe {
                for (stage, groups) in [(0, rows), (1, dirs), (2, 1), (3, rows)] {
                    let mut p = *push;
                    p.method = method_words(&[stage]);
                    record_dispatch(d, cb, prefix, &p, (groups, 1));
                }
            })?;
            self.build.layers = rec.stat(STAT_LAYERS) as u64;
            self.ensure_layers(rec.gpu, self.build.layers)?;
            rec.set_method_buffers(self.addresses());
            let filled = self.raster_pass(rec, push, FILL, &all)?;
            debug_assert!(filled, "the filling pass queues nothing");
            break;
        }
        // What this build needs (the buffers may be larger, kept from an earlier one).
        self.build.bytes =
            self.build.layers * 8 + texels * 4 + self.tables.as_ref().map_or(0, |b| b.size);
        rec.set_stat(STAT_QUEUED, 0);
        Ok(())
    }

    /// Zeroes every texel's count, and the lost layers.
    pub(super) fn clear_counts(&mut self, rec: &mut Recorder, texels: u64) -> Result<()> {
        let work = self.work.as_ref().expect("ensured").buffer;
        self.build.time += rec
            .gpu
            .timed(|d, cb| unsafe { d.cmd_fill_buffer(cb, work, 0, texels * 4, 0) })?;
        rec.set_stat(STAT_LAYERS, 0);
        Ok(())
    }

    /// Copies every texel's count from `from` to `to`.
    pub(super) fn copy_counts(
        &mut self,
        rec: &mut Recorder,
        from: vk::Buffer,
        to: vk::Buffer,
        texels: u64,
    ) -> Result<()> {
        self.build.time += rec.gpu.timed(|d, cb| unsafe {
            let region = vk::BufferCopy::default().size(texels * 4);
            d.cmd_copy_buffer(cb, from, to, &[region]);
        })?;
        Ok(())
    }
}

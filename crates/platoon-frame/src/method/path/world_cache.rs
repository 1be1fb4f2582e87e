//! The world cache (issue 43): the radiance surfaces reflect, averaged over the cells of a
//! grid in world space (one cell per side of a surface), read where a path reaches its second
//! vertex, so that the bounces after the first cost one lookup (shaders/path/world_cache.glsl).
//! Biased: a cell stands for its whole area and for every direction it was seen from.
//!
//! The cache learns from training paths (shaders/path/world_cache_train.comp): each frame one
//! pixel in `train_stride` (a pattern fixed by the image pixel and the frame) traces a path of its
//! own that does not read the cache and notes the light it gathered from its second vertex on,
//! per unit of throughput: a record of the cell's key and that radiance, left per pixel in the
//! band (`Band::per_pixel`). The frame's records, joined in pixel order, update the cells here in
//! that order, so the cache holds the same bits whatever the split between devices; the next
//! frame's tracers all read one table ([`CacheTable`], in the path tracer's state:
//! `PathTracing::world_cache`).

use std::sync::Arc;

use crate::frame::PixelRecord;

/// What a pixel leaves for the cells each frame (world_cache_train.comp's record, one vec4): the
/// key bits of the cell its training path's second vertex fell in (0: the pixel did not train)
/// and the radiance gathered from there on, per unit of throughput.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TrainingRecord {
    pub key: u32,
    pub radiance: [f32; 3],
}

impl PixelRecord for TrainingRecord {
    const KIND: &'static str = "path.world_cache_training";
}

// One vec4, as the kernel writes it.
const _: () = assert!(std::mem::size_of::<TrainingRecord>() == 16);

/// The cache's settings.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WorldCacheOptions {
    /// Cells across the diameter of the scene's bounding sphere.
    pub resolution: u32,
    /// One pixel in this many trains a frame.
    pub train_stride: u32,
    /// A cell's mean counts at most this many samples (a running mean after: what moves or
    /// changes its light is forgotten at that pace).
    pub history: u32,
    /// Samples a cell needs before paths read it.
    pub min_samples: u32,
    /// The table holds 2^slots_log2 cells.
    pub slots_log2: u32,
    /// A cell not trained for this many frames gives its slot to another that wants it.
    pub stale_frames: u32,
}

impl Default for WorldCacheOptions {
    fn default() -> Self {
        WorldCacheOptions {
            resolution: 64,
            train_stride: 4,
            history: 64,
            min_samples: 4,
            slots_log2: 16,
            stale_frames: 16,
        }
    }
}

impl WorldCacheOptions {
    pub fn validate(&self) -> Result<(), String> {
        if self.resolution == 0 || self.train_stride == 0 || self.history == 0 {
            return Err(
                "the world cache needs a resolution, a training stride and a history \
                        of at least 1"
                    .into(),
            );
        }
        if !(4..=22).contains(&self.slots_log2) {
            return Err(format!(
                "the world cache's table holds 2^4 to 2^22 cells, not 2^{}",
                self.slots_log2
            ));
        }
        Ok(())
    }
}

/// What the kernels read: the cell size, the training pattern, and per slot the cell's key
/// (as f32 bits; 0: empty) and mean reflected radiance, for cells with enough samples.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CacheTable {
    pub cell_size: f32,
    pub train_stride: u32,
    /// A power of two long.
    #[serde(with = "crate::frame::pod_bytes")]
    pub slots: Vec<[f32; 4]>,
}

impl CacheTable {
    /// The mask of a key's slot bits (world_cache.glsl's cache_slot_mask).
    pub fn slot_mask(&self) -> u32 {
        self.slots.len() as u32 - 1
    }
}

/// The slot of `key` in a table of `mask + 1` slots (world_cache.glsl's cache_slot).
pub fn slot_of(key: u32, mask: u32) -> usize {
    ((key >> 1) & mask) as usize
}

#[derive(Clone, Copy, Debug, Default)]
struct Cell {
    key: u32,
    mean: [f32; 3],
    count: u32,
    /// The last frame that trained it.
    trained: u32,
}

/// What one frame's records did to the cache.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct CacheUpdate {
    pub records: u32,
    /// Records whose slot another cell holds (dropped).
    pub collisions: u32,
    /// Cells that took over a stale cell's slot.
    pub replaced: u32,
    /// Cells the next frame's paths read (with enough samples).
    pub cells: u32,
}

/// The cache: its cells, updated from each frame's records in pixel order.
#[derive(Clone, Debug)]
pub struct WorldCache {
    options: WorldCacheOptions,
    cell_size: f32,
    cells: Vec<Cell>,
    /// The table of the cells as they stand, made again after an update.
    table: Arc<CacheTable>,
}

impl WorldCache {
    /// An empty cache over a scene whose bounding sphere has radius `scene_radius`.
    pub fn new(options: WorldCacheOptions, scene_radius: f32) -> Result<WorldCache, String> {
        options.validate()?;
        let cell_size = (2.0 * scene_radius.max(1e-6)) / options.resolution as f32;
        let slots = 1usize << options.slots_log2;
        let mut cache = WorldCache {
            options,
            cell_size,
            cells: vec![Cell::default(); slots],
            table: Arc::new(CacheTable {
                cell_size,
                train_stride: options.train_stride,
                slots: Vec::new(),
            }),
        };
        cache.table = Arc::new(cache.make_table());
        Ok(cache)
    }

    pub fn options(&self) -> WorldCacheOptions {
        self.options
    }

    /// The table the next frame reads.
    pub fn table(&self) -> Arc<CacheTable> {
        Arc::clone(&self.table)
    }

    /// Joins frame `frame`'s records (its bands' `per_pixel`, in pixel order) to the cells, in
    /// that order.
    pub fn update(&mut self, records: &[TrainingRecord], frame: u32) -> CacheUpdate {
        let mask = self.cells.len() as u32 - 1;
        let mut u = CacheUpdate::default();
        for r in records {
            let key = r.key;
            if key == 0 {
                continue;
            }
            u.records += 1;
            let cell = &mut self.cells[slot_of(key, mask)];
            if cell.key != key {
                let stale = frame.wrapping_sub(cell.trained) > self.options.stale_frames;
                if cell.count > 0 && !stale {
                    u.collisions += 1;
                    continue;
                }
                if cell.count > 0 {
                    u.replaced += 1;
                }
                *cell = Cell {
                    key,
                    ..Cell::default()
                };
            }
            cell.count = (cell.count + 1).min(self.options.history);
            cell.trained = frame;
            let a = 1.0 / cell.count as f32;
            for (m, x) in cell.mean.iter_mut().zip(&r.radiance) {
                *m += (x - *m) * a;
            }
        }
        self.table = Arc::new(self.make_table());
        u.cells = self.cells_read() as u32;
        u
    }

    /// Cells that paths read (enough samples).
    pub fn cells_read(&self) -> usize {
        self.cells
            .iter()
            .filter(|c| c.count >= self.options.min_samples)
            .count()
    }

    fn make_table(&self) -> CacheTable {
        let slots = self
            .cells
            .iter()
            .map(|c| {
                if c.count >= self.options.min_samples {
                    [f32::from_bits(c.key), c.mean[0], c.mean[1], c.mean[2]]
                } else {
                    [0.0; 4]
                }
            })
            .collect();
        CacheTable {
            cell_size: self.cell_size,
            train_stride: self.options.train_stride,
            slots,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(key: u32, v: f32) -> TrainingRecord {
        TrainingRecord {
            key,
            radiance: [v, v * 2.0, v * 3.0],
        }
    }

    fn options() -> WorldCacheOptions {
        WorldCacheOptions {
            slots_log2: 4,
            min_samples: 2,
            history: 4,
            ..Default::default()
        }
    }

    #[test]
    fn a_cell_is_read_once_it_has_enough_samples_and_holds_their_running_mean() {
        let mut c = WorldCache::new(options(), 1.0).unwrap();
        let key = 0x0080_0007; // slot 3
        c.update(&[record(key, 1.0), TrainingRecord::default()], 0);
        assert_eq!(c.table().slots[3], [0.0; 4], "one sample: not read yet");
        c.update(&[record(key, 3.0)], 1);
        let t = c.table();
        assert_eq!(t.slots[3], [f32::from_bits(key), 2.0, 4.0, 6.0]);
        assert_eq!(t.cell_size, 2.0 / 64.0);
        // Past the history the mean runs: the fifth sample weighs 1/4.
        c.update(&[record(key, 2.0), record(key, 2.0), record(key, 6.0)], 2);
        assert_eq!(c.table().slots[3][1], 2.0 + (6.0 - 2.0) / 4.0);
    }

    #[test]
    fn a_colliding_cell_waits_until_the_holder_is_stale() {
        let mut c = WorldCache::new(options(), 1.0).unwrap();
        let (a, b) = (0x0080_000b, 0x1080_000b); // both slot 5
        c.update(&[record(a, 1.0), record(a, 1.0)], 0);
        let u = c.update(&[record(b, 9.0)], 1);
        assert_eq!((u.records, u.collisions, u.replaced), (1, 1, 0));
        assert_eq!(c.table().slots[5][0].to_bits(), a);
        let u = c.update(&[record(b, 9.0), record(b, 9.0)], 1 + 17);
        assert_eq!((u.collisions, u.replaced), (0, 1));
        assert_eq!(c.table().slots[5], [f32::from_bits(b), 9.0, 18.0, 27.0]);
    }

    #[test]
    fn pixels_that_did_not_train_change_nothing_and_bad_options_are_refused() {
        let records: Vec<TrainingRecord> = (0..200u32)
            .map(|i| record(0x0080_0001 | ((i % 7) << 1), (i as f32 * 0.37).sin().abs()))
            .collect();
        let with_gaps: Vec<TrainingRecord> = records
            .iter()
            .flat_map(|r| [*r, TrainingRecord::default()])
            .collect();
        let (mut x, mut y) = (
            WorldCache::new(options(), 3.0).unwrap(),
            WorldCache::new(options(), 3.0).unwrap(),
        );
        let (ux, uy) = (x.update(&records, 0), y.update(&with_gaps, 0));
        assert_eq!(x.table(), y.table());
        assert_eq!((ux, uy.records), (uy, 200));
        for bad in [
            WorldCacheOptions {
                slots_log2: 30,
                ..options()
            },
            WorldCacheOptions {
                train_stride: 0,
                ..options()
            },
        ] {
            assert!(WorldCache::new(bad, 1.0).is_err());
        }
    }
}

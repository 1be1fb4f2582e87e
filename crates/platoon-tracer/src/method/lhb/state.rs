//! What layered hit buffers keep on one device between bands and frames (`LhbPasses`, the last
//! build's figures, the kept layers' bookkeeping) and the kernels and constants their passes use;
//! the build (`build`), the kept layers (`kept`) and the passes (mod.rs) act on it.

use std::sync::Arc;
use std::time::Duration;

use platoon_core::frame::FrameParams;
use platoon_core::method::lhb::frame::BufferFrame;
use platoon_core::method::lhb::tables::Tables;
use platoon_core::method::lhb::{Lhb, LhbOptions};

use crate::buffer::GpuBuffer;

pub(super) const RASTER: &str = "lhb/raster.comp";
pub(super) const BLOCKS: &str = "lhb/blocks.comp";
pub(super) const PREFIX: &str = "lhb/prefix.comp";
pub(super) const CAMERA: &str = "lhb/camera.comp";
pub(super) const PROBE: &str = "lhb/probe.comp";

/// Build passes (shaders/lhb/raster.glsl).
pub(super) const APPEND: u32 = 0;
pub(super) const COUNT: u32 = 1;
pub(super) const FILL: u32 = 2;
/// Counters of the band's stats while building (shaders/lhb/lhb.glsl): blocks queued, layers
/// lost (capacity) or in all (exact); during image passes the first counts lookups.
pub(super) const STAT_QUEUED: usize = 2;
pub(super) const STAT_LAYERS: usize = 3;
/// Directions one rasterizer dispatch takes (its workgroups' rows).
pub(super) const DIRECTIONS_PER_DISPATCH: u32 = 64;
/// Workgroups a dispatch's row takes at most (Vulkan's guaranteed minimum limit).
pub(super) const MAX_GROUPS_X: u32 = 65535;
/// Samples an image pass adds per pixel at most (llvmpipe's loop limit, as vertex links').
pub(super) const CAMERA_SAMPLES_PER_PASS: u32 = 4;

/// What the last build did.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Build {
    pub(super) layers: u64,
    pub(super) lost: u64,
    pub(super) blocks: u64,
    pub(super) bytes: u64,
    pub(super) time: Duration,
    pub(super) attempts: u32,
    /// With the kept part: whether it was kept as it was (else built again), and the instances
    /// rasterized on top of it.
    pub(super) kept: Option<(bool, u32)>,
    /// Lists without a capacity: `layers` counts the layers, else the slots.
    pub(super) exact: bool,
}

pub(crate) struct LhbPasses {
    pub(super) tables: Option<GpuBuffer>,
    pub(super) work: Option<GpuBuffer>,
    pub(super) layers: Option<GpuBuffer>,
    /// The tables the buffer holds.
    pub(super) uploaded: Option<Arc<Tables>>,
    /// Entries the queue has room for (grown when a build needs more; kept between frames).
    pub(super) queue_capacity: u32,
    pub(super) build: Build,
    pub(super) statics: Option<Statics>,
}

impl Default for LhbPasses {
    fn default() -> Self {
        LhbPasses {
            tables: None,
            work: None,
            layers: None,
            uploaded: None,
            queue_capacity: 1 << 16,
            build: Build::default(),
            statics: None,
        }
    }
}

pub(super) fn lhb(params: &FrameParams) -> &Lhb {
    params
        .method
        .state::<Lhb>()
        .expect("layered hit buffers' passes render their frames")
}

pub(super) fn tables(params: &FrameParams) -> &Arc<Tables> {
    lhb(params)
        .tables
        .as_ref()
        .expect("validated: an lhb frame has its tables")
}

/// Words before the queue (shaders/lhb/lhb.glsl: lhb_queue_at).
pub(super) fn queue_at(directions: u64, resolution: u64) -> u64 {
    let texels = directions * resolution * resolution;
    (texels + directions * resolution + directions + 3) & !3
}

/// The layers of the instances that have not moved, kept between frames (the capacity variant):
/// they are the first of every texel's list, up to the counts saved after them.
pub(super) struct Statics {
    pub(super) options: LhbOptions,
    pub(super) frame: BufferFrame,
    /// Each instance's digest when the kept part was built.
    pub(super) digests: Vec<u64>,
    /// Instances left out of the kept part (they moved once), rasterized every frame.
    pub(super) moving: Vec<bool>,
    /// Every texel's count after the kept part, and the layers it lost.
    pub(super) counts: Option<GpuBuffer>,
    pub(super) lost: u64,
    pub(super) valid: bool,
}

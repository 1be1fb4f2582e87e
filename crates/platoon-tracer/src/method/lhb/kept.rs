//! The thesis' static buffers: the layers of the instances that have not moved, kept between
//! frames (the capacity variant), with what moved rasterized on top of them every frame.

use gpu_allocator::MemoryLocation;
use platoon_core::method::lhb::tables::Tables;
use platoon_core::method::lhb::LhbOptions;

use super::state::{LhbPasses, Statics, APPEND, STAT_LAYERS};
use crate::globals::Push;
use crate::method::{ensure, Recorder};
use crate::Result;

impl LhbPasses {
    /// The capacity variant keeping what did not move (the thesis' static buffers): when the
    /// kept part is of these options and frame and no instance of it moved, its counts are
    /// restored and only the instances left out of it are rasterized again; otherwise the
    /// instances that moved join those left out and the kept part is built again. False when
    /// the queue overflowed.
    pub(super) fn build_kept(
        &mut self,
        rec: &mut Recorder,
        push: &Push,
        t: &Tables,
        o: &LhbOptions,
    ) -> Result<bool> {
        let texels = o.texels();
        let instances = t.instance_digests.len();
        let compatible = self
            .statics
            .as_ref()
            .is_some_and(|s| s.options == *o && s.frame == t.frame && s.digests.len() == instances);
        if !compatible {
            self.statics = Some(Statics {
                options: *o,
                frame: t.frame,
                digests: t.instance_digests.clone(),
                moving: vec![false; instances],
                counts: None,
                lost: 0,
                valid: false,
            });
        }
        let s = self.statics.as_mut().expect("just made");
        let mut moved = 0;
        for i in 0..instances {
            if t.instance_digests[i] != s.digests[i] && !s.moving[i] {
                s.moving[i] = true;
                moved += 1;
            }
        }
        let ranges = |moving: bool, s: &Statics| -> Vec<[u32; 2]> {
            (0..instances)
                .filter(|&i| s.moving[i] == moving)
                .map(|i| t.instance_placed[i])
                .collect()
        };
        let keep = s.valid && moved == 0;
        let work = self.work.as_ref().expect("ensured").buffer;
        if keep {
            let (kept, lost) = (s.counts.as_ref().expect("valid").buffer, s.lost);
            self.copy_counts(rec, kept, work, texels)?;
            rec.set_stat(STAT_LAYERS, lost as u32);
        } else {
            s.valid = false;
            s.digests = t.instance_digests.clone();
            let still = ranges(false, s);
            self.clear_counts(rec, texels)?;
            if !self.raster_pass(rec, push, APPEND, &still)? {
                return Ok(false);
            }
            let s = self.statics.as_mut().expect("made above");
            ensure(
                rec.gpu,
                &mut s.counts,
                "lhb kept counts",
                texels * 4,
                MemoryLocation::GpuOnly,
            )?;
            let kept = s.counts.as_ref().expect("ensured").buffer;
            self.copy_counts(rec, work, kept, texels)?;
            let s = self.statics.as_mut().expect("made above");
            s.lost = rec.stat(STAT_LAYERS) as u64;
            s.valid = true;
        }
        let moving = ranges(true, self.statics.as_ref().expect("made above"));
        self.build.kept = Some((keep, moving.len() as u32));
        if !self.raster_pass(rec, push, APPEND, &moving)? {
            return Ok(false);
        }
        self.build.lost = rec.stat(STAT_LAYERS) as u64;
        self.build.layers = texels * o.layers as u64;
        Ok(true)
    }
}

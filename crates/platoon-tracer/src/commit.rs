//! Applying a commit: the tracer's copy of the scene follows the core's next flattened scene by
//! uploading only the changed ranges ([`platoon_core::flatten::commit::Commit`]). An array that
//! outgrew its buffer gets a new one with slack, uploaded whole, and the arrays are bound again.

use ash::vk;
use platoon_core::flatten::commit::Commit;
use platoon_core::flatten::GpuScene;

use crate::memory::{self, SCENE_ARRAYS};
use crate::{Result, Tracer};

/// What applying a commit cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CommitStats {
    /// Bytes sent to the device (changed ranges, and whole arrays that were reallocated).
    pub bytes: u64,
    /// Arrays that needed a bigger buffer.
    pub reallocated: u32,
}

impl Tracer {
    /// Brings this tracer's scene to `scene`, given the `commit` from the scene it holds now
    /// (`Commit::between(previous, scene)`). Call between frames.
    pub fn apply_commit(&mut self, scene: &GpuScene, commit: &Commit) -> Result<CommitStats> {
        let arrays = memory::scene_array_bytes(scene);
        let mut stats = CommitStats::default();
        let mut writes: Vec<(vk::Buffer, u64, &[u8])> = Vec::new();
        for a in &commit.arrays {
            let bytes = arrays[a.array];
            if a.len > self.scene.list[a.array].size {
                // Half as much again, so a growing array is not reallocated every frame.
                let capacity = a.len + a.len / 2;
                let buffer = self.array_buffer(SCENE_ARRAYS[a.array].name, capacity)?;
                let mut old = std::mem::replace(&mut self.scene.list[a.array], buffer);
                self.wait_idle()?;
                old.destroy(&self.ctx.device, &mut self.allocator);
                stats.reallocated += 1;
                // The new buffer holds nothing yet: send the array whole.
                writes.push((self.scene.list[a.array].buffer, 0, bytes));
                continue;
            }
            let buffer = self.scene.list[a.array].buffer;
            for &(offset, len) in &a.ranges {
                let (o, l) = (offset as usize, len as usize);
                writes.push((buffer, offset, &bytes[o..o + l]));
            }
        }
        stats.bytes = writes.iter().map(|w| w.2.len() as u64).sum();
        self.write_buffers(&writes)?;
        if stats.reallocated > 0 {
            self.bind_scene_arrays()?;
        }
        self.refresh_globals(scene);
        Ok(stats)
    }
}

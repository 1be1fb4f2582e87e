//! Applying a commit: the tracer's copy of the scene follows the core's next flattened scene by
//! uploading only the changed ranges ([`platoon_core::flatten::commit::Commit`]). An array that
//! outgrew its buffer gets a new one with slack, uploaded whole, and the arrays are bound again;
//! a ray-query tracer's acceleration structures follow (`structures.rs`).

use platoon_core::flatten::commit::Commit;

use crate::memory::SCENE_ARRAYS;
use crate::{Error, Result, Tracer};

/// What applying a commit cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CommitStats {
    /// Bytes sent to the device (changed ranges, and whole arrays that were reallocated).
    pub bytes: u64,
    /// Arrays that needed a bigger buffer.
    pub reallocated: u32,
}

impl Tracer {
    /// Brings this tracer's scene to the next generation: `commit` holds what changed since the
    /// scene it has (with the bytes). Call between frames.
    pub fn apply_commit(&mut self, commit: &Commit) -> Result<CommitStats> {
        // The structures' builds of the last commit read the arrays about to be written.
        if let Some(s) = self.structures.as_mut() {
            s.settle(&mut self.gpu)?;
        }
        let mut stats = CommitStats::default();
        let mut writes: Vec<(usize, u64, &[u8])> = Vec::new();
        for a in &commit.arrays {
            if a.len > self.scene.list[a.array].size {
                if !a.is_whole() {
                    return Err(Error::Invalid(format!(
                        "a commit grows {} past its buffer without sending it whole",
                        SCENE_ARRAYS[a.array].name
                    )));
                }
                // Half as much again, so a growing array is not reallocated every frame.
                let capacity = a.len + a.len / 2;
                let buffer = self.array_buffer(SCENE_ARRAYS[a.array].name, capacity)?;
                let mut old = std::mem::replace(&mut self.scene.list[a.array], buffer);
                self.gpu.wait_idle()?;
                self.gpu.destroy_buffer(&mut old);
                stats.reallocated += 1;
            }
            writes.extend(a.pieces().map(|(offset, bytes)| (a.array, offset, bytes)));
        }
        stats.bytes = writes.iter().map(|w| w.2.len() as u64).sum();
        self.write_arrays(&writes)?;
        if stats.reallocated > 0 {
            self.bind_scene_arrays()?;
        }
        // With ray queries: the changed meshes' structures and the instances' again.
        self.follow_with_structures(commit)?;
        self.refresh_globals(&commit.header);
        Ok(stats)
    }
}

//! Commit buffers: what a tracer must upload to go from one flattened scene to the next. Each
//! scene array is compared in fixed-size chunks and only the chunks that differ are sent, so a
//! frame where only the camera moved commits no scene bytes at all and a skinned character
//! commits its own vertices, triangles and nodes but not the static world around it.

use super::GpuScene;

/// The scene arrays in upload and binding order (the tracer's `SCENE_ARRAYS` follow it).
pub const ARRAY_COUNT: usize = 15;

/// Indices of the arrays that hold mesh data (vertices, triangle positions, triangles, their
/// light indices, bottom-level nodes): what a camera-only frame must not send.
pub const MESH_ARRAYS: [usize; 5] = [0, 1, 2, 3, 4];

/// Granularity of the comparison: small enough that a moving character does not drag its
/// neighbours along, large enough that a commit holds few ranges.
pub const CHUNK_BYTES: usize = 16 << 10;

impl GpuScene {
    /// The bytes of each scene array, in binding order.
    pub fn array_bytes(&self) -> [&[u8]; ARRAY_COUNT] {
        use bytemuck::cast_slice as b;
        [
            b(&self.vertices),
            b(&self.triangle_positions),
            b(&self.triangles),
            b(&self.triangle_lights),
            b(&self.blas_nodes),
            b(&self.tlas_nodes),
            b(&self.instances),
            b(&self.materials),
            b(&self.textures),
            b(&self.texels),
            b(&self.lights),
            b(&self.light_cdf),
            b(&self.env.texels),
            b(&self.env.marginal_cdf),
            b(&self.env.conditional_cdf),
        ]
    }
}

/// The changed byte ranges of one array; `len` is its new length in bytes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArrayCommit {
    pub array: usize,
    pub len: u64,
    /// (offset, length) in bytes, ascending, not overlapping.
    pub ranges: Vec<(u64, u64)>,
}

/// Everything that changed between two flattened scenes. The bytes themselves are read from the
/// new scene when the commit is applied, so a commit is small and cheap to share.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Commit {
    pub arrays: Vec<ArrayCommit>,
}

impl Commit {
    /// The chunks of `new` that differ from `old` (every byte of an array that grew or shrank
    /// past the old length counts as changed).
    pub fn between(old: &GpuScene, new: &GpuScene) -> Commit {
        let (old, new) = (old.array_bytes(), new.array_bytes());
        let mut arrays = Vec::new();
        for (array, (a, b)) in old.iter().zip(&new).enumerate() {
            if a == b {
                continue;
            }
            let mut ranges: Vec<(u64, u64)> = Vec::new();
            for start in (0..b.len()).step_by(CHUNK_BYTES) {
                let end = (start + CHUNK_BYTES).min(b.len());
                if a.get(start..end) == Some(&b[start..end]) {
                    continue;
                }
                match ranges.last_mut() {
                    Some((o, l)) if *o + *l == start as u64 => *l += (end - start) as u64,
                    _ => ranges.push((start as u64, (end - start) as u64)),
                }
            }
            arrays.push(ArrayCommit {
                array,
                len: b.len() as u64,
                ranges,
            });
        }
        Commit { arrays }
    }

    /// Bytes the commit sends.
    pub fn bytes(&self) -> u64 {
        self.arrays
            .iter()
            .flat_map(|a| &a.ranges)
            .map(|(_, l)| l)
            .sum()
    }

    /// Bytes it sends of mesh data ([`MESH_ARRAYS`]).
    pub fn mesh_bytes(&self) -> u64 {
        self.arrays
            .iter()
            .filter(|a| MESH_ARRAYS.contains(&a.array))
            .flat_map(|a| &a.ranges)
            .map(|(_, l)| l)
            .sum()
    }

    pub fn is_empty(&self) -> bool {
        self.arrays.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_changed_chunks_are_committed() {
        let old = GpuScene {
            texels: vec![7u32; 3 * CHUNK_BYTES / 4 + 5],
            materials: vec![Default::default(); 2],
            ..Default::default()
        };
        let mut new = old.clone();
        assert!(Commit::between(&old, &new).is_empty());
        new.texels[CHUNK_BYTES / 4 + 1] = 8; // the second chunk
        new.texels.push(9); // and the tail grows
        let c = Commit::between(&old, &new);
        assert_eq!(c.arrays.len(), 1);
        let a = &c.arrays[0];
        assert_eq!(a.array, 9);
        assert_eq!(a.len, new.texels.len() as u64 * 4);
        let chunk = CHUNK_BYTES as u64;
        assert_eq!(a.ranges, vec![(chunk, chunk), (3 * chunk, 24)]);
        assert_eq!(c.bytes(), chunk + 24);
        assert_eq!(c.mesh_bytes(), 0);
        new.vertices.push(Default::default());
        assert_eq!(Commit::between(&old, &new).mesh_bytes(), 48);
    }
}

//! Commit buffers: what a tracer must upload to go from one flattened scene to the next, with
//! the bytes. Ranges come from the updater (what it rewrote) or from comparing two scenes in
//! fixed-size chunks; either way only what differs is sent, so a
//! frame where only the camera moved commits no scene bytes at all and a skinned character
//! commits its own vertices, triangles and nodes but not the static world around it.

pub use super::arrays::ARRAY_COUNT;
use super::arrays::{SceneArray, ARRAYS};
use super::{GpuScene, MeshRegion};

/// Indices of the arrays that hold mesh data (vertices, triangle positions, triangles, their
/// light indices, bottom-level nodes, vertex extras): what a camera-only frame must not send.
pub const MESH_ARRAYS: [usize; 6] = [
    SceneArray::Vertices.index(),
    SceneArray::TrianglePositions.index(),
    SceneArray::Triangles.index(),
    SceneArray::TriangleLights.index(),
    SceneArray::Blas.index(),
    SceneArray::VertexExtras.index(),
];

/// Granularity of the comparison: small enough that a moving character does not drag its
/// neighbours along, large enough that a commit holds few ranges.
pub const CHUNK_BYTES: usize = 16 << 10;

impl GpuScene {
    /// The bytes of each scene array, in binding order.
    pub fn array_bytes(&self) -> [&[u8]; ARRAY_COUNT] {
        ARRAYS.map(|a| self.bytes_of(a.array))
    }

    /// The bytes of one scene array.
    pub fn bytes_of(&self, array: SceneArray) -> &[u8] {
        use bytemuck::cast_slice as b;
        use SceneArray::*;
        match array {
            Vertices => b(&self.vertices),
            TrianglePositions => b(&self.triangle_positions),
            Triangles => b(&self.triangles),
            TriangleLights => b(&self.triangle_lights),
            Blas => b(&self.blas_nodes),
            Tlas => b(&self.tlas_nodes),
            Instances => b(&self.instances),
            Materials => b(&self.materials),
            Textures => b(&self.textures),
            Texels => b(&self.texels),
            Lights => b(&self.lights),
            LightCdf => b(&self.light_cdf),
            EnvTexels => b(&self.env.texels),
            EnvMarginal => b(&self.env.marginal_cdf),
            EnvConditional => b(&self.env.conditional_cdf),
            VertexExtras => b(&self.vertex_extras),
        }
    }
}

impl GpuScene {
    /// Frees the host's copy of `array`, once every device holds it, when it is one of the
    /// large ones (mesh data, bottom-level nodes, texels: nothing on the host reads them while
    /// a still renders on its devices); the others are small and stay. Its bytes are empty
    /// after: not for a scene that commits, is sent to other processes or that a method reads
    /// on the host.
    pub fn release(&mut self, array: SceneArray) {
        use SceneArray::*;
        match array {
            Vertices => self.vertices = Vec::new(),
            TrianglePositions => self.triangle_positions = Vec::new(),
            Triangles => self.triangles = Vec::new(),
            Blas => self.blas_nodes = Vec::new(),
            Texels => self.texels = Vec::new(),
            VertexExtras => self.vertex_extras = Vec::new(),
            _ => {}
        }
    }
}

/// What a tracer needs of a scene besides its arrays (the counts and the environment that go
/// into its per-frame constants, and the feature set that picks its kernel).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneHeader {
    pub lights: u32,
    pub instances: u32,
    pub tlas_root: u32,
    pub env_kind: u32,
    pub env_color: [f32; 3],
    pub env_integral: f32,
    pub env_size: [u32; 2],
    pub features: crate::features::SceneFeatures,
    /// The scene's bounding sphere: centre and radius.
    pub scene_sphere: [f32; 4],
}

impl GpuScene {
    pub fn header(&self) -> SceneHeader {
        SceneHeader {
            lights: self.lights.len() as u32,
            instances: self.instances.len() as u32,
            tlas_root: self.tlas_root,
            env_kind: self.env.kind,
            env_color: self.env.color,
            env_integral: self.env.integral,
            env_size: [self.env.width, self.env.height],
            features: self.features,
            scene_sphere: [
                self.scene_center[0],
                self.scene_center[1],
                self.scene_center[2],
                self.scene_radius as f32,
            ],
        }
    }
}

/// The changed byte ranges of one array and their bytes; `len` is its new length in bytes. An
/// array that grew is sent whole (a tracer may need a bigger buffer for it).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArrayCommit {
    pub array: usize,
    pub len: u64,
    /// (offset, length) in bytes, ascending, not overlapping.
    pub ranges: Vec<(u64, u64)>,
    /// The bytes of the ranges, one after the other.
    pub data: Vec<u8>,
}

impl ArrayCommit {
    fn new(array: usize, bytes: &[u8], ranges: Vec<(u64, u64)>) -> ArrayCommit {
        let mut data = Vec::with_capacity(ranges.iter().map(|r| r.1 as usize).sum());
        for &(o, l) in &ranges {
            data.extend_from_slice(&bytes[o as usize..(o + l) as usize]);
        }
        ArrayCommit {
            array,
            len: bytes.len() as u64,
            ranges,
            data,
        }
    }

    /// Whether the ranges cover the whole array.
    pub fn is_whole(&self) -> bool {
        self.ranges == [(0, self.len)] || self.len == 0
    }

    /// Each range with its bytes.
    pub fn pieces(&self) -> impl Iterator<Item = (u64, &[u8])> {
        let mut at = 0usize;
        self.ranges.iter().map(move |&(o, l)| {
            let piece = &self.data[at..at + l as usize];
            at += l as usize;
            (o, piece)
        })
    }

    /// Writes each range's bytes into `array`, a copy of the array (`len` bytes) as it was.
    pub fn write_into(&self, array: &mut [u8]) {
        for (offset, piece) in self.pieces() {
            array[offset as usize..offset as usize + piece.len()].copy_from_slice(piece);
        }
    }
}

/// Everything that changed between two flattened scenes, with the bytes: what a tracer uploads
/// to follow, shared by all tracers.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Commit {
    pub arrays: Vec<ArrayCommit>,
    pub header: SceneHeader,
    /// Where each mesh lives in the arrays after it (`GpuScene::regions`): what a tracer's
    /// acceleration structures are built over (a bottom level per mesh; the ray-query
    /// traversal).
    pub regions: Vec<MeshRegion>,
    /// The meshes (by region) whose BVH the core built again in this commit rather than
    /// refitted (its SAH cost drifted past `RefitPolicy`'s bound, or its leaves' layout
    /// changed): a device's structure of the mesh is built again with it where it would be
    /// refitted otherwise. Empty for a commit between two scenes, which cannot tell.
    pub rebuilt: Vec<u32>,
    /// The meshes (by region) the core deformed in this commit, refitted or rebuilt (a skin's
    /// pose): what a device keeps refittable where it builds every structure again (a mesh
    /// added). Empty for a commit between two scenes.
    pub deformed: Vec<u32>,
}

/// Merges chunk-sized pieces into ranges.
fn push_range(ranges: &mut Vec<(u64, u64)>, start: usize, end: usize) {
    match ranges.last_mut() {
        Some((o, l)) if *o + *l == start as u64 => *l += (end - start) as u64,
        _ => ranges.push((start as u64, (end - start) as u64)),
    }
}

impl Commit {
    /// The chunks of `new` that differ from `old`; an array longer than before is sent whole.
    pub fn between(old: &GpuScene, new: &GpuScene) -> Commit {
        let old_arrays = old.array_bytes();
        let mut arrays = Vec::new();
        for (array, (a, b)) in old_arrays.iter().zip(new.array_bytes()).enumerate() {
            if *a == b {
                continue;
            }
            let ranges = if b.len() > a.len() {
                vec![(0, b.len() as u64)]
            } else {
                let mut ranges = Vec::new();
                for start in (0..b.len()).step_by(CHUNK_BYTES) {
                    let end = (start + CHUNK_BYTES).min(b.len());
                    if a[start..end] != b[start..end] {
                        push_range(&mut ranges, start, end);
                    }
                }
                ranges
            };
            arrays.push(ArrayCommit::new(array, b, ranges));
        }
        Commit {
            arrays,
            header: new.header(),
            regions: new.regions.clone(),
            rebuilt: Vec::new(),
            deformed: Vec::new(),
        }
    }

    /// The given byte ranges of `scene`'s arrays (`(array, offset, length)`, any order; ranges
    /// of one array must not overlap).
    pub fn of_ranges(scene: &GpuScene, mut ranges: Vec<(usize, u64, u64)>) -> Commit {
        ranges.sort_unstable();
        let bytes = scene.array_bytes();
        let mut arrays: Vec<ArrayCommit> = Vec::new();
        let mut i = 0;
        while i < ranges.len() {
            let array = ranges[i].0;
            let mut mine = Vec::new();
            while i < ranges.len() && ranges[i].0 == array {
                let (_, o, l) = ranges[i];
                if l > 0 {
                    push_range(&mut mine, o as usize, (o + l) as usize);
                }
                i += 1;
            }
            if !mine.is_empty() {
                arrays.push(ArrayCommit::new(array, bytes[array], mine));
            }
        }
        Commit {
            arrays,
            header: scene.header(),
            regions: scene.regions.clone(),
            rebuilt: Vec::new(),
            deformed: Vec::new(),
        }
    }

    /// Bytes the commit sends.
    pub fn bytes(&self) -> u64 {
        self.arrays.iter().map(|a| a.data.len() as u64).sum()
    }

    /// Bytes it sends of mesh data ([`MESH_ARRAYS`]).
    pub fn mesh_bytes(&self) -> u64 {
        self.arrays
            .iter()
            .filter(|a| MESH_ARRAYS.contains(&a.array))
            .map(|a| a.data.len() as u64)
            .sum()
    }

    /// No array changed (the header may have).
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
        new.texels[3 * CHUNK_BYTES / 4 + 2] = 8; // and the short last one
        let c = Commit::between(&old, &new);
        assert_eq!(c.arrays.len(), 1);
        let a = &c.arrays[0];
        assert_eq!(a.array, SceneArray::Texels.index());
        assert_eq!(a.len, new.texels.len() as u64 * 4);
        let chunk = CHUNK_BYTES as u64;
        assert_eq!(a.ranges, vec![(chunk, chunk), (3 * chunk, 20)]);
        assert_eq!(c.bytes(), chunk + 20);
        assert_eq!(c.mesh_bytes(), 0);
        let bytes = bytemuck::cast_slice::<u32, u8>(&new.texels);
        for (o, piece) in a.pieces() {
            assert_eq!(piece, &bytes[o as usize..o as usize + piece.len()]);
        }
        // Grown: sent whole.
        new.texels.push(9);
        assert!(Commit::between(&old, &new).arrays[0].is_whole());
        new.vertices.push(Default::default());
        assert_eq!(Commit::between(&old, &new).mesh_bytes(), 48);
        let some = Commit::of_ranges(&new, vec![(9, 8, 4), (9, 0, 8), (9, 100, 0)]);
        assert_eq!(some.arrays[0].ranges, vec![(0, 12)]);
    }
}

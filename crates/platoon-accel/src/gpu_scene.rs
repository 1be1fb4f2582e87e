//! What flattening makes: the arrays the kernel reads (`GpuScene`) and where each mesh lives
//! in them (`MeshRegion`). The files beside it fill them, one job each.

use super::bvh::{self, BvhNode};
use super::features::SceneFeatures;
use super::layout::{
    GpuEnvironment, GpuInstance, GpuLight, GpuMaterial, GpuTexture, GpuTriangle, GpuVertex,
    GpuVertexExtra,
};

/// Everything the kernel needs, as flat arrays.
#[derive(Clone, Debug, Default)]
pub struct GpuScene {
    pub vertices: Vec<GpuVertex>,
    /// One per vertex when some mesh has COLOR_0 or TEXCOORD_1, else empty.
    pub vertex_extras: Vec<GpuVertexExtra>,
    /// Object-space triangle corners in BLAS leaf order, xyz + pad.
    pub triangle_positions: Vec<[f32; 4]>,
    pub triangles: Vec<GpuTriangle>,
    /// Per triangle: index of its emissive light relative to the instance's `light_base`.
    pub triangle_lights: Vec<u32>,
    pub blas_nodes: Vec<BvhNode>,
    pub tlas_nodes: Vec<BvhNode>,
    /// The item the top level starts at (inner node 0, or the one instance's leaf).
    pub tlas_root: u32,
    pub instances: Vec<GpuInstance>,
    pub materials: Vec<GpuMaterial>,
    pub textures: Vec<GpuTexture>,
    pub texels: Vec<u32>,
    pub lights: Vec<GpuLight>,
    /// Light selection CDF, `lights.len() + 1` entries.
    pub light_cdf: Vec<f32>,
    pub env: GpuEnvironment,
    pub features: SceneFeatures,
    pub triangle_count: usize,
    pub build_times: bvh::BuildTimes,
    /// Radius of the scene's bounding sphere (for directional and environment light power), in
    /// f64: a vertex at 1e30 makes its square overflow f32.
    pub scene_radius: f64,
    /// Centre of that sphere (where IGI's particles from directional lights and the
    /// environment aim).
    pub scene_center: [f32; 3],
    /// Where each posed mesh lives in the arrays (CPU side).
    pub regions: Vec<MeshRegion>,
    /// What names the object and material of a hit (CPU side: Cryptomatte).
    pub hit_names: super::HitNames,
}

/// Where one mesh lives in the global arrays (a CPU-side record: a deforming mesh is rewritten in
/// place, and the tracers get just that range).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshRegion {
    pub vertex_base: u32,
    pub vertex_count: u32,
    pub triangle_base: u32,
    pub triangle_count: u32,
    pub node_base: u32,
    pub node_capacity: u32,
    /// The root item of the mesh's BVH (global indices).
    pub root: u32,
}

//! CPU-side BVHs: one BVH2 per mesh (bottom level) and one over instances (top level), built with
//! obvhs and flattened into the node layout the GLSL traversal reads.
//!
//! Layout choice (BVH2 rather than CWBVH): see docs/ARCHITECTURE.md, "BVH layout".

use std::time::{Duration, Instant};

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::triangle::Triangle;
use obvhs::BvhBuildParams;
use rayon::prelude::*;

use crate::scene::Mesh;

/// GPU node: bounds, and either two children at `index`, `index + 1` (count == 0) or `count`
/// primitives starting at `index`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BvhNode {
    pub min: [f32; 3],
    pub count: u32,
    pub max: [f32; 3],
    pub index: u32,
}

/// A flattened BVH over `order.len()` primitives: leaves index primitives in `order` order.
#[derive(Clone, Debug, Default)]
pub struct FlatBvh {
    pub nodes: Vec<BvhNode>,
    /// Original primitive index of each position referenced by leaves.
    pub order: Vec<u32>,
}

impl FlatBvh {
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match self.nodes.first() {
            Some(n) => (Vec3::from_array(n.min), Vec3::from_array(n.max)),
            None => (Vec3::ZERO, Vec3::ZERO),
        }
    }
}

fn flatten(bvh: &Bvh2) -> FlatBvh {
    let nodes = bvh
        .nodes
        .iter()
        .map(|n| BvhNode {
            min: n.aabb.min.to_array(),
            count: n.prim_count,
            max: n.aabb.max.to_array(),
            index: n.first_index,
        })
        .collect();
    FlatBvh {
        nodes,
        order: bvh.primitive_indices.clone(),
    }
}

/// The build preset: obvhs' "medium" (PLOC + reinsertion), without spatial pre-splits so that
/// every triangle appears in exactly one leaf (triangles are reordered into leaf order).
fn params() -> BvhBuildParams {
    let mut p = BvhBuildParams::medium_build();
    p.pre_split = false;
    p
}

/// Largest coordinate magnitude a triangle may have to enter a BVH. Far beyond it, box extents
/// and surface areas overflow f32 and the builder's arithmetic turns to NaN (obvhs asserts on
/// NaN bounds); a vertex at 1e30 still renders.
pub const MAX_COORDINATE: f32 = 1e32;

/// Whether a point can be placed in a BVH: finite and within [`MAX_COORDINATE`].
pub fn placeable(p: Vec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_COORDINATE
}

/// The BVH of a mesh's triangles. Triangles with an unplaceable corner (NaN or Inf from a file
/// or from skinning) are left out of it, so they are never drawn.
pub fn build_mesh_bvh(mesh: &Mesh) -> FlatBvh {
    let mut tris = Vec::with_capacity(mesh.indices.len());
    let mut original = Vec::with_capacity(mesh.indices.len());
    for (i, t) in mesh.indices.iter().enumerate() {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize]);
        if placeable(a) && placeable(b) && placeable(c) {
            tris.push(Triangle {
                v0: a.into(),
                v1: b.into(),
                v2: c.into(),
            });
            original.push(i as u32);
        }
    }
    if tris.is_empty() {
        return FlatBvh::default();
    }
    let mut time = Duration::ZERO;
    let mut flat = flatten(&obvhs::bvh2::builder::build_bvh2_from_tris(
        &tris,
        params(),
        &mut time,
    ));
    for o in &mut flat.order {
        *o = original[*o as usize];
    }
    flat
}

/// Per-mesh BVHs, built in parallel on the CPU threads.
pub fn build_mesh_bvhs(meshes: &[std::sync::Arc<Mesh>]) -> Vec<FlatBvh> {
    meshes.par_iter().map(|m| build_mesh_bvh(m)).collect()
}

/// World-space box of an object-space box under `m`.
pub fn transform_bounds(m: &Mat4, (lo, hi): (Vec3, Vec3)) -> Aabb {
    let mut aabb = Aabb::empty();
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        aabb.extend(Vec3A::from(m.transform_point3(c)));
    }
    aabb
}

/// The top level over instance boxes; every box must be finite (see [`placeable`]).
pub fn build_instance_bvh(boxes: &[Aabb]) -> FlatBvh {
    if boxes.is_empty() {
        return FlatBvh::default();
    }
    let mut time = Duration::ZERO;
    let mut p = params();
    // One instance per leaf keeps the leaf loop of the top level trivial.
    p.max_prims_per_leaf = 1;
    flatten(&obvhs::bvh2::builder::build_bvh2(boxes, p, &mut time))
}

/// Build timings, reported by `platoon bench`.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuildTimes {
    pub meshes: Duration,
    pub instances: Duration,
}

pub fn timed<T>(f: impl FnOnce() -> T) -> (T, Duration) {
    let t = Instant::now();
    let r = f();
    (r, t.elapsed())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_triangle_is_in_exactly_one_leaf() {
        let mut mesh = Mesh::default();
        for i in 0..100 {
            let o = Vec3::new(i as f32, (i * 7 % 13) as f32, 0.0);
            let b = mesh.positions.len() as u32;
            mesh.positions.extend([o, o + Vec3::X, o + Vec3::Y]);
            mesh.indices.push([b, b + 1, b + 2]);
        }
        let bvh = build_mesh_bvh(&mesh);
        let mut seen = vec![0; 100];
        for n in &bvh.nodes {
            for k in 0..n.count {
                seen[bvh.order[(n.index + k) as usize] as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        let (lo, hi) = bvh.bounds();
        assert_eq!(lo, Vec3::new(0.0, 0.0, 0.0));
        assert_eq!(hi, Vec3::new(100.0, 13.0, 0.0));
    }

    #[test]
    fn unplaceable_triangles_are_left_out_and_far_ones_kept() {
        let mut mesh = Mesh::default();
        let far = Vec3::splat(1e30);
        for (i, corner) in [Vec3::NAN, Vec3::INFINITY, Vec3::splat(3e38), far]
            .into_iter()
            .enumerate()
        {
            let b = mesh.positions.len() as u32;
            let o = Vec3::new(i as f32, 0.0, 0.0);
            mesh.positions.extend([o, o + Vec3::X, corner]);
            mesh.indices.push([b, b + 1, b + 2]);
        }
        let bvh = build_mesh_bvh(&mesh);
        assert_eq!(bvh.order, vec![3]);
        assert_eq!(bvh.bounds().1, far);
    }
}

/// CPU traversal cost of the two node layouts obvhs builds, on the same triangles and rays:
/// the evidence behind the BVH2 choice (docs/ARCHITECTURE.md). lavapipe runs kernels on these
/// same CPU cores, so the CPU figures bound what each layout can reach there.
#[derive(Clone, Copy, Debug)]
pub struct LayoutComparison {
    pub bvh2_rays_per_s: f64,
    pub cwbvh_rays_per_s: f64,
    pub bvh2_node_bytes: usize,
    pub cwbvh_node_bytes: usize,
    pub bvh2_build: Duration,
    pub cwbvh_build: Duration,
    /// Both layouts found the same closest hits.
    pub hits_agree: bool,
}

pub fn compare_layouts(tris: &[Triangle], rays: &[obvhs::ray::Ray]) -> LayoutComparison {
    use obvhs::ray::RayHit;
    let mut bvh2_build = Duration::ZERO;
    let mut cwbvh_build = Duration::ZERO;
    let b2 = obvhs::bvh2::builder::build_bvh2_from_tris(tris, params(), &mut bvh2_build);
    let cw = obvhs::cwbvh::builder::build_cwbvh_from_tris(tris, params(), &mut cwbvh_build);
    let run = |trace: &dyn Fn(&obvhs::ray::Ray) -> f32| {
        let start = Instant::now();
        let hits: Vec<f32> = rays.iter().map(trace).collect();
        (rays.len() as f64 / start.elapsed().as_secs_f64(), hits)
    };
    let (bvh2_rays_per_s, h2) = run(&|ray| {
        let mut hit = RayHit::none();
        b2.ray_traverse(*ray, &mut hit, |r, i| {
            tris[b2.primitive_indices[i] as usize].intersect(r)
        });
        hit.t
    });
    let (cwbvh_rays_per_s, hc) = run(&|ray| {
        let mut hit = RayHit::none();
        cw.ray_traverse(*ray, &mut hit, |r, i| {
            tris[cw.primitive_indices[i] as usize].intersect(r)
        });
        hit.t
    });
    LayoutComparison {
        bvh2_rays_per_s,
        cwbvh_rays_per_s,
        bvh2_node_bytes: std::mem::size_of::<BvhNode>() * b2.nodes.len(),
        cwbvh_node_bytes: std::mem::size_of_val(cw.nodes.as_slice()),
        bvh2_build,
        cwbvh_build,
        hits_agree: h2 == hc,
    }
}

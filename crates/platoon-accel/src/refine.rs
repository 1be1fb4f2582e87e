//! The refined build of big static geometry: the quick binned-SAH tree
//! ([`super::binned_sah`]) with every node reinserted where the surface area heuristic wants it
//! (Meister and Bittner 2018, obvhs' optimizer), what a living scene builds in the background
//! and swaps in when done (platoon-live's `refinement`).
//!
//! Reinsertion from the binned tree rather than from obvhs' PLOC: PLOC's tree, reinserted,
//! still costs more than the binned one on tessellated surfaces (docs/PERFORMANCE.md, "Scenes of
//! production size"), so the refinement starts from the better of the two.

use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::node::Bvh2Node;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::bvh2::Bvh2;

use super::bvh::{flatten, unpack_item, FlatBvh};

/// The fraction of the nodes reinsertion considers at its first pass (obvhs' "very slow"
/// preset: all of them).
const REINSERTION_BATCH_RATIO: f32 = 1.0;

/// `flat` with its nodes reinserted: the same triangles (each in one leaf, leaves as `flat`
/// made them), a tree of lower SAH cost. Deterministic, as the binned build is.
pub fn refine(flat: &FlatBvh) -> FlatBvh {
    if flat.nodes.is_empty() {
        return flat.clone();
    }
    let mut bvh = to_bvh2(flat);
    ReinsertionOptimizer::default().run(&mut bvh, REINSERTION_BATCH_RATIO, None);
    flatten(&bvh)
}

/// `flat` as obvhs' binary BVH: one node per item (a leaf of `flat` stays one leaf, its
/// primitives the same positions of the order), children side by side.
fn to_bvh2(flat: &FlatBvh) -> Bvh2 {
    let aabb = |lo: [f32; 3], hi: [f32; 3]| Aabb::new(Vec3A::from(lo), Vec3A::from(hi));
    let (lo, hi) = flat.bounds;
    let mut nodes = Vec::with_capacity(2 * flat.nodes.len() + 1);
    nodes.push(node(aabb(lo.to_array(), hi.to_array()), flat.root));
    let mut open = vec![(0usize, flat.root)];
    while let Some((at, it)) = open.pop() {
        let (index, count) = unpack_item(it);
        if count > 0 {
            continue;
        }
        let n = &flat.nodes[index as usize];
        let first = nodes.len();
        nodes[at].first_index = first as u32;
        nodes.push(node(aabb(n.min0, n.max0), n.item0));
        nodes.push(node(aabb(n.min1, n.max1), n.item1));
        open.push((first, n.item0));
        open.push((first + 1, n.item1));
    }
    Bvh2 {
        nodes,
        primitive_indices: flat.order.clone(),
        ..Default::default()
    }
}

/// The obvhs node of an item under `aabb` (an inner node's first child set when it is placed).
fn node(aabb: Aabb, it: u32) -> Bvh2Node {
    let (index, count) = unpack_item(it);
    Bvh2Node::new(aabb, count, if count > 0 { index } else { 0 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::binned_sah;
    use crate::bvh::{placeable_triangles, BvhNode};

    fn quick(cells: u32) -> FlatBvh {
        let scene = platoon_scene::cornell::tessellated(cells);
        let (tris, _) = placeable_triangles(&scene.meshes[0]);
        binned_sah::build(&tris, 1.5)
    }

    #[test]
    fn refining_lowers_the_cost_and_keeps_the_leaves_their_triangles_and_the_node_count() {
        let quick = quick(40);
        let fine = refine(&quick);
        assert!(
            fine.sah_cost() < 0.995 * quick.sah_cost(),
            "SAH {} against {}",
            fine.sah_cost(),
            quick.sah_cost()
        );
        // Only the nodes move: the triangles stay in their places (what the kernel's triangle
        // arrays and the light list are ordered by) and every leaf is one of the quick tree's.
        assert!(fine.order == quick.order);
        assert_eq!(fine.nodes.len(), quick.nodes.len());
        assert_eq!(fine.bounds, quick.bounds);
        assert_eq!(fine.root, quick.root);
        let leaves = |b: &FlatBvh| {
            let mut l: Vec<(u32, u32)> = b.leaves().collect();
            l.sort();
            l
        };
        assert_eq!(leaves(&fine), leaves(&quick));
        // Every node's boxes hold its children's.
        for n in &fine.nodes {
            for (lo, hi, it) in [(n.min0, n.max0, n.item0), (n.min1, n.max1, n.item1)] {
                let (index, count) = unpack_item(it);
                if count == 0 {
                    let c = &fine.nodes[index as usize];
                    for (clo, chi) in [(c.min0, c.max0), (c.min1, c.max1)] {
                        assert!((0..3).all(|k| lo[k] <= clo[k] && chi[k] <= hi[k]));
                    }
                }
            }
        }
    }

    #[test]
    fn a_refinement_gives_the_same_bytes_whatever_the_threads_running_it() {
        let quick = quick(30);
        let on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let b = pool.install(|| refine(&quick));
            bytemuck::cast_slice::<BvhNode, u8>(&b.nodes).to_vec()
        };
        let one = on(1);
        assert!(on(2) == one && on(3) == one);
    }
}

//! A top-down BVH build by the surface area heuristic over binned centroids (Wald 2007, "On fast
//! Construction of SAH-based Bounding Volume Hierarchies"), straight into the kernel's layout:
//! the quick build of big static geometry ([`super::bvh::BuildQuality::Quick`]).
//!
//! obvhs builds bottom-up (PLOC), which on finely tessellated surfaces needs every node
//! reinserted to reach a good tree: the Cornell box cut into 3.24 million triangles takes 10.7 s
//! that way (SAH cost 53), and PLOC with little reinsertion leaves boxes that overlap widely
//! (1.1 s, SAH 876: rays visit 16 times the nodes). Splitting top-down where the SAH says gives
//! a tree of nearly the reinserted one's cost in a fraction of the time (docs/PERFORMANCE.md,
//! "Scenes of production size").
//!
//! Deterministic: the same triangles give the same bytes whatever the threads building it (the
//! subtrees built in parallel are joined in a fixed order).

use glam::{Vec3, Vec3A};
use obvhs::triangle::Triangle;
use rayon::prelude::*;

use super::bvh::{item, BvhNode, FlatBvh, MAX_LEAF_ITEM};

/// Bins per axis: 32 finds splits about as good as a full sweep on real meshes (Wald 2007).
const BINS: usize = 32;

/// Above this depth subtrees are built on their own threads (2^4 = 16 tasks).
const PARALLEL_DEPTH: u32 = 4;

/// Subtrees under this many primitives are built on the thread that reached them.
const PARALLEL_PRIMITIVES: usize = 4096;

#[derive(Clone, Copy)]
struct Bounds {
    lo: Vec3A,
    hi: Vec3A,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        lo: Vec3A::splat(f32::INFINITY),
        hi: Vec3A::splat(f32::NEG_INFINITY),
    };

    fn grow(&mut self, o: &Bounds) {
        self.lo = self.lo.min(o.lo);
        self.hi = self.hi.max(o.hi);
    }

    fn grow_point(&mut self, p: Vec3A) {
        self.lo = self.lo.min(p);
        self.hi = self.hi.max(p);
    }

    /// Half the surface area (the heuristic only compares areas).
    fn half_area(&self) -> f32 {
        let d = (self.hi - self.lo).max(Vec3A::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }

    fn corners(&self) -> (Vec3, Vec3) {
        (Vec3::from(self.lo), Vec3::from(self.hi))
    }
}

/// A triangle as the build reads it: its box and its index, 32 bytes. The build moves these
/// records themselves, so that every pass over a node reads memory in order (an index array
/// into boxes elsewhere made each pass a gather: half the build's time in cache misses).
#[derive(Clone, Copy)]
#[repr(C)]
struct Prim {
    lo: Vec3,
    index: u32,
    hi: Vec3,
    _pad: u32,
}

impl Prim {
    fn bounds(&self) -> Bounds {
        Bounds {
            lo: self.lo.into(),
            hi: self.hi.into(),
        }
    }

    fn centroid(&self) -> Vec3A {
        (Vec3A::from(self.lo) + Vec3A::from(self.hi)) * 0.5
    }
}

/// A subtree built on its own: its nodes (root first when it is an inner node) with items
/// local to this list, and its root item.
struct Subtree {
    nodes: Vec<BvhNode>,
    root: u32,
    bounds: Bounds,
}

/// The BVH of `tris` (leaves name positions of `order`, which holds triangle indices) by binned
/// SAH, a node step costing `traversal_cost` triangle tests.
pub fn build(tris: &[Triangle], traversal_cost: f32) -> FlatBvh {
    if tris.is_empty() {
        return FlatBvh::default();
    }
    let mut prims: Vec<Prim> = tris
        .par_iter()
        .enumerate()
        .map(|(i, t)| {
            let mut b = Bounds::EMPTY;
            for v in [t.v0, t.v1, t.v2] {
                b.grow_point(v);
            }
            Prim {
                lo: b.lo.into(),
                index: i as u32,
                hi: b.hi.into(),
                _pad: 0,
            }
        })
        .collect();
    let tree = subtree(&mut prims, 0, 0, traversal_cost);
    FlatBvh {
        nodes: tree.nodes,
        root: tree.root,
        order: prims.iter().map(|p| p.index).collect(),
        bounds: tree.bounds.corners(),
    }
}

/// The subtree over `prims` (whose first is at position `first` of the whole order).
fn subtree(prims: &mut [Prim], first: u32, depth: u32, cost: f32) -> Subtree {
    let n = prims.len();
    let (bounds, split) = choose_split(prims, cost);
    let Some(split) = split else {
        return Subtree {
            nodes: Vec::new(),
            root: leaf(first, n as u32),
            bounds,
        };
    };
    let mid = partition(prims, split);
    let (left, right) = prims.split_at_mut(mid);
    let second = first + mid as u32;
    if depth >= PARALLEL_DEPTH || n < PARALLEL_PRIMITIVES {
        // About one inner node for every 1.5 triangles at this traversal cost.
        let mut nodes = Vec::with_capacity(n);
        nodes.push(BvhNode::default());
        let a = build_into(left, first, &mut nodes, cost);
        let b = build_into(right, second, &mut nodes, cost);
        nodes[0] = BvhNode::pair(a, b);
        return Subtree {
            nodes,
            root: item(0, 0),
            bounds,
        };
    }
    let (a, b) = rayon::join(
        || subtree(left, first, depth + 1, cost),
        || subtree(right, second, depth + 1, cost),
    );
    let mut nodes = Vec::with_capacity(1 + a.nodes.len() + b.nodes.len());
    nodes.push(BvhNode::default());
    let child = |t: Subtree, nodes: &mut Vec<BvhNode>| {
        let base = nodes.len() as u32;
        let moved = |it: u32| moved_item(it, base);
        nodes.extend(t.nodes.iter().map(|n| BvhNode {
            item0: moved(n.item0),
            item1: moved(n.item1),
            ..*n
        }));
        let (lo, hi) = t.bounds.corners();
        (lo, hi, moved(t.root))
    };
    let ca = child(a, &mut nodes);
    let cb = child(b, &mut nodes);
    nodes[0] = BvhNode::pair(ca, cb);
    Subtree {
        nodes,
        root: item(0, 0),
        bounds,
    }
}

/// An inner node's item moved `base` nodes down the list; a leaf's unchanged.
fn moved_item(it: u32, base: u32) -> u32 {
    let (index, count) = super::bvh::unpack_item(it);
    if count == 0 {
        item(index + base, 0)
    } else {
        it
    }
}

/// Builds the subtree over `prims` into `nodes` (sequentially): its (lo, hi, item).
fn build_into(
    prims: &mut [Prim],
    first: u32,
    nodes: &mut Vec<BvhNode>,
    cost: f32,
) -> (Vec3, Vec3, u32) {
    let (bounds, split) = choose_split(prims, cost);
    let (lo, hi) = bounds.corners();
    let Some(split) = split else {
        return (lo, hi, leaf(first, prims.len() as u32));
    };
    let mid = partition(prims, split);
    let index = nodes.len();
    nodes.push(BvhNode::default());
    let (left, right) = prims.split_at_mut(mid);
    let a = build_into(left, first, nodes, cost);
    let b = build_into(right, first + mid as u32, nodes, cost);
    nodes[index] = BvhNode::pair(a, b);
    (lo, hi, item(index as u32, 0))
}

/// A leaf of `count` primitives from `first` ([`choose_split`] splits any more than an item
/// names).
fn leaf(first: u32, count: u32) -> u32 {
    debug_assert!(count <= MAX_LEAF_ITEM);
    item(first, count)
}

/// Where to cut: on `axis`, centroids in bins below `bin` go left.
#[derive(Clone, Copy)]
enum Split {
    Bin {
        axis: usize,
        bin: usize,
        lo: f32,
        scale: f32,
    },
    /// Every centroid in one point: halves by position in the order.
    Median,
}

/// The box of `prims` and the cheapest split of them by the SAH, or None where a leaf costs
/// less (and holds them). Two passes: the boxes of the primitives and of their centroids, then
/// the bins of all three axes at once.
fn choose_split(prims: &[Prim], cost: f32) -> (Bounds, Option<Split>) {
    let n = prims.len();
    let mut bounds = Bounds::EMPTY;
    let mut centre = Bounds::EMPTY;
    for p in prims {
        bounds.grow(&p.bounds());
        centre.grow_point(p.centroid());
    }
    if n <= 1 {
        return (bounds, None);
    }
    let extent = centre.hi - centre.lo;
    // Per axis: where bins start and bins per unit; 0 where the centroids do not spread (zero
    // or NaN extent), which puts every primitive in bin 0 and leaves the axis no cut.
    let mut scale = [0.0f32; 3];
    for axis in 0..3 {
        if extent[axis] > 0.0 {
            // Just under BINS / extent, so the largest centroid lands in the last bin.
            scale[axis] = BINS as f32 * (1.0 - 1e-6) / extent[axis];
        }
    }
    let lo = centre.lo;
    let mut boxes = [[Bounds::EMPTY; BINS]; 3];
    let mut counts = [[0u32; BINS]; 3];
    for p in prims {
        let (b, c) = (p.bounds(), p.centroid());
        for axis in 0..3 {
            let bin = bin_of(c[axis], lo[axis], scale[axis]);
            counts[axis][bin] += 1;
            boxes[axis][bin].grow(&b);
        }
    }
    let area = bounds.half_area();
    let mut best: Option<(f32, Split)> = None;
    for axis in (0..3).filter(|&a| scale[a] > 0.0) {
        let (boxes, counts) = (&boxes[axis], &counts[axis]);
        // Areas and counts right of each cut, then a sweep from the left.
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0u32; BINS];
        let mut acc = Bounds::EMPTY;
        let mut count = 0;
        for b in (1..BINS).rev() {
            acc.grow(&boxes[b]);
            count += counts[b];
            right_area[b] = acc.half_area();
            right_count[b] = count;
        }
        let mut left = Bounds::EMPTY;
        let mut left_count = 0;
        for b in 1..BINS {
            left.grow(&boxes[b - 1]);
            left_count += counts[b - 1];
            if left_count == 0 || right_count[b] == 0 {
                continue;
            }
            let c = left.half_area() * left_count as f32 + right_area[b] * right_count[b] as f32;
            if best.is_none_or(|(best, _)| c < best) {
                let split = Split::Bin {
                    axis,
                    bin: b,
                    lo: lo[axis],
                    scale: scale[axis],
                };
                best = Some((c, split));
            }
        }
    }
    let split_cost = |c: f32| if area > 0.0 { cost + c / area } else { cost };
    let split = match best {
        Some((c, split)) if n as u32 > MAX_LEAF_ITEM || split_cost(c) < n as f32 => Some(split),
        Some(_) => None,
        // Centroids in one point: halves, until a leaf can hold them.
        None if n as u32 > MAX_LEAF_ITEM => Some(Split::Median),
        None => None,
    };
    (bounds, split)
}

fn bin_of(c: f32, lo: f32, scale: f32) -> usize {
    (((c - lo) * scale) as usize).min(BINS - 1)
}

/// Moves the primitives left of `split` to the front of `prims`, in place (two cursors swapping
/// from the ends: no allocation, which at the top levels would be tens of MiB a node, each
/// freshly mapped and faulted in); returns how many.
fn partition(prims: &mut [Prim], split: Split) -> usize {
    let Split::Bin {
        axis,
        bin,
        lo,
        scale,
    } = split
    else {
        return prims.len() / 2;
    };
    let goes_left = |p: &Prim| bin_of(p.centroid()[axis], lo, scale) < bin;
    let (mut left, mut right) = (0, prims.len());
    while left < right {
        if goes_left(&prims[left]) {
            left += 1;
        } else {
            right -= 1;
            prims.swap(left, right);
        }
    }
    left
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flatten::bvh::{build_bvh2, flatten_mesh, placeable_triangles, BuildQuality};

    fn tessellated(cells: u32) -> (Vec<Triangle>, Vec<u32>) {
        let scene = crate::scene::cornell::tessellated(cells);
        placeable_triangles(&scene.meshes[0])
    }

    #[test]
    fn every_triangle_is_in_exactly_one_leaf_under_a_box_that_holds_it() {
        let (tris, _) = tessellated(12);
        let bvh = build(&tris, 1.5);
        let mut seen = vec![0; tris.len()];
        let mut boxes = vec![(Vec3::ZERO, Vec3::ZERO); tris.len()];
        let mut visit = vec![(bvh.bounds.0, bvh.bounds.1, bvh.root)];
        while let Some((lo, hi, it)) = visit.pop() {
            let (index, count) = super::super::bvh::unpack_item(it);
            if count == 0 {
                let n = &bvh.nodes[index as usize];
                visit.push((n.min0.into(), n.max0.into(), n.item0));
                visit.push((n.min1.into(), n.max1.into(), n.item1));
                continue;
            }
            for k in index..index + count {
                let t = bvh.order[k as usize] as usize;
                seen[t] += 1;
                boxes[t] = (lo, hi);
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        for (t, (lo, hi)) in tris.iter().zip(boxes) {
            for v in [t.v0, t.v1, t.v2] {
                let v = Vec3::from(v);
                assert!(v.cmpge(lo).all() && v.cmple(hi).all());
            }
        }
    }

    #[test]
    fn tessellated_walls_cost_rays_about_what_the_reinserted_tree_costs() {
        let (tris, original) = tessellated(24);
        let quick = build(&tris, 1.5).sah_cost();
        let fine = flatten_mesh(&build_bvh2(&tris, BuildQuality::Static), &original).sah_cost();
        let ploc = flatten_mesh(&build_bvh2(&tris, BuildQuality::Deforming), &original).sah_cost();
        assert!(
            quick < 1.3 * fine,
            "binned {quick} against reinserted {fine}"
        );
        assert!(quick < 0.5 * ploc, "binned {quick} against PLOC {ploc}");
    }

    #[test]
    fn a_build_gives_the_same_bytes_whatever_the_threads_building_it() {
        let (tris, _) = tessellated(40);
        let build_on = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let b = pool.install(|| build(&tris, 1.5));
            let mut out = bytemuck::cast_slice::<BvhNode, u8>(&b.nodes).to_vec();
            out.extend(b.root.to_le_bytes());
            out.extend(bytemuck::cast_slice::<u32, u8>(&b.order));
            out
        };
        let one = build_on(1);
        for threads in [2, 3] {
            assert!(build_on(threads) == one, "{threads} threads");
        }
    }

    #[test]
    fn coincident_centroids_are_split_into_leaves_an_item_can_name() {
        let t = Triangle {
            v0: Vec3A::ZERO,
            v1: Vec3A::X,
            v2: Vec3A::Y,
        };
        let bvh = build(&vec![t; 40], 1.5);
        let total: u32 = bvh.leaves().map(|(_, c)| c).sum();
        assert_eq!(total, 40);
        assert!(bvh.leaves().all(|(_, c)| c <= MAX_LEAF_ITEM));
    }
}

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
use platoon_scene::placeable::placeable;

/// Bins per axis: 32 finds splits as good as a full sweep on real meshes (Wald 2007).
const BINS: usize = 32;

/// Above this depth subtrees are built on their own threads (2^4 = 16 tasks).
const PARALLEL_DEPTH: u32 = 4;

/// Nodes of at most this many primitives are split by a full sweep over their sorted centroids
/// rather than by bins: at the deep levels, where most nodes are, setting up and sweeping 32
/// bins on three axes cost more than sorting a few centroids, and the sweep finds the exact
/// SAH split.
const SWEEP_PRIMITIVES: usize = 16;

/// Subtrees under this many primitives are built on the thread that reached them.
const PARALLEL_PRIMITIVES: usize = 4096;

#[derive(Clone, Copy, Debug, PartialEq)]
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
}

/// What the build reads of each primitive.
struct Primitives {
    bounds: Vec<Bounds>,
    centroids: Vec<Vec3A>,
    /// A node step's cost in triangle tests.
    traversal_cost: f32,
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
    let bounds = tris
        .par_iter()
        .map(|t| corners_bounds([t.v0, t.v1, t.v2]))
        .collect();
    build_over(bounds, traversal_cost)
}

/// [`build`] of a mesh's triangles (`indices` into `positions`) whose corners are all
/// [`placeable`]: each primitive's box is made straight from the mesh, without an array of
/// its triangles (48 bytes each, 192 MB beside the build's own for 4 million). Leaves name
/// positions of `order`, which holds mesh triangle indices.
pub fn build_mesh(positions: &[Vec3], indices: &[[u32; 3]], traversal_cost: f32) -> FlatBvh {
    let (bounds, original): (Vec<Bounds>, Vec<u32>) = indices
        .par_iter()
        .enumerate()
        .filter_map(|(i, t)| {
            let corners = t.map(|v| positions[v as usize]);
            corners
                .iter()
                .all(|&c| placeable(c))
                .then(|| (corners_bounds(corners.map(Vec3A::from)), i as u32))
        })
        .unzip();
    let mut flat = build_over(bounds, traversal_cost);
    for o in &mut flat.order {
        *o = original[*o as usize];
    }
    flat
}

fn corners_bounds(corners: [Vec3A; 3]) -> Bounds {
    let mut b = Bounds::EMPTY;
    for v in corners {
        b.grow_point(v);
    }
    b
}

/// The BVH of primitives of these boxes (leaves name positions of `order`, which holds their
/// indices).
fn build_over(bounds: Vec<Bounds>, traversal_cost: f32) -> FlatBvh {
    if bounds.is_empty() {
        return FlatBvh::default();
    }
    let centroids: Vec<Vec3A> = bounds.par_iter().map(|b| (b.lo + b.hi) * 0.5).collect();
    let prims = Primitives {
        bounds,
        centroids,
        traversal_cost,
    };
    let mut order: Vec<u32> = (0..prims.bounds.len() as u32).collect();
    let span = (0..prims.bounds.len())
        .into_par_iter()
        .fold(
            || Span::EMPTY,
            |mut s, i| {
                s.bounds.grow(&prims.bounds[i]);
                s.centre.grow_point(prims.centroids[i]);
                s
            },
        )
        .reduce(|| Span::EMPTY, |a, b| a.joined(&b));
    let tree = subtree(&prims, &mut order, 0, 0, span);
    FlatBvh {
        nodes: tree.nodes,
        root: tree.root,
        order,
        bounds: (Vec3::from(tree.bounds.lo), Vec3::from(tree.bounds.hi)),
    }
}

/// What a node's split starts from, which its parent's split already found: the box of its
/// primitives and the box of their centroids.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Span {
    bounds: Bounds,
    centre: Bounds,
}

impl Span {
    const EMPTY: Span = Span {
        bounds: Bounds::EMPTY,
        centre: Bounds::EMPTY,
    };

    fn of(p: &Primitives, order: &[u32]) -> Span {
        let mut s = Span::EMPTY;
        for &i in order {
            s.bounds.grow(&p.bounds[i as usize]);
            s.centre.grow_point(p.centroids[i as usize]);
        }
        s
    }

    fn joined(mut self, o: &Span) -> Span {
        self.bounds.grow(&o.bounds);
        self.centre.grow(&o.centre);
        self
    }
}

/// Splits `order` as `split` says: the position of the cut and the two sides' spans.
fn split_at(p: &Primitives, order: &mut [u32], split: Split) -> (usize, [Span; 2]) {
    match split {
        Split::Bin {
            axis,
            bin,
            lo,
            scale,
            bounds,
        } => {
            let (mid, centres) = partition(p, order, axis, bin, lo, scale);
            let sides = [0, 1].map(|k| Span {
                bounds: bounds[k],
                centre: centres[k],
            });
            (mid, sides)
        }
        Split::Median | Split::Sweep { .. } => {
            let mid = match split {
                Split::Sweep { axis, count } => {
                    order.sort_unstable_by(|&a, &b| sweep_key(p, axis, a, b));
                    count
                }
                _ => order.len() / 2,
            };
            let (left, right) = order.split_at(mid);
            (mid, [Span::of(p, left), Span::of(p, right)])
        }
    }
}

/// The subtree over `order` (whose first position is `first` in the whole order).
fn subtree(p: &Primitives, order: &mut [u32], first: u32, depth: u32, span: Span) -> Subtree {
    let bounds = span.bounds;
    let Some(split) = choose_split(p, order, &span) else {
        let root = leaf(first, order.len() as u32);
        return Subtree {
            nodes: Vec::new(),
            root,
            bounds,
        };
    };
    let (mid, [sa, sb]) = split_at(p, order, split);
    let n = order.len();
    let (left, right) = order.split_at_mut(mid);
    let second = first + mid as u32;
    if depth >= PARALLEL_DEPTH || n < PARALLEL_PRIMITIVES {
        let mut nodes = Vec::with_capacity(2 * (left.len() + right.len()) / 3);
        nodes.push(BvhNode::default());
        let a = build_into(p, left, first, &mut nodes, sa);
        let b = build_into(p, right, second, &mut nodes, sb);
        nodes[0] = BvhNode::pair(a, b);
        return Subtree {
            nodes,
            root: item(0, 0),
            bounds,
        };
    }
    let (a, b) = rayon::join(
        || subtree(p, left, first, depth + 1, sa),
        || subtree(p, right, second, depth + 1, sb),
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
        (
            Vec3::from(t.bounds.lo),
            Vec3::from(t.bounds.hi),
            moved(t.root),
        )
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

/// Builds the subtree over `order` into `nodes` (sequentially): its (lo, hi, item).
fn build_into(
    p: &Primitives,
    order: &mut [u32],
    first: u32,
    nodes: &mut Vec<BvhNode>,
    span: Span,
) -> (Vec3, Vec3, u32) {
    let (lo, hi) = (Vec3::from(span.bounds.lo), Vec3::from(span.bounds.hi));
    let Some(split) = choose_split(p, order, &span) else {
        return (lo, hi, leaf(first, order.len() as u32));
    };
    let (mid, [sa, sb]) = split_at(p, order, split);
    let index = nodes.len();
    nodes.push(BvhNode::default());
    let (left, right) = order.split_at_mut(mid);
    let a = build_into(p, left, first, nodes, sa);
    let b = build_into(p, right, first + mid as u32, nodes, sb);
    nodes[index] = BvhNode::pair(a, b);
    (lo, hi, item(index as u32, 0))
}

/// A leaf of `count` primitives from `first` ([`choose_split`] splits any more than an item
/// names).
fn leaf(first: u32, count: u32) -> u32 {
    debug_assert!(count <= MAX_LEAF_ITEM);
    item(first, count)
}

/// Where to cut.
#[derive(Clone, Copy)]
enum Split {
    /// On `axis`, centroids in bins below `bin` go left; `bounds` are the two sides' boxes
    /// (the bins' boxes joined).
    Bin {
        axis: usize,
        bin: usize,
        lo: f32,
        scale: f32,
        bounds: [Bounds; 2],
    },
    /// Every centroid in one point: halves by position in the order.
    Median,
    /// The first `count` of the centroids sorted on `axis` go left.
    Sweep { axis: usize, count: usize },
}

/// The cheapest split of `order` by the SAH, or None where a leaf costs less (and holds them).
/// One pass over the primitives bins them on all three axes (each primitive's centroid and box
/// read once).
fn choose_split(p: &Primitives, order: &[u32], span: &Span) -> Option<Split> {
    let n = order.len();
    // What the parent's split passed down is what a pass over the primitives finds.
    debug_assert_eq!(*span, Span::of(p, order));
    if n <= 1 {
        return None;
    }
    if n <= SWEEP_PRIMITIVES {
        return sweep_split(p, order, &span.bounds);
    }
    let centre = span.centre;
    let extent = centre.hi - centre.lo;
    // Zero or NaN: no spread of centroids on this axis to cut.
    let live = [0, 1, 2].map(|a| extent[a] > 0.0);
    // Just under BINS / extent, so the largest centroid lands in the last bin.
    let scale = Vec3A::from([0, 1, 2].map(|a| {
        if live[a] {
            BINS as f32 * (1.0 - 1e-6) / extent[a]
        } else {
            0.0
        }
    }));
    let mut boxes = [[Bounds::EMPTY; BINS]; 3];
    let mut counts = [[0u32; BINS]; 3];
    for &i in order {
        let c = p.centroids[i as usize];
        let b = &p.bounds[i as usize];
        let bins = ((c - centre.lo) * scale).to_array();
        for axis in 0..3 {
            let bin = (bins[axis] as usize).min(BINS - 1);
            counts[axis][bin] += 1;
            boxes[axis][bin].grow(b);
        }
    }
    let mut best: Option<(f32, Split)> = None;
    for axis in (0..3).filter(|&a| live[a]) {
        let (boxes, counts) = (&boxes[axis], &counts[axis]);
        // Boxes and counts right of each cut, then a sweep from the left.
        let mut right_box = [Bounds::EMPTY; BINS];
        let mut right_count = [0u32; BINS];
        let mut acc = Bounds::EMPTY;
        let mut count = 0;
        for b in (1..BINS).rev() {
            acc.grow(&boxes[b]);
            count += counts[b];
            right_box[b] = acc;
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
            let cost = left.half_area() * left_count as f32
                + right_box[b].half_area() * right_count[b] as f32;
            if best.is_none_or(|(c, _)| cost < c) {
                best = Some((
                    cost,
                    Split::Bin {
                        axis,
                        bin: b,
                        lo: centre.lo[axis],
                        scale: scale[axis],
                        bounds: [left, right_box[b]],
                    },
                ));
            }
        }
    }
    decide(p, n, &span.bounds, best)
}

/// The split `best` (its SAH cost unnormalised) if it is cheaper than a leaf of `n`
/// primitives or a leaf cannot hold them.
fn decide(p: &Primitives, n: usize, bounds: &Bounds, best: Option<(f32, Split)>) -> Option<Split> {
    let area = bounds.half_area();
    let split_cost = |cost: f32| {
        if area > 0.0 {
            p.traversal_cost + cost / area
        } else {
            p.traversal_cost
        }
    };
    match best {
        Some((cost, split)) if n as u32 > MAX_LEAF_ITEM || split_cost(cost) < n as f32 => {
            Some(split)
        }
        Some(_) => None,
        // Centroids in one point: halves, until a leaf can hold them.
        None if n as u32 > MAX_LEAF_ITEM => Some(Split::Median),
        None => None,
    }
}

/// [`choose_split`] of a few primitives: every cut between their centroids sorted on each
/// axis (ties by index, so the order is total).
fn sweep_split(p: &Primitives, order: &[u32], bounds: &Bounds) -> Option<Split> {
    let n = order.len();
    let mut sorted = [0u32; SWEEP_PRIMITIVES];
    let sorted = &mut sorted[..n];
    let mut right_area = [0.0f32; SWEEP_PRIMITIVES];
    let mut best: Option<(f32, Split)> = None;
    for axis in 0..3 {
        sorted.copy_from_slice(order);
        // The order the partition sorts them in (`split_at`), so that its cut is this one.
        sorted.sort_unstable_by(|&a, &b| sweep_key(p, axis, a, b));
        // Centroids in one point on this axis: no cut separates them.
        let c = |i: u32| p.centroids[i as usize][axis];
        if c(sorted[0]) == c(sorted[n - 1]) {
            continue;
        }
        let mut acc = Bounds::EMPTY;
        for k in (1..n).rev() {
            acc.grow(&p.bounds[sorted[k] as usize]);
            right_area[k] = acc.half_area();
        }
        let mut left = Bounds::EMPTY;
        for k in 1..n {
            left.grow(&p.bounds[sorted[k - 1] as usize]);
            let cost = left.half_area() * k as f32 + right_area[k] * (n - k) as f32;
            if best.is_none_or(|(b, _)| cost < b) {
                best = Some((cost, Split::Sweep { axis, count: k }));
            }
        }
    }
    decide(p, n, bounds, best)
}

fn sweep_key(p: &Primitives, axis: usize, a: u32, b: u32) -> std::cmp::Ordering {
    let c = |i: u32| p.centroids[i as usize][axis];
    c(a).total_cmp(&c(b)).then(a.cmp(&b))
}

/// Moves `order`'s primitives whose centroid on `axis` falls in a bin below `bin` to its
/// front, in place (two cursors swapping from the ends: no allocation, which at the top levels
/// would be tens of MiB a node, each freshly mapped and faulted in); returns how many, and the
/// boxes of the two sides' centroids (found on the way).
fn partition(
    p: &Primitives,
    order: &mut [u32],
    axis: usize,
    bin: usize,
    lo: f32,
    scale: f32,
) -> (usize, [Bounds; 2]) {
    let mut centres = [Bounds::EMPTY; 2];
    let (mut left, mut right) = (0, order.len());
    while left < right {
        let c = p.centroids[order[left] as usize];
        if (((c[axis] - lo) * scale) as usize).min(BINS - 1) < bin {
            centres[0].grow_point(c);
            left += 1;
        } else {
            centres[1].grow_point(c);
            right -= 1;
            order.swap(left, right);
        }
    }
    (left, centres)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bvh::{build_bvh2, flatten_mesh, placeable_triangles, BuildQuality};

    fn tessellated(cells: u32) -> (Vec<Triangle>, Vec<u32>) {
        let scene = platoon_scene::cornell::tessellated(cells);
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
    fn a_mesh_built_from_its_indices_gives_the_tree_of_its_placeable_triangles() {
        let mut scene = platoon_scene::cornell::tessellated(16);
        let mesh = std::sync::Arc::make_mut(&mut scene.meshes[0]);
        // Unplaceable corners leave their triangles out of both.
        mesh.positions[5] = Vec3::NAN;
        mesh.positions[40] = Vec3::splat(f32::INFINITY);
        let (tris, original) = placeable_triangles(mesh);
        assert!(tris.len() < mesh.indices.len());
        let mut by_tris = build(&tris, 1.5);
        for o in &mut by_tris.order {
            *o = original[*o as usize];
        }
        let by_mesh = build_mesh(&mesh.positions, &mesh.indices, 1.5);
        let bytes = |b: &FlatBvh| {
            let mut out = bytemuck::cast_slice::<BvhNode, u8>(&b.nodes).to_vec();
            out.extend(b.root.to_le_bytes());
            out.extend(bytemuck::cast_slice::<u32, u8>(&b.order));
            out
        };
        assert!(bytes(&by_mesh) == bytes(&by_tris));
        assert_eq!(by_mesh.bounds, by_tris.bounds);
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

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

use platoon_scene::Mesh;

/// Bits of an item that hold a leaf's primitive count.
const COUNT_BITS: u32 = 4;
/// Most primitives one leaf item can name; larger leaves are split.
pub const MAX_LEAF_ITEM: u32 = (1 << COUNT_BITS) - 1;
/// Items index nodes and primitives below this.
pub const MAX_ITEM_INDEX: u32 = 1 << (32 - COUNT_BITS);

/// A reference to a child: `(index << 4) | count`, where count 0 names the inner node `index`
/// of the same array and count 1..=15 names `count` primitives from `index`.
pub fn item(index: u32, count: u32) -> u32 {
    debug_assert!(index < MAX_ITEM_INDEX && count <= MAX_LEAF_ITEM);
    (index << COUNT_BITS) | count
}

/// The (index, count) of an item.
pub fn unpack_item(item: u32) -> (u32, u32) {
    (item >> COUNT_BITS, item & MAX_LEAF_ITEM)
}

/// GPU node: an inner node of a BVH2 holding both children's boxes and items (64 bytes, four
/// 16-byte texels), so a visit reads everything its two box tests need in four vector loads and
/// a leaf is reached without reading a node of its own. Node 0 is the root.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BvhNode {
    pub min0: [f32; 3],
    pub item0: u32,
    pub max0: [f32; 3],
    pub pad0: u32,
    pub min1: [f32; 3],
    pub item1: u32,
    pub max1: [f32; 3],
    pub pad1: u32,
}

impl BvhNode {
    pub(crate) fn pair(
        (min0, max0, item0): (Vec3, Vec3, u32),
        (min1, max1, item1): (Vec3, Vec3, u32),
    ) -> Self {
        BvhNode {
            min0: min0.to_array(),
            item0,
            max0: max0.to_array(),
            min1: min1.to_array(),
            item1,
            max1: max1.to_array(),
            ..Default::default()
        }
    }

    /// The children's items, in order.
    pub fn items(&self) -> [u32; 2] {
        [self.item0, self.item1]
    }

    /// The node with its items moved by [`rebase_item`].
    pub fn rebased(&self, node_base: u32, prim_base: u32) -> Option<BvhNode> {
        Some(BvhNode {
            item0: rebase_item(self.item0, node_base, prim_base)?,
            item1: rebase_item(self.item1, node_base, prim_base)?,
            ..*self
        })
    }
}

/// The surface area heuristic's cost of a ray through the box of the BVH of `nodes` from item
/// `root` (every node of `nodes` below it, or zero-area padding), in the kernel's layout: a visit
/// of an inner node (two box tests) costs 1 and a triangle test 1, each weighed by the chance
/// that a ray through the root's box meets the box that leads to it: its area over the root's
/// (MacDonald and Booth 1990). The lower, the fewer nodes and triangles a ray visits.
pub fn sah_cost(nodes: &[BvhNode], root: u32) -> f64 {
    let (index, count) = unpack_item(root);
    if count > 0 {
        return count as f64;
    }
    let area = |lo: [f32; 3], hi: [f32; 3]| {
        let d = (Vec3::from(hi) - Vec3::from(lo)).max(Vec3::ZERO);
        (d.x * d.y + d.y * d.z + d.z * d.x) as f64
    };
    let r = &nodes[index as usize];
    let lo = Vec3::from(r.min0).min(Vec3::from(r.min1)).to_array();
    let hi = Vec3::from(r.max0).max(Vec3::from(r.max1)).to_array();
    let root_area = area(lo, hi);
    if root_area <= 0.0 {
        return 1.0;
    }
    let mut cost = 1.0;
    for n in nodes {
        for (lo, hi, it) in [(n.min0, n.max0, n.item0), (n.min1, n.max1, n.item1)] {
            let (_, count) = unpack_item(it);
            let weight = if count == 0 { 1.0 } else { count as f64 };
            cost += weight * area(lo, hi) / root_area;
        }
    }
    cost
}

/// The item moved into arrays where its BVH's nodes start at `node_base` and its primitives at
/// `prim_base`; None past [`MAX_ITEM_INDEX`].
pub fn rebase_item(it: u32, node_base: u32, prim_base: u32) -> Option<u32> {
    let (index, count) = unpack_item(it);
    let base = if count == 0 { node_base } else { prim_base };
    let index = index.checked_add(base)?;
    let last = index.checked_add(count)?;
    (last <= MAX_ITEM_INDEX).then(|| item(index, count))
}

/// A flattened BVH over `order.len()` primitives: leaves index primitives in `order` order.
/// Traversal starts at the `root` item: inner node 0, or a leaf when the BVH is one leaf (then
/// `nodes` is empty, and no node is read to reach it).
#[derive(Clone, Debug, Default)]
pub struct FlatBvh {
    pub nodes: Vec<BvhNode>,
    pub root: u32,
    /// Original primitive index of each position referenced by leaves.
    pub order: Vec<u32>,
    /// The root's box.
    pub bounds: (Vec3, Vec3),
}

impl FlatBvh {
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }

    /// The surface area heuristic's cost of a ray through the root's box: [`sah_cost`] of this
    /// BVH, what `platoon info` reports per scene.
    pub fn sah_cost(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        sah_cost(&self.nodes, self.root)
    }

    /// Every (first primitive, count) range the leaves name.
    pub fn leaves(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        std::iter::once(self.root)
            .chain(self.nodes.iter().flat_map(|n| n.items()))
            .map(unpack_item)
            .filter(|&(_, count)| count > 0)
    }
}

/// The item of obvhs leaf or inner node `j`; leaves over [`MAX_LEAF_ITEM`] primitives become
/// inner nodes appended to `nodes`, splitting the range under the same box.
fn child_item(bvh: &Bvh2, j: usize, wide_of: &[u32], nodes: &mut Vec<BvhNode>) -> u32 {
    let n = &bvh.nodes[j];
    if n.prim_count == 0 {
        return item(wide_of[j], 0);
    }
    let (lo, hi) = (Vec3::from(n.aabb.min), Vec3::from(n.aabb.max));
    leaf_item(n.first_index, n.prim_count, lo, hi, nodes)
}

fn leaf_item(first: u32, count: u32, lo: Vec3, hi: Vec3, nodes: &mut Vec<BvhNode>) -> u32 {
    if count <= MAX_LEAF_ITEM {
        return item(first, count);
    }
    let half = count / 2;
    let index = nodes.len();
    nodes.push(BvhNode::default());
    let a = leaf_item(first, half, lo, hi, nodes);
    let b = leaf_item(first + half, count - half, lo, hi, nodes);
    nodes[index] = BvhNode::pair((lo, hi, a), (lo, hi, b));
    item(index as u32, 0)
}

/// The BVH2 `bvh` in the kernel's layout: both children's boxes in the node.
pub fn flatten(bvh: &Bvh2) -> FlatBvh {
    let Some(root) = bvh.nodes.first() else {
        return FlatBvh::default();
    };
    let mut wide_of = vec![u32::MAX; bvh.nodes.len()];
    let inner: Vec<usize> = (0..bvh.nodes.len())
        .filter(|&j| bvh.nodes[j].prim_count == 0)
        .collect();
    for (w, &j) in inner.iter().enumerate() {
        wide_of[j] = w as u32;
    }
    let mut nodes = vec![BvhNode::default(); inner.len()];
    let child = |j: usize, nodes: &mut Vec<BvhNode>| {
        let n = &bvh.nodes[j];
        let it = child_item(bvh, j, &wide_of, nodes);
        (Vec3::from(n.aabb.min), Vec3::from(n.aabb.max), it)
    };
    for (w, &j) in inner.iter().enumerate() {
        let first = bvh.nodes[j].first_index as usize;
        let a = child(first, &mut nodes);
        let b = child(first + 1, &mut nodes);
        nodes[w] = BvhNode::pair(a, b);
    }
    let (lo, hi, root_item) = child(0, &mut nodes);
    debug_assert!(root.prim_count > 0 || root_item == item(0, 0));
    FlatBvh {
        nodes,
        root: root_item,
        order: bvh.primitive_indices.clone(),
        bounds: (lo, hi),
    }
}

/// How much time a bottom level's build may take to lower its traversal cost.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuildQuality {
    /// Geometry built once (static meshes, the merged static geometry): PLOC and then every
    /// node reinserted where the surface area heuristic wants it (Meister and Bittner 2018,
    /// obvhs' "very slow" preset). On tessellated surfaces PLOC alone leaves boxes that overlap
    /// widely: the Cornell box cut into 48 x 48 quads a face costs 309 against 44 (SAH, merged)
    /// and the generated atrium 320 against 66; rays visit that many fewer nodes. It takes 3-5x
    /// the build time (docs/PERFORMANCE.md, "Real scenes").
    Static,
    /// A deforming mesh's rebuild, which the refit guard asks for while the scene lives (a
    /// skinned character's 4,672 triangles: 2.3 ms against 9 ms): PLOC with 5% of the nodes
    /// reinserted (obvhs' "medium").
    Deforming,
    /// Static geometry past [`QUICK_BUILD_TRIANGLES`]: split top-down by binned SAH
    /// ([`super::binned_sah`]), where [`BuildQuality::Static`]'s reinsertion grows to many
    /// seconds (the Cornell box cut into 3.24 million triangles: 10.7 s).
    Quick,
}

/// Static meshes of more triangles than this (2^19) are built [`BuildQuality::Quick`]: every
/// scene of the bench and test suites (the atrium's 264k triangles the largest) keeps the tree,
/// and so the images, it had.
pub const QUICK_BUILD_TRIANGLES: usize = 1 << 19;

impl BuildQuality {
    /// The build of a static mesh of `triangles` triangles.
    pub fn for_static(triangles: usize) -> BuildQuality {
        BuildQuality::for_static_above(triangles, QUICK_BUILD_TRIANGLES)
    }

    /// The same with meshes of more than `quick_above` triangles built quick.
    pub fn for_static_above(triangles: usize, quick_above: usize) -> BuildQuality {
        if triangles > quick_above {
            BuildQuality::Quick
        } else {
            BuildQuality::Static
        }
    }
}

/// The obvhs build parameters of `quality`, without spatial pre-splits in either, so that every
/// triangle appears in exactly one leaf (triangles are reordered into leaf order; obvhs' splits
/// changed the atrium's SAH cost by +0.7% and the others' by nothing, docs/PERFORMANCE.md).
pub fn build_params(quality: BuildQuality) -> BvhBuildParams {
    let mut p = match quality {
        BuildQuality::Static | BuildQuality::Quick => BvhBuildParams::very_slow_build(),
        BuildQuality::Deforming => BvhBuildParams::medium_build(),
    };
    p.pre_split = false;
    if quality != BuildQuality::Deforming {
        p.collapse_traversal_cost = STATIC_COLLAPSE_TRAVERSAL_COST;
    }
    p
}

/// The cost of a node step, in triangle tests, by which obvhs collapses subtrees into leaves
/// (its presets: 3). On llvmpipe a triangle test (three corner fetches) costs more against a
/// node step than on a GPU, and a long leaf keeps every lane of a group waiting: at 1.5 leaves
/// are smaller and a static scene renders 3-37% faster (the conference room most, the 48 x 48
/// box within noise; docs/PERFORMANCE.md, "Leaf size"), for twice the nodes.
pub(crate) const STATIC_COLLAPSE_TRAVERSAL_COST: f32 = 1.5;

pub use platoon_scene::placeable::{placeable, MAX_COORDINATE};

/// The mesh's triangles that can enter a BVH (every corner [`placeable`]), with the mesh index
/// of each.
pub fn placeable_triangles(mesh: &Mesh) -> (Vec<Triangle>, Vec<u32>) {
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
    (tris, original)
}

/// The obvhs BVH2 of triangles, built at `quality`. The same triangles give the same tree
/// whatever the number of threads building it (tested: the tracers' copies and the game
/// thread's queries must hold the same bytes).
pub fn build_bvh2(tris: &[Triangle], quality: BuildQuality) -> Bvh2 {
    let mut time = Duration::ZERO;
    obvhs::bvh2::builder::build_bvh2_from_tris(tris, build_params(quality), &mut time)
}

/// The flattened BVH of `bvh`, whose primitive `i` is mesh triangle `original[i]`.
pub(crate) fn flatten_mesh(bvh: &Bvh2, original: &[u32]) -> FlatBvh {
    let mut flat = flatten(bvh);
    for o in &mut flat.order {
        *o = original[*o as usize];
    }
    flat
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

/// Build timings, reported by `platoon bench kernel`.
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

    /// A mesh's static BVH as obvhs builds it (what `mesh_bvh` builds under the quick size).
    fn build_mesh_bvh(mesh: &Mesh) -> FlatBvh {
        let (tris, original) = placeable_triangles(mesh);
        if tris.is_empty() {
            return FlatBvh::default();
        }
        flatten_mesh(&build_bvh2(&tris, BuildQuality::Static), &original)
    }

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
        for (index, count) in bvh.leaves() {
            for k in 0..count {
                seen[bvh.order[(index + k) as usize] as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        let (lo, hi) = bvh.bounds();
        assert_eq!(lo, Vec3::new(0.0, 0.0, 0.0));
        assert_eq!(hi, Vec3::new(100.0, 13.0, 0.0));
    }

    #[test]
    fn leaves_past_the_item_count_are_split_under_the_same_box() {
        let mut nodes = Vec::new();
        let root = leaf_item(100, 40, Vec3::ZERO, Vec3::ONE, &mut nodes);
        assert_eq!(unpack_item(root), (0, 0));
        let flat = FlatBvh {
            nodes,
            root,
            ..Default::default()
        };
        let mut covered: Vec<u32> = flat
            .leaves()
            .flat_map(|(i, c)| {
                assert!((1..=MAX_LEAF_ITEM).contains(&c));
                i..i + c
            })
            .collect();
        covered.sort();
        assert_eq!(covered, (100..140).collect::<Vec<_>>());
        assert!(flat
            .nodes
            .iter()
            .all(|n| n.min0 == [0.0; 3] && n.max1 == [1.0; 3]));
    }

    /// The flattened BVH's bytes: nodes, root, triangle order.
    fn bytes(b: &FlatBvh) -> Vec<u8> {
        let mut out = bytemuck::cast_slice::<BvhNode, u8>(&b.nodes).to_vec();
        out.extend(b.root.to_le_bytes());
        out.extend(bytemuck::cast_slice::<u32, u8>(&b.order));
        out
    }

    #[test]
    fn a_build_gives_the_same_bytes_whatever_the_threads_building_it() {
        // Tessellated walls: many nodes of equal areas, where ties in the builder's sorts and
        // reinsertions would show any dependence on the order the threads finish in.
        let scene = platoon_scene::cornell::tessellated(24);
        let mesh = &scene.meshes[0];
        let (tris, original) = placeable_triangles(mesh);
        for quality in [BuildQuality::Static, BuildQuality::Deforming] {
            let build = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                bytes(&pool.install(|| flatten_mesh(&build_bvh2(&tris, quality), &original)))
            };
            let one = build(1);
            for threads in [3, 2, 3] {
                assert!(build(threads) == one, "{quality:?} on {threads} threads");
            }
        }
    }

    #[test]
    fn the_static_build_costs_rays_less_on_tessellated_walls() {
        let scene = platoon_scene::cornell::tessellated(24);
        let (tris, original) = placeable_triangles(&scene.meshes[0]);
        let cost = |q| flatten_mesh(&build_bvh2(&tris, q), &original).sah_cost();
        let (fine, quick) = (cost(BuildQuality::Static), cost(BuildQuality::Deforming));
        assert!(fine < 0.5 * quick, "SAH {fine} against {quick}");
    }

    #[test]
    fn the_sah_cost_of_one_leaf_is_its_triangles_and_of_a_split_its_boxes() {
        let one = FlatBvh {
            root: item(0, 3),
            order: vec![0, 1, 2],
            bounds: (Vec3::ZERO, Vec3::ONE),
            ..Default::default()
        };
        assert_eq!(one.sah_cost(), 3.0);
        // Two unit-area halves of a 2 x 1 x 0 box (area 2) with 1 and 2 triangles: the root's
        // visit, then each half met half the time.
        let split = FlatBvh {
            nodes: vec![BvhNode::pair(
                (Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), item(0, 1)),
                (
                    Vec3::new(1.0, 0.0, 0.0),
                    Vec3::new(2.0, 1.0, 0.0),
                    item(1, 2),
                ),
            )],
            root: item(0, 0),
            order: vec![0, 1, 2],
            bounds: (Vec3::ZERO, Vec3::new(2.0, 1.0, 0.0)),
        };
        assert_eq!(split.sah_cost(), 1.0 + 0.5 * 1.0 + 0.5 * 2.0);
    }

    #[test]
    fn rebasing_moves_nodes_and_primitives_and_refuses_overflow() {
        let n = BvhNode {
            item0: item(3, 0),
            item1: item(5, 2),
            ..Default::default()
        };
        let r = n.rebased(10, 1000).unwrap();
        assert_eq!(r.items().map(unpack_item), [(13, 0), (1005, 2)]);
        assert!(n.rebased(0, MAX_ITEM_INDEX - 6).is_none());
    }

    #[test]
    fn a_single_leaf_bvh_is_its_root_item_without_nodes() {
        let mut mesh = Mesh::default();
        mesh.positions.extend([Vec3::ZERO, Vec3::X, Vec3::Y]);
        mesh.indices.push([0, 1, 2]);
        let bvh = build_mesh_bvh(&mesh);
        assert!(bvh.nodes.is_empty());
        assert_eq!(unpack_item(bvh.root), (0, 1));
        assert_eq!(bvh.leaves().collect::<Vec<_>>(), vec![(0, 1)]);
        assert_eq!(bvh.bounds(), (Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)));
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

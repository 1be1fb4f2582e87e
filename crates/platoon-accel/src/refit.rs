//! A mesh's bottom-level BVH kept from frame to frame (Bikker's algorithm 3.1): built once;
//! when the mesh deforms, its leaf boxes are recomputed from their triangles and the inner
//! boxes refitted in one bottom-up sweep (nodes are kept in stack traversal order, so every
//! parent precedes its children); rebuilt when refitting has degraded it past a bound on its
//! SAH cost, or after a number of refits.

use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;

use super::bvh::{
    build_bvh2, flatten_mesh, placeable, placeable_triangles, BuildQuality, FlatBvh, MAX_COORDINATE,
};
use platoon_scene::Mesh;

/// When a refitted BVH is rebuilt instead.
#[derive(Clone, Copy, Debug)]
pub struct RefitPolicy {
    /// Rebuild once the SAH cost exceeds the fresh build's by this factor.
    pub max_cost_ratio: f32,
    /// Rebuild after this many refits in a row, whatever the cost.
    pub max_refits: u32,
    /// Most rebuilds the guard may ask for in one update: the others wait their turn (still
    /// refitted), so meshes that degrade together do not all rebuild in the same frame.
    pub max_rebuilds_per_update: usize,
}

impl Default for RefitPolicy {
    fn default() -> Self {
        RefitPolicy {
            max_cost_ratio: 1.25,
            max_refits: 64,
            max_rebuilds_per_update: 2,
        }
    }
}

/// What [`MeshBvh::update`] did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Update {
    Refitted,
    /// The guard asked for it, or the set of placeable triangles changed.
    Rebuilt,
}

/// A mesh's BVH that follows the mesh as it deforms.
#[derive(Clone)]
pub struct MeshBvh {
    bvh: Bvh2,
    /// Mesh triangle of each BVH primitive (the placeable triangles at the last build).
    original: Vec<u32>,
    /// The mesh's other triangles (unplaceable at the last build).
    left_out: Vec<u32>,
    /// The vertex indices of each BVH primitive slot, so a refit reads positions directly.
    slot_vertices: Vec<[u32; 3]>,
    /// One past the largest vertex index they use.
    vertex_count: usize,
    /// The three corners of each slot's triangle as the kernel reads them (the flattened
    /// layout keeps the slots' order): gathered by the refit, which reads them anyway.
    corners: Vec<[f32; 4]>,
    /// The obvhs inner node behind each node of the flattened layout (see `bvh::flatten`).
    inner: Vec<u32>,
    /// SAH cost right after the last build.
    fresh_cost: f32,
    /// Refits since the last build.
    refits: u32,
}

impl MeshBvh {
    pub fn build(mesh: &Mesh) -> MeshBvh {
        let (tris, original) = placeable_triangles(mesh);
        let mut bvh = if tris.is_empty() {
            Bvh2::default()
        } else {
            build_bvh2(&tris, BuildQuality::Deforming)
        };
        bvh.reorder_in_stack_traversal_order();
        let fresh_cost = sah_cost(&bvh);
        let mut left_out = Vec::new();
        let mut kept = original.iter().peekable();
        for t in 0..mesh.indices.len() as u32 {
            if kept.peek() == Some(&&t) {
                kept.next();
            } else {
                left_out.push(t);
            }
        }
        let inner = (0..bvh.nodes.len() as u32)
            .filter(|&j| bvh.nodes[j as usize].prim_count == 0)
            .collect();
        let slot_vertices: Vec<[u32; 3]> = bvh
            .primitive_indices
            .iter()
            .map(|&p| mesh.indices[original[p as usize] as usize])
            .collect();
        let vertex_count = slot_vertices
            .iter()
            .flatten()
            .max()
            .map_or(0, |&v| v as usize + 1);
        let corners = slot_vertices
            .iter()
            .flatten()
            .map(|&v| mesh.positions[v as usize].extend(0.0).to_array())
            .collect();
        MeshBvh {
            bvh,
            original,
            left_out,
            slot_vertices,
            vertex_count,
            corners,
            inner,
            fresh_cost,
            refits: 0,
        }
    }

    /// Follows `mesh` (the same triangles as at the last build, moved): refits, or rebuilds
    /// when a triangle became unplaceable (or placeable again) or when the policy's guard asks
    /// for it and `may_rebuild()` grants it (a budget shared by the meshes of one update).
    pub fn update(
        &mut self,
        mesh: &Mesh,
        policy: &RefitPolicy,
        may_rebuild: impl FnOnce() -> bool,
    ) -> Update {
        let worn_out = self.refits >= policy.max_refits;
        if !self.refit(mesh) {
            *self = MeshBvh::build(mesh);
            return Update::Rebuilt;
        }
        let degraded = self.sah_cost() > policy.max_cost_ratio * self.fresh_cost;
        if (worn_out || degraded) && may_rebuild() {
            *self = MeshBvh::build(mesh);
            return Update::Rebuilt;
        }
        Update::Refitted
    }

    /// Recomputes every leaf box from its triangles' corners in `mesh`, then every inner box.
    /// False (and the BVH left stale) when the placeable triangles are not the ones it was built
    /// over: then it must be rebuilt.
    pub fn refit(&mut self, mesh: &Mesh) -> bool {
        let corners = |t: u32| mesh.indices[t as usize].map(|v| mesh.positions[v as usize]);
        if mesh.indices.len() != self.original.len() + self.left_out.len()
            || mesh.positions.len() < self.vertex_count
            || self
                .left_out
                .iter()
                .any(|&t| corners(t).iter().all(|&v| placeable(v)))
        {
            return false;
        }
        let limit = Vec3A::splat(MAX_COORDINATE);
        let positions = &mesh.positions;
        let slots = &self.slot_vertices;
        let corners = &mut self.corners;
        let bvh = &mut self.bvh;
        for node in bvh.nodes.iter_mut().filter(|n| n.is_leaf()) {
            let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
            // NaN fails the comparison too, so one test per corner finds every unplaceable one.
            let mut placeable = true;
            let first = node.first_index as usize;
            let count = node.prim_count as usize;
            let out = &mut corners[3 * first..3 * (first + count)];
            for (tri, out) in slots[first..first + count]
                .iter()
                .zip(out.chunks_exact_mut(3))
            {
                for (&v, out) in tri.iter().zip(out) {
                    let p = positions[v as usize];
                    *out = [p.x, p.y, p.z, 0.0];
                    let v = Vec3A::from(p);
                    placeable &= v.abs().cmple(limit).all();
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
            if !placeable {
                return false;
            }
            node.set_aabb(Aabb::new(lo, hi));
        }
        bvh.refit_all();
        self.refits += 1;
        true
    }

    /// Surface-area heuristic cost (traversal 1, intersection 1 per triangle), relative to the
    /// root's area: what the guard compares with the fresh build's.
    pub fn sah_cost(&self) -> f32 {
        sah_cost(&self.bvh)
    }

    pub fn refits_since_build(&self) -> u32 {
        self.refits
    }

    pub fn triangle_count(&self) -> usize {
        self.original.len()
    }

    /// Each primitive slot's three corners (x, y, z, 0) as of the last refit or build, in the
    /// order of [`MeshBvh::flat`]'s triangles.
    pub fn corners(&self) -> &[[f32; 4]] {
        &self.corners
    }

    /// The obvhs BVH (nodes in stack traversal order) and the mesh triangle of each primitive.
    pub fn bvh2(&self) -> (&Bvh2, &[u32]) {
        (&self.bvh, &self.original)
    }

    /// Brings `flat` (this BVH's [`MeshBvh::flat`] before the refits since) up to date: after a
    /// refit only boxes change, so they are copied over instead of flattening anew. False when
    /// `flat` has nodes the refit cannot map (split leaves): then call `flat()`.
    pub fn refit_flat(&self, flat: &mut FlatBvh) -> bool {
        if flat.nodes.len() != self.inner.len() || self.bvh.nodes.is_empty() {
            return false;
        }
        for (node, &j) in flat.nodes.iter_mut().zip(&self.inner) {
            let first = self.bvh.nodes[j as usize].first_index as usize;
            let (a, b) = (
                self.bvh.nodes[first].aabb(),
                self.bvh.nodes[first + 1].aabb(),
            );
            node.min0 = a.min.to_array();
            node.max0 = a.max.to_array();
            node.min1 = b.min.to_array();
            node.max1 = b.max.to_array();
        }
        let root = self.bvh.nodes[0].aabb();
        flat.bounds = (root.min.into(), root.max.into());
        true
    }

    /// The kernel's layout of it.
    pub fn flat(&self) -> FlatBvh {
        if self.original.is_empty() {
            return FlatBvh::default();
        }
        flatten_mesh(&self.bvh, &self.original)
    }
}

fn sah_cost(bvh: &Bvh2) -> f32 {
    let Some(root) = bvh.nodes.first() else {
        return 0.0;
    };
    let root_area = root.aabb().half_area().max(f32::MIN_POSITIVE);
    bvh.nodes
        .iter()
        .map(|n| {
            let weight = if n.is_leaf() {
                n.prim_count as f32
            } else {
                1.0
            };
            weight * n.aabb().half_area() / root_area
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use obvhs::ray::{Ray, RayHit};
    use obvhs::triangle::Triangle;

    /// A wavy grid of `n` x `n` quads; `phase` moves the waves.
    fn grid(n: u32, phase: f32) -> Mesh {
        let mut mesh = Mesh::default();
        for y in 0..=n {
            for x in 0..=n {
                let (fx, fy) = (x as f32 / n as f32, y as f32 / n as f32);
                let z = 0.2 * (6.0 * fx + phase).sin() * (4.0 * fy - phase).cos();
                mesh.positions.push(Vec3::new(fx, fy, z));
            }
        }
        for y in 0..n {
            for x in 0..n {
                let i = y * (n + 1) + x;
                mesh.indices.push([i, i + 1, i + n + 1]);
                mesh.indices.push([i + 1, i + n + 2, i + n + 1]);
            }
        }
        mesh.triangle_materials = vec![0; mesh.indices.len()];
        mesh
    }

    fn triangles(mesh: &Mesh) -> Vec<Triangle> {
        placeable_triangles(mesh).0
    }

    /// Closest-hit t of each ray through `bvh` over `tris` (BVH primitive order = `tris`).
    fn hits(bvh: &Bvh2, tris: &[Triangle], rays: &[Ray]) -> Vec<f32> {
        rays.iter()
            .map(|r| {
                let mut hit = RayHit::none();
                bvh.ray_traverse(*r, &mut hit, |ray, id| {
                    tris[bvh.primitive_indices[id] as usize].intersect(ray)
                });
                hit.t
            })
            .collect()
    }

    fn rays() -> Vec<Ray> {
        let mut rays = Vec::new();
        for i in 0..4096u32 {
            let (u, v) = ((i % 64) as f32 / 63.0, (i / 64) as f32 / 63.0);
            let origin = Vec3::new(u * 1.2 - 0.1, v * 1.2 - 0.1, 1.0);
            let dir = Vec3::new(0.3 * (u - 0.5), 0.2 * (v - 0.5), -1.0).normalize();
            rays.push(Ray::new_inf(origin.into(), dir.into()));
        }
        rays
    }

    #[test]
    fn a_refitted_bvh_is_valid_tight_and_finds_the_rebuilt_bvhs_hits() {
        let mut bvh = MeshBvh::build(&grid(40, 0.0));
        let moved = grid(40, 1.3);
        assert!(bvh.refit(&moved));
        let tris = triangles(&moved);
        bvh.bvh.validate(&tris, false, true);
        let rebuilt = MeshBvh::build(&moved);
        let rays = rays();
        let (a, b) = (
            hits(&bvh.bvh, &tris, &rays),
            hits(&rebuilt.bvh, &tris, &rays),
        );
        let found = a.iter().filter(|t| t.is_finite()).count();
        assert!(found > 1500, "{found} hits");
        assert_eq!(a, b);
        // Refitting the flat layout in place gives the layout flattened anew.
        let mut stale = MeshBvh::build(&grid(40, 0.0)).flat();
        assert!(bvh.refit_flat(&mut stale));
        let fresh = bvh.flat();
        assert_eq!((stale.nodes, stale.bounds), (fresh.nodes, fresh.bounds));
        // The flat layout covers every triangle once.
        let mut seen = vec![0; tris.len()];
        let flat = bvh.flat();
        for (i, c) in flat.leaves() {
            for k in i..i + c {
                seen[flat.order[k as usize] as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
    }

    #[test]
    fn the_guard_rebuilds_a_degraded_or_stale_bvh() {
        let policy = RefitPolicy::default();
        let mut bvh = MeshBvh::build(&grid(16, 0.0));
        assert_eq!(
            bvh.update(&grid(16, 0.1), &policy, || true),
            Update::Refitted
        );
        // Scramble the vertices: the refitted boxes overlap and the cost explodes.
        let mut scrambled = grid(16, 0.0);
        let n = scrambled.positions.len();
        for i in 0..n {
            scrambled.positions.swap(i, (i * 7919) % n);
        }
        assert_eq!(bvh.update(&scrambled, &policy, || true), Update::Rebuilt);
        assert_eq!(bvh.refits_since_build(), 0);
        // A vertex turned NaN (a broken skin) takes its triangles out: rebuild.
        let mut broken = grid(16, 0.0);
        broken.positions[5] = Vec3::NAN;
        assert_eq!(bvh.update(&broken, &policy, || true), Update::Rebuilt);
        assert!(bvh.triangle_count() < broken.indices.len());
        // Healed, the left-out triangles come back: rebuild again.
        assert_eq!(
            bvh.update(&grid(16, 0.0), &policy, || true),
            Update::Rebuilt
        );
        assert_eq!(bvh.triangle_count(), 512);
        let every = RefitPolicy {
            max_refits: 2,
            ..policy
        };
        let mut bvh = MeshBvh::build(&grid(16, 0.0));
        let updates: Vec<Update> = (0..3)
            .map(|i| bvh.update(&grid(16, 0.01 * i as f32), &every, || true))
            .collect();
        assert_eq!(
            updates,
            [Update::Refitted, Update::Refitted, Update::Rebuilt]
        );
    }
}

//! What a flattened scene's BVHs cost a ray, for `platoon info` and the benches: the surface area
//! heuristic of every bottom level (weighted by its triangles) and of the top level.

use super::bvh::{item, sah_cost, unpack_item};
use super::GpuScene;

/// The SAH costs of a scene's BVHs ([`super::bvh::sah_cost`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BvhReport {
    /// The bottom levels' costs, each weighed by its share of the triangles.
    pub bottom: f64,
    /// The cost of the largest bottom level, and its triangles.
    pub largest: f64,
    pub largest_triangles: u32,
    /// The top level's cost over the instances' boxes.
    pub top: f64,
    pub instances: usize,
    /// Nodes in use by the bottom levels (two boxes each).
    pub nodes: usize,
}

impl GpuScene {
    pub fn bvh_report(&self) -> BvhReport {
        let mut r = BvhReport {
            instances: self.instances.len(),
            ..Default::default()
        };
        let total: u64 = self.regions.iter().map(|g| g.triangle_count as u64).sum();
        for g in self.regions.iter().filter(|g| g.triangle_count > 0) {
            let region = &self.blas_nodes[g.node_base as usize..][..g.node_capacity as usize];
            let (index, count) = unpack_item(g.root);
            let root = if count > 0 {
                g.root
            } else {
                item(index - g.node_base, 0)
            };
            let cost = sah_cost(region, root);
            r.bottom += cost * g.triangle_count as f64 / total as f64;
            r.nodes += region.iter().filter(|n| n.items() != [0, 0]).count();
            if g.triangle_count > r.largest_triangles {
                r.largest = cost;
                r.largest_triangles = g.triangle_count;
            }
        }
        if !self.instances.is_empty() {
            r.top = sah_cost(&self.tlas_nodes, self.tlas_root);
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh_bvh::build_mesh_bvh;

    #[test]
    fn the_report_reads_the_costs_of_the_bvhs_the_scene_was_built_from() {
        let scene = platoon_scene::cornell::tessellated(8);
        let g = crate::GpuScene::build(&scene, &scene.pose(0.0), None).unwrap();
        let r = g.bvh_report();
        let own = build_mesh_bvh(&scene.meshes[0]);
        assert!((r.bottom - own.sah_cost()).abs() < 1e-9 * own.sah_cost());
        assert_eq!(r.largest, r.bottom);
        assert_eq!(r.largest_triangles as usize, scene.meshes[0].indices.len());
        assert_eq!(r.nodes, own.nodes.len());
        assert_eq!((r.instances, r.top), (1, 1.0));
    }
}

//! The flattened scene's geometry where it is placed (render space), for the CPU passes that
//! read it triangle by triangle: vertex links' elements and layered hit buffers' oracle.

use glam::{Vec3, Vec4};

use super::GpuScene;

impl GpuScene {
    /// Scene vertex `v` (a global index) of instance `instance` in render space.
    pub fn world_vertex(&self, instance: u32, v: u32) -> Vec3 {
        let rows = self.instances[instance as usize].object_to_world;
        let p = Vec3::from_slice(&self.vertices[v as usize].position_u[..3]).extend(1.0);
        Vec3::new(
            Vec4::from(rows[0]).dot(p),
            Vec4::from(rows[1]).dot(p),
            Vec4::from(rows[2]).dot(p),
        )
    }

    /// The scene triangles instance `instance` places (empty where it places none).
    pub fn instance_triangles(&self, instance: usize) -> std::ops::Range<u32> {
        self.region_of_instance(instance).map_or(0..0, |r| {
            let r = &self.regions[r];
            r.triangle_base..r.triangle_base + r.triangle_count
        })
    }

    /// Every placed triangle, (instance, scene triangle), instance after instance.
    pub fn placed_triangles(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        (0..self.instances.len())
            .flat_map(move |i| self.instance_triangles(i).map(move |t| (i as u32, t)))
    }

    /// The corners of scene triangle `t` as instance `instance` places it, in render space.
    pub fn placed_corners(&self, instance: u32, t: u32) -> [Vec3; 3] {
        self.triangles[t as usize]
            .v
            .map(|v| self.world_vertex(instance, v))
    }

    /// The mesh region (`regions`) instance `instance` places: the one with its tree's root
    /// and triangles (an empty region, a mesh the static merge took in, may name the same root).
    pub fn region_of_instance(&self, instance: usize) -> Option<usize> {
        let root = self.instances.get(instance)?.blas_root;
        self.regions
            .iter()
            .position(|r| r.root == root && r.triangle_count > 0)
    }
}

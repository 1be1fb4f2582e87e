//! platoon-accel: a posed scene flattened into the plain arrays the kernel reads (std430 layouts
//! in [`layout`], mirrored in shaders/scene.glsl), and the CPU's ray queries over them
//! ([`queries`]). It knows the scene (`platoon-scene`) and nothing of frames, methods or Vulkan;
//! the core re-exports it as `platoon_core::flatten`, the only scene data the tracer crate
//! receives. One file per job: [`bvh`] and `geometry` (bottom and top levels),
//! `materials` (and textures), `instances` (with their emissive triangles as lights),
//! `lights` (punctual, environment, selection CDF), [`features`] (what the kernel compiles);
//! [`refit`] keeps a deforming mesh's BVH from frame to frame; [`static_merge`] makes one mesh of
//! the objects that never move; [`commit`] says what changed between two flattened scenes.

pub mod arrays;
pub mod binned_sah;
pub mod bvh;
mod bvh_report;
pub mod commit;
pub mod features;
mod geometry;
mod gpu_scene;
mod hit_names;
pub mod instance_bvh;
mod instances;
pub mod layout;
mod lights;
mod materials;
pub mod mesh_bvh;
mod placed;
pub mod queries;
pub mod refine;
pub mod refit;
pub mod sheen_albedo;
mod sheen_albedo_table;
pub mod static_merge;

pub use bvh_report::BvhReport;

pub use layout::*;
pub use lights::selection_distribution;

use crate::features::SceneFeatures;
use bvh::FlatBvh;
pub use geometry::used_meshes;
pub use gpu_scene::{GpuScene, MeshRegion};
pub use hit_names::HitNames;
use platoon_scene::environment::Environment;
use platoon_scene::error::Result;
use platoon_scene::{Posed, Scene};

impl GpuScene {
    /// A hash of everything the kernel reads (arrays, environment): two scenes with the same
    /// hash render the same image. What renders cached across runs are keyed by.
    pub fn content_hash(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = xxhash_rust::xxh3::Xxh3::new();
        let e = &self.env;
        for bytes in self.array_bytes() {
            bytes.hash(&mut h);
        }
        bytemuck::cast_slice::<_, u8>(&e.color).hash(&mut h);
        (
            self.tlas_root,
            e.kind,
            e.width,
            e.height,
            e.integral.to_bits(),
        )
            .hash(&mut h);
        self.features.defines().hash(&mut h);
        h.finish()
    }

    /// Flattens `posed` (a pose of `scene`). `environment` is the distant light in effect.
    /// Fails when the light-selection distribution is not finite (an emitter of infinite power).
    pub fn build(
        scene: &Scene,
        posed: &Posed,
        environment: Option<&Environment>,
    ) -> Result<GpuScene> {
        GpuScene::build_at(scene, posed, environment, None)
    }

    /// [`GpuScene::build`] with every mesh's BVH built at `quality` (None: by the size rule,
    /// [`bvh::BuildQuality::for_static`]).
    pub fn build_at(
        scene: &Scene,
        posed: &Posed,
        environment: Option<&Environment>,
        quality: Option<bvh::BuildQuality>,
    ) -> Result<GpuScene> {
        let meshes = geometry::used_meshes(posed);
        let (mesh_bvhs, mesh_time) = bvh::timed(|| mesh_bvh::build_mesh_bvhs(&meshes, quality));
        let capacity: Vec<usize> = mesh_bvhs.iter().map(|b| b.nodes.len()).collect();
        let refs: Vec<&FlatBvh> = mesh_bvhs.iter().collect();
        let mut g = GpuScene::build_with(scene, posed, environment, &refs, &capacity)?;
        g.build_times.meshes = mesh_time;
        Ok(g)
    }

    /// Flattens `posed` with the BVH of each of its meshes given (empty for meshes no instance
    /// uses, see [`used_meshes`]), each mesh's node region sized to `node_capacity` (at least
    /// its node count; a deforming mesh gets room for any rebuild of itself, so the layout of
    /// every array stays put from frame to frame).
    pub fn build_with(
        scene: &Scene,
        posed: &Posed,
        environment: Option<&Environment>,
        mesh_bvhs: &[&FlatBvh],
        node_capacity: &[usize],
    ) -> Result<GpuScene> {
        let mut g = GpuScene::default();
        let meshes = geometry::used_meshes(posed);
        geometry::bottom_level(scene, &meshes, mesh_bvhs, node_capacity, &mut g)?;
        g.set_materials(scene);
        g.hit_names.set_names(scene);
        g.set_environment(environment);
        g.place(scene, posed, mesh_bvhs)?;
        Ok(g)
    }

    /// Materials and textures from `scene` (again, after an edit).
    pub fn set_materials(&mut self, scene: &Scene) {
        self.materials.clear();
        self.textures.clear();
        self.texels.clear();
        materials::add(scene, self);
    }

    /// The distant light (its map and CDFs): call [`GpuScene::place`] after it, which adds it to
    /// the lights.
    pub fn set_environment(&mut self, environment: Option<&Environment>) {
        lights::set_environment(environment, self);
    }

    /// Rewrites mesh `index` in place with `mesh` and its BVH (same vertex and triangle counts,
    /// nodes within the region's capacity: a deforming mesh); returns its region.
    pub fn rewrite_mesh(
        &mut self,
        scene: &Scene,
        index: usize,
        mesh: &platoon_scene::Mesh,
        flat: &FlatBvh,
    ) -> Result<MeshRegion> {
        geometry::write_mesh(scene, index, mesh, flat, self)?;
        Ok(self.regions[index])
    }

    /// Rewrites mesh `index`'s nodes with `flat`, a tree over its triangles in the order they
    /// have in place (a refinement, [`refine::refine`]): the nodes and the root, nothing else.
    pub fn rewrite_nodes(&mut self, index: usize, flat: &FlatBvh) -> Result<MeshRegion> {
        geometry::write_nodes(index, flat, self)?;
        Ok(self.regions[index])
    }

    /// The same after a refit, which keeps the triangle order and the nodes' shape: only the
    /// vertices, the triangles' `corners` (in leaf order, as the refit gathered them) and the
    /// nodes' boxes are written.
    pub fn rewrite_refitted(
        &mut self,
        index: usize,
        mesh: &platoon_scene::Mesh,
        flat: &FlatBvh,
        corners: &[[f32; 4]],
    ) -> Result<MeshRegion> {
        geometry::write_refitted(index, mesh, flat, corners, self)?;
        Ok(self.regions[index])
    }

    /// Everything that follows from where the instances and lights are, over the bottom level
    /// already in place: the top level, the instances, every light and the selection CDF, the
    /// feature set.
    pub fn place(&mut self, scene: &Scene, posed: &Posed, mesh_bvhs: &[&FlatBvh]) -> Result<()> {
        self.tlas_nodes.clear();
        self.instances.clear();
        self.lights.clear();
        self.light_cdf.clear();
        let (tlas, live, instance_time) = geometry::top_level(posed, mesh_bvhs, self);
        self.build_times.instances = instance_time;
        // Light order: emissive triangles (by instance), punctual lights, the environment.
        let mut power = instances::add(scene, &tlas, &live, mesh_bvhs, self);
        lights::add_punctual(scene, posed, self, &mut power);
        if self.env.kind != ENV_NONE {
            lights::add_environment_light(self, &mut power);
        }
        lights::set_selection(self, &power)?;
        self.features = SceneFeatures::of_scene(scene);
        self.features.emissive_triangles = self.lights.iter().any(|l| l.ids[0] == LIGHT_TRIANGLE);
        self.features.environment_map = self.env.kind == ENV_MAP;
        Ok(())
    }
}

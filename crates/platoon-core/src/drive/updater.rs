//! The updater: owns the authoritative scene, takes the game's edits, and makes each next
//! generation of the flattened scene. Objects are handled as Bikker's algorithm 3.1 classifies
//! them: a static mesh's BVH is built once; a rigid object only moves its instance (no
//! bottom-level work); a deforming (skinned) mesh is re-posed and its BVH refitted, rebuilt only
//! when the guard asks ([`RefitPolicy`]); the top level is rebuilt every generation. A deforming
//! mesh's node region has room for any rebuild of itself, so the arrays keep their layout and a
//! commit holds only what moved.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::DVec3;

use crate::error::Result;
use crate::flatten::bvh::{build_mesh_bvh, FlatBvh};
use crate::flatten::commit::Commit;
use crate::flatten::refit::{MeshBvh, RefitPolicy, Update};
use crate::flatten::{used_meshes, GpuScene};
use crate::scene::placement::{invalid, Placement};
use crate::scene::{Material, Node, Posed, Scene};

/// Where an update spent its time.
#[derive(Clone, Copy, Debug, Default)]
pub struct UpdateTimes {
    /// Animation, world transforms and skinning.
    pub pose: Duration,
    /// Bottom levels: refits, rebuilds, static builds on first use.
    pub bottom_level: Duration,
    /// Top level, instances, lights and the other arrays.
    pub flatten: Duration,
    /// Comparing with the previous generation.
    pub commit: Duration,
}

/// One generation of the scene: immutable, shared with every tracer.
#[derive(Clone)]
pub struct Generation {
    pub id: u64,
    pub scene: Arc<GpuScene>,
    /// What changed from the previous generation's scene (everything, for the first).
    pub commit: Arc<Commit>,
    pub times: UpdateTimes,
    /// Deforming meshes refitted and rebuilt in this update.
    pub refitted: usize,
    pub rebuilt: usize,
}

pub struct Updater {
    scene: Scene,
    /// Render-space origin (see `Scene::pose_around`).
    origin: DVec3,
    time: f32,
    policy: RefitPolicy,
    /// Flattened BVHs of static meshes, by scene mesh.
    static_bvhs: HashMap<usize, FlatBvh>,
    /// BVHs of skinned meshes, by the node that poses them.
    deforming: HashMap<usize, MeshBvh>,
    /// Nodes whose instance the game removed.
    removed: HashSet<usize>,
    current: Arc<GpuScene>,
    generation: u64,
}

impl Updater {
    /// The updater of `scene` at animation `time`, posed around `origin`, and its first
    /// generation (whose commit is the whole scene).
    pub fn new(scene: Scene, time: f32, origin: DVec3) -> Result<(Updater, Generation)> {
        let mut updater = Updater {
            scene,
            origin,
            time,
            policy: RefitPolicy::default(),
            static_bvhs: HashMap::new(),
            deforming: HashMap::new(),
            removed: HashSet::new(),
            current: Arc::new(GpuScene::default()),
            generation: 0,
        };
        let first = updater.update()?;
        Ok((updater, first))
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    pub fn time(&self) -> f32 {
        self.time
    }

    /// The latest generation's flattened scene.
    pub fn current(&self) -> &Arc<GpuScene> {
        &self.current
    }

    pub fn set_refit_policy(&mut self, policy: RefitPolicy) {
        self.policy = policy;
    }

    /// Animation time of the next generation (glTF animations and the skins they drive).
    pub fn set_time(&mut self, time: f32) -> Result<()> {
        if !time.is_finite() {
            return Err(invalid(format!("animation time {time} is not finite")));
        }
        self.time = time;
        Ok(())
    }

    /// Moves, rotates and scales `node` relative to its parent. An animated node follows its
    /// animation again at the next update.
    pub fn set_placement(&mut self, node: usize, placement: Placement) -> Result<()> {
        let p = placement.checked()?;
        let n = self.live_node(node)?;
        n.translation = p.translation;
        n.rotation = p.rotation;
        n.scale = p.scale;
        Ok(())
    }

    /// A new instance of scene mesh `mesh` at `placement` (in world space); returns its node.
    pub fn add_instance(&mut self, mesh: usize, placement: Placement) -> Result<usize> {
        let p = placement.checked()?;
        if mesh >= self.scene.meshes.len() {
            return Err(invalid(format!(
                "no mesh {mesh} (the scene has {})",
                self.scene.meshes.len()
            )));
        }
        let mut node = Node::new(format!("instance of mesh {mesh}"));
        node.mesh = Some(mesh);
        node.translation = p.translation;
        node.rotation = p.rotation;
        node.scale = p.scale;
        self.scene.nodes.push(node);
        Ok(self.scene.nodes.len() - 1)
    }

    /// Removes the instance `node` places (the node stays, without its mesh: node indices used
    /// by parents, skins and animations keep their meaning).
    pub fn remove_instance(&mut self, node: usize) -> Result<()> {
        let n = self.live_node(node)?;
        if n.mesh.take().is_none() {
            return Err(invalid(format!("node {node} places no instance")));
        }
        n.skin = None;
        self.removed.insert(node);
        self.deforming.remove(&node);
        Ok(())
    }

    /// Replaces material `index`; its factors must be finite.
    pub fn set_material(&mut self, index: usize, material: Material) -> Result<()> {
        let count = self.scene.materials.len();
        let slot = self
            .scene
            .materials
            .get_mut(index)
            .ok_or_else(|| invalid(format!("no material {index} (the scene has {count})")))?;
        check_material(index, &material)?;
        *slot = material;
        Ok(())
    }

    fn live_node(&mut self, node: usize) -> Result<&mut Node> {
        if self.removed.contains(&node) {
            return Err(invalid(format!(
                "node {node}'s instance was already removed"
            )));
        }
        let count = self.scene.nodes.len();
        self.scene
            .nodes
            .get_mut(node)
            .ok_or_else(|| invalid(format!("no node {node} (the scene has {count})")))
    }

    /// Makes the next generation from the scene as edited so far.
    pub fn update(&mut self) -> Result<Generation> {
        let mut times = UpdateTimes::default();
        let start = Instant::now();
        let posed = self.scene.pose_around(self.time, self.origin);
        times.pose = start.elapsed();

        let start = Instant::now();
        let (bvhs, capacity, refitted, rebuilt) = self.bottom_levels(&posed);
        times.bottom_level = start.elapsed();

        let start = Instant::now();
        let env = self.scene.environment.as_ref();
        let next = GpuScene::build_with(&self.scene, &posed, env, &bvhs, &capacity)?;
        times.flatten = start.elapsed();

        let start = Instant::now();
        let commit = Commit::between(&self.current, &next);
        times.commit = start.elapsed();

        self.current = Arc::new(next);
        self.generation += 1;
        Ok(Generation {
            id: self.generation,
            scene: self.current.clone(),
            commit: Arc::new(commit),
            times,
            refitted,
            rebuilt,
        })
    }

    /// The BVH and node capacity of every posed mesh: static ones from the cache, skinned ones
    /// refitted (or built, for a node seen for the first time).
    fn bottom_levels(&mut self, posed: &Posed) -> (Vec<FlatBvh>, Vec<usize>, usize, usize) {
        let meshes = used_meshes(posed);
        let base = self.scene.meshes.len();
        // A skinned mesh is posed once per node, after the scene's own meshes.
        let node_of: HashMap<usize, usize> = posed
            .instances
            .iter()
            .filter(|i| i.mesh >= base)
            .map(|i| (i.mesh, i.node))
            .collect();
        let (mut refitted, mut rebuilt) = (0, 0);
        let mut bvhs = Vec::with_capacity(meshes.len());
        let mut capacity = Vec::with_capacity(meshes.len());
        for (i, mesh) in meshes.iter().enumerate() {
            if mesh.indices.is_empty() {
                bvhs.push(FlatBvh::default());
                capacity.push(0);
            } else if let Some(&node) = node_of.get(&i) {
                let bvh = match self.deforming.get_mut(&node) {
                    Some(b) => {
                        match b.update(mesh, &self.policy) {
                            Update::Refitted => refitted += 1,
                            Update::Rebuilt => rebuilt += 1,
                        }
                        b
                    }
                    None => {
                        rebuilt += 1;
                        self.deforming.entry(node).or_insert(MeshBvh::build(mesh))
                    }
                };
                bvhs.push(bvh.flat());
                // A binary tree over n triangles has fewer than n inner nodes: any rebuild fits.
                capacity.push(mesh.indices.len().max(1));
            } else {
                let flat = self
                    .static_bvhs
                    .entry(i)
                    .or_insert_with(|| build_mesh_bvh(mesh))
                    .clone();
                capacity.push(flat.nodes.len());
                bvhs.push(flat);
            }
        }
        // Forget the BVHs of skinned nodes that no longer pose a mesh.
        let live: HashSet<usize> = node_of.values().copied().collect();
        self.deforming.retain(|node, _| live.contains(node));
        (bvhs, capacity, refitted, rebuilt)
    }
}

/// A material a game may set: every factor finite.
pub(crate) fn check_material(index: usize, m: &Material) -> Result<()> {
    let finite = [
        m.base_color.is_finite(),
        m.emissive.is_finite(),
        m.metallic.is_finite(),
        m.roughness.is_finite(),
        m.transmission.is_finite(),
        m.ior.is_finite(),
        m.specular.is_finite(),
        m.specular_color.is_finite(),
        m.normal_scale.is_finite(),
    ];
    if finite.contains(&false) {
        return Err(invalid(format!("material {index} has a non-finite factor")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flatten::commit::MESH_ARRAYS;

    fn cornell() -> (Updater, Generation) {
        Updater::new(crate::scene::cornell::scene(), 0.0, DVec3::ZERO).unwrap()
    }

    #[test]
    fn the_first_generation_is_the_whole_scene_and_an_unchanged_one_commits_nothing() {
        let (mut u, first) = cornell();
        assert_eq!(first.commit.bytes(), {
            let s = first.scene.array_bytes();
            s.iter().map(|a| a.len() as u64).sum::<u64>()
        });
        let fresh = GpuScene::build(u.scene(), &u.scene().pose(0.0), None).unwrap();
        assert_eq!(fresh.vertices.len(), first.scene.vertices.len());
        let next = u.update().unwrap();
        assert!(next.commit.is_empty(), "{:?}", next.commit);
        assert_eq!(next.id, first.id + 1);
    }

    #[test]
    fn a_rigid_move_commits_no_mesh_data() {
        let (mut u, _) = cornell();
        let node = u
            .scene()
            .nodes
            .iter()
            .position(|n| n.mesh.is_some())
            .unwrap();
        u.set_placement(node, Placement::at(DVec3::new(0.1, 0.0, 0.0)))
            .unwrap();
        let g = u.update().unwrap();
        assert!(!g.commit.is_empty());
        assert_eq!(g.commit.mesh_bytes(), 0, "{:?}", g.commit);
        assert!(g.commit.arrays.iter().any(|a| a.array == 6), "instances");
    }

    #[test]
    fn instances_come_and_go_and_bad_edits_are_refused() {
        let (mut u, first) = cornell();
        let node = u
            .add_instance(0, Placement::at(DVec3::new(3.0, 0.0, 0.0)))
            .unwrap();
        let g = u.update().unwrap();
        assert_eq!(g.scene.instances.len(), first.scene.instances.len() + 1);
        // The new instance reuses the mesh: no bottom-level bytes.
        assert!(g
            .commit
            .arrays
            .iter()
            .all(|a| !MESH_ARRAYS.contains(&a.array)));
        u.remove_instance(node).unwrap();
        let g = u.update().unwrap();
        assert_eq!(g.scene.instances.len(), first.scene.instances.len());
        let twice = u.remove_instance(node).unwrap_err().to_string();
        assert!(twice.contains("already removed"), "{twice}");
        assert!(u.add_instance(99, Placement::at(DVec3::ZERO)).is_err());
        assert!(u.set_placement(999, Placement::at(DVec3::ZERO)).is_err());
        assert!(u.set_time(f32::NAN).is_err());
        let mut m = u.scene().materials[0].clone();
        m.roughness = f32::NAN;
        assert!(u.set_material(0, m).is_err());
        // Nothing refused reached the scene.
        assert!(u.update().unwrap().commit.is_empty());
    }
}

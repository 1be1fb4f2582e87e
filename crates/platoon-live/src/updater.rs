//! The updater: owns the authoritative scene, takes the game's edits, and makes each next
//! generation of the flattened scene. Objects are handled as Bikker's algorithm 3.1 classifies
//! them: a static mesh's BVH is built once; a rigid object only moves its instance (no
//! bottom-level work); a deforming (skinned) mesh is re-posed and its BVH refitted, rebuilt only
//! when the guard asks ([`RefitPolicy`]); the top level is rebuilt every generation. A deforming
//! mesh's node region has room for any rebuild of itself, so the arrays keep their layout and a
//! commit holds only what moved. Objects that never move are merged into one bottom level
//! (`flatten::static_merge`); an edit that moves one splits it out (the merged mesh and its BVH
//! are built again, counted with the rebuilds).

use std::collections::{HashMap, HashSet};
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::DVec3;

use platoon_core::error::Result;
use platoon_core::flatten::arrays::SceneArray;
use platoon_core::flatten::bvh::BuildQuality;
use platoon_core::flatten::bvh::FlatBvh;
use platoon_core::flatten::commit::Commit;
use platoon_core::flatten::mesh_bvh::build_mesh_bvh_at;
use platoon_core::flatten::refit::{MeshBvh, RefitPolicy, Update};
use platoon_core::flatten::static_merge::{StaticMerge, MERGED_NODE};
use platoon_core::flatten::{used_meshes, GpuScene, MeshRegion};
use platoon_core::frame::hit_geometry::HitGeometry;
use platoon_core::scene::floating_origin::FloatingOrigin;
use platoon_core::scene::{Mesh, Node, Posed, Scene};

use super::edit::{Edit, Structure};
use super::refinement::{Refiner, StaticBuild, Target};

/// Where an update spent its time.
#[derive(Clone, Copy, Debug, Default)]
pub struct UpdateTimes {
    /// Animation, world transforms and skinning.
    pub pose: Duration,
    /// Bottom levels: refits, rebuilds, static builds on first use.
    pub bottom_level: Duration,
    /// Rewriting the deformed meshes, the top level, instances, lights and the other arrays.
    pub flatten: Duration,
    /// Of which the top-level BVH build.
    pub top_level: Duration,
    /// Building the commit (copying what changed, or comparing with the previous generation).
    pub commit: Duration,
    /// The whole update, from its first step to the generation handed over (what the parts
    /// leave out: the bookkeeping between them, freeing the previous poses).
    pub total: Duration,
}

/// One generation of the scene as the tracers receive it: what changed since the previous one,
/// immutable and shared by every tracer.
#[derive(Clone)]
pub struct Generation {
    pub id: u64,
    /// The world point at render space's origin in this generation (see
    /// `Edit::FollowCamera`): the frame's camera is placed relative to it.
    pub origin: DVec3,
    /// What changed from the previous generation's scene, with the bytes.
    pub commit: Arc<Commit>,
    pub times: UpdateTimes,
    /// Deforming meshes refitted and rebuilt in this update (rebuilt counts the merged static
    /// geometry too, built again after an edit split an object out of it).
    pub refitted: usize,
    pub rebuilt: usize,
    /// Static BVHs whose refined tree was swapped in by this update
    /// ([`super::refinement::Refinement::Background`]).
    pub refined: usize,
    /// The generation's flattened scene, when the pipeline keeps them (`Pipeline::keep_scenes`)
    /// and the scene changed.
    pub scene: Option<Arc<GpuScene>>,
    /// What carries the generation's hits back to the frame before, when the pipeline keeps
    /// it (`Pipeline::keep_hit_geometry`) and the scene changed.
    pub hits: Option<Arc<HitGeometry>>,
}

/// How an updater treats the scene's static geometry.
#[derive(Clone, Copy, Debug)]
pub struct UpdaterOptions {
    /// The objects that never move merged into one bottom level (else each keeps its
    /// instance).
    pub merge_static: bool,
    pub static_build: StaticBuild,
}

impl Default for UpdaterOptions {
    fn default() -> Self {
        UpdaterOptions {
            merge_static: true,
            static_build: StaticBuild::default(),
        }
    }
}

pub struct Updater {
    scene: Scene,
    /// Render-space origin (see `Scene::pose_around`), following the camera.
    origin: FloatingOrigin,
    time: f32,
    policy: RefitPolicy,
    /// Flattened BVHs of static meshes, by scene mesh.
    static_bvhs: HashMap<usize, Arc<FlatBvh>>,
    /// The objects that never moved, merged; the BVH of their mesh as last built.
    merge: StaticMerge,
    merged_bvh: Option<(Arc<Mesh>, Arc<FlatBvh>)>,
    /// How static BVHs are built, and their refinements under way.
    static_build: StaticBuild,
    refiner: Refiner,
    /// Skinned meshes by the node that poses them: the pose last flattened, its BVH kept from
    /// frame to frame, and that BVH flattened.
    deforming: HashMap<usize, Skinned>,
    /// What edits are checked against.
    structure: Structure,
    /// The latest generation, flattened (rewritten in place where meshes deform).
    state: GpuScene,
    /// Per posed mesh: vertices, triangles and node capacity of the layout of `state`.
    layout: Vec<(usize, usize, usize)>,
    materials_dirty: bool,
    environment_dirty: bool,
    /// Any edit since the last update (none: the next generation is the same scene).
    edited: bool,
    generation: u64,
}

impl Updater {
    /// The updater of `scene` at animation `time`, posed around `origin`, with its first
    /// generation flattened (see [`Updater::flattened`]: what a new tracer uploads).
    pub fn new(scene: Scene, time: f32, origin: DVec3) -> Result<Updater> {
        Updater::with_merge(scene, time, origin, true)
    }

    /// The same, with the objects that never move merged into one bottom level or not
    /// (`merge_static`: each keeps its instance).
    pub fn with_merge(
        scene: Scene,
        time: f32,
        origin: DVec3,
        merge_static: bool,
    ) -> Result<Updater> {
        let options = UpdaterOptions {
            merge_static,
            ..Default::default()
        };
        Updater::with_options(scene, time, origin, options)
    }

    /// The same, as `options` say.
    pub fn with_options(
        scene: Scene,
        time: f32,
        origin: DVec3,
        options: UpdaterOptions,
    ) -> Result<Updater> {
        let merge = if options.merge_static {
            StaticMerge::of_scene(&scene)
        } else {
            StaticMerge::none()
        };
        let mut updater = Updater {
            structure: Structure::of(&scene),
            merge,
            merged_bvh: None,
            static_build: options.static_build,
            refiner: Refiner::new(options.static_build.refinement),
            scene,
            origin: FloatingOrigin {
                origin,
                ..Default::default()
            },
            time,
            policy: RefitPolicy::default(),
            static_bvhs: HashMap::new(),
            deforming: HashMap::new(),
            state: GpuScene::default(),
            layout: Vec::new(),
            materials_dirty: false,
            environment_dirty: false,
            edited: true,
            generation: 0,
        };
        updater.update()?;
        Ok(updater)
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    pub fn time(&self) -> f32 {
        self.time
    }

    /// The latest generation's flattened scene: what a tracer created now uploads.
    pub fn flattened(&self) -> &GpuScene {
        &self.state
    }

    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The world point at the origin of render space: generations, their cameras and ray
    /// queries are relative to it.
    pub fn origin(&self) -> DVec3 {
        self.origin.origin
    }

    /// Static BVHs whose refinement is under way or done and not yet swapped in.
    pub fn refinements_pending(&self) -> usize {
        self.refiner.pending()
    }

    /// Waits for the refinements under way: the next update swaps them in (what makes the
    /// generation of a swap a chosen one, for tests and benches).
    pub fn finish_refinements(&mut self) {
        self.refiner.wait();
    }

    pub fn set_refit_policy(&mut self, policy: RefitPolicy) {
        self.policy = policy;
    }

    /// Applies `edit` to the scene of the next generation after checking it (its values, and
    /// that it names what exists); returns the node of an added instance.
    pub fn apply(&mut self, edit: Edit) -> Result<Option<usize>> {
        let edit = edit.checked()?;
        let added = self.structure.admit(&edit)?;
        match edit {
            Edit::Time(t) => self.time = t,
            Edit::Placement { node, placement } => {
                placement.place(&mut self.scene.nodes[node]);
                self.split_out_moved(node);
            }
            Edit::AddInstance { mesh, placement } => {
                let mut node = Node::new(format!("instance of mesh {mesh}"));
                node.mesh = Some(mesh);
                placement.place(&mut node);
                self.scene.nodes.push(node);
            }
            Edit::RemoveInstance(node) => {
                self.merge.split_out(node);
                let n = &mut self.scene.nodes[node];
                n.mesh = None;
                n.skin = None;
                self.deforming.remove(&node);
            }
            Edit::Material(i, m) => {
                self.scene.materials[i] = *m;
                self.materials_dirty = true;
            }
            Edit::Light(i, l) => self.scene.lights[i] = *l,
            Edit::Environment(e) => {
                self.scene.environment = *e;
                self.environment_dirty = true;
            }
            Edit::FollowCamera(c) => {
                // Only a moved origin changes the scene (the camera is the frame's).
                if !self.origin.follow(c) {
                    return Ok(None);
                }
            }
        }
        self.edited = true;
        Ok(added)
    }

    /// `node` moved: it and every node under it leave the merged static geometry.
    fn split_out_moved(&mut self, node: usize) {
        let mut moved = vec![false; self.scene.nodes.len()];
        moved[node] = true;
        // Parents come before their children.
        for i in node + 1..self.scene.nodes.len() {
            if let Some(p) = self.scene.nodes[i].parent {
                moved[i] = moved[p];
            }
        }
        for (i, _) in moved.iter().enumerate().filter(|(_, &m)| m) {
            self.merge.split_out(i);
        }
    }

    /// Makes the next generation from the scene as edited so far. When every posed mesh keeps
    /// its counts (the common case: rigid motion, skinning, refits), the previous generation is
    /// updated in place and the commit holds exactly what was rewritten; otherwise (instances of
    /// new meshes, a changed layout) the scene is flattened anew and compared chunk by chunk.
    pub fn update(&mut self) -> Result<Generation> {
        let refined = self.take_refined();
        if !refined.is_empty() {
            self.edited = true;
        }
        if !std::mem::take(&mut self.edited) {
            // Nothing changed (only the camera moved, which is the frame's, not the scene's):
            // no pose, no skinning, an empty commit.
            self.generation += 1;
            return Ok(Generation {
                id: self.generation,
                origin: self.origin.origin,
                commit: Arc::new(Commit {
                    arrays: Vec::new(),
                    header: self.state.header(),
                    regions: self.state.regions.clone(),
                    rebuilt: Vec::new(),
                    deformed: Vec::new(),
                }),
                times: UpdateTimes::default(),
                refitted: 0,
                rebuilt: 0,
                refined: 0,
                scene: None,
                hits: None,
            });
        }
        let mut times = UpdateTimes::default();
        let begin = Instant::now();
        let start = Instant::now();
        let posed = self.scene.pose_around(self.time, self.origin.origin);
        let merges = self.merge.rebuilds();
        let posed = self.merge.apply(&self.scene, posed);
        times.pose = start.elapsed();

        let start = Instant::now();
        let meshes = used_meshes(&posed);
        let mut levels = self.bottom_levels(&posed, &meshes);
        levels.rebuilt += self.merge.rebuilds() - merges;
        times.bottom_level = start.elapsed();

        let start = Instant::now();
        let refs: Vec<&FlatBvh> = levels
            .bvhs
            .iter()
            .map(|b| match b {
                Level::Static(i) => &*self.static_bvhs[i],
                Level::Skinned(node) => &self.deforming[node].flat,
                Level::Merged => &*self.merged_bvh.as_ref().expect("built with the level").1,
                Level::Empty => &EMPTY,
            })
            .collect();
        let layout: Vec<(usize, usize, usize)> = meshes
            .iter()
            .zip(&refs)
            .zip(&levels.capacity)
            .map(|((m, b), &c)| (m.positions.len(), b.order.len(), c.max(b.nodes.len())))
            .collect();
        // The posed meshes whose refined tree came (those rebuilt this update already are).
        let swapped: Vec<usize> = (levels.bvhs.iter().enumerate())
            .filter(|(i, level)| {
                let target = match level {
                    Level::Static(m) => Target::Static(*m),
                    Level::Merged => Target::Merged,
                    _ => return false,
                };
                refined.contains(&target) && !levels.deformed.iter().any(|d| d.0 == *i)
            })
            .map(|(i, _)| i)
            .collect();
        let commit = if self.generation > 0 && layout == self.layout {
            let mut ranges = Vec::new();
            for &i in &swapped {
                // The triangles stay where they are: the nodes alone.
                let r = self.state.rewrite_nodes(i, refs[i])?;
                ranges.push(node_range(&r, r.node_capacity as u64));
            }
            for &(i, node, reshaped) in &levels.deformed {
                let r = if reshaped {
                    self.state
                        .rewrite_mesh(&self.scene, i, &meshes[i], refs[i])?
                } else {
                    let corners = self.deforming[&node].bvh.corners();
                    self.state
                        .rewrite_refitted(i, &meshes[i], refs[i], corners)?
                };
                ranges.extend(region_ranges(&r, refs[i].nodes.len() as u64, reshaped));
            }
            if std::mem::take(&mut self.materials_dirty) {
                self.state.set_materials(&self.scene);
                ranges.extend([7, 8, 9].map(|a| (a, 0, self.state.array_bytes()[a].len() as u64)));
            }
            if std::mem::take(&mut self.environment_dirty) {
                self.state.set_environment(self.scene.environment.as_ref());
                ranges
                    .extend([12, 13, 14].map(|a| (a, 0, self.state.array_bytes()[a].len() as u64)));
            }
            let before = top_arrays(&self.state);
            self.state.place(&self.scene, &posed, &refs)?;
            let after = top_arrays(&self.state);
            for (k, (b, a)) in before.iter().zip(&after).enumerate() {
                if b != a {
                    ranges.push((TOP_ARRAYS[k], 0, a.len() as u64));
                }
            }
            times.flatten = start.elapsed();
            times.top_level = self.state.build_times.instances;
            let start = Instant::now();
            let mut commit = Commit::of_ranges(&self.state, ranges);
            commit.rebuilt = (levels.deformed.iter())
                .filter(|d| d.2)
                .map(|d| d.0 as u32)
                .collect();
            commit.deformed = levels.deformed.iter().map(|d| d.0 as u32).collect();
            times.commit = start.elapsed();
            commit
        } else {
            let env = self.scene.environment.as_ref();
            let next = GpuScene::build_with(&self.scene, &posed, env, &refs, &levels.capacity)?;
            times.flatten = start.elapsed();
            times.top_level = next.build_times.instances;
            let start = Instant::now();
            let mut commit = Commit::between(&self.state, &next);
            commit.deformed = levels.deformed.iter().map(|d| d.0 as u32).collect();
            times.commit = start.elapsed();
            self.state = next;
            self.layout = layout;
            self.materials_dirty = false;
            self.environment_dirty = false;
            commit
        };
        drop(posed);
        self.generation += 1;
        times.total = begin.elapsed();
        Ok(Generation {
            id: self.generation,
            origin: self.origin.origin,
            commit: Arc::new(commit),
            times,
            refitted: levels.refitted,
            rebuilt: levels.rebuilt,
            refined: swapped.len(),
            scene: None,
            hits: None,
        })
    }

    /// The BVH and node capacity of every posed mesh: static ones from the cache (built on
    /// first use), skinned ones refitted (or built, for a node seen for the first time).
    fn bottom_levels(&mut self, posed: &Posed, meshes: &[Arc<Mesh>]) -> Levels {
        let base = self.scene.meshes.len();
        // A skinned mesh is posed once per node, after the scene's own meshes.
        let node_of: HashMap<usize, usize> = posed
            .instances
            .iter()
            .filter(|i| i.mesh >= base && i.node != MERGED_NODE)
            .map(|i| (i.mesh, i.node))
            .collect();
        let merged = self.merge.mesh().cloned();
        let mut levels = Levels::default();
        // Skinned meshes whose pose changed, taken out of the map to refit in parallel.
        let mut changed: Vec<(usize, usize, Option<Skinned>)> = Vec::new();
        for (i, mesh) in meshes.iter().enumerate() {
            if mesh.indices.is_empty() {
                levels.bvhs.push(Level::Empty);
                levels.capacity.push(0);
            } else if merged.as_ref().is_some_and(|m| Arc::ptr_eq(m, mesh)) {
                // The merged static geometry: its BVH is built once per merge.
                let fresh = self
                    .merged_bvh
                    .as_ref()
                    .is_some_and(|(m, _)| Arc::ptr_eq(m, mesh));
                if !fresh {
                    let bvh = self.build_static(Target::Merged, mesh);
                    self.merged_bvh = Some((mesh.clone(), bvh));
                    // Built again (a split, or render space moved): its region is rewritten
                    // whole when the layout stays.
                    levels.deformed.push((i, MERGED_NODE, true));
                }
                let flat = &self.merged_bvh.as_ref().expect("just built").1;
                levels.capacity.push(flat.nodes.len());
                levels.bvhs.push(Level::Merged);
            } else if let Some(&node) = node_of.get(&i) {
                match self.deforming.get(&node) {
                    // The same pose as last time (time and joints unchanged): nothing to do.
                    Some(s) if same_pose(&s.posed, mesh) => {}
                    _ => changed.push((i, node, self.deforming.remove(&node))),
                }
                levels.bvhs.push(Level::Skinned(node));
                // A binary tree over n triangles has fewer than n inner nodes: any rebuild fits.
                levels.capacity.push(mesh.indices.len().max(1));
            } else {
                if !self.static_bvhs.contains_key(&i) {
                    let bvh = self.build_static(Target::Static(i), mesh);
                    self.static_bvhs.insert(i, bvh);
                }
                levels.capacity.push(self.static_bvhs[&i].nodes.len());
                levels.bvhs.push(Level::Static(i));
            }
        }
        use rayon::prelude::*;
        use std::sync::atomic::{AtomicUsize, Ordering};
        let budget = AtomicUsize::new(self.policy.max_rebuilds_per_update);
        let policy = self.policy;
        let updated: Vec<(usize, usize, Skinned, bool, bool)> = changed
            .into_par_iter()
            .map(|(i, node, before)| {
                let mesh = &meshes[i];
                let (bvh, flat, rebuilt, reshaped) = match before {
                    Some(mut s) => {
                        let grant = || {
                            budget
                                .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |b| {
                                    b.checked_sub(1)
                                })
                                .is_ok()
                        };
                        let rebuilt = s.bvh.update(mesh, &policy, grant) == Update::Rebuilt;
                        let mut flat = s.flat;
                        let reshaped = rebuilt || !s.bvh.refit_flat(&mut flat);
                        if reshaped {
                            flat = s.bvh.flat();
                        }
                        (s.bvh, flat, rebuilt, reshaped)
                    }
                    None => {
                        let bvh = MeshBvh::build(mesh);
                        let flat = bvh.flat();
                        (bvh, flat, true, true)
                    }
                };
                let posed = mesh.clone();
                (i, node, Skinned { posed, bvh, flat }, rebuilt, reshaped)
            })
            .collect();
        for (i, node, skinned, rebuilt, reshaped) in updated {
            if rebuilt {
                levels.rebuilt += 1;
            } else {
                levels.refitted += 1;
            }
            levels.deformed.push((i, node, reshaped));
            self.deforming.insert(node, skinned);
        }
        // Forget the BVHs of skinned nodes that no longer pose a mesh.
        let live: HashSet<usize> = node_of.values().copied().collect();
        self.deforming.retain(|node, _| live.contains(node));
        levels
    }
}

impl Updater {
    /// The BVH of a static mesh (or the merged static geometry), built by the size rule of
    /// [`StaticBuild`]; a quick one is handed to the refiner.
    fn build_static(&mut self, target: Target, mesh: &Mesh) -> Arc<FlatBvh> {
        let quality =
            BuildQuality::for_static_above(mesh.indices.len(), self.static_build.quick_above);
        let flat = build_mesh_bvh_at(mesh, Some(quality));
        match quality {
            BuildQuality::Quick => self.refiner.built(target, flat),
            _ => Arc::new(flat),
        }
    }

    /// Puts the refined trees that are done in place of the quick ones they were made from
    /// (unless those were replaced meanwhile: a split rebuilt the merged geometry); returns
    /// whose.
    fn take_refined(&mut self) -> Vec<Target> {
        let mut swapped = Vec::new();
        for (target, from, tree) in self.refiner.finished() {
            let slot = match target {
                Target::Static(m) => self.static_bvhs.get_mut(&m),
                Target::Merged => self.merged_bvh.as_mut().map(|(_, b)| b),
            };
            if let Some(slot) = slot.filter(|b| Arc::ptr_eq(b, &from)) {
                *slot = Arc::new(tree);
                swapped.push(target);
            }
        }
        swapped
    }
}

/// The byte range of the first `nodes` nodes of a mesh region.
fn node_range(r: &MeshRegion, nodes: u64) -> (usize, u64, u64) {
    let node = std::mem::size_of::<platoon_core::flatten::bvh::BvhNode>() as u64;
    (
        SceneArray::Blas.index(),
        r.node_base as u64 * node,
        nodes * node,
    )
}

static EMPTY: FlatBvh = FlatBvh {
    nodes: Vec::new(),
    root: 0,
    order: Vec::new(),
    bounds: (glam::Vec3::ZERO, glam::Vec3::ZERO),
};

/// One posed mesh's BVH for this generation.
enum Level {
    Empty,
    /// In the static cache, by mesh.
    Static(usize),
    /// Posed by this node.
    Skinned(usize),
    /// The merged static geometry (`Updater::merged_bvh`).
    Merged,
}

struct Skinned {
    posed: Arc<Mesh>,
    bvh: MeshBvh,
    flat: FlatBvh,
}

/// Whether a skinned mesh came out of posing exactly as last time.
fn same_pose(before: &Mesh, now: &Mesh) -> bool {
    before.positions == now.positions
        && before.normals == now.normals
        && before.tangents == now.tangents
}

#[derive(Default)]
struct Levels {
    bvhs: Vec<Level>,
    capacity: Vec<usize>,
    /// Posed meshes rewritten this generation, the node posing each, and whether its BVH was
    /// flattened anew (a rebuild, which reorders the triangles and reshapes the nodes) rather
    /// than refitted.
    deformed: Vec<(usize, usize, bool)>,
    refitted: usize,
    rebuilt: usize,
}

/// The arrays rebuilt whole every generation: top level, instances, lights, selection CDF.
const TOP_ARRAYS: [usize; 4] = [
    SceneArray::Tlas.index(),
    SceneArray::Instances.index(),
    SceneArray::Lights.index(),
    SceneArray::LightCdf.index(),
];

fn top_arrays(g: &GpuScene) -> [Vec<u8>; 4] {
    let b = g.array_bytes();
    TOP_ARRAYS.map(|a| b[a].to_vec())
}

/// The byte ranges of a mesh's region that a rewrite changed: vertices, triangle corners and the
/// `nodes` in use; its triangles and their light indices too when the BVH was rebuilt (a refit
/// keeps the triangle order), and then every node of the region's capacity: a rebuild may use
/// fewer nodes than the BVH before it, and the rewrite clears the rest, so that a copy that
/// follows the commits holds the updater's bytes, not the old tree's leftovers.
fn region_ranges(r: &MeshRegion, nodes: u64, rebuilt: bool) -> Vec<(usize, u64, u64)> {
    use platoon_core::flatten::{GpuTriangle, GpuVertex};
    use std::mem::size_of;
    let (tb, tc) = (r.triangle_base as u64, r.triangle_count as u64);
    let vertex = size_of::<GpuVertex>() as u64;
    let triangle = size_of::<GpuTriangle>() as u64;
    let mut ranges = vec![
        (
            0,
            r.vertex_base as u64 * vertex,
            r.vertex_count as u64 * vertex,
        ),
        (1, 3 * tb * 16, 3 * tc * 16),
        node_range(
            r,
            if rebuilt {
                r.node_capacity as u64
            } else {
                nodes
            },
        ),
    ];
    if rebuilt {
        ranges.extend([(2, tb * triangle, tc * triangle), (3, tb * 4, tc * 4)]);
    }
    ranges
}

#[cfg(test)]
mod tests {
    use super::*;
    use platoon_core::flatten::commit::MESH_ARRAYS;
    use platoon_core::scene::Placement;

    /// The Cornell box with an instance per node: these tests follow instances; the merged
    /// static geometry has tests of its own (and tests/drive/living.rs).
    fn cornell() -> Updater {
        Updater::with_merge(
            platoon_core::scene::cornell::scene(),
            0.0,
            DVec3::ZERO,
            false,
        )
        .unwrap()
    }

    #[test]
    fn the_first_generation_is_a_fresh_build_and_an_unchanged_one_commits_nothing() {
        let merged = Updater::new(platoon_core::scene::cornell::scene(), 0.0, DVec3::ZERO).unwrap();
        let scene = merged.scene();
        let levels = StaticMerge::of_scene(scene).apply(scene, scene.pose(0.0));
        let fresh = GpuScene::build(scene, &levels, None).unwrap();
        assert_eq!(fresh.array_bytes(), merged.flattened().array_bytes());
        let mut u = cornell();
        let fresh = GpuScene::build(u.scene(), &u.scene().pose(0.0), None).unwrap();
        assert_eq!(fresh.array_bytes(), u.flattened().array_bytes());
        let next = u.update().unwrap();
        assert!(next.commit.is_empty(), "{:?}", next.commit.arrays);
        assert_eq!(next.id, 2);
        // Without an edit nothing is posed or flattened at all.
        assert_eq!(next.times.pose + next.times.flatten, Duration::ZERO);
    }

    /// The Cornell box cut into `cells` quads a face, its merged geometry built quick (past 100
    /// triangles) and refined as `refinement` says.
    fn refined_box(cells: u32, refinement: super::super::refinement::Refinement) -> Updater {
        let static_build = StaticBuild {
            quick_above: 100,
            refinement,
        };
        let options = UpdaterOptions {
            static_build,
            ..Default::default()
        };
        let scene = platoon_core::scene::cornell::tessellated(cells);
        Updater::with_options(scene, 0.0, DVec3::ZERO, options).unwrap()
    }

    fn merged_sah(u: &Updater) -> f64 {
        u.merged_bvh.as_ref().unwrap().1.sah_cost()
    }

    #[test]
    fn a_refined_tree_is_swapped_in_by_the_next_update_and_commits_its_nodes_alone() {
        use super::super::refinement::Refinement;
        let mut u = refined_box(24, Refinement::Background);
        let quick = merged_sah(&u);
        let before = u.flattened().clone();
        assert_eq!(u.refinements_pending(), 1);
        u.finish_refinements();
        let g = u.update().unwrap();
        assert_eq!((g.refined, u.refinements_pending()), (1, 0));
        let refined = merged_sah(&u);
        assert!(refined < 0.995 * quick, "SAH {refined} against {quick}");
        // Only the nodes moved: a copy that follows the commit holds the updater's bytes.
        let blas = SceneArray::Blas.index();
        assert!(g.commit.arrays.iter().all(|a| a.array == blas));
        let mut followed = crate::QueryScene::new(&before);
        followed.apply_commit(&g.commit);
        assert!(followed.scene().array_bytes() == u.flattened().array_bytes());
        assert!(before.bytes_of(SceneArray::Blas) != u.flattened().bytes_of(SceneArray::Blas));
        // Nothing more to swap.
        assert!(u.update().unwrap().commit.is_empty());
        // Waiting for it gives the same tree in the first generation.
        let waited = refined_box(24, Refinement::Wait);
        assert_eq!(
            (waited.refinements_pending(), merged_sah(&waited)),
            (0, refined)
        );
        assert!(waited.flattened().array_bytes() == u.flattened().array_bytes());
        let off = refined_box(24, Refinement::Off);
        assert_eq!((off.refinements_pending(), merged_sah(&off)), (0, quick));
    }

    #[test]
    fn a_refinement_of_a_tree_rebuilt_meanwhile_gives_way_to_the_new_trees() {
        use super::super::refinement::Refinement;
        // Two boxes side by side, merged; the second moves before the refinement is swapped
        // in: the merged geometry (the first box alone now) and the moved box's own mesh are
        // built again, each refined, and the old refinement is dropped.
        let two = |refinement| {
            let mut u = refined_box(16, refinement);
            let mut node = u.scene.nodes[0].clone();
            node.translation.x += 6.0;
            u.scene.nodes.push(node);
            u.structure = Structure::of(&u.scene);
            u.merge = StaticMerge::of_scene(&u.scene);
            u.edited = true;
            u.update().unwrap();
            u
        };
        let moved = |u: &mut Updater| {
            let node = u.scene.nodes.len() - 1;
            let placement = Placement::at(DVec3::new(6.0, 0.5, 0.0));
            u.apply(Edit::Placement { node, placement }).unwrap();
            u.update().unwrap()
        };
        let mut u = two(Refinement::Background);
        let g = moved(&mut u);
        assert_eq!(g.rebuilt, 1);
        assert_eq!(u.refinements_pending(), 2);
        u.finish_refinements();
        assert_eq!(u.update().unwrap().refined, 2);
        // The trees the same as where every quick tree is refined before it is used.
        let mut waited = two(Refinement::Wait);
        moved(&mut waited);
        assert!(waited.flattened().array_bytes() == u.flattened().array_bytes());
    }

    #[test]
    fn the_render_origin_follows_a_far_camera_and_keeps_a_far_room_precise() {
        // The Cornell box 1e7 units from the world origin.
        let mut scene = platoon_core::scene::cornell::scene();
        for n in scene.nodes.iter_mut().filter(|n| n.parent.is_none()) {
            n.translation += DVec3::new(1e7, 0.0, 0.0);
        }
        let mut u = Updater::with_merge(scene, 0.0, DVec3::ZERO, false).unwrap();
        let far = u.flattened().instances[0].object_to_world[0][3];
        assert_eq!(far, 1e7);
        u.apply(Edit::FollowCamera(DVec3::new(100.0, 0.0, 0.0)))
            .unwrap();
        assert!(
            u.update().unwrap().commit.is_empty(),
            "within the recentring distance"
        );
        u.apply(Edit::FollowCamera(DVec3::new(1e7, 0.0, -5.0)))
            .unwrap();
        let g = u.update().unwrap();
        assert_eq!(g.origin, DVec3::new(1e7, 0.0, -5.0));
        assert_eq!(g.commit.mesh_bytes(), 0, "object-space meshes do not move");
        let near = u.flattened().instances[0].object_to_world[0][3];
        assert_eq!(near, 0.0);
        assert!(u.apply(Edit::FollowCamera(DVec3::splat(f64::NAN))).is_err());
    }

    #[test]
    fn a_rigid_move_commits_no_mesh_data() {
        let mut u = cornell();
        let node = u
            .scene()
            .nodes
            .iter()
            .position(|n| n.mesh.is_some())
            .unwrap();
        u.apply(Edit::Placement {
            node,
            placement: Placement::at(DVec3::new(0.1, 0.0, 0.0)),
        })
        .unwrap();
        let g = u.update().unwrap();
        assert!(!g.commit.is_empty());
        assert_eq!(g.commit.mesh_bytes(), 0);
        assert!(g.commit.arrays.iter().any(|a| a.array == 6), "instances");
        // In place and by the commit's ranges, the same as flattening the moved scene anew.
        let fresh = GpuScene::build(u.scene(), &u.scene().pose(0.0), None).unwrap();
        assert_eq!(fresh.array_bytes(), u.flattened().array_bytes());
    }

    #[test]
    fn instances_come_and_go_and_bad_edits_are_refused() {
        let mut u = cornell();
        let instances = u.flattened().instances.len();
        let node = u
            .apply(Edit::AddInstance {
                mesh: 0,
                placement: Placement::at(DVec3::new(3.0, 0.0, 0.0)),
            })
            .unwrap()
            .unwrap();
        let g = u.update().unwrap();
        assert_eq!(u.flattened().instances.len(), instances + 1);
        // The new instance reuses the mesh: no bottom-level bytes.
        assert!(g
            .commit
            .arrays
            .iter()
            .all(|a| !MESH_ARRAYS.contains(&a.array)));
        u.apply(Edit::RemoveInstance(node)).unwrap();
        u.update().unwrap();
        assert_eq!(u.flattened().instances.len(), instances);
        let twice = u.apply(Edit::RemoveInstance(node)).unwrap_err().to_string();
        assert!(twice.contains("already removed"), "{twice}");
        assert!(u
            .apply(Edit::AddInstance {
                mesh: 99,
                placement: Placement::at(DVec3::ZERO)
            })
            .is_err());
        assert!(u
            .apply(Edit::Placement {
                node: 999,
                placement: Placement::at(DVec3::ZERO)
            })
            .is_err());
        assert!(u.apply(Edit::Time(f32::NAN)).is_err());
        let mut m = u.scene().materials[0].clone();
        m.roughness = f32::NAN;
        assert!(u.apply(Edit::Material(0, Box::new(m))).is_err());
        // Nothing refused reached the scene.
        assert!(u.update().unwrap().commit.is_empty());
        // A material edit sends the materials.
        let mut m = u.scene().materials[0].clone();
        m.roughness = 0.5;
        u.apply(Edit::Material(0, Box::new(m))).unwrap();
        let g = u.update().unwrap();
        assert_eq!(
            g.commit.arrays.iter().map(|a| a.array).collect::<Vec<_>>(),
            vec![7]
        );
    }
}

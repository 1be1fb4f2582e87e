//! Static geometry merged (issue 21): the instances of objects that never move (no animation,
//! no skin, no morph targets, never edited) become one mesh in render space under one
//! instance, so a scene written as a node per wall and chair is traversed as one bottom level
//! instead of a top level over many small ones. Two levels stay for what moves and for meshes
//! instanced so often that copying them would cost more memory than it saves time.
//!
//! A living scene's node that starts moving is split out: the merged mesh is built again
//! without it (a counted rebuild) and the node gets an instance of its own.

use std::collections::BTreeSet;
use std::sync::Arc;

use glam::{DMat4, DVec3, Mat3, Mat4, Vec4};

use platoon_scene::animation::Property;
use platoon_scene::{Instance, Mesh, MeshPart, Posed, Scene};

/// A mesh instanced more than once stays instanced when its instances hold more triangles
/// than this together: merging is for scenes written a node per object, not for forests.
pub const INSTANCED_TRIANGLE_BUDGET: usize = 1 << 20;

/// The node standing for the merged mesh's instance (no scene node poses it).
pub const MERGED_NODE: usize = usize::MAX;

/// The merged mesh of one set of nodes in the render space of the origin it was built at: its
/// vertices were placed in f64 and rounded relative to that origin (near the camera), so a room
/// far from the world origin keeps its precision as render space does (a vertex at 1e30 in the
/// same mesh does not drag the others' precision with it, as a centre of the bounds would).
#[derive(Clone, Debug)]
struct Merged {
    mesh: Arc<Mesh>,
    origin: DVec3,
}

/// Which nodes' instances are merged, and their mesh.
#[derive(Clone, Debug, Default)]
pub struct StaticMerge {
    nodes: BTreeSet<usize>,
    merged: Option<Merged>,
    rebuilds: usize,
}

impl StaticMerge {
    /// Merges nothing (every instance keeps its own level).
    pub fn none() -> StaticMerge {
        StaticMerge::default()
    }

    /// Merges every node of `scene` with a mesh that never moves: neither it nor an ancestor
    /// animated by the scene's (first, played) animation, not skinned, its mesh without morph
    /// targets and not instanced past [`INSTANCED_TRIANGLE_BUDGET`].
    pub fn of_scene(scene: &Scene) -> StaticMerge {
        let mut animated = vec![false; scene.nodes.len()];
        if let Some(a) = scene.animations.first() {
            for c in &a.channels {
                if c.property != Property::Weights && c.node < animated.len() {
                    animated[c.node] = true;
                }
            }
        }
        // Parents come before their children.
        for i in 0..scene.nodes.len() {
            if let Some(p) = scene.nodes[i].parent {
                animated[i] |= animated[p];
            }
        }
        let mut uses = vec![0usize; scene.meshes.len()];
        for n in &scene.nodes {
            if let Some(m) = n.mesh {
                uses[m] += 1;
            }
        }
        let nodes = scene
            .nodes
            .iter()
            .enumerate()
            .filter(|(i, n)| {
                let Some(m) = n.mesh else { return false };
                let mesh = &scene.meshes[m];
                let instanced_heavily =
                    uses[m] > 1 && uses[m] * mesh.triangle_count() > INSTANCED_TRIANGLE_BUDGET;
                !animated[*i] && n.skin.is_none() && mesh.targets.is_empty() && !instanced_heavily
            })
            .map(|(i, _)| i)
            .collect();
        StaticMerge {
            nodes,
            merged: None,
            rebuilds: 0,
        }
    }

    /// Whether `node` is merged.
    pub fn contains(&self, node: usize) -> bool {
        self.nodes.contains(&node)
    }

    /// `node` starts moving (or is gone): the next [`StaticMerge::apply`] builds the merged
    /// mesh again without it. Whether it was merged.
    pub fn split_out(&mut self, node: usize) -> bool {
        let was = self.nodes.remove(&node);
        if was {
            self.merged = None;
        }
        was
    }

    /// How often the merged mesh was built (the first time included).
    pub fn rebuilds(&self) -> usize {
        self.rebuilds
    }

    /// The merged mesh as last built, when there is one (a living scene's bottom level keeps
    /// its BVH while this stays the same `Arc`).
    pub fn mesh(&self) -> Option<&Arc<Mesh>> {
        self.merged.as_ref().map(|m| &m.mesh)
    }

    /// `posed` (a pose of `scene`) with the instances of the merged nodes replaced by one
    /// instance of the merged mesh (appended to its meshes, node [`MERGED_NODE`]). The mesh is
    /// built on first use, after a split and when render space's origin moved (which a living
    /// scene does only when its camera went far).
    pub fn apply(&mut self, scene: &Scene, mut posed: Posed) -> Posed {
        let (merged, kept): (Vec<Instance>, Vec<Instance>) = posed
            .instances
            .drain(..)
            .partition(|i| self.nodes.contains(&i.node));
        posed.instances = kept;
        if merged.is_empty() {
            return posed;
        }
        let m = match &self.merged {
            Some(m) if m.origin == posed.origin => m.clone(),
            _ => {
                self.rebuilds += 1;
                let m = Merged {
                    mesh: Arc::new(merge(scene, &merged, posed.origin)),
                    origin: posed.origin,
                };
                self.merged = Some(m.clone());
                m
            }
        };
        posed.meshes.push(m.mesh);
        posed.instances.push(Instance {
            mesh: posed.meshes.len() - 1,
            object_to_world: Mat4::IDENTITY,
            node: MERGED_NODE,
        });
        posed
    }
}

/// One mesh of `instances` (poses of `scene`'s static nodes) in the render space of `origin`.
/// The nodes' world transforms are composed again in f64 (the posed ones are rounded already),
/// so that each vertex is rounded once, relative to the origin.
fn merge(scene: &Scene, instances: &[Instance], origin: DVec3) -> Mesh {
    let local: Vec<DMat4> = scene.nodes.iter().map(|n| n.local_matrix()).collect();
    let world = scene.world_matrices(&local);
    let parts: Vec<(&Mesh, DMat4, usize)> = instances
        .iter()
        .map(|i| {
            let mesh = &*scene.meshes[scene.nodes[i.node].mesh.expect("a mesh node")];
            (
                mesh,
                world[i.node] * DMat4::from_translation(mesh.offset),
                i.node,
            )
        })
        .collect();
    let any = |f: fn(&Mesh) -> bool| parts.iter().any(|(m, _, _)| f(m));
    let (normals, tangents, uvs) = (
        any(|m| !m.normals.is_empty()),
        any(|m| !m.tangents.is_empty()),
        any(|m| !m.uvs.is_empty()),
    );
    let (uvs1, colors) = (any(|m| !m.uvs1.is_empty()), any(|m| !m.colors.is_empty()));
    let mut out = Mesh {
        name: "static geometry".into(),
        ..Default::default()
    };
    for &(mesh, to_world, node) in &parts {
        out.parts.push(MeshPart {
            node,
            first_triangle: out.indices.len() as u32,
        });
        let base = out.positions.len() as u32;
        let n = mesh.positions.len();
        let linear = to_world.as_mat4();
        let normal_matrix = Mat3::from_mat4(linear).inverse().transpose();
        let mirrored = to_world.determinant() < 0.0;
        out.positions.extend(
            mesh.positions
                .iter()
                .map(|p| (to_world.transform_point3(p.as_dvec3()) - origin).as_vec3()),
        );
        if normals {
            // A flat-shaded mesh keeps zero normals: the kernel shades it by its faces.
            out.normals.extend((0..n).map(|v| {
                mesh.normals.get(v).map_or(glam::Vec3::ZERO, |n| {
                    (normal_matrix * *n).normalize_or_zero()
                })
            }));
        }
        if tangents {
            out.tangents
                .extend((0..n).map(|v| tangent(mesh.tangents.get(v), linear, mirrored)));
        }
        if uvs {
            out.uvs
                .extend((0..n).map(|v| mesh.uvs.get(v).copied().unwrap_or_default()));
        }
        if uvs1 {
            out.uvs1
                .extend((0..n).map(|v| mesh.uvs1.get(v).copied().unwrap_or_default()));
        }
        if colors {
            out.colors
                .extend((0..n).map(|v| mesh.colors.get(v).copied().unwrap_or(Vec4::ONE)));
        }
        // A mirroring transform turns the winding; the kernel's faces keep theirs.
        out.indices.extend(mesh.indices.iter().map(|t| {
            let t = t.map(|v| v + base);
            if mirrored {
                [t[0], t[2], t[1]]
            } else {
                t
            }
        }));
        out.triangle_materials.extend(&mesh.triangle_materials);
    }
    out
}

/// A tangent (xyz, w the bitangent's sign) carried to render space by `to_world`.
fn tangent(t: Option<&Vec4>, to_world: Mat4, mirrored: bool) -> Vec4 {
    let Some(t) = t else { return Vec4::ZERO };
    let xyz = to_world.transform_vector3(t.truncate()).normalize_or_zero();
    let w = if mirrored { -t.w } else { t.w };
    xyz.extend(w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Quat, Vec3};
    use platoon_scene::animation::{Animation, Channel, Interpolation};
    use platoon_scene::{Node, Skin};

    /// A triangle mesh and nodes: 0 plain, 1 animated, 2 its child, 3 skinned, 4 mirrored.
    fn scene() -> Scene {
        let tri = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            indices: vec![[0, 1, 2]],
            triangle_materials: vec![0],
            ..Default::default()
        };
        let mut nodes: Vec<Node> = (0..5).map(|i| Node::new(format!("n{i}"))).collect();
        for n in &mut nodes {
            n.mesh = Some(0);
        }
        nodes[0].translation = glam::DVec3::new(5.0, 0.0, 0.0);
        nodes[2].parent = Some(1);
        nodes[3].skin = Some(0);
        nodes[4].scale = Vec3::new(-1.0, 1.0, 1.0);
        Scene {
            nodes,
            meshes: vec![Arc::new(tri)],
            skins: vec![Skin {
                name: "skin".into(),
                joints: vec![0],
                inverse_bind_matrices: vec![Mat4::IDENTITY],
            }],
            animations: vec![Animation {
                name: "spin".into(),
                channels: vec![Channel {
                    node: 1,
                    property: Property::Rotation,
                    interpolation: Interpolation::Linear,
                    times: vec![0.0, 1.0],
                    values: Quat::IDENTITY.to_array().repeat(2),
                }],
            }],
            ..Default::default()
        }
    }

    #[test]
    fn what_never_moves_is_merged_and_what_moves_keeps_its_instance() {
        let scene = scene();
        let mut merge = StaticMerge::of_scene(&scene);
        assert_eq!(merge.nodes.iter().copied().collect::<Vec<_>>(), vec![0, 4]);
        let posed = merge.apply(&scene, scene.pose(0.0));
        // Nodes 1, 2 (animated, and under an animated node), 3 (skinned) and the merged mesh.
        assert_eq!(posed.instances.len(), 4);
        let merged = posed.instances.last().unwrap();
        assert_eq!(merged.node, MERGED_NODE);
        let mesh = &posed.meshes[merged.mesh];
        assert_eq!(mesh.indices.len(), 2);
        // In render space: node 0's triangle moved by 5 along x; node 4's mirrored, wound the
        // other way round so that its face keeps its side.
        assert_eq!(merged.object_to_world, Mat4::IDENTITY);
        assert_eq!(
            mesh.positions[..3],
            [
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(6.0, 0.0, 0.0),
                Vec3::new(5.0, 1.0, 0.0)
            ]
        );
        assert_eq!(mesh.positions[4], Vec3::new(-1.0, 0.0, 0.0));
        assert_eq!(mesh.indices[1], [3, 5, 4]);
        assert!(mesh.normals.iter().all(|n| *n == Vec3::Z));
        assert_eq!(merge.rebuilds(), 1);
    }

    #[test]
    fn the_merged_mesh_is_built_once_and_again_after_a_split_or_a_move_of_the_origin() {
        let scene = scene();
        let mut merge = StaticMerge::of_scene(&scene);
        let first = merge.apply(&scene, scene.pose(0.0));
        let mesh = first.meshes.last().unwrap().clone();
        let again = merge.apply(&scene, scene.pose(0.0));
        assert!(Arc::ptr_eq(again.meshes.last().unwrap(), &mesh));
        assert_eq!(merge.rebuilds(), 1);
        // Render space moved: the mesh is placed about the new origin.
        let moved = merge.apply(
            &scene,
            scene.pose_around(0.0, glam::DVec3::new(1.0, 2.0, 3.0)),
        );
        assert_eq!(merge.rebuilds(), 2);
        assert_eq!(
            moved.meshes.last().unwrap().positions[0],
            Vec3::new(4.0, -2.0, -3.0)
        );
        assert!(merge.split_out(0));
        assert!(!merge.split_out(1), "an animated node was never merged");
        let split = merge.apply(&scene, scene.pose(0.0));
        assert_eq!(merge.rebuilds(), 3);
        assert_eq!(split.meshes.last().unwrap().indices.len(), 1);
        assert!(split.instances.iter().any(|i| i.node == 0));
    }

    #[test]
    fn a_room_far_from_the_world_origin_keeps_its_precision() {
        let mut scene = scene();
        for n in &mut scene.nodes {
            n.translation += glam::DVec3::new(1e7, 0.0, 0.0);
        }
        let mut merge = StaticMerge::of_scene(&scene);
        let posed = merge.apply(
            &scene,
            scene.pose_around(0.0, glam::DVec3::new(1e7, 0.0, 0.0)),
        );
        let mesh = posed.meshes.last().unwrap();
        // Rounded once relative to render space's origin: the 1 m triangle keeps its exact
        // corners (at 1e7, f32 has a step of 1 m).
        assert_eq!(mesh.positions[1] - mesh.positions[0], Vec3::X);
        assert_eq!(mesh.positions[2] - mesh.positions[0], Vec3::Y);
    }

    #[test]
    fn a_mesh_instanced_past_the_budget_stays_instanced() {
        let mut scene = scene();
        let big = Mesh {
            positions: vec![Vec3::ZERO; 3],
            indices: vec![[0, 1, 2]; INSTANCED_TRIANGLE_BUDGET / 2 + 1],
            triangle_materials: vec![0; INSTANCED_TRIANGLE_BUDGET / 2 + 1],
            ..Default::default()
        };
        scene.meshes.push(Arc::new(big));
        for i in 0..2 {
            let mut n = Node::new(format!("tree {i}"));
            n.mesh = Some(1);
            scene.nodes.push(n);
        }
        let merge = StaticMerge::of_scene(&scene);
        assert!(!merge.contains(5) && !merge.contains(6));
        assert!(merge.contains(0));
        assert!(StaticMerge::none().nodes.is_empty());
    }
}

//! What carries a hit back to the frame before (motion vectors, the temporal denoiser's
//! reprojection): a frame's instances (node, posed mesh, transforms) and its meshes' vertices
//! in object space, with the triangles' corners when the frame is the one the hits were
//! traced in. A hit (its position and its Ids: instance, triangle) is carried back through its
//! triangle: its barycentric place on the triangle now, the same place on the same vertices as
//! the frame before has them (so skinned and morphed meshes move with their vertices), through
//! the instance of the same node then. A few bytes per vertex and triangle: cheap to keep per
//! frame, unlike the whole flattened scene.

use std::collections::HashMap;

use glam::{Mat4, Quat, Vec3, Vec4};

use platoon_accel::static_merge::MERGED_NODE;
use platoon_accel::GpuScene;
use platoon_scene::Posed;

/// An instance as the table holds it.
#[derive(Clone, Copy, Debug)]
struct Placed {
    node: usize,
    mesh: usize,
    world_to_object: Mat4,
    object_to_world: Mat4,
}

/// Where a hit was in the frame before.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Before {
    /// Its point then (render space then).
    pub position: Vec3,
    /// What turns a direction on the surface now into the same direction then: the turn of
    /// the hit triangle's face normal (its instance's rotation, or its vertices' for a
    /// deforming mesh).
    pub turn: Quat,
}

/// A frame's geometry as hits are carried back through it.
#[derive(Clone, Debug, Default)]
pub struct HitGeometry {
    /// In the instance order of the hits' Ids (the flattened scene's top-level order).
    instances: Vec<Placed>,
    /// The instance of each node (the first one, where a node has several).
    by_node: HashMap<usize, usize>,
    /// First vertex and vertex count of each posed mesh in `positions`.
    meshes: Vec<(u32, u32)>,
    /// Every posed mesh's vertices, in object space.
    positions: Vec<Vec3>,
    /// The corners (indices into `positions`) of each triangle, in the order of the hits'
    /// Ids; empty for a frame only read as the frame before.
    triangles: Vec<[u32; 3]>,
}

impl HitGeometry {
    /// The frame `gpu` flattens: the one hits are traced in.
    pub fn of_flattened(gpu: &GpuScene) -> HitGeometry {
        let names = &gpu.hit_names;
        let instances = gpu
            .instances
            .iter()
            .zip(names.instance_nodes.iter().zip(&names.instance_meshes))
            .map(|(g, (&node, &mesh))| Placed {
                node,
                mesh,
                world_to_object: from_rows(g.world_to_object),
                object_to_world: from_rows(g.object_to_world),
            })
            .collect();
        HitGeometry {
            by_node: HashMap::new(),
            instances,
            meshes: gpu
                .regions
                .iter()
                .map(|r| (r.vertex_base, r.vertex_count))
                .collect(),
            positions: gpu
                .vertices
                .iter()
                .map(|v| Vec3::from_slice(&v.position_u[..3]))
                .collect(),
            triangles: gpu.triangles.iter().map(|t| t.v).collect(),
        }
        .indexed()
    }

    /// The frame before, as `posed` poses it (no triangles: a hit is never traced in it).
    pub fn of_posed(posed: &Posed) -> HitGeometry {
        let mut meshes = Vec::with_capacity(posed.meshes.len());
        let mut positions = Vec::new();
        for m in &posed.meshes {
            meshes.push((positions.len() as u32, m.positions.len() as u32));
            positions.extend_from_slice(&m.positions);
        }
        HitGeometry {
            instances: posed
                .instances
                .iter()
                .map(|i| Placed {
                    node: i.node,
                    mesh: i.mesh,
                    world_to_object: i.object_to_world.inverse(),
                    object_to_world: i.object_to_world,
                })
                .collect(),
            by_node: HashMap::new(),
            meshes,
            positions,
            triangles: Vec::new(),
        }
        .indexed()
    }

    fn indexed(mut self) -> HitGeometry {
        for (k, i) in self.instances.iter().enumerate() {
            self.by_node.entry(i.node).or_insert(k);
        }
        self
    }

    /// What names the object `instance` (of this frame's Ids) draws from one frame to the
    /// next, whatever the order of instances: its node + 2, 1 for the geometry merged because
    /// it never moves (an f32, as the Ids pass holds it; exact up to 2^24 nodes).
    pub fn object_key(&self, instance: u32) -> f32 {
        match self.instances.get(instance as usize) {
            Some(i) if i.node == MERGED_NODE => 1.0,
            Some(i) => (i.node + 2) as f32,
            None => 0.0,
        }
    }

    /// Where the point `now` (render space) on `triangle` of `instance`, as traced in this
    /// frame, was in the frame `before`: None when that frame did not have its node or its
    /// mesh had other vertices (an added instance, another mesh). Geometry merged because it
    /// never moves stays put.
    pub fn position_before(
        &self,
        now: Vec3,
        instance: u32,
        triangle: u32,
        before: &HitGeometry,
    ) -> Option<Vec3> {
        self.before(now, instance, triangle, before)
            .map(|b| b.position)
    }

    /// The same with the turn of the surface there ([`Before::turn`]).
    pub fn before(
        &self,
        now: Vec3,
        instance: u32,
        triangle: u32,
        before: &HitGeometry,
    ) -> Option<Before> {
        let here = self.instances.get(instance as usize)?;
        if here.node == MERGED_NODE {
            return Some(Before {
                position: now,
                turn: Quat::IDENTITY,
            });
        }
        let then = &before.instances[*before.by_node.get(&here.node)?];
        let (base, count) = *self.meshes.get(here.mesh)?;
        let (base_then, count_then) = *before.meshes.get(then.mesh)?;
        if count != count_then {
            return None;
        }
        let corners = self.triangles.get(triangle as usize)?;
        let local = corners.map(|v| v.wrapping_sub(base));
        if local.iter().any(|&v| v >= count) {
            return None;
        }
        let corners_now = local.map(|v| self.positions[(base + v) as usize]);
        let corners_then = local.map(|v| before.positions[(base_then + v) as usize]);
        let b = barycentric(here.world_to_object.transform_point3(now), corners_now);
        let object = (0..3).map(|k| corners_then[k] * b[k]).sum::<Vec3>();
        let face = |c: [Vec3; 3], to_world: Mat4| {
            let [a, b, c] = c.map(|p| to_world.transform_point3(p));
            (b - a).cross(c - a).normalize_or_zero()
        };
        let (n_now, n_then) = (
            face(corners_now, here.object_to_world),
            face(corners_then, then.object_to_world),
        );
        Some(Before {
            position: then.object_to_world.transform_point3(object),
            turn: if n_now == Vec3::ZERO || n_then == Vec3::ZERO {
                Quat::IDENTITY
            } else {
                Quat::from_rotation_arc(n_now, n_then)
            },
        })
    }
}

/// A 4x4 matrix from the rows of a 3x4 affine one.
fn from_rows(rows: [[f32; 4]; 3]) -> Mat4 {
    Mat4::from_cols(
        Vec4::from(rows[0]),
        Vec4::from(rows[1]),
        Vec4::from(rows[2]),
        Vec4::W,
    )
    .transpose()
}

/// The barycentric coordinates of `p`'s projection onto the triangle `t`'s plane.
fn barycentric(p: Vec3, t: [Vec3; 3]) -> [f32; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let det = d11 * d22 - d12 * d12;
    if det.abs() <= f32::MIN_POSITIVE {
        return [1.0, 0.0, 0.0];
    }
    let u = (d22 * d1 - d12 * d2) / det;
    let v = (d11 * d2 - d12 * d1) / det;
    [1.0 - u - v, u, v]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;
    use platoon_scene::{Instance, Mesh};
    use std::sync::Arc;

    #[test]
    fn a_point_on_a_triangle_is_its_barycentric_mix() {
        let t = [Vec3::ZERO, Vec3::X * 2.0, Vec3::new(0.0, 3.0, 1.0)];
        let b = [0.2, 0.5, 0.3];
        let p = t[0] * b[0] + t[1] * b[1] + t[2] * b[2];
        let got = barycentric(p, t);
        for k in 0..3 {
            assert!((got[k] - b[k]).abs() < 1e-6, "{got:?}");
        }
    }

    fn posed(positions: Vec<Vec3>, object_to_world: Mat4) -> Posed {
        let mesh = Mesh {
            positions,
            ..Default::default()
        };
        Posed {
            origin: glam::DVec3::ZERO,
            meshes: vec![Arc::new(mesh)],
            instances: vec![Instance {
                mesh: 0,
                object_to_world,
                node: 7,
            }],
            lights: Vec::new(),
            cameras: Vec::new(),
        }
    }

    /// A frame with the hits of one triangle, corners `corners` of instance 0 placed by
    /// `object_to_world`.
    fn traced(corners: [Vec3; 3], object_to_world: Mat4) -> HitGeometry {
        let mut g = HitGeometry::of_posed(&posed(corners.to_vec(), object_to_world));
        g.triangles = vec![[0, 1, 2]];
        g
    }

    const CORNERS: [Vec3; 3] = [Vec3::ZERO, Vec3::X, Vec3::Y];

    #[test]
    fn a_point_of_a_moved_instance_was_where_its_previous_placement_put_it() {
        let now = Mat4::from_rotation_translation(Quat::from_rotation_z(0.4), Vec3::X * 3.0);
        let then = Mat4::from_translation(Vec3::new(1.0, 2.0, -1.0));
        let object = Vec3::new(0.25, 0.5, 0.0);
        let before = HitGeometry::of_posed(&posed(CORNERS.to_vec(), then));
        let at = traced(CORNERS, now)
            .before(now.transform_point3(object), 0, 0, &before)
            .unwrap();
        let want = then.transform_point3(object);
        assert!(at.position.distance(want) < 1e-5, "{at:?} vs {want}");
        // The face's normal now (+z turned about z: +z) turned back: +z again.
        assert!((at.turn * Vec3::Z).distance(Vec3::Z) < 1e-5, "{at:?}");
    }

    #[test]
    fn a_point_of_a_deformed_mesh_follows_its_vertices() {
        // The same barycentric place (1/4, 1/4, 1/2) on the triangle's corners then.
        let then = [Vec3::Z, Vec3::new(2.0, 0.0, 1.0), Vec3::new(0.0, 4.0, 1.0)];
        let before = HitGeometry::of_posed(&posed(then.to_vec(), Mat4::IDENTITY));
        let object = CORNERS[0] * 0.25 + CORNERS[1] * 0.25 + CORNERS[2] * 0.5;
        let at = traced(CORNERS, Mat4::IDENTITY)
            .position_before(object, 0, 0, &before)
            .unwrap();
        let want = then[0] * 0.25 + then[1] * 0.25 + then[2] * 0.5;
        assert!(at.distance(want) < 1e-5, "{at} vs {want}");
    }

    #[test]
    fn a_turned_face_turns_its_directions_with_it() {
        let (now, then) = (Mat4::IDENTITY, Mat4::from_rotation_x(0.5));
        let before = HitGeometry::of_posed(&posed(CORNERS.to_vec(), then));
        let at = traced(CORNERS, now)
            .before(Vec3::new(0.2, 0.2, 0.0), 0, 0, &before)
            .unwrap();
        let want = then.transform_vector3(Vec3::Z);
        assert!(
            (at.turn * Vec3::Z).distance(want) < 1e-5,
            "{at:?} vs {want}"
        );
    }

    #[test]
    fn a_node_the_frame_before_lacked_or_another_mesh_has_no_place_then() {
        let now = traced(CORNERS, Mat4::IDENTITY);
        let mut other_node = posed(CORNERS.to_vec(), Mat4::IDENTITY);
        other_node.instances[0].node = 8;
        let other_mesh = posed(vec![Vec3::ZERO; 4], Mat4::IDENTITY);
        for before in [other_node, other_mesh] {
            let before = HitGeometry::of_posed(&before);
            assert_eq!(now.position_before(Vec3::ZERO, 0, 0, &before), None);
        }
    }
}

//! Posing a scene: its first animation at a time, every node's world transform, skinned and
//! morphed meshes, instances, placed lights and cameras, around a floating origin.

use std::sync::Arc;

use glam::{DMat4, DVec3, Mat4, Vec3};

use crate::{Mesh, Node, Scene};

/// One use of a mesh in world space.
#[derive(Clone, Debug)]
pub struct Instance {
    pub mesh: usize,
    pub object_to_world: Mat4,
    pub node: usize,
}

#[derive(Clone, Debug)]
pub struct PlacedLight {
    pub light: usize,
    pub position: Vec3,
    /// Direction the light points to (-Z of its node).
    pub direction: Vec3,
}

#[derive(Clone, Debug)]
pub struct PlacedCamera {
    pub camera: usize,
    pub camera_to_world: Mat4,
}

/// The scene at one instant: every mesh in its final object space (skinned meshes re-posed),
/// instances with world transforms, and placed lights and cameras. All positions are relative
/// to `origin` (render space); see [`Scene::pose_around`].
#[derive(Clone, Debug)]
pub struct Posed {
    /// The world point that render space is centred on.
    pub origin: DVec3,
    pub meshes: Vec<Arc<Mesh>>,
    pub instances: Vec<Instance>,
    pub lights: Vec<PlacedLight>,
    pub cameras: Vec<PlacedCamera>,
}

impl Scene {
    /// World matrices of all nodes given their local matrices.
    pub fn world_matrices(&self, local: &[DMat4]) -> Vec<DMat4> {
        let mut world = Vec::with_capacity(self.nodes.len());
        for (i, node) in self.nodes.iter().enumerate() {
            let m = match node.parent {
                Some(p) => world[p] * local[i],
                None => local[i],
            };
            world.push(m);
        }
        world
    }

    /// Poses the scene at `time` seconds of its first animation (static scenes ignore time),
    /// with render space equal to world space.
    pub fn pose(&self, time: f32) -> Posed {
        self.pose_around(time, DVec3::ZERO)
    }

    /// Poses the scene with render space centred on `origin` (a floating origin near the
    /// camera): transforms are composed in f64 and rounded to f32 only after `origin` is
    /// subtracted, so a room 1e7 units from the world origin keeps full f32 precision.
    /// Instances whose transform is singular (a node scaled to zero hides it) or not finite in
    /// f32 are left out: they have no surface to hit.
    pub fn pose_around(&self, time: f32, origin: DVec3) -> Posed {
        let mut nodes = self.nodes.clone();
        if let Some(anim) = self.animations.first() {
            anim.apply(time, &mut nodes);
        }
        let local: Vec<DMat4> = nodes.iter().map(Node::local_matrix).collect();
        let to_render = DMat4::from_translation(-origin);
        let world64: Vec<DMat4> = self
            .world_matrices(&local)
            .iter()
            .map(|m| to_render * *m)
            .collect();
        let world: Vec<Mat4> = world64.iter().map(DMat4::as_mat4).collect();
        let mut meshes = self.meshes.clone();
        // (posed slot, mesh, skin, node): meshes posed per node, after the scene's own.
        let mut skins: Vec<(usize, usize, Option<usize>, usize)> = Vec::new();
        let mut instances = Vec::new();
        let mut lights = Vec::new();
        let mut cameras = Vec::new();
        for (i, node) in nodes.iter().enumerate() {
            if let Some(m) = node.mesh {
                let morphs = !self.meshes[m].targets.is_empty();
                match node.skin {
                    // glTF: a skinned mesh ignores its node's transform; joints place it.
                    Some(s) => {
                        // Skinned below, in parallel: placeholder until then.
                        skins.push((meshes.len(), m, Some(s), i));
                        meshes.push(Arc::default());
                        instances.push(Instance {
                            mesh: meshes.len() - 1,
                            object_to_world: Mat4::IDENTITY,
                            node: i,
                        });
                    }
                    None => {
                        let placed =
                            (world64[i] * DMat4::from_translation(self.meshes[m].offset)).as_mat4();
                        if invertible_and_finite(&placed) {
                            // A morphing mesh is posed per node (weights are the node's), so a
                            // living scene deforms it as it deforms a skinned one.
                            let mesh = if morphs {
                                skins.push((meshes.len(), m, None, i));
                                meshes.push(Arc::default());
                                meshes.len() - 1
                            } else {
                                m
                            };
                            instances.push(Instance {
                                mesh,
                                object_to_world: placed,
                                node: i,
                            });
                        }
                    }
                }
            }
            if let Some(l) = node.light {
                let position = world[i].transform_point3(Vec3::ZERO);
                let direction = world[i].transform_vector3(-Vec3::Z).normalize_or(-Vec3::Z);
                // A light placed at a non-finite point lights nothing.
                if position.is_finite() {
                    lights.push(PlacedLight {
                        light: l,
                        position,
                        direction,
                    });
                }
            }
            if let Some(c) = node.camera {
                cameras.push(PlacedCamera {
                    camera: c,
                    camera_to_world: world[i],
                });
            }
        }
        // Each skinned mesh on its own: spread over the CPU threads.
        use rayon::prelude::*;
        let skinned: Vec<(usize, Mesh)> = skins
            .par_iter()
            .map(|&(slot, m, s, node)| {
                use crate::animation::{morph_mesh, skin_mesh};
                let source = &self.meshes[m];
                let weights = nodes[node]
                    .weights
                    .as_ref()
                    .unwrap_or(&source.morph_weights);
                let posed = match s {
                    Some(s) if source.targets.is_empty() => {
                        skin_mesh(source, &self.skins[s], &world)
                    }
                    Some(s) => skin_mesh(&morph_mesh(source, weights), &self.skins[s], &world),
                    None => morph_mesh(source, weights),
                };
                (slot, posed)
            })
            .collect();
        for (slot, mesh) in skinned {
            meshes[slot] = Arc::new(mesh);
        }
        Posed {
            origin,
            meshes,
            instances,
            lights,
            cameras,
        }
    }
}

/// A transform that can place an instance: finite, with a finite inverse.
fn invertible_and_finite(m: &Mat4) -> bool {
    let det = m.determinant();
    m.is_finite() && det != 0.0 && det.is_finite() && m.inverse().is_finite()
}

impl Posed {
    /// Render-space bounds of all instanced geometry that can be drawn.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for inst in &self.instances {
            for p in &self.meshes[inst.mesh].positions {
                let w = inst.object_to_world.transform_point3(*p);
                // What the BVH leaves out (NaN, Inf, beyond 1e32) does not frame the view.
                if crate::placeable::placeable(w) {
                    lo = lo.min(w);
                    hi = hi.max(w);
                }
            }
        }
        if lo.x > hi.x {
            (Vec3::ZERO, Vec3::ZERO)
        } else {
            (lo, hi)
        }
    }
}

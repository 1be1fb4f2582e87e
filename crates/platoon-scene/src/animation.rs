//! Keyframe animation (glTF samplers: STEP, LINEAR, CUBICSPLINE) and linear-blend skinning on
//! the CPU. Skinned meshes are re-posed into a fresh object-space mesh each time the scene is posed.

use glam::{Affine3A, Mat3A, Mat4, Quat, Vec3, Vec3A, Vec4};

use crate::{Mesh, Node, Skin};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Interpolation {
    Step,
    Linear,
    CubicSpline,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
    /// Morph-target weights (as many as the node's mesh has targets).
    Weights,
}

#[derive(Clone, Debug)]
pub struct Channel {
    pub node: usize,
    pub property: Property,
    pub interpolation: Interpolation,
    pub times: Vec<f32>,
    /// Flat output values; for CUBICSPLINE each key holds (in-tangent, value, out-tangent).
    pub values: Vec<f32>,
}

#[derive(Clone, Debug)]
pub struct Animation {
    pub name: String,
    pub channels: Vec<Channel>,
}

impl Animation {
    pub fn duration(&self) -> f32 {
        self.channels
            .iter()
            .filter_map(|c| c.times.last().copied())
            .fold(0.0, f32::max)
    }

    /// Writes the animated TRS of every channel at `time` into `nodes`.
    pub fn apply(&self, time: f32, nodes: &mut [Node]) {
        for ch in &self.channels {
            let Some(node) = nodes.get_mut(ch.node) else {
                continue;
            };
            match ch.property {
                Property::Translation => {
                    node.translation = Vec3::from_slice(&ch.sample::<3>(time)).as_dvec3()
                }
                Property::Scale => node.scale = Vec3::from_slice(&ch.sample::<3>(time)),
                Property::Rotation => {
                    let q = ch.sample::<4>(time);
                    node.rotation = Quat::from_array(q).normalize();
                }
                Property::Weights => node.weights = Some(ch.sample_weights(time)),
            }
        }
    }
}

impl Channel {
    /// Values of one key: `n` of them from output slot `slot` (CUBICSPLINE keys hold three).
    fn key(&self, i: usize, slot: usize, n: usize) -> &[f32] {
        let base = (i * self.stride() + slot) * n;
        &self.values[base..base + n]
    }

    fn stride(&self) -> usize {
        if self.interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        }
    }

    /// Value at `time`, clamped to the first and last keys.
    pub fn sample<const N: usize>(&self, time: f32) -> [f32; N] {
        let mut out = [0.0; N];
        out.copy_from_slice(&self.sample_n(time, N, N == 4));
        out
    }

    /// Morph-target weights at `time`: as many as the keys hold (the mesh's target count).
    pub fn sample_weights(&self, time: f32) -> Vec<f32> {
        let keys = self.times.len() * self.stride();
        let n = self.values.len().checked_div(keys).unwrap_or(0);
        self.sample_n(time, n, false)
    }

    /// `n` values at `time`; `slerp`: they are a rotation, interpolated spherically.
    fn sample_n(&self, time: f32, n: usize, slerp: bool) -> Vec<f32> {
        let value_slot = if self.interpolation == Interpolation::CubicSpline {
            1
        } else {
            0
        };
        let keys = self.times.len();
        if keys == 0 || self.values.len() < keys * self.stride() * n {
            return vec![0.0; n];
        }
        if time <= self.times[0] || keys == 1 {
            return self.key(0, value_slot, n).to_vec();
        }
        if time >= self.times[keys - 1] {
            return self.key(keys - 1, value_slot, n).to_vec();
        }
        let i = self.times.partition_point(|&t| t <= time) - 1;
        let (t0, t1) = (self.times[i], self.times[i + 1]);
        let dt = t1 - t0;
        let s = if dt > 0.0 { (time - t0) / dt } else { 0.0 };
        match self.interpolation {
            Interpolation::Step => self.key(i, 0, n).to_vec(),
            Interpolation::Linear => {
                let (a, b) = (self.key(i, 0, n), self.key(i + 1, 0, n));
                if slerp {
                    Quat::from_slice(a)
                        .slerp(Quat::from_slice(b), s)
                        .to_array()
                        .to_vec()
                } else {
                    a.iter().zip(b).map(|(a, b)| a + (b - a) * s).collect()
                }
            }
            Interpolation::CubicSpline => {
                // glTF spec, Appendix C: Hermite spline with tangents scaled by the key interval.
                let (v0, b0) = (self.key(i, 1, n), self.key(i, 2, n));
                let (a1, v1) = (self.key(i + 1, 0, n), self.key(i + 1, 1, n));
                let (s2, s3) = (s * s, s * s * s);
                (0..n)
                    .map(|k| {
                        (2.0 * s3 - 3.0 * s2 + 1.0) * v0[k]
                            + (s3 - 2.0 * s2 + s) * dt * b0[k]
                            + (-2.0 * s3 + 3.0 * s2) * v1[k]
                            + (s3 - s2) * dt * a1[k]
                    })
                    .collect()
            }
        }
    }
}

/// A mesh with its morph targets blended in at `weights` (glTF 2.0, 3.7.2.2: each attribute
/// plus the weighted sum of its targets' displacements). Normals and tangents are renormalised;
/// a tangent keeps its handedness.
pub fn morph_mesh(mesh: &Mesh, weights: &[f32]) -> Mesh {
    let mut out = Mesh {
        targets: Vec::new(),
        morph_weights: Vec::new(),
        ..mesh.clone()
    };
    for (target, &w) in mesh.targets.iter().zip(weights) {
        if w == 0.0 {
            continue;
        }
        for (p, d) in out.positions.iter_mut().zip(&target.positions) {
            *p += w * *d;
        }
        for (n, d) in out.normals.iter_mut().zip(&target.normals) {
            *n += w * *d;
        }
        for (t, d) in out.tangents.iter_mut().zip(&target.tangents) {
            *t += (w * *d).extend(0.0);
        }
    }
    if !mesh.targets.is_empty() {
        for n in &mut out.normals {
            *n = n.normalize_or_zero();
        }
        for t in &mut out.tangents {
            *t = t.truncate().normalize_or_zero().extend(t.w);
        }
    }
    out
}

/// Linear-blend skinning of `mesh` into world space (the skinned instance then has an identity
/// transform, as glTF prescribes).
pub fn skin_mesh(mesh: &Mesh, skin: &Skin, world: &[Mat4]) -> Mesh {
    let joint_matrices: Vec<Affine3A> = skin
        .joints
        .iter()
        .enumerate()
        .map(|(j, &node)| {
            let m = world[node]
                * skin
                    .inverse_bind_matrices
                    .get(j)
                    .copied()
                    .unwrap_or(Mat4::IDENTITY);
            // Joint matrices are affine (glTF): the bottom row carries nothing.
            Affine3A::from_mat4(m)
        })
        .collect();
    // Only what skinning changes is computed, each array written once (the rest is copied;
    // joints and weights are not: the posed mesh is final).
    let count = mesh.positions.len();
    let mut positions = Vec::with_capacity(count);
    let mut normals = Vec::with_capacity(mesh.normals.len());
    let mut tangents = Vec::with_capacity(mesh.tangents.len());
    for v in 0..count {
        let (Some(joints), Some(weights)) = (mesh.joints.get(v), mesh.weights.get(v)) else {
            // An unweighted vertex stays where the bind pose put it.
            positions.push(mesh.positions[v]);
            normals.extend(mesh.normals.get(v));
            tangents.extend(mesh.tangents.get(v));
            continue;
        };
        let total = weights.dot(Vec4::ONE);
        let scale = if total > 0.0 { total.recip() } else { 1.0 };
        let mut m = Affine3A::ZERO;
        for k in 0..4 {
            // Most vertices follow one or two joints: the others weigh nothing.
            if weights[k] == 0.0 {
                continue;
            }
            if let Some(jm) = joint_matrices.get(joints[k] as usize) {
                let w = weights[k] * scale;
                m.matrix3 += jm.matrix3 * w;
                m.translation += jm.translation * w;
            }
        }
        positions.push(m.transform_point3(mesh.positions[v]));
        if let Some(n) = mesh.normals.get(v) {
            // Normals go by the inverse transpose of the linear part (the translation does not
            // move a direction): the cofactor matrix, which is that times the determinant, the
            // determinant's sign kept (a mirroring joint turns the normal around).
            let c = &m.matrix3;
            let cofactor = Mat3A::from_cols(
                c.y_axis.cross(c.z_axis),
                c.z_axis.cross(c.x_axis),
                c.x_axis.cross(c.y_axis),
            );
            let determinant = c.x_axis.dot(cofactor.x_axis);
            let n = cofactor * Vec3A::from(*n);
            let length = n.length();
            let scale = if length > 0.0 && length.is_finite() {
                length.recip().copysign(determinant)
            } else {
                0.0
            };
            normals.push(Vec3::from(n * scale));
        }
        if let Some(t) = mesh.tangents.get(v) {
            let tt = m.transform_vector3(t.truncate()).normalize_or_zero();
            tangents.push(tt.extend(t.w));
        }
    }
    Mesh {
        name: mesh.name.clone(),
        positions,
        normals,
        tangents,
        uvs: mesh.uvs.clone(),
        uvs1: mesh.uvs1.clone(),
        colors: mesh.colors.clone(),
        indices: mesh.indices.clone(),
        triangle_materials: mesh.triangle_materials.clone(),
        joints: Vec::new(),
        weights: Vec::new(),
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn morphing_vertex() -> Mesh {
        Mesh {
            positions: vec![Vec3::ZERO],
            normals: vec![Vec3::Z],
            tangents: vec![Vec4::new(1.0, 0.0, 0.0, -1.0)],
            indices: vec![[0, 0, 0]],
            triangle_materials: vec![0],
            targets: vec![crate::MorphTarget {
                positions: vec![Vec3::X],
                normals: vec![Vec3::Y],
                tangents: vec![Vec3::Y],
            }],
            morph_weights: vec![1.0],
            ..Default::default()
        }
    }

    #[test]
    fn morphs_blend_positions_normals_and_tangents_keeping_handedness() {
        let m = morph_mesh(&morphing_vertex(), &[0.5]);
        assert_eq!(m.positions[0], Vec3::new(0.5, 0.0, 0.0));
        assert!((m.normals[0] - Vec3::new(0.0, 0.5, 1.0).normalize()).length() < 1e-6);
        assert!((m.tangents[0].truncate() - Vec3::new(1.0, 0.5, 0.0).normalize()).length() < 1e-6);
        assert_eq!(m.tangents[0].w, -1.0);
        assert!(m.targets.is_empty(), "the morphed mesh carries no targets");
    }

    #[test]
    fn a_skinned_mesh_is_morphed_first_then_skinned_at_the_nodes_weights() {
        use crate::{Node, Scene};
        let mut scene = Scene {
            meshes: vec![std::sync::Arc::new(morphing_vertex())],
            ..Default::default()
        };
        scene.meshes[0] = std::sync::Arc::new(Mesh {
            joints: vec![[0, 0, 0, 0]],
            weights: vec![Vec4::X],
            ..morphing_vertex()
        });
        let mut joint = Node::new("joint");
        joint.translation = glam::DVec3::new(0.0, 2.0, 0.0);
        let mut skinned = Node::new("skinned");
        skinned.mesh = Some(0);
        skinned.skin = Some(0);
        skinned.weights = Some(vec![0.25]);
        scene.nodes = vec![joint, skinned];
        scene.skins.push(Skin {
            name: String::new(),
            joints: vec![0],
            inverse_bind_matrices: Vec::new(),
        });
        let posed = scene.pose(0.0);
        let instance = posed.instances.iter().find(|i| i.node == 1).expect("posed");
        // Morphed to (0.25, 0, 0) by the node's weight (not the mesh's 1), then moved by the joint.
        assert_eq!(
            posed.meshes[instance.mesh].positions[0],
            Vec3::new(0.25, 2.0, 0.0)
        );
    }

    #[test]
    fn linear_translation_interpolates_and_clamps() {
        let ch = Channel {
            node: 0,
            property: Property::Translation,
            interpolation: Interpolation::Linear,
            times: vec![0.0, 2.0],
            values: vec![0.0, 0.0, 0.0, 2.0, 4.0, 6.0],
        };
        assert_eq!(ch.sample::<3>(1.0), [1.0, 2.0, 3.0]);
        assert_eq!(ch.sample::<3>(5.0), [2.0, 4.0, 6.0]);
        assert_eq!(ch.sample::<3>(-1.0), [0.0, 0.0, 0.0]);
    }

    #[test]
    fn cubic_spline_hits_keys_and_is_smooth() {
        // Zero tangents: value goes 0 -> 1 along smoothstep.
        let ch = Channel {
            node: 0,
            property: Property::Scale,
            interpolation: Interpolation::CubicSpline,
            times: vec![0.0, 1.0],
            values: vec![0.0; 3]
                .into_iter()
                .chain([0.0; 3])
                .chain([0.0; 3])
                .chain([0.0; 3])
                .chain([1.0; 3])
                .chain([0.0; 3])
                .collect(),
        };
        assert_eq!(ch.sample::<3>(0.5), [0.5, 0.5, 0.5]);
        assert!((ch.sample::<3>(0.25)[0] - 0.15625).abs() < 1e-6);
    }

    #[test]
    fn skinned_normals_follow_the_inverse_transpose_through_a_mirror() {
        // One vertex, two joints half and half: a non-uniform scale that mirrors x, and a
        // rotation; the normal must come out as the blended matrix's inverse transpose says.
        let a = Mat4::from_scale(Vec3::new(-2.0, 0.5, 1.0));
        let b = Mat4::from_rotation_z(0.7) * Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0));
        let mesh = Mesh {
            positions: vec![Vec3::new(0.3, -0.2, 0.9)],
            normals: vec![Vec3::new(0.6, 0.0, 0.8)],
            joints: vec![[0, 1, 0, 0]],
            weights: vec![Vec4::new(1.0, 1.0, 0.0, 0.0)],
            ..Default::default()
        };
        let skin = Skin {
            name: String::new(),
            joints: vec![0, 1],
            inverse_bind_matrices: Vec::new(),
        };
        let posed = skin_mesh(&mesh, &skin, &[a, b]);
        let blended = a * 0.5 + b * 0.5;
        let expected_position = blended.transform_point3(mesh.positions[0]);
        let expected_normal = (Mat3A::from_mat4(blended).inverse().transpose()
            * Vec3A::from(mesh.normals[0]))
        .normalize();
        assert!((posed.positions[0] - expected_position).length() < 1e-5);
        assert!(
            (Vec3A::from(posed.normals[0]) - expected_normal).length() < 1e-5,
            "{} against {expected_normal}",
            posed.normals[0]
        );
    }
}

//! The scene's nodes (a transform, what they carry) and skins (the joints a mesh follows).

use glam::{DMat4, DVec3, Mat4, Quat, Vec3};

#[derive(Clone, Debug)]
pub struct Node {
    pub name: String,
    pub parent: Option<usize>,
    /// In f64: a game world is larger than f32 can place a small room in (see [`crate::Scene::pose_around`]).
    pub translation: DVec3,
    pub rotation: Quat,
    pub scale: Vec3,
    pub mesh: Option<usize>,
    pub skin: Option<usize>,
    pub camera: Option<usize>,
    pub light: Option<usize>,
    /// Morph-target weights of the node's mesh (glTF node.weights, or animated); the mesh's
    /// defaults when `None`.
    pub weights: Option<Vec<f32>>,
}

impl Node {
    pub fn new(name: impl Into<String>) -> Self {
        Node {
            name: name.into(),
            parent: None,
            translation: DVec3::ZERO,
            rotation: Quat::IDENTITY,
            scale: Vec3::ONE,
            mesh: None,
            skin: None,
            camera: None,
            light: None,
            weights: None,
        }
    }
    pub fn local_matrix(&self) -> DMat4 {
        DMat4::from_scale_rotation_translation(
            self.scale.as_dvec3(),
            self.rotation.as_dquat(),
            self.translation,
        )
    }
}

#[derive(Clone, Debug)]
pub struct Skin {
    pub name: String,
    pub joints: Vec<usize>,
    pub inverse_bind_matrices: Vec<Mat4>,
}

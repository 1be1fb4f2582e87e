//! Triangle meshes in object space, as the scene stores them once for every node that uses them.

use glam::{DVec3, Vec2, Vec3, Vec4};

/// Triangle mesh in object space. Meshes are stored once and instanced by every node using them.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    /// Per-vertex shading normals; empty when the source had none (flat shading).
    pub normals: Vec<Vec3>,
    /// Per-vertex tangents (xyz, w = bitangent sign); empty when not needed.
    pub tangents: Vec<Vec4>,
    /// TEXCOORD_0; empty when absent.
    pub uvs: Vec<Vec2>,
    /// TEXCOORD_1; empty when absent.
    pub uvs1: Vec<Vec2>,
    /// COLOR_0 as linear RGBA (RGB files get alpha 1); empty when absent (white).
    pub colors: Vec<Vec4>,
    pub indices: Vec<[u32; 3]>,
    /// Material index of each triangle (a glTF mesh's primitives are merged into one mesh).
    pub triangle_materials: Vec<u32>,
    /// Skinning data (JOINTS_0 / WEIGHTS_0) when the mesh is skinned.
    pub joints: Vec<[u16; 4]>,
    pub weights: Vec<Vec4>,
    /// Morph targets: displacements of the positions, normals and tangents (each empty or one
    /// per vertex), blended in at the node's weights when the scene is posed.
    pub targets: Vec<MorphTarget>,
    /// The mesh's default target weights (a node's own, or an animation's, take their place).
    pub morph_weights: Vec<f32>,
    /// Where the positions were moved from: the glTF loader recentres a mesh whose vertices an
    /// exporter baked far from the origin (in f64, so they keep f32's precision), and every
    /// instance's transform puts it back (source position = position + offset).
    pub offset: DVec3,
}

/// One morph target of a mesh (glTF 2.0, 3.7.2.2).
#[derive(Clone, Debug, Default)]
pub struct MorphTarget {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub tangents: Vec<Vec3>,
}

impl Mesh {
    /// A mesh made by code: `indices` three to a triangle, every triangle of `material`;
    /// `normals` one per position, or empty for flat shading (a box's faces stay flat).
    pub fn from_arrays(
        name: &str,
        positions: &[[f32; 3]],
        normals: &[[f32; 3]],
        indices: &[u32],
        material: u32,
    ) -> Mesh {
        let v3 = |p: &[f32; 3]| Vec3::from_array(*p);
        Mesh {
            name: name.into(),
            positions: positions.iter().map(v3).collect(),
            normals: normals.iter().map(v3).collect(),
            indices: indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
            triangle_materials: vec![material; indices.len() / 3],
            ..Default::default()
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }
}

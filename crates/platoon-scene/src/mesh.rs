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
    /// The nodes a merged mesh was made of (`flatten::static_merge`), each with its first
    /// triangle, in triangle order: what names the object a ray hit (Cryptomatte). Empty for a
    /// mesh of the scene.
    pub parts: Vec<MeshPart>,
}

/// A node's triangles in a merged mesh: from `first_triangle` to the next part's first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshPart {
    pub node: usize,
    pub first_triangle: u32,
}

impl Mesh {
    /// The node whose part holds triangle `triangle` (a merged mesh's; None for a scene's).
    pub fn part_node(&self, triangle: u32) -> Option<usize> {
        let after = self.parts.partition_point(|p| p.first_triangle <= triangle);
        after.checked_sub(1).map(|i| self.parts[i].node)
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_merged_meshs_triangles_belong_to_their_parts() {
        let part = |node, first_triangle| MeshPart {
            node,
            first_triangle,
        };
        let mesh = Mesh {
            parts: vec![part(4, 0), part(7, 3), part(2, 5)],
            ..Default::default()
        };
        let nodes: Vec<_> = (0..7).map(|t| mesh.part_node(t)).collect();
        let want = [4, 4, 4, 7, 7, 2, 2].map(Some);
        assert_eq!(nodes, want);
        assert_eq!(Mesh::default().part_node(0), None);
    }
}

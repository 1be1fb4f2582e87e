//! Meshes made by code (`platoon-scenegen`) as a scene holds them, for the tests, benches and
//! games that build their scenes rather than load them.

use glam::Vec3;
use platoon_core::scene::Mesh;
use platoon_scenegen::MeshData;

/// `data` as a scene mesh, every triangle of `material`; with `smooth` false its normals are
/// left out and it is shaded flat (a box's faces stay flat).
pub fn mesh(data: &MeshData, material: u32, smooth: bool) -> Mesh {
    let v3 = |p: &[f32; 3]| Vec3::from_array(*p);
    Mesh {
        name: "generated".into(),
        positions: data.positions.iter().map(v3).collect(),
        normals: if smooth {
            data.normals.iter().map(v3).collect()
        } else {
            Vec::new()
        },
        indices: data
            .indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect(),
        triangle_materials: vec![material; data.indices.len() / 3],
        ..Default::default()
    }
}

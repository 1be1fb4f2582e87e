//! Meshes made by code (`platoon-scenegen`) as a scene holds them, for the tests, benches and
//! games that build their scenes rather than load them.

use anyhow::Result;
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

/// A character walking in a room (vertex links' living-scene tests and bench): the Cornell
/// box with every face `cells` x `cells` quads and `character` (CesiumMan: its skin walks)
/// appended at [`walk_step`] 0; returns the scene and the node that places the character.
pub fn walk_in_a_room(
    character: &platoon_core::Scene,
    cells: u32,
) -> Result<(platoon_core::Scene, usize)> {
    let mut scene = platoon_core::scene::cornell::tessellated(cells);
    let node = scene.append(character, walk_step(0.0))?;
    Ok((scene, node))
}

/// The edits that take the walk's character `node` to whole step `step`: its animation at
/// 0.3 s a step and its placement ([`walk_step`]); one generation a step.
pub fn walk_edits(node: usize, step: usize) -> [platoon_core::drive::Edit; 2] {
    [
        platoon_core::drive::Edit::Time(0.3 * step as f32),
        platoon_core::drive::Edit::Placement {
            node,
            placement: walk_step(step as f64),
        },
    ]
}

/// Where step `k` of the walk (a fraction between steps too) puts the character: 0.4 m further
/// along the floor each step, between the Cornell box's blocks, one and a half times its size.
pub fn walk_step(k: f64) -> platoon_core::scene::Placement {
    platoon_core::scene::Placement {
        scale: Vec3::splat(1.5),
        ..platoon_core::scene::Placement::at(glam::DVec3::new(1.6 + 0.4 * k, 0.0, 2.8))
    }
}

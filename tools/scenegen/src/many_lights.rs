//! The many-light interior (issue 43): a hall of 16 x 4 x 10 m lit by 128 small emissive
//! ceiling panels in four colours and strengths and 48 wall sconces (point lights), with
//! columns, tables and a textured floor: where picking one light in proportion to power wastes
//! most shadow rays on lights far away or behind the point shaded, the case resampled direct
//! light is for. A character walks in it when the bench or a test appends one
//! (`Scene::append`: CesiumMan from ../shared/scenes).

use serde_json::{json, Value};

use crate::{flat_box, grid, quad, MeshData, NodeData, SceneData};

/// Half width (x), height (y) and half depth (z) of the hall.
const HALF_WIDTH: f64 = 8.0;
const HEIGHT: f64 = 4.0;
const HALF_DEPTH: f64 = 5.0;
/// Ceiling panels: a grid of this many along x by along z.
const PANELS: (usize, usize) = (16, 8);
/// Sconces on each long wall.
const SCONCES_PER_WALL: usize = 24;

/// The panels' colours and strengths (glTF `emissiveStrength`), by turns across the ceiling.
const PANEL_LIGHTS: [([f32; 3], f32); 4] = [
    ([1.0, 0.85, 0.65], 1.0),
    ([0.7, 0.85, 1.0], 0.6),
    ([1.0, 0.95, 0.9], 1.5),
    ([1.0, 0.6, 0.4], 0.5),
];

fn diffuse(name: &str, colour: [f32; 3], roughness: f32) -> Value {
    json!({"name": name, "pbrMetallicRoughness": {"baseColorFactor": [colour[0], colour[1], colour[2], 1], "metallicFactor": 0, "roughnessFactor": roughness}})
}

/// A quaternion turning by `degrees` about axis `axis` (0 x, 1 y, 2 z).
fn turn(axis: usize, degrees: f32) -> [f32; 4] {
    let (s, c) = (degrees.to_radians() / 2.0).sin_cos();
    let mut q = [0.0, 0.0, 0.0, c];
    q[axis] = s;
    q
}

/// The hall: see the module's documentation. About 60k triangles, 176 lights (256 emissive
/// triangles and 48 points).
pub fn many_lights() -> SceneData {
    let mut materials = vec![
        json!({"name": "floor", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 0.6}}),
        diffuse("walls", [0.7, 0.68, 0.62], 1.0),
        diffuse("ceiling", [0.8, 0.8, 0.8], 1.0),
        diffuse("columns", [0.55, 0.5, 0.45], 0.8),
        diffuse("tables", [0.4, 0.25, 0.15], 0.5),
    ];
    let panel_material = materials.len();
    for (k, (colour, strength)) in PANEL_LIGHTS.iter().enumerate() {
        materials.push(
            json!({"name": format!("panel {k}"), "emissiveFactor": colour,
            "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]},
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}}),
        );
    }
    let (w, h, d) = (HALF_WIDTH, HEIGHT, HALF_DEPTH);
    let mut meshes: Vec<(MeshData, usize)> = Vec::new();
    let mut nodes: Vec<NodeData> = Vec::new();
    let mut place = |mesh: usize, at: [f64; 3], rotation: [f32; 4], scale: [f32; 3]| {
        nodes.push(NodeData {
            mesh: Some(mesh),
            translation: at,
            rotation,
            scale,
            ..NodeData::new()
        });
    };
    let id = [0.0, 0.0, 0.0, 1.0];
    // The floor, its checker repeating every metre.
    let mut floor = grid(96);
    floor.uvs = floor
        .positions
        .iter()
        .map(|p| [p[0] * w as f32, p[2] * d as f32])
        .collect();
    meshes.push((floor, 0));
    place(0, [0.0, 0.0, 0.0], id, [w as f32, 1.0, d as f32]);
    meshes.push((grid(96), 2));
    place(1, [0.0, h, 0.0], turn(0, 180.0), [w as f32, 1.0, d as f32]);
    meshes.push((grid(48), 1));
    let (hh, half) = ((h / 2.0) as f32, [w as f32, d as f32]);
    place(2, [0.0, h / 2.0, -d], turn(0, 90.0), [half[0], 1.0, hh]);
    place(2, [0.0, h / 2.0, d], turn(0, -90.0), [half[0], 1.0, hh]);
    place(2, [-w, h / 2.0, 0.0], turn(2, -90.0), [hh, 1.0, half[1]]);
    place(2, [w, h / 2.0, 0.0], turn(2, 90.0), [hh, 1.0, half[1]]);
    // Two rows of columns and a table between each pair.
    meshes.push((flat_box(), 3));
    meshes.push((flat_box(), 4));
    for k in 0..6 {
        let x = -6.25 + k as f64 * 2.5;
        for z in [-2.5, 2.5] {
            place(3, [x, h / 2.0, z], id, [0.25, hh, 0.25]);
        }
        if k < 5 {
            place(4, [x + 1.25, 0.75, 0.0], id, [0.8, 0.04, 0.5]);
        }
    }
    // The panels, a little below the ceiling and facing down, in four colours by turns.
    let panel_mesh = meshes.len();
    for k in 0..PANEL_LIGHTS.len() {
        meshes.push((quad(0.2, -1.0), panel_material + k));
    }
    let (nx, nz) = PANELS;
    for i in 0..nx {
        for j in 0..nz {
            let x = -w + (i as f64 + 0.5) * 2.0 * w / nx as f64;
            let z = -d + (j as f64 + 0.5) * 2.0 * d / nz as f64;
            place(
                panel_mesh + (i + j) % PANEL_LIGHTS.len(),
                [x, h - 0.02, z],
                id,
                [1.0; 3],
            );
        }
    }
    // Sconces: warm point lights a hand off the long walls, dim and near (what they light is
    // the wall around them and the floor below).
    let mut lights = Vec::new();
    for (side, z) in [(0, -d + 0.15), (1, d - 0.15)] {
        for k in 0..SCONCES_PER_WALL {
            let x = -w + (k as f64 + 0.5) * 2.0 * w / SCONCES_PER_WALL as f64;
            let colour = if (k + side) % 2 == 0 {
                [1.0, 0.7, 0.45]
            } else {
                [0.9, 0.9, 1.0]
            };
            lights.push(json!({"type": "point", "color": colour, "intensity": 1.5}));
            nodes.push(NodeData {
                translation: [x, 2.2, z],
                light: Some(lights.len() - 1),
                ..NodeData::new()
            });
        }
    }
    let mut camera = NodeData::new();
    camera.translation = [-7.6, 1.7, 1.2];
    // Down the hall between the columns: turned about y, tilted down a little.
    camera.rotation = crate::bench::turned(-78.0, -10.0);
    camera.camera_yfov = Some(1.0);
    nodes.push(camera);
    SceneData {
        meshes,
        materials,
        nodes,
        lights,
        extensions_used: vec!["KHR_materials_emissive_strength".into()],
        images: vec![crate::bench::checker_png(2, 32)],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hall_has_over_a_hundred_panels_and_sconces_inside_it() {
        let hall = many_lights();
        let emissive: Vec<usize> = (0..hall.materials.len())
            .filter(|&m| hall.materials[m].get("emissiveFactor").is_some())
            .collect();
        let panels = hall
            .nodes
            .iter()
            .filter_map(|n| n.mesh)
            .filter(|&m| emissive.contains(&hall.meshes[m].1))
            .count();
        assert_eq!(panels, 128);
        assert_eq!(hall.lights.len(), 48);
        assert!(hall.lights.iter().all(|l| l["type"] == "point"));
        let tris = hall.triangle_count();
        assert!((40_000..120_000).contains(&tris), "{tris} triangles");
        // Every light, panel and the camera inside the hall.
        for n in hall
            .nodes
            .iter()
            .filter(|n| n.mesh.is_none_or(|m| emissive.contains(&hall.meshes[m].1)))
        {
            let [x, y, z] = n.translation;
            assert!(x.abs() < HALF_WIDTH && z.abs() < HALF_DEPTH, "{n:?}");
            assert!(y > 0.0 && y < HEIGHT, "{n:?}");
        }
        assert!(to_glb_ok(&hall));
    }

    fn to_glb_ok(s: &SceneData) -> bool {
        crate::to_glb(s).starts_with(b"glTF")
    }
}

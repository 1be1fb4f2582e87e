//! The bench scenes of issue 21, written the way exporters write scenes: a node and a mesh per
//! object, glTF materials, textures and punctual lights (`platoon bench against`, and
//! tools/reference_bench.py renders the same files in Mitsuba 3 through platoon's export).

use serde_json::{json, Value};

use crate::{cut_quads, flat_box, grid, icosphere, quad_from, MeshData, NodeData, SceneData};

/// The rotation (x, y, z, w) that turns -Z (where glTF cameras look and lights point) to `d`,
/// turning about +Y when `d` is +Z so that a camera stays upright.
pub fn facing(d: [f32; 3]) -> [f32; 4] {
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let b = [d[0] / l, d[1] / l, d[2] / l];
    // a = -Z: a x b = (b.y, -b.x, 0), a . b = -b.z.
    let w = 1.0 - b[2];
    if w < 1e-6 {
        return [0.0, 1.0, 0.0, 0.0];
    }
    let q = [b[1], -b[0], 0.0, w];
    let n = (q[0] * q[0] + q[1] * q[1] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, 0.0, q[3] / n]
}

/// The rotation (x, y, z, w) of a camera turned `yaw` degrees about +Y, then tilted `pitch`
/// degrees about its own x (negative: down).
pub fn turned(yaw: f32, pitch: f32) -> [f32; 4] {
    let (sy, cy) = (yaw.to_radians() / 2.0).sin_cos();
    let (sx, cx) = (pitch.to_radians() / 2.0).sin_cos();
    [cy * sx, sy * cx, -sy * sx, cy * cx]
}

/// A Lambertian glTF material (dielectric with KHR_materials_specular's factor 0), as
/// platoon's built-in Cornell box has.
fn lambertian(name: &str, albedo: [f32; 3]) -> Value {
    json!({"name": name,
           "pbrMetallicRoughness": {"baseColorFactor": [albedo[0], albedo[1], albedo[2], 1], "metallicFactor": 0, "roughnessFactor": 1},
           "extensions": {"KHR_materials_specular": {"specularFactor": 0}}})
}

/// A one-sided quad given by its world corners (counter-clockwise seen from the side it faces)
/// as a mesh about its centre and the node's translation to that centre.
fn placed_quad(corners: [[f32; 3]; 4]) -> (MeshData, [f64; 3]) {
    let c: [f32; 3] = std::array::from_fn(|k| corners.iter().map(|p| p[k]).sum::<f32>() / 4.0);
    let local = corners.map(|p| [p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
    (quad_from(local), c.map(f64::from))
}

/// The built-in Cornell box (crates/platoon-scene/src/cornell.rs) as an exporter writes
/// it: five walls, the light and two closed blocks, each its own mesh under its own node (8
/// instances, 36 triangles), and the built-in's camera.
pub fn cornell_nodes() -> SceneData {
    cornell_cut(1)
}

/// [`cornell_nodes`] with every face (walls, light, each side of the blocks) cut into `cells` x
/// `cells` quads: 36 * cells^2 triangles, the same surfaces tessellated as a scanned or
/// subdivided asset is (48 cells: 82,944 triangles).
pub fn cornell_cut(cells: u32) -> SceneData {
    let s = 5.55f32;
    let materials = vec![
        lambertian("white", [0.73, 0.73, 0.73]),
        lambertian("red", [0.65, 0.05, 0.05]),
        lambertian("green", [0.12, 0.45, 0.15]),
        {
            let mut light = lambertian("light", [0.78, 0.78, 0.78]);
            light["emissiveFactor"] = json!([1.0, 12.0 / 17.0, 4.0 / 17.0]);
            light["extensions"]["KHR_materials_emissive_strength"] =
                json!({"emissiveStrength": 17.0});
            light
        },
    ];
    let (l0, l1, ly) = (2.13, 3.43, s - 0.001);
    let quads = [
        ([[0., 0., 0.], [0., 0., s], [s, 0., s], [s, 0., 0.]], 0), // floor
        ([[0., s, 0.], [s, s, 0.], [s, s, s], [0., s, s]], 0),     // ceiling
        ([[0., 0., s], [0., s, s], [s, s, s], [s, 0., s]], 0),     // back
        ([[s, 0., 0.], [s, 0., s], [s, s, s], [s, s, 0.]], 1),     // red wall
        ([[0., 0., 0.], [0., s, 0.], [0., s, s], [0., 0., s]], 2), // green wall
        (
            [
                [l0, ly, 2.27],
                [l1, ly, 2.27],
                [l1, ly, 3.32],
                [l0, ly, 3.32],
            ],
            3,
        ), // light
    ];
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    for (corners, material) in quads {
        let (mesh, at) = placed_quad(corners);
        meshes.push((cut_quads(&mesh, cells), material));
        nodes.push(NodeData::mesh(meshes.len() - 1, at, 1.0));
    }
    // The blocks: centre on the floor, size, turn about y in degrees.
    for ((x, z), (w, h), degrees) in [
        ((1.855f64, 1.69f64), (1.65f32, 1.65f32), -18.0f32),
        ((3.685, 3.51), (1.65, 3.3), 15.0),
    ] {
        meshes.push((cut_quads(&flat_box(), cells), 0));
        let (sin, cos) = (degrees.to_radians() / 2.0).sin_cos();
        nodes.push(NodeData {
            mesh: Some(meshes.len() - 1),
            translation: [x, h as f64 / 2.0, z],
            rotation: [0.0, sin, 0.0, cos],
            scale: [w / 2.0, h / 2.0, w / 2.0],
            ..NodeData::new()
        });
    }
    let mut camera = NodeData::new();
    camera.translation = [s as f64 / 2.0, s as f64 / 2.0, -8.0];
    camera.rotation = facing([0.0, 0.0, 1.0]);
    camera.camera_yfov = Some(39.3077f32.to_radians());
    nodes.push(camera);
    SceneData {
        meshes,
        materials,
        nodes,
        extensions_used: vec![
            "KHR_materials_specular".into(),
            "KHR_materials_emissive_strength".into(),
        ],
        ..Default::default()
    }
}

/// A checker of `cells` x `cells` squares of `size` pixels in two greys (RGBA8 as a PNG).
pub(crate) fn checker_png(cells: u32, size: u32) -> Vec<u8> {
    let n = cells * size;
    let mut px = Vec::with_capacity((n * n * 4) as usize);
    for y in 0..n {
        for x in 0..n {
            let v = if (x / size + y / size).is_multiple_of(2) {
                200
            } else {
                70
            };
            px.extend([v, v, v, 255]);
        }
    }
    crate::twins::png(n, n, px)
}

/// Five smooth spheres (icosphere level 4, 5,120 triangles each) of glTF materials (rough
/// dielectric, rough gold, glossy silver, a coloured specular layer, a half metal) over a
/// textured 12 x 12 m ground, lit by a point light, a sun and a small emissive panel (the
/// bench adds a constant sky with `--env-color`).
pub fn spheres() -> SceneData {
    let materials = vec![
        json!({"name": "ground", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 0.8}}),
        json!({"name": "rough dielectric", "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.97, 1, 1], "metallicFactor": 0, "roughnessFactor": 0.3},
               "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.5}}}),
        json!({"name": "rough gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.766, 0.336, 1], "metallicFactor": 1, "roughnessFactor": 0.4}}),
        json!({"name": "glossy silver", "pbrMetallicRoughness": {"baseColorFactor": [0.972, 0.96, 0.915, 1], "metallicFactor": 1, "roughnessFactor": 0.1}}),
        json!({"name": "coloured specular", "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.08, 0.1, 1], "metallicFactor": 0, "roughnessFactor": 0.2},
               "extensions": {"KHR_materials_specular": {"specularFactor": 1, "specularColorFactor": [0.3, 0.6, 1.0]}}}),
        json!({"name": "half metal", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.2, 1], "metallicFactor": 0.5, "roughnessFactor": 0.5}}),
        json!({"name": "panel", "emissiveFactor": [1, 0.9, 0.7], "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]},
               "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 20}}}),
    ];
    let mut ground = grid(12);
    // One checker square a metre: the 2 x 2-square image repeats every 2 m.
    ground.uvs = ground
        .positions
        .iter()
        .map(|p| [p[0] * 3.0, p[2] * 3.0])
        .collect();
    let mut meshes = vec![(ground, 0)];
    let mut nodes = vec![NodeData::mesh(0, [0.0; 3], 6.0)];
    for k in 0..5 {
        meshes.push((icosphere(4), k + 1));
        nodes.push(NodeData::mesh(
            k + 1,
            [-5.0 + 2.5 * k as f64, 1.0, 0.0],
            1.0,
        ));
    }
    let (panel, at) = placed_quad([
        [-3.3, 3.5, 1.7],
        [-2.7, 3.5, 1.7],
        [-2.7, 3.5, 2.3],
        [-3.3, 3.5, 2.3],
    ]);
    meshes.push((panel, 6));
    nodes.push(NodeData::mesh(meshes.len() - 1, at, 1.0));
    let lights = vec![
        json!({"type": "point", "color": [1.0, 0.85, 0.7], "intensity": 30.0}),
        json!({"type": "directional", "color": [1.0, 0.97, 0.9], "intensity": 2.0}),
    ];
    nodes.push(NodeData {
        translation: [2.0, 4.0, 3.0],
        light: Some(0),
        ..NodeData::new()
    });
    nodes.push(NodeData {
        rotation: facing([-0.4, -1.0, -0.6]),
        light: Some(1),
        ..NodeData::new()
    });
    let mut camera = NodeData::new();
    camera.translation = [0.0, 3.4, 10.5];
    camera.rotation = facing([0.0, -0.3, -1.0]);
    camera.camera_yfov = Some(1.0);
    nodes.push(camera);
    SceneData {
        meshes,
        materials,
        nodes,
        lights,
        extensions_used: vec![
            "KHR_materials_transmission".into(),
            "KHR_materials_ior".into(),
            "KHR_materials_specular".into(),
            "KHR_materials_emissive_strength".into(),
        ],
        images: vec![checker_png(2, 32)],
    }
}

/// The ground a character walks on in `platoon bench realtime walk`: a grey quad `half` units
/// from its centre each way under a low sun from the side (long shadows), as the game's world
/// has (crates/platoon-game/src/world.rs); the sky is the environment the bench adds.
pub fn walk_ground(half: f32) -> SceneData {
    let g = half;
    let ground = quad_from([[-g, 0.0, g], [g, 0.0, g], [g, 0.0, -g], [-g, 0.0, -g]]);
    let materials = vec![json!({"name": "ground",
        "pbrMetallicRoughness": {"baseColorFactor": [0.45, 0.45, 0.45, 1], "metallicFactor": 0, "roughnessFactor": 0.9}})];
    let sun = NodeData {
        rotation: turned(40.0, -43.0),
        light: Some(0),
        ..NodeData::new()
    };
    SceneData {
        meshes: vec![(ground, 0)],
        materials,
        nodes: vec![NodeData::mesh(0, [0.0; 3], 1.0), sun],
        lights: vec![json!({"type": "directional", "color": [1.0, 0.92, 0.8], "intensity": 2.5})],
        extensions_used: vec!["KHR_lights_punctual".into()],
        images: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_multi_node_box_has_eight_instances_and_36_triangles() {
        let c = cornell_nodes();
        assert_eq!(c.nodes.iter().filter(|n| n.mesh.is_some()).count(), 8);
        assert_eq!(c.meshes.len(), 8);
        assert_eq!(c.triangle_count(), 36);
        let cut = cornell_cut(48);
        assert_eq!(cut.triangle_count(), 82_944);
        // The same surfaces: every cut mesh spans its uncut mesh's box.
        for ((whole, _), (pieces, _)) in c.meshes.iter().zip(&cut.meshes) {
            assert_eq!(bounds(whole), bounds(pieces));
        }
    }

    fn bounds(m: &MeshData) -> ([f32; 3], [f32; 3]) {
        let mut b = ([f32::MAX; 3], [f32::MIN; 3]);
        for p in &m.positions {
            b.0 = std::array::from_fn(|k| b.0[k].min(p[k]));
            b.1 = std::array::from_fn(|k| b.1[k].max(p[k]));
        }
        b
    }

    #[test]
    fn the_spheres_scene_has_five_smooth_spheres_a_textured_ground_and_three_lights() {
        let s = spheres();
        assert_eq!(s.triangle_count(), 5 * 5120 + 2 * 144 + 2);
        assert_eq!(s.lights.len(), 2);
        assert!(!s.meshes[0].0.uvs.is_empty());
        assert_eq!(s.images.len(), 1);
        assert!(to_glb_ok(&s));
    }

    fn to_glb_ok(s: &SceneData) -> bool {
        crate::to_glb(s).starts_with(b"glTF")
    }

    #[test]
    fn facing_turns_minus_z_onto_the_direction() {
        for d in [
            [0.0, 0.0, 1.0],
            [0.0, -0.28, -1.0],
            [-0.4, -1.0, -0.6],
            [1.0, 0.0, 0.0],
        ] {
            let q = facing(d);
            let r = glam::Quat::from_xyzw(q[0], q[1], q[2], q[3]) * glam::Vec3::NEG_Z;
            let d = glam::Vec3::from(d).normalize();
            assert!((r - d).length() < 1e-5, "{r} vs {d}");
        }
        // An upright camera stays upright.
        let q = facing([0.0, 0.0, 1.0]);
        let up = glam::Quat::from_xyzw(q[0], q[1], q[2], q[3]) * glam::Vec3::Y;
        assert!((up - glam::Vec3::Y).length() < 1e-6);
    }
}

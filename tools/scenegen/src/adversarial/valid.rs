//! Valid scenes that are numerically hard, each with a known answer.

use serde_json::{json, Value};

use super::{Case, Expect};
use crate::{icosphere, quad, quad_from, smooth_box, to_glb, MeshData, NodeData, SceneData};

fn lambert(name: &str, rgb: [f32; 3]) -> Value {
    json!({"name": name, "pbrMetallicRoughness": {"baseColorFactor": [rgb[0], rgb[1], rgb[2], 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0},
           "extensions": {"KHR_materials_specular": {"specularFactor": 0.0}}})
}

fn emitter(strength: f32, double_sided: bool) -> Value {
    json!({"name": "emitter", "emissiveFactor": [1.0, 0.9, 0.8], "doubleSided": double_sided,
           "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": strength}},
           "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0]}})
}

const EXTENSIONS: [&str; 2] = ["KHR_materials_emissive_strength", "KHR_materials_specular"];

fn scene(
    meshes: Vec<(MeshData, usize)>,
    materials: Vec<Value>,
    nodes: Vec<NodeData>,
    lights: Vec<Value>,
) -> SceneData {
    SceneData {
        meshes,
        materials,
        nodes,
        lights,
        extensions_used: EXTENSIONS.iter().map(|s| s.to_string()).collect(),
        ..Default::default()
    }
}

/// A camera node at `at`, turned by the unit quaternion `rotation` (glTF cameras look down -Z).
fn camera(at: [f64; 3], rotation: [f32; 4], yfov: f32) -> NodeData {
    let norm = rotation.iter().map(|c| c * c).sum::<f32>().sqrt();
    let rotation = rotation.map(|c| c / norm);
    NodeData {
        translation: at,
        rotation,
        camera_yfov: Some(yfov),
        ..NodeData::new()
    }
}

/// Rotation turning the camera's -Z to -Y (looking straight down).
const LOOK_DOWN: [f32; 4] = [
    -std::f32::consts::FRAC_1_SQRT_2,
    0.0,
    0.0,
    std::f32::consts::FRAC_1_SQRT_2,
];

/// A 2-unit room ([-1, 1]^3, open towards +z) with coloured walls, two blocks and a one-sided
/// ceiling light, under a root node at `offset` with uniform `scale` that also holds the camera.
pub fn room(offset: [f64; 3], scale: f32) -> SceneData {
    let q = |c: [[f32; 3]; 4]| quad_from(c);
    let block = |x: f32, z: f32, h: f32| {
        let mut m = smooth_box();
        m.positions
            .iter_mut()
            .for_each(|p| *p = [x + p[0] * 0.25, -1.0 + (p[1] + 1.0) * h, z + p[2] * 0.25]);
        // Flat shading: the blocks are boxes, not blobs.
        m.normals.clear();
        m
    };
    let meshes = vec![
        (
            q([
                [-1., -1., -1.],
                [-1., -1., 1.],
                [1., -1., 1.],
                [1., -1., -1.],
            ]),
            0,
        ), // floor
        (
            q([[-1., 1., -1.], [1., 1., -1.], [1., 1., 1.], [-1., 1., 1.]]),
            0,
        ), // ceiling
        (
            q([
                [-1., -1., -1.],
                [1., -1., -1.],
                [1., 1., -1.],
                [-1., 1., -1.],
            ]),
            0,
        ), // back
        (
            q([
                [-1., -1., -1.],
                [-1., 1., -1.],
                [-1., 1., 1.],
                [-1., -1., 1.],
            ]),
            1,
        ), // left, red
        (
            q([[1., -1., -1.], [1., -1., 1.], [1., 1., 1.], [1., 1., -1.]]),
            2,
        ), // right, green
        (
            q([
                [-0.3, 0.999, -0.3],
                [0.3, 0.999, -0.3],
                [0.3, 0.999, 0.3],
                [-0.3, 0.999, 0.3],
            ]),
            3,
        ), // light, facing down
        (block(-0.4, -0.3, 0.6), 0),
        (block(0.4, 0.2, 1.2), 0),
    ];
    let mut nodes: Vec<NodeData> = (0..meshes.len())
        .map(|m| NodeData::mesh(m, [0.0; 3], 1.0))
        .collect();
    nodes.push(camera([0.0, 0.0, 3.6], [0.0, 0.0, 0.0, 1.0], 0.7));
    let children = (0..nodes.len()).collect();
    nodes.push(NodeData {
        translation: offset,
        scale: [scale; 3],
        children,
        ..NodeData::new()
    });
    let materials = vec![
        lambert("white", [0.73; 3]),
        lambert("red", [0.65, 0.05, 0.05]),
        lambert("green", [0.12, 0.45, 0.15]),
        emitter(12.0, false),
    ];
    scene(meshes, materials, nodes, vec![])
}

/// A floor under a one-sided emitter facing down, under a root node scaled by (sx, 1, 1): sx = -1
/// mirrors it (a negative determinant), and the camera above sees the mirror image.
pub fn mirrored_emitter(sx: f32) -> SceneData {
    let mut panel = quad(0.3, -1.0);
    panel
        .positions
        .iter_mut()
        .for_each(|p| *p = [p[0] + 0.6, 1.2, p[2] + 0.2]);
    let meshes = vec![(quad(2.0, 1.0), 0), (panel, 1)];
    let nodes = vec![
        NodeData::mesh(0, [0.0; 3], 1.0),
        NodeData::mesh(1, [0.0; 3], 1.0),
        NodeData {
            scale: [sx, 1.0, 1.0],
            children: vec![0, 1],
            ..NodeData::new()
        },
        camera([0.0, 3.0, 0.0], LOOK_DOWN, 1.0),
    ];
    scene(
        meshes,
        vec![lambert("floor", [0.8; 3]), emitter(20.0, false)],
        nodes,
        vec![],
    )
}

fn point_light(intensity: f32) -> Value {
    json!({"type": "point", "color": [1.0, 1.0, 1.0], "intensity": intensity})
}

/// A closed smooth-shaded shell (`shell`) with a point light and a small double-sided emitter
/// inside, seen from outside: no light may leave it.
pub fn sealed(shell: MeshData) -> SceneData {
    let mut bulb = icosphere(1);
    bulb.positions
        .iter_mut()
        .for_each(|p| *p = [p[0] * 0.15 - 0.4, p[1] * 0.15, p[2] * 0.15]);
    let meshes = vec![(shell, 0), (bulb, 1)];
    let nodes = vec![
        NodeData::mesh(0, [0.0; 3], 1.0),
        NodeData::mesh(1, [0.0; 3], 1.0),
        NodeData {
            translation: [0.3, 0.1, 0.0],
            light: Some(0),
            ..NodeData::new()
        },
        camera([0.8, 0.6, 3.4], [-0.08, 0.11, 0.0, 0.99], 0.9),
    ];
    scene(
        meshes,
        vec![lambert("shell", [0.8; 3]), emitter(30.0, true)],
        nodes,
        vec![point_light(20.0)],
    )
}

/// The camera inside a closed smooth sphere, the lights outside it.
pub fn camera_in_sealed_sphere() -> SceneData {
    let meshes = vec![(icosphere(3), 0)];
    let nodes = vec![
        NodeData::mesh(0, [0.0; 3], 1.0),
        NodeData {
            translation: [0.0, 0.0, -3.0],
            light: Some(0),
            ..NodeData::new()
        },
        NodeData {
            rotation: [-0.38, 0.0, 0.0, 0.92],
            light: Some(1),
            ..NodeData::new()
        },
        camera([0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0], 1.2),
    ];
    let sun = json!({"type": "directional", "color": [1.0, 1.0, 1.0], "intensity": 5.0});
    scene(
        meshes,
        vec![lambert("shell", [0.8; 3])],
        nodes,
        vec![point_light(50.0), sun],
    )
}

/// A floor and a ball under a directional light and a small emitter; `far_vertex` adds a mesh at
/// 1e30, which makes the scene's bounding radius (and so the sun's selection power) enormous.
pub fn sunlit(far_vertex: bool) -> SceneData {
    let mut ball = icosphere(2);
    ball.positions
        .iter_mut()
        .for_each(|p| *p = [p[0] * 0.5, p[1] * 0.5 + 0.5, p[2] * 0.5]);
    let mut panel = quad(0.25, -1.0);
    panel
        .positions
        .iter_mut()
        .for_each(|p| *p = [p[0] - 0.8, 1.0, p[2]]);
    let mut meshes = vec![(quad(2.0, 1.0), 0), (ball, 0), (panel, 1)];
    let mut nodes: Vec<NodeData> = (0..3).map(|m| NodeData::mesh(m, [0.0; 3], 1.0)).collect();
    nodes.push(NodeData {
        rotation: [-0.42, 0.2, 0.1, 0.88],
        light: Some(0),
        ..NodeData::new()
    });
    nodes.push(camera([0.0, 2.2, 3.0], [-0.3, 0.0, 0.0, 0.954], 0.9));
    if far_vertex {
        let far = MeshData {
            positions: vec![
                [1e30, 1e30, 1e30],
                [1.0000001e30, 1e30, 1e30],
                [1e30, 1.0000001e30, 1e30],
            ],
            normals: vec![[0.0, 0.0, 1.0]; 3],
            indices: vec![0, 1, 2],
            ..Default::default()
        };
        meshes.push((far, 0));
        nodes.push(NodeData::mesh(3, [0.0; 3], 1.0));
    }
    let sun = json!({"type": "directional", "color": [1.0, 0.95, 0.9], "intensity": 3.0});
    scene(
        meshes,
        vec![lambert("white", [0.7; 3]), emitter(10.0, false)],
        nodes,
        vec![sun],
    )
}

/// A thicket: `n` triangles, each with its corners at random places on the surface of the cube
/// [-1, 1]^3 (a fixed sequence), so that every one crosses the cube and every box of a BVH over
/// them spans most of it: a ray through the cube tests nearly all of them, whatever the BVH.
/// Lit by a point light; the camera looks at it from +z. What runs a SIMD group of the path
/// tracer's megakernel past llvmpipe's loop limit (65,535 iterations an invocation) at a few
/// samples a pixel, while one traversal stays well within it.
pub fn thicket(n: u32) -> SceneData {
    let mut state = 0x9e37_79b9u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32 * 2.0 - 1.0
    };
    let mut on_cube = || {
        let mut p = [next(), next(), next()];
        let face = ((next() + 1.0) * 3.0).min(5.99) as usize;
        p[face % 3] = if face < 3 { -1.0 } else { 1.0 };
        p
    };
    let mut mesh = MeshData::default();
    for t in 0..n {
        let corners = [on_cube(), on_cube(), on_cube()];
        let e1: [f32; 3] = std::array::from_fn(|k| corners[1][k] - corners[0][k]);
        let e2: [f32; 3] = std::array::from_fn(|k| corners[2][k] - corners[0][k]);
        let c = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let l = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt().max(1e-12);
        mesh.positions.extend(corners);
        mesh.normals.extend([c.map(|v| v / l); 3]);
        mesh.indices.extend([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    let nodes = vec![
        NodeData::mesh(0, [0.0; 3], 1.0),
        NodeData {
            translation: [0.5, 2.0, 2.5],
            light: Some(0),
            ..NodeData::new()
        },
        camera([0.0, 0.0, 3.5], [0.0, 0.0, 0.0, 1.0], 0.7),
    ];
    scene(
        vec![(mesh, 0)],
        vec![lambert("leaves", [0.6; 3])],
        nodes,
        vec![point_light(30.0)],
    )
}

/// Every valid hard case with its expected answer.
pub fn valid() -> Vec<Case> {
    vec![
        Case::glb("room", to_glb(&room([0.0; 3], 1.0)), Expect::Finite),
        Case::glb(
            "room_at_1e6",
            to_glb(&room([1e6, 0.5e6, -1e6], 1.0)),
            Expect::Twin("room"),
        ),
        Case::glb(
            "room_at_1e7",
            to_glb(&room([1e7, -1e7, 1e7], 1.0)),
            Expect::Twin("room"),
        ),
        Case::glb(
            "room_scaled_1e-4",
            to_glb(&room([0.0; 3], 1e-4)),
            Expect::Twin("room"),
        ),
        Case::glb("emitter", to_glb(&mirrored_emitter(1.0)), Expect::Finite),
        Case::glb(
            "emitter_mirrored",
            to_glb(&mirrored_emitter(-1.0)),
            Expect::Twin("emitter"),
        ),
        Case::glb(
            "sealed_smooth_sphere",
            to_glb(&sealed(icosphere(3))),
            Expect::Black,
        ),
        Case::glb(
            "sealed_smooth_box",
            to_glb(&sealed(smooth_box())),
            Expect::Black,
        ),
        Case::glb(
            "camera_in_sealed_sphere",
            to_glb(&camera_in_sealed_sphere()),
            Expect::Black,
        ),
        Case::glb("sunlit", to_glb(&sunlit(false)), Expect::Finite),
        Case::glb(
            "sunlit_far_vertex",
            to_glb(&sunlit(true)),
            Expect::Twin("sunlit"),
        ),
    ]
}

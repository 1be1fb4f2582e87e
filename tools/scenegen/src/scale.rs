//! Scenes of production size for `platoon bench scale` (issue 59): millions of unique
//! triangles, a million instances of a few meshes, hundreds of large textures. Each is what a
//! user's big file stresses: the loader, the BVH build, the memory of the host and the devices.

use serde_json::{json, Value};

use crate::bench::{cornell_cut, facing};
use crate::{flat_box, glb, icosphere, to_json, uv_sphere, MeshData, NodeData, SceneData};

/// The Cornell box with every face cut into quads, as near `triangles` as 36 * cells^2 comes
/// (the scene the issue measured against Mitsuba: 3.24M triangles at 300 cells).
pub fn cut_box(triangles: usize) -> SceneData {
    let cells = ((triangles as f64 / 36.0).sqrt().round() as u32).max(1);
    cornell_cut(cells)
}

/// A deterministic stream of numbers in [0, 1) (a 64-bit LCG's top bits): the same scene on
/// every run.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// `instances` instances of three small meshes (rocks, crates, bushes: 80, 12 and 192
/// triangles) scattered on a square ground, written with EXT_mesh_gpu_instancing (one node per
/// mesh, its instances' translation, rotation and scale in the binary chunk, as exporters of
/// forests and cities write them), under a sun, three coloured point lights and an emissive
/// panel. The camera looks over the field from one corner.
pub fn instanced_field(instances: usize) -> Vec<u8> {
    let side = (instances as f64).sqrt().ceil().max(1.0) as usize;
    let spacing = 1.5f32;
    let half = side as f32 * spacing / 2.0;
    let materials = vec![
        json!({"name": "rock", "pbrMetallicRoughness": {"baseColorFactor": [0.45, 0.42, 0.4, 1], "metallicFactor": 0, "roughnessFactor": 0.9}}),
        json!({"name": "crate", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.4, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.6}}),
        json!({"name": "bush", "pbrMetallicRoughness": {"baseColorFactor": [0.15, 0.45, 0.12, 1], "metallicFactor": 0, "roughnessFactor": 0.8}}),
        json!({"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.45, 1], "metallicFactor": 0, "roughnessFactor": 1}}),
        json!({"name": "panel", "emissiveFactor": [1, 0.9, 0.7], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 6}}, "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}),
    ];
    let ground = crate::quad_from([
        [-half, 0.0, -half],
        [-half, 0.0, half],
        [half, 0.0, half],
        [half, 0.0, -half],
    ]);
    let panel = crate::quad_from([
        [-2.0, 6.0, -2.0],
        [2.0, 6.0, -2.0],
        [2.0, 6.0, 2.0],
        [-2.0, 6.0, 2.0],
    ]);
    let meshes = vec![
        (icosphere(1), 0),
        (flat_box(), 1),
        (uv_sphere(8, 13), 2),
        (ground, 3),
        (panel, 4),
    ];
    let mut nodes = vec![
        NodeData::mesh(0, [0.0; 3], 1.0),
        NodeData::mesh(1, [0.0; 3], 1.0),
        NodeData::mesh(2, [0.0; 3], 1.0),
        NodeData::mesh(3, [0.0; 3], 1.0),
        NodeData::mesh(4, [0.0; 3], 1.0),
    ];
    let lights = vec![
        json!({"type": "directional", "color": [1.0, 0.95, 0.85], "intensity": 2.5}),
        json!({"type": "point", "color": [1.0, 0.5, 0.2], "intensity": 60.0}),
        json!({"type": "point", "color": [0.3, 0.6, 1.0], "intensity": 60.0}),
        json!({"type": "point", "color": [0.9, 0.9, 0.4], "intensity": 60.0}),
    ];
    nodes.push(NodeData {
        rotation: facing([-0.5, -1.0, -0.3]),
        light: Some(0),
        ..NodeData::new()
    });
    for (k, at) in [[-4.0, 2.0, -3.0], [3.0, 2.5, 2.0], [-1.0, 1.5, 5.0]]
        .into_iter()
        .enumerate()
    {
        nodes.push(NodeData {
            translation: at,
            light: Some(k + 1),
            ..NodeData::new()
        });
    }
    let mut camera = NodeData::new();
    camera.translation = [-half as f64 * 0.9, 6.0, -half as f64 * 0.9];
    camera.rotation = facing([1.0, -0.35, 1.0]);
    camera.camera_yfov = Some(0.9);
    nodes.push(camera);
    let scene = SceneData {
        meshes,
        materials,
        nodes,
        lights,
        extensions_used: vec!["KHR_materials_emissive_strength".into()],
        images: Vec::new(),
    };
    let mut bin = Vec::new();
    let mut root = to_json(&scene, &mut bin);
    // Instance k goes to mesh k % 3, on a jittered grid, turned about y and scaled.
    let mut rng = Lcg(59);
    let mut placed: [Vec<[f32; 10]>; 3] = Default::default();
    for k in 0..instances {
        let (i, j) = (k % side, k / side);
        let x = (i as f32 + 0.5 + 0.6 * (rng.next() - 0.5)) * spacing - half;
        let z = (j as f32 + 0.5 + 0.6 * (rng.next() - 0.5)) * spacing - half;
        let (sin, cos) = (std::f32::consts::PI * rng.next()).sin_cos();
        let s = 0.25 + 0.35 * rng.next();
        placed[k % 3].push([x, s, z, 0.0, sin, 0.0, cos, s, s, s]);
    }
    for (mesh, list) in placed.iter().enumerate() {
        let attribute = |bin: &mut Vec<u8>, root: &mut Value, range: std::ops::Range<usize>| {
            let offset = bin.len();
            for v in list {
                for c in &v[range.clone()] {
                    bin.extend(c.to_le_bytes());
                }
            }
            let views = root["bufferViews"].as_array_mut().expect("views");
            views
                .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bin.len() - offset}));
            let view = views.len() - 1;
            let accessors = root["accessors"].as_array_mut().expect("accessors");
            let kind = if range.len() == 4 { "VEC4" } else { "VEC3" };
            accessors.push(json!({"bufferView": view, "componentType": 5126, "count": list.len(), "type": kind}));
            accessors.len() - 1
        };
        let t = attribute(&mut bin, &mut root, 0..3);
        let r = attribute(&mut bin, &mut root, 3..7);
        let s = attribute(&mut bin, &mut root, 7..10);
        root["nodes"][mesh]["extensions"] = json!({"EXT_mesh_gpu_instancing": {"attributes": {
            "TRANSLATION": t, "ROTATION": r, "SCALE": s}}});
    }
    root["buffers"][0]["byteLength"] = json!(bin.len());
    root["extensionsUsed"]
        .as_array_mut()
        .expect("extensions used")
        .push(json!("EXT_mesh_gpu_instancing"));
    glb(&root, &bin)
}

/// `count` unit quads in rows of 20 facing the camera, each with a material of its own whose
/// base colour is a texture of its own, `size` x `size` texels (a pattern of stripes and
/// rings in a colour of the texture's, so every texel differs from its neighbours' and no
/// texture is another's), lit by a sun and an emissive strip. With 200 textures of 2048 x 2048
/// that is 800 million texels: the scene the texture budget and mip maps are for.
pub fn textured_wall(count: usize, size: u32) -> SceneData {
    let columns = 20usize;
    let rows = count.div_ceil(columns).max(1);
    let mut meshes = Vec::new();
    let mut materials = Vec::new();
    let mut images = Vec::new();
    let mut nodes = Vec::new();
    for k in 0..count {
        let hue = k as f32 / count.max(1) as f32;
        images.push(pattern_png(size, hue, k as u32));
        materials.push(
            json!({"name": format!("tile {k}"), "pbrMetallicRoughness": {
            "baseColorTexture": {"index": k}, "metallicFactor": 0, "roughnessFactor": 0.7}}),
        );
        let (x, y) = ((k % columns) as f64 * 1.1, (k / columns) as f64 * 1.1);
        meshes.push((textured_quad(), k));
        nodes.push(NodeData::mesh(meshes.len() - 1, [x, y, 0.0], 1.0));
    }
    let width = columns as f64 * 1.1;
    let height = rows as f64 * 1.1;
    materials.push(json!({"name": "strip", "emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 3}}, "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}));
    let strip = crate::quad_from([
        [-1.0, height as f32 + 1.0, 4.0],
        [width as f32 + 1.0, height as f32 + 1.0, 4.0],
        [width as f32 + 1.0, height as f32 + 1.0, 1.0],
        [-1.0, height as f32 + 1.0, 1.0],
    ]);
    meshes.push((strip, materials.len() - 1));
    nodes.push(NodeData::mesh(meshes.len() - 1, [0.0; 3], 1.0));
    nodes.push(NodeData {
        rotation: facing([0.2, -0.5, -1.0]),
        light: Some(0),
        ..NodeData::new()
    });
    let mut camera = NodeData::new();
    camera.translation = [width / 2.0, height / 2.0, width.max(height) * 0.9];
    camera.rotation = facing([0.0, 0.0, -1.0]);
    camera.camera_yfov = Some(1.0);
    nodes.push(camera);
    SceneData {
        meshes,
        materials,
        nodes,
        lights: vec![json!({"type": "directional", "color": [1.0, 0.97, 0.92], "intensity": 2.0})],
        extensions_used: vec!["KHR_materials_emissive_strength".into()],
        images,
    }
}

/// A unit quad in the xy plane facing +z, its UVs over the whole texture.
fn textured_quad() -> MeshData {
    MeshData {
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 4],
        uvs: vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]],
        indices: vec![0, 1, 2, 0, 2, 3],
    }
}

/// A `size` x `size` RGB PNG: stripes and rings in the colour of `hue`, shifted by `seed`.
fn pattern_png(size: u32, hue: f32, seed: u32) -> Vec<u8> {
    let tau = std::f32::consts::TAU;
    let base = [
        0.5 + 0.5 * (tau * hue).cos(),
        0.5 + 0.5 * (tau * (hue + 0.33)).cos(),
        0.5 + 0.5 * (tau * (hue + 0.67)).cos(),
    ];
    let mut px = Vec::with_capacity((size * size * 3) as usize);
    let c = size as i64 / 2;
    for y in 0..size {
        for x in 0..size {
            let (dx, dy) = (x as i64 - c, y as i64 - c);
            let ring = ((dx * dx + dy * dy) as u64 / 97 + seed as u64) % 7;
            let stripe = ((x + y + seed) / 5) % 2;
            let v = 0.35 + 0.1 * ring as f32 + 0.15 * stripe as f32;
            px.extend(base.map(|b| (255.0 * (b * v).min(1.0)) as u8));
        }
    }
    let mut out = std::io::Cursor::new(Vec::new());
    let encoder = image::codecs::png::PngEncoder::new_with_quality(
        &mut out,
        image::codecs::png::CompressionType::Fast,
        image::codecs::png::FilterType::Sub,
    );
    image::ImageEncoder::write_image(encoder, &px, size, size, image::ExtendedColorType::Rgb8)
        .expect("PNG encodes");
    out.into_inner()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_scenes_hold_what_their_names_say() {
        let b = cut_box(1_000_000);
        assert!((b.triangle_count() as i64 - 1_000_000).abs() < 20_000);
        let field = instanced_field(1000);
        let json_len = u32::from_le_bytes(field[12..16].try_into().unwrap()) as usize;
        let root: Value = serde_json::from_slice(&field[20..20 + json_len]).unwrap();
        let counts: usize = (0..3)
            .map(|n| {
                let t = &root["nodes"][n]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]
                    ["TRANSLATION"];
                root["accessors"][t.as_u64().unwrap() as usize]["count"]
                    .as_u64()
                    .unwrap() as usize
            })
            .sum();
        assert_eq!(counts, 1000);
        let wall = textured_wall(3, 16);
        assert_eq!(wall.images.len(), 3);
        assert_ne!(wall.images[0], wall.images[1]);
    }
}

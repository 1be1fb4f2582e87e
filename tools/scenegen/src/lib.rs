//! Scene generators: write glTF 2.0 binaries (.glb) from code, so that test and benchmark scenes
//! are reproducible rather than hand-edited files.

use std::f32::consts::PI;

/// One mesh as flat arrays.
#[derive(Default)]
pub struct MeshData {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
}

/// UV sphere of radius 1 with 2 * rings * (segments - 1) triangles or so.
pub fn uv_sphere(rings: u32, segments: u32) -> MeshData {
    let mut m = MeshData::default();
    for r in 0..=rings {
        let theta = PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = 2.0 * PI * s as f32 / segments as f32;
            let p = [
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ];
            m.positions.push(p);
            m.normals.push(p);
        }
    }
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let (a, b, c, d) = (
                r * row + s,
                r * row + s + 1,
                (r + 1) * row + s,
                (r + 1) * row + s + 1,
            );
            if r != 0 {
                m.indices.extend([a, b, c]);
            }
            if r != rings - 1 {
                m.indices.extend([b, d, c]);
            }
        }
    }
    m
}

/// Quad in the y = 0 plane of half-size `h`, facing `ny` (+1 up, -1 down).
pub fn quad(h: f32, ny: f32) -> MeshData {
    let positions = vec![[-h, 0.0, -h], [h, 0.0, -h], [h, 0.0, h], [-h, 0.0, h]];
    let indices = if ny > 0.0 {
        vec![0, 2, 1, 0, 3, 2]
    } else {
        vec![0, 1, 2, 0, 2, 3]
    };
    MeshData {
        positions,
        normals: vec![[0.0, ny, 0.0]; 4],
        indices,
    }
}

pub struct NodeData {
    pub mesh: usize,
    pub translation: [f32; 3],
    pub scale: f32,
}

/// Material JSON objects are passed through verbatim.
pub struct SceneData {
    pub meshes: Vec<(MeshData, usize)>,
    pub materials: Vec<String>,
    pub nodes: Vec<NodeData>,
    pub extensions_used: Vec<String>,
}

fn pad4(v: &mut Vec<u8>, byte: u8) {
    while !v.len().is_multiple_of(4) {
        v.push(byte);
    }
}

/// Serialises a scene as a .glb.
pub fn to_glb(scene: &SceneData) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut meshes) = (Vec::new(), Vec::new(), Vec::new());
    for (mesh, material) in &scene.meshes {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in &mesh.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let mut view = |bin: &mut Vec<u8>, data: &[u8], target: u32| {
            let offset = bin.len();
            bin.extend_from_slice(data);
            pad4(bin, 0);
            views.push(format!(
                r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{},"target":{target}}}"#,
                data.len()
            ));
            views.len() - 1
        };
        let pos: Vec<u8> = mesh
            .positions
            .iter()
            .flatten()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        let nrm: Vec<u8> = mesh
            .normals
            .iter()
            .flatten()
            .flat_map(|f| f.to_le_bytes())
            .collect();
        let idx: Vec<u8> = mesh.indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let (vp, vn, vi) = (
            view(&mut bin, &pos, 34962),
            view(&mut bin, &nrm, 34962),
            view(&mut bin, &idx, 34963),
        );
        let n = mesh.positions.len();
        accessors.push(format!(
            r#"{{"bufferView":{vp},"componentType":5126,"count":{n},"type":"VEC3","min":[{},{},{}],"max":[{},{},{}]}}"#,
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        ));
        accessors.push(format!(
            r#"{{"bufferView":{vn},"componentType":5126,"count":{n},"type":"VEC3"}}"#
        ));
        accessors.push(format!(
            r#"{{"bufferView":{vi},"componentType":5125,"count":{},"type":"SCALAR"}}"#,
            mesh.indices.len()
        ));
        let a = accessors.len() - 3;
        meshes.push(format!(
            r#"{{"primitives":[{{"attributes":{{"POSITION":{a},"NORMAL":{}}},"indices":{},"material":{material}}}]}}"#,
            a + 1,
            a + 2
        ));
    }
    let nodes: Vec<String> = scene
        .nodes
        .iter()
        .map(|n| {
            format!(
                r#"{{"mesh":{},"translation":[{},{},{}],"scale":[{s},{s},{s}]}}"#,
                n.mesh,
                n.translation[0],
                n.translation[1],
                n.translation[2],
                s = n.scale
            )
        })
        .collect();
    let roots: Vec<String> = (0..nodes.len()).map(|i| i.to_string()).collect();
    let ext: Vec<String> = scene
        .extensions_used
        .iter()
        .map(|e| format!("\"{e}\""))
        .collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0","generator":"platoon-scenegen"}},"extensionsUsed":[{}],"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}],"meshes":[{}],"materials":[{}],"accessors":[{}],"bufferViews":[{}],"buffers":[{{"byteLength":{}}}]}}"#,
        ext.join(","),
        roots.join(","),
        nodes.join(","),
        meshes.join(","),
        scene.materials.join(","),
        accessors.join(","),
        views.join(","),
        bin.len()
    );
    let mut json = json.into_bytes();
    pad4(&mut json, b' ');
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// The benchmark scene: a `grid` x `grid` field of instanced glossy spheres (6,468 triangles
/// each) on a diffuse ground under an emissive panel. grid = 4 gives 16 x 6,468 + 4 = 103,492
/// triangles, 16 instances of one BLAS; `unique = true` makes every sphere its own mesh.
pub fn sphere_field(grid: u32, unique: bool) -> SceneData {
    let sphere_materials = [
        r#"{"name":"glossy","pbrMetallicRoughness":{"baseColorFactor":[0.8,0.3,0.2,1],"metallicFactor":0,"roughnessFactor":0.3}}"#,
        r#"{"name":"metal","pbrMetallicRoughness":{"baseColorFactor":[0.9,0.8,0.5,1],"metallicFactor":1,"roughnessFactor":0.2}}"#,
    ];
    let mut materials: Vec<String> = sphere_materials.iter().map(|s| s.to_string()).collect();
    materials.push(r#"{"name":"ground","pbrMetallicRoughness":{"baseColorFactor":[0.6,0.6,0.6,1],"metallicFactor":0,"roughnessFactor":0.9}}"#.into());
    materials.push(r#"{"name":"panel","emissiveFactor":[1,0.9,0.8],"extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":8}},"pbrMetallicRoughness":{"baseColorFactor":[0,0,0,1]}}"#.into());
    let mut meshes = vec![(quad(1.0, 1.0), 2), (quad(1.0, -1.0), 3)];
    let mut nodes = vec![
        NodeData {
            mesh: 0,
            translation: [0.0, 0.0, 0.0],
            scale: 3.0 * grid as f32,
        },
        NodeData {
            mesh: 1,
            translation: [0.0, 3.0 * grid as f32, 0.0],
            scale: 0.8 * grid as f32,
        },
    ];
    let offset = (grid as f32 - 1.0) * 1.25;
    for i in 0..grid * grid {
        let mesh = if unique || i == 0 {
            meshes.push((uv_sphere(50, 66), (i % 2) as usize));
            meshes.len() - 1
        } else {
            2
        };
        let (x, z) = (
            (i % grid) as f32 * 2.5 - offset,
            (i / grid) as f32 * 2.5 - offset,
        );
        nodes.push(NodeData {
            mesh,
            translation: [x, 1.0, z],
            scale: 1.0,
        });
    }
    SceneData {
        meshes,
        materials,
        nodes,
        extensions_used: vec!["KHR_materials_emissive_strength".into()],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_triangle_count() {
        assert_eq!(uv_sphere(48, 66).indices.len() / 3, 2 * 48 * 66 - 2 * 66);
    }

    #[test]
    fn benchmark_field_has_over_100k_triangles() {
        for unique in [false, true] {
            let field = sphere_field(4, unique);
            let tris: usize = field
                .nodes
                .iter()
                .map(|n| field.meshes[n.mesh].0.indices.len() / 3)
                .sum();
            assert_eq!(tris, 103_492);
        }
        let glb = to_glb(&sphere_field(2, true));
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(
            u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize,
            glb.len()
        );
    }
}

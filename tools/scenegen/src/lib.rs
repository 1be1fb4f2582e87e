//! Scene generators: write glTF 2.0 binaries (.glb) from code, so that test and benchmark scenes
//! are reproducible rather than hand-edited files.

use std::f32::consts::PI;

use serde_json::{json, Value};

pub mod adversarial;
pub mod atrium;
pub mod bench;
pub mod ktx2;
pub mod many_lights;
pub mod materials;
pub mod scale;
pub mod twins;

/// One mesh as flat arrays.
#[derive(Default)]
pub struct MeshData {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    /// TEXCOORD_0; empty when the mesh has none.
    pub uvs: Vec<[f32; 2]>,
    pub indices: Vec<u32>,
}

/// UV sphere of radius 1 with 2 * rings * (segments - 1) triangles or so; u runs around the
/// axis (+y), v from pole to pole.
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
            m.uvs
                .push([s as f32 / segments as f32, r as f32 / rings as f32]);
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

/// Icosphere of radius 1 with smooth normals: every vertex shared, so the mesh is closed
/// (watertight), unlike a UV sphere whose seam and poles repeat vertices with rounding.
pub fn icosphere(subdivisions: u32) -> MeshData {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut p: Vec<[f32; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .to_vec();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mid = std::collections::HashMap::new();
        let mut midpoint = |a: u32, b: u32, p: &mut Vec<[f32; 3]>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (u, v) = (p[a as usize], p[b as usize]);
                p.push([
                    (u[0] + v[0]) / 2.0,
                    (u[1] + v[1]) / 2.0,
                    (u[2] + v[2]) / 2.0,
                ]);
                p.len() as u32 - 1
            })
        };
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (
                    midpoint(a, b, &mut p),
                    midpoint(b, c, &mut p),
                    midpoint(c, a, &mut p),
                );
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let positions: Vec<[f32; 3]> = p
        .iter()
        .map(|v| {
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            [v[0] / l, v[1] / l, v[2] / l]
        })
        .collect();
    MeshData {
        normals: positions.clone(),
        positions,
        indices: tris.into_iter().flatten().collect(),
        ..Default::default()
    }
}

/// The cube [-1, 1]^3 from 8 shared corners, outward winding, with smooth normals on the
/// diagonals: interpolated normals lean far from the faces' geometric normals.
pub fn smooth_box() -> MeshData {
    let positions: Vec<[f32; 3]> = (0..8)
        .map(|i| {
            [
                (i & 1) as f32 * 2.0 - 1.0,
                ((i >> 1) & 1) as f32 * 2.0 - 1.0,
                ((i >> 2) & 1) as f32 * 2.0 - 1.0,
            ]
        })
        .collect();
    let s = 1.0 / 3f32.sqrt();
    let normals = positions
        .iter()
        .map(|p| [p[0] * s, p[1] * s, p[2] * s])
        .collect();
    // Faces as (a, b, c, d), counter-clockwise seen from outside.
    let faces = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let indices = faces
        .iter()
        .flat_map(|&[a, b, c, d]| [a, b, c, a, c, d])
        .collect();
    MeshData {
        positions,
        normals,
        indices,
        ..Default::default()
    }
}

/// The cube [-1, 1]^3 with a flat normal per face (24 corners): furniture.
pub fn flat_box() -> MeshData {
    // Each face: its normal and two in-plane axes (u x v = normal, so corners wind outward).
    let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
        ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
        ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]),
    ];
    let mut m = MeshData::default();
    for (n, u, v) in faces {
        let base = m.positions.len() as u32;
        for (a, b) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            m.positions
                .push(std::array::from_fn(|k| n[k] + a * u[k] + b * v[k]));
            m.normals.push(n);
        }
        m.indices
            .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    m
}

/// A square grid of `cells` x `cells` quads over [-1, 1]^2 in the xz plane facing +y: a floor
/// or wall with enough triangles to weigh like real architecture.
pub fn grid(cells: u32) -> MeshData {
    grid_rect(cells, cells)
}

/// A grid of `nx` x `nz` quads (at least one each way) over [-1, 1]^2 in the xz plane facing +y.
pub fn grid_rect(nx: u32, nz: u32) -> MeshData {
    let (nx, nz) = (nx.max(1), nz.max(1));
    let mut m = MeshData::default();
    for j in 0..=nz {
        for i in 0..=nx {
            let (x, z) = (
                i as f32 / nx as f32 * 2.0 - 1.0,
                j as f32 / nz as f32 * 2.0 - 1.0,
            );
            m.positions.push([x, 0.0, z]);
            m.normals.push([0.0, 1.0, 0.0]);
        }
    }
    for j in 0..nz {
        for i in 0..nx {
            let a = j * (nx + 1) + i;
            let (b, c, d) = (a + 1, a + nx + 2, a + nx + 1);
            // Counter-clockwise seen from +y.
            m.indices.extend([a, d, c, a, c, b]);
        }
    }
    m
}

/// A one-sided quad (a, b, c, d), counter-clockwise seen from the side it faces.
pub fn quad_from(corners: [[f32; 3]; 4]) -> MeshData {
    let [a, b, c, _] = corners;
    let (e1, e2) = (
        [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
        [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
    );
    let n = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    MeshData {
        positions: corners.to_vec(),
        normals: vec![[n[0] / l, n[1] / l, n[2] / l]; 4],
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Default::default()
    }
}

/// `m`, whose indices are quads written as two triangles (a, b, c) and (a, c, d) as
/// [`quad_from`] and [`flat_box`] write them, with every quad cut into `cells` x `cells` quads
/// (positions, normals and UVs interpolated bilinearly): the same surfaces with as many
/// triangles as a tessellated asset has.
pub fn cut_quads(m: &MeshData, cells: u32) -> MeshData {
    let n = cells.max(1);
    let mut out = MeshData::default();
    let lerp = |a: &[f32], b: &[f32], c: &[f32], d: &[f32], u: f32, v: f32, k: usize| {
        let ab = a[k] + (b[k] - a[k]) * u;
        let dc = d[k] + (c[k] - d[k]) * u;
        ab + (dc - ab) * v
    };
    for q in m.indices.chunks_exact(6) {
        assert!(
            q[0] == q[3] && q[2] == q[4],
            "cut_quads: indices {q:?} are not a quad (a, b, c, a, c, d)"
        );
        let [a, b, c, d] = [q[0], q[1], q[2], q[5]].map(|i| i as usize);
        let base = out.positions.len() as u32;
        for j in 0..=n {
            for i in 0..=n {
                let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                let p = &m.positions;
                out.positions.push(std::array::from_fn(|k| {
                    lerp(&p[a], &p[b], &p[c], &p[d], u, v, k)
                }));
                if !m.normals.is_empty() {
                    let s = &m.normals;
                    out.normals.push(std::array::from_fn(|k| {
                        lerp(&s[a], &s[b], &s[c], &s[d], u, v, k)
                    }));
                }
                if !m.uvs.is_empty() {
                    let t = &m.uvs;
                    out.uvs.push(std::array::from_fn(|k| {
                        lerp(&t[a], &t[b], &t[c], &t[d], u, v, k)
                    }));
                }
            }
        }
        for j in 0..n {
            for i in 0..n {
                let p = base + j * (n + 1) + i;
                let (pb, pc, pd) = (p + 1, p + n + 2, p + n + 1);
                out.indices.extend([p, pb, pc, p, pc, pd]);
            }
        }
    }
    out
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
        ..Default::default()
    }
}

/// A node: an optional mesh, camera (vertical field of view) or KHR_lights_punctual light, a
/// TRS transform (translation in f64, as a game world needs) and children.
#[derive(Clone, Debug)]
pub struct NodeData {
    pub mesh: Option<usize>,
    pub translation: [f64; 3],
    pub rotation: [f32; 4],
    pub scale: [f32; 3],
    pub children: Vec<usize>,
    pub camera_yfov: Option<f32>,
    pub light: Option<usize>,
}

impl NodeData {
    pub fn new() -> NodeData {
        NodeData {
            mesh: None,
            translation: [0.0; 3],
            rotation: [0.0, 0.0, 0.0, 1.0],
            scale: [1.0; 3],
            children: Vec::new(),
            camera_yfov: None,
            light: None,
        }
    }

    /// A node of `mesh` at `translation` with a uniform `scale`.
    pub fn mesh(mesh: usize, translation: [f64; 3], scale: f32) -> NodeData {
        NodeData {
            mesh: Some(mesh),
            translation,
            scale: [scale; 3],
            ..NodeData::new()
        }
    }
}

impl Default for NodeData {
    fn default() -> Self {
        NodeData::new()
    }
}

/// Materials and lights are glTF JSON objects, passed through verbatim. Nodes that are no
/// other node's child are the scene's roots.
#[derive(Default)]
pub struct SceneData {
    pub meshes: Vec<(MeshData, usize)>,
    pub materials: Vec<Value>,
    pub nodes: Vec<NodeData>,
    pub lights: Vec<Value>,
    pub extensions_used: Vec<String>,
    /// PNG or KTX2 images (the latter through KHR_texture_basisu), texture `i` showing image
    /// `i` (repeating, bilinear): what materials' `{"index": i}` texture infos name.
    pub images: Vec<Vec<u8>>,
}

impl SceneData {
    /// Triangles of the meshes the nodes place, each placement counted.
    pub fn triangle_count(&self) -> usize {
        self.nodes
            .iter()
            .filter_map(|n| n.mesh)
            .map(|m| self.meshes[m].0.indices.len() / 3)
            .sum()
    }
}

fn pad4(v: &mut Vec<u8>, byte: u8) {
    while !v.len().is_multiple_of(4) {
        v.push(byte);
    }
}

fn le_bytes<const N: usize>(values: impl Iterator<Item = [u8; N]>) -> Vec<u8> {
    values.flatten().collect()
}

/// The glTF JSON of a scene whose mesh data is appended to `bin`.
pub fn to_json(scene: &SceneData, bin: &mut Vec<u8>) -> Value {
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
        let mut view = |data: &[u8], target: u32| {
            let offset = bin.len();
            bin.extend_from_slice(data);
            pad4(bin, 0);
            views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len(), "target": target}));
            views.len() - 1
        };
        let pos = le_bytes(mesh.positions.iter().flatten().map(|f| f.to_le_bytes()));
        let nrm = le_bytes(mesh.normals.iter().flatten().map(|f| f.to_le_bytes()));
        let uv = le_bytes(mesh.uvs.iter().flatten().map(|f| f.to_le_bytes()));
        let idx = le_bytes(mesh.indices.iter().map(|i| i.to_le_bytes()));
        let n = mesh.positions.len();
        let vp = view(&pos, 34962);
        accessors.push(json!({"bufferView": vp, "componentType": 5126, "count": n, "type": "VEC3", "min": lo, "max": hi}));
        let mut attributes = json!({"POSITION": accessors.len() - 1});
        // Without normals the mesh is flat-shaded.
        if !mesh.normals.is_empty() {
            let vn = view(&nrm, 34962);
            accessors
                .push(json!({"bufferView": vn, "componentType": 5126, "count": n, "type": "VEC3"}));
            attributes["NORMAL"] = json!(accessors.len() - 1);
        }
        if !mesh.uvs.is_empty() {
            let vt = view(&uv, 34962);
            accessors
                .push(json!({"bufferView": vt, "componentType": 5126, "count": n, "type": "VEC2"}));
            attributes["TEXCOORD_0"] = json!(accessors.len() - 1);
        }
        let vi = view(&idx, 34963);
        accessors.push(json!({"bufferView": vi, "componentType": 5125, "count": mesh.indices.len(), "type": "SCALAR"}));
        meshes.push(json!({"primitives": [{"attributes": attributes, "indices": accessors.len() - 1, "material": material}]}));
    }
    let mut images = Vec::new();
    for file in &scene.images {
        let offset = bin.len();
        bin.extend_from_slice(file);
        pad4(bin, 0);
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": file.len()}));
        let mime = if ktx2::is_ktx2(file) {
            "image/ktx2"
        } else {
            "image/png"
        };
        images.push(json!({"bufferView": views.len() - 1, "mimeType": mime}));
    }
    let mut cameras = Vec::new();
    let nodes: Vec<Value> = scene
        .nodes
        .iter()
        .map(|n| {
            let mut node =
                json!({"translation": n.translation, "rotation": n.rotation, "scale": n.scale});
            if let Some(m) = n.mesh {
                node["mesh"] = json!(m);
            }
            if !n.children.is_empty() {
                node["children"] = json!(n.children);
            }
            if let Some(yfov) = n.camera_yfov {
                node["camera"] = json!(cameras.len());
                cameras.push(
                    json!({"type": "perspective", "perspective": {"yfov": yfov, "znear": 0.001}}),
                );
            }
            if let Some(l) = n.light {
                node["extensions"] = json!({"KHR_lights_punctual": {"light": l}});
            }
            node
        })
        .collect();
    let roots: Vec<usize> = (0..nodes.len())
        .filter(|i| !scene.nodes.iter().any(|n| n.children.contains(i)))
        .collect();
    let mut extensions_used = scene.extensions_used.clone();
    let mut root = json!({
        "asset": {"version": "2.0", "generator": "platoon-scenegen"},
        "scene": 0,
        "scenes": [{"nodes": roots}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": scene.materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}],
    });
    if !cameras.is_empty() {
        root["cameras"] = json!(cameras);
    }
    let mut extensions_required = Vec::new();
    if !images.is_empty() {
        // A KTX2 image through KHR_texture_basisu, without a fallback: the extension is then
        // required.
        let textures: Vec<Value> = (0..images.len())
            .map(|i| match ktx2::is_ktx2(&scene.images[i]) {
                true => json!({"extensions": {"KHR_texture_basisu": {"source": i}}, "sampler": 0}),
                false => json!({"source": i, "sampler": 0}),
            })
            .collect();
        if scene.images.iter().any(|f| ktx2::is_ktx2(f)) {
            extensions_used.push("KHR_texture_basisu".to_string());
            extensions_required.push("KHR_texture_basisu".to_string());
        }
        root["images"] = json!(images);
        root["textures"] = json!(textures);
        // REPEAT both ways, bilinear.
        root["samplers"] =
            json!([{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}]);
    }
    if !scene.lights.is_empty() {
        root["extensions"] = json!({"KHR_lights_punctual": {"lights": scene.lights}});
        extensions_used.push("KHR_lights_punctual".into());
    }
    if !extensions_used.is_empty() {
        root["extensionsUsed"] = json!(extensions_used);
    }
    if !extensions_required.is_empty() {
        root["extensionsRequired"] = json!(extensions_required);
    }
    root
}

/// Packs glTF JSON and its binary chunk as a .glb.
pub fn glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut json = serde_json::to_vec(json).expect("JSON values serialise");
    pad4(&mut json, b' ');
    let mut bin = bin.to_vec();
    pad4(&mut bin, 0);
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

/// Serialises a scene as a .glb.
pub fn to_glb(scene: &SceneData) -> Vec<u8> {
    let mut bin = Vec::new();
    let json = to_json(scene, &mut bin);
    glb(&json, &bin)
}

/// The benchmark scene: a `grid` x `grid` field of instanced glossy spheres (6,468 triangles
/// each) on a diffuse ground under an emissive panel. grid = 4 gives 16 x 6,468 + 4 = 103,492
/// triangles, 16 instances of one BLAS; `unique = true` makes every sphere its own mesh.
pub fn sphere_field(grid: u32, unique: bool) -> SceneData {
    let materials = vec![
        json!({"name": "glossy", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.3}}),
        json!({"name": "metal", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.5, 1], "metallicFactor": 1, "roughnessFactor": 0.2}}),
        json!({"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0, "roughnessFactor": 0.9}}),
        json!({"name": "panel", "emissiveFactor": [1, 0.9, 0.8], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8}}, "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}),
    ];
    let mut meshes = vec![(quad(1.0, 1.0), 2), (quad(1.0, -1.0), 3)];
    let mut nodes = vec![
        NodeData::mesh(0, [0.0; 3], 3.0 * grid as f32),
        NodeData::mesh(1, [0.0, 3.0 * grid as f64, 0.0], 0.8 * grid as f32),
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
        nodes.push(NodeData::mesh(mesh, [x as f64, 1.0, z as f64], 1.0));
    }
    SceneData {
        meshes,
        materials,
        nodes,
        extensions_used: vec!["KHR_materials_emissive_strength".into()],
        ..Default::default()
    }
}

/// The trade-off tool's glossy-and-glass scene: a smooth glass sphere (caustics that only
/// BSDF sampling finds), a rough glass one, a polished and a brushed metal sphere and a diffuse
/// one on a diffuse floor before a wall, lit by a small bright panel above.
pub fn glossy_glass() -> SceneData {
    let materials = vec![
        json!({"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1], "metallicFactor": 0, "roughnessFactor": 0.9}}),
        json!({"name": "wall", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.55, 0.7, 1], "metallicFactor": 0, "roughnessFactor": 1}}),
        json!({"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": 0},
               "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.5}}}),
        json!({"name": "frosted", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 1, 0.95, 1], "metallicFactor": 0, "roughnessFactor": 0.3},
               "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.5}}}),
        json!({"name": "polished", "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.8, 0.5, 1], "metallicFactor": 1, "roughnessFactor": 0.05}}),
        json!({"name": "brushed", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.85, 1], "metallicFactor": 1, "roughnessFactor": 0.35}}),
        json!({"name": "diffuse", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.25, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.6}}),
        json!({"name": "panel", "emissiveFactor": [1, 0.95, 0.9], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 30}}, "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}}),
    ];
    let wall = quad_from([
        [-6.0, 0.0, -3.0],
        [6.0, 0.0, -3.0],
        [6.0, 6.0, -3.0],
        [-6.0, 6.0, -3.0],
    ]);
    let mut meshes = vec![(quad(1.0, 1.0), 0), (wall, 1), (quad(1.0, -1.0), 7)];
    let mut nodes = vec![
        NodeData::mesh(0, [0.0; 3], 6.0),
        NodeData::mesh(1, [0.0; 3], 1.0),
        NodeData::mesh(2, [0.0, 5.0, 0.5], 0.6),
    ];
    for (k, (material, x)) in [(2usize, -3.0f64), (3, -1.5), (4, 0.0), (5, 1.5), (6, 3.0)]
        .into_iter()
        .enumerate()
    {
        meshes.push((icosphere(4), material));
        nodes.push(NodeData::mesh(k + 3, [x, 0.65, 0.0], 0.65));
    }
    let mut camera = NodeData::new();
    camera.translation = [0.0, 2.2, 7.5];
    // Tilted down by 10 degrees about x.
    let half = (-10.0f32).to_radians() / 2.0;
    camera.rotation = [half.sin(), 0.0, 0.0, half.cos()];
    camera.camera_yfov = Some(0.7);
    nodes.push(camera);
    SceneData {
        meshes,
        materials,
        nodes,
        extensions_used: vec![
            "KHR_materials_emissive_strength".into(),
            "KHR_materials_transmission".into(),
            "KHR_materials_ior".into(),
        ],
        ..Default::default()
    }
}

/// The IGI scene (issue 11, after Marques and Santos' conference room): a 12 x 3 x 8 m room
/// of tessellated walls, floor and ceiling, a long table with twelve chairs, a whiteboard, a
/// row of vases along the walls, lit by four point lights under the ceiling; all diffuse, about
/// 130k triangles.
pub fn conference_room() -> SceneData {
    let materials = vec![
        json!({"name": "walls", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.72, 0.65, 1], "metallicFactor": 0, "roughnessFactor": 1}}),
        json!({"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.25, 0.18, 1], "metallicFactor": 0, "roughnessFactor": 0.9}}),
        json!({"name": "ceiling", "pbrMetallicRoughness": {"baseColorFactor": [0.85, 0.85, 0.85, 1], "metallicFactor": 0, "roughnessFactor": 1}}),
        json!({"name": "table", "pbrMetallicRoughness": {"baseColorFactor": [0.45, 0.3, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 0.8}}),
        json!({"name": "chairs", "pbrMetallicRoughness": {"baseColorFactor": [0.15, 0.25, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 1}}),
        json!({"name": "board", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1], "metallicFactor": 0, "roughnessFactor": 0.7}}),
        json!({"name": "vases", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.3, 0.2, 1], "metallicFactor": 0, "roughnessFactor": 1}}),
    ];
    let (w, h, d) = (6.0f64, 3.0f64, 4.0f64); // half width, height, half depth
    let mut meshes: Vec<(MeshData, usize)> = Vec::new();
    let mut nodes: Vec<NodeData> = Vec::new();
    let mut place =
        |mesh: MeshData, material: usize, at: [f64; 3], rotation: [f32; 4], scale: [f32; 3]| {
            meshes.push((mesh, material));
            nodes.push(NodeData {
                mesh: Some(meshes.len() - 1),
                translation: at,
                rotation,
                scale,
                ..NodeData::new()
            });
        };
    let turn = |axis: usize, degrees: f32| -> [f32; 4] {
        let (s, c) = (degrees.to_radians() / 2.0).sin_cos();
        let mut q = [0.0, 0.0, 0.0, c];
        q[axis] = s;
        q
    };
    let id = [0.0, 0.0, 0.0, 1.0];
    // Floor (facing up), ceiling (down), four walls (inward), each a tessellated grid.
    place(grid(96), 1, [0.0, 0.0, 0.0], id, [w as f32, 1.0, d as f32]);
    place(
        grid(96),
        2,
        [0.0, h, 0.0],
        turn(0, 180.0),
        [w as f32, 1.0, d as f32],
    );
    place(
        grid(64),
        0,
        [0.0, h / 2.0, -d],
        turn(0, 90.0),
        [w as f32, 1.0, (h / 2.0) as f32],
    );
    place(
        grid(64),
        0,
        [0.0, h / 2.0, d],
        turn(0, -90.0),
        [w as f32, 1.0, (h / 2.0) as f32],
    );
    place(
        grid(64),
        0,
        [-w, h / 2.0, 0.0],
        turn(2, -90.0),
        [(h / 2.0) as f32, 1.0, d as f32],
    );
    place(
        grid(64),
        0,
        [w, h / 2.0, 0.0],
        turn(2, 90.0),
        [(h / 2.0) as f32, 1.0, d as f32],
    );
    // The table: top and four legs.
    place(flat_box(), 3, [0.0, 0.75, 0.0], id, [3.0, 0.03, 1.0]);
    for (x, z) in [(-2.8, -0.8), (2.8, -0.8), (-2.8, 0.8), (2.8, 0.8)] {
        place(flat_box(), 3, [x, 0.36, z], id, [0.05, 0.36, 0.05]);
    }
    // Twelve chairs: seat, back, four legs each.
    for k in 0..12 {
        let side = if k < 6 { -1.0 } else { 1.0 };
        let x = -2.5 + (k % 6) as f64 * 1.0;
        let z = side * 1.5;
        place(flat_box(), 4, [x, 0.45, z], id, [0.22, 0.03, 0.22]);
        place(
            flat_box(),
            4,
            [x, 0.75, z + side * 0.2],
            id,
            [0.22, 0.3, 0.03],
        );
        for (dx, dz) in [(-0.18, -0.18), (0.18, -0.18), (-0.18, 0.18), (0.18, 0.18)] {
            place(
                flat_box(),
                4,
                [x + dx, 0.22, z + dz],
                id,
                [0.02, 0.22, 0.02],
            );
        }
    }
    // A whiteboard on the far wall.
    place(flat_box(), 5, [0.0, 1.6, -d + 0.03], id, [2.0, 0.6, 0.02]);
    // Vases along the side walls (the bulk of the triangles, as their furniture was).
    for k in 0..16 {
        let x = -5.0 + (k % 8) as f64 * (10.0 / 7.0);
        let z = if k < 8 { -d + 0.4 } else { d - 0.4 };
        place(icosphere(4), 6, [x, 0.3, z], id, [0.25, 0.3, 0.25]);
    }
    // Four point lights under the ceiling, above the table.
    let lights: Vec<Value> = (0..4)
        .map(|_| json!({"type": "point", "color": [1.0, 0.92, 0.8], "intensity": 5.0}))
        .collect();
    for (k, x) in [-4.0, -1.35, 1.35, 4.0].into_iter().enumerate() {
        nodes.push(NodeData {
            translation: [x, h - 0.3, 0.0],
            light: Some(k),
            ..NodeData::new()
        });
    }
    let mut camera = NodeData::new();
    camera.translation = [-5.3, 1.7, 3.4];
    // Looking along the room towards its far corner: turned about y, tilted down a little.
    camera.rotation = bench::turned(-50.0, -12.0);
    camera.camera_yfov = Some(1.0);
    nodes.push(camera);
    SceneData {
        meshes,
        materials,
        nodes,
        lights,
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_is_closed() {
        let m = icosphere(2);
        assert_eq!(m.indices.len() / 3, 320);
        // Closed: every edge is used exactly twice, once in each direction.
        let mut edges = std::collections::HashMap::new();
        for t in m.indices.chunks(3) {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        assert!(edges
            .iter()
            .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1)));
    }

    #[test]
    fn the_glossy_glass_scene_has_its_five_spheres_a_light_and_a_camera() {
        let g = glossy_glass();
        assert_eq!(g.meshes.len(), 8);
        assert_eq!(
            g.nodes.iter().filter(|n| n.camera_yfov.is_some()).count(),
            1
        );
        let glass = g
            .materials
            .iter()
            .filter(|m| m["extensions"]["KHR_materials_transmission"]["transmissionFactor"] == 1);
        assert_eq!(glass.count(), 2);
        assert!(g.extensions_used.iter().any(|e| e == "KHR_materials_ior"));
        // It serialises to a glb (platoon loads and sweeps it in tests/lab/tradeoff.rs).
        assert!(to_glb(&g).starts_with(b"glTF"));
    }

    #[test]
    fn the_conference_room_is_big_diffuse_and_lit_by_points() {
        let room = conference_room();
        let tris = room.triangle_count();
        assert!((100_000..300_000).contains(&tris), "{tris} triangles");
        assert_eq!(room.lights.len(), 4);
        assert!(room.lights.iter().all(|l| l["type"] == "point"));
        // Mostly diffuse: no metal, no transmission.
        assert!(room
            .materials
            .iter()
            .all(|m| m["pbrMetallicRoughness"]["metallicFactor"] == 0
                && m.get("extensions").is_none()));
        let b = flat_box();
        assert_eq!((b.positions.len(), b.indices.len()), (24, 36));
        // Flat faces: every corner's normal is its face's, and each face winds outward.
        for t in b.indices.chunks(3) {
            let [p0, p1, p2] = [t[0], t[1], t[2]].map(|i| b.positions[i as usize]);
            let e1 = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
            let e2 = [p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]];
            let n = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            let s = b.normals[t[0] as usize];
            assert!(n[0] * s[0] + n[1] * s[1] + n[2] * s[2] > 0.0);
        }
        assert_eq!(grid(4).indices.len() / 3, 32);
    }

    #[test]
    fn sphere_triangle_count() {
        assert_eq!(uv_sphere(48, 66).indices.len() / 3, 2 * 48 * 66 - 2 * 66);
    }

    #[test]
    fn benchmark_field_has_over_100k_triangles() {
        for unique in [false, true] {
            let field = sphere_field(4, unique);
            assert!(field.nodes.iter().all(|n| n.mesh.is_some()));
            assert_eq!(field.triangle_count(), 103_492);
        }
        let glb = to_glb(&sphere_field(2, true));
        assert_eq!(&glb[..4], b"glTF");
        assert_eq!(
            u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize,
            glb.len()
        );
    }
}

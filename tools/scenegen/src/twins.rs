//! Twin scenes: pairs of glTF files that write the same scene two ways, one with a glTF feature
//! (a triangle strip, vertex colours, a second UV set, a texture transform, quantized
//! attributes, a WebP image) and one without it. A renderer that implements the feature as the
//! specification defines it renders both alike; that, not a viewer's screenshot, is the reference.
//!
//! Every twin is a small scene seen by a camera at (0, 0, 3) looking down -Z (yfov 0.8) at a
//! surface in the z = 0 plane within [-1, 1]^2, with no lights: the test chooses the sky.

use serde_json::{json, Value};

use crate::glb;

/// A glTF document under construction: accessors over one binary buffer.
#[derive(Default)]
pub struct Doc {
    pub bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    images: Vec<Value>,
}

/// glTF component types.
pub const BYTE: u32 = 5120;
pub const UNSIGNED_BYTE: u32 = 5121;
pub const SHORT: u32 = 5122;
pub const UNSIGNED_SHORT: u32 = 5123;
pub const UNSIGNED_INT: u32 = 5125;
pub const FLOAT: u32 = 5126;

fn type_name(n: usize) -> &'static str {
    ["SCALAR", "VEC2", "VEC3", "VEC4"][n - 1]
}

impl Doc {
    fn view(&mut self, data: &[u8], stride: Option<usize>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": data.len()});
        if let Some(s) = stride {
            view["byteStride"] = json!(s);
        }
        self.bin.extend_from_slice(data);
        self.views.push(view);
        self.views.len() - 1
    }

    /// An accessor of `values` (N components each) stored as `component` (normalized when asked),
    /// each element padded to 4 bytes as the spec requires of vertex attributes.
    pub fn accessor<const N: usize>(
        &mut self,
        values: &[[f64; N]],
        component: u32,
        normalized: bool,
    ) -> usize {
        let size = match component {
            BYTE | UNSIGNED_BYTE => 1,
            SHORT | UNSIGNED_SHORT => 2,
            _ => 4,
        };
        let stride = (N * size).next_multiple_of(4);
        let mut data = Vec::with_capacity(values.len() * stride);
        for v in values {
            let start = data.len();
            for &c in v {
                match component {
                    BYTE => data.push(c as i8 as u8),
                    UNSIGNED_BYTE => data.push(c as u8),
                    SHORT => data.extend((c as i16).to_le_bytes()),
                    UNSIGNED_SHORT => data.extend((c as u16).to_le_bytes()),
                    UNSIGNED_INT => data.extend((c as u32).to_le_bytes()),
                    _ => data.extend((c as f32).to_le_bytes()),
                }
            }
            data.resize(start + stride, 0);
        }
        let view = self.view(&data, (N > 1).then_some(stride));
        let mut lo = [f64::INFINITY; N];
        let mut hi = [f64::NEG_INFINITY; N];
        for v in values {
            for k in 0..N {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        let mut a = json!({"bufferView": view, "componentType": component, "count": values.len(),
            "type": type_name(N), "min": lo.to_vec(), "max": hi.to_vec()});
        if normalized {
            a["normalized"] = json!(true);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    pub fn floats<const N: usize>(&mut self, values: &[[f32; N]]) -> usize {
        let wide: Vec<[f64; N]> = values.iter().map(|v| v.map(f64::from)).collect();
        self.accessor(&wide, FLOAT, false)
    }

    pub fn indices(&mut self, indices: &[u32]) -> usize {
        let data: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&data, None);
        self.accessors
            .push(json!({"bufferView": view, "componentType": UNSIGNED_INT,
            "count": indices.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// An image stored in the buffer (`mime`: image/png, image/webp).
    pub fn image(&mut self, encoded: &[u8], mime: &str) -> usize {
        let view = self.view(encoded, None);
        self.images
            .push(json!({"bufferView": view, "mimeType": mime}));
        self.images.len() - 1
    }

    /// The .glb of a scene of `meshes` (each a list of primitives, one node each, placed by
    /// `mesh_nodes`' TRS objects) seen from the twins' camera; `extra` is merged into the root.
    pub fn glb(self, meshes: Vec<Value>, mesh_nodes: Vec<Value>, extra: Value) -> Vec<u8> {
        self.glb_seen_from([0.0, 0.0, 3.0], meshes, mesh_nodes, extra)
    }

    /// [`Doc::glb`] with the camera at `eye` (still looking down -Z).
    pub fn glb_seen_from(
        mut self,
        eye: [f64; 3],
        meshes: Vec<Value>,
        mesh_nodes: Vec<Value>,
        extra: Value,
    ) -> Vec<u8> {
        let mut nodes = vec![json!({"camera": 0, "translation": eye})];
        for (i, mut n) in mesh_nodes.into_iter().enumerate() {
            n["mesh"] = json!(i);
            nodes.push(n);
        }
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut root = json!({
            "asset": {"version": "2.0", "generator": "platoon-scenegen twins"},
            "scene": 0,
            "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
            "nodes": nodes,
            "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.001}}],
            "meshes": meshes.into_iter().map(|p| json!({"primitives": p})).collect::<Vec<_>>(),
            "accessors": self.accessors,
            "bufferViews": self.views,
            "buffers": [{"byteLength": self.bin.len()}],
        });
        if !self.images.is_empty() {
            root["images"] = json!(self.images);
        }
        if let (Some(root), Value::Object(extra)) = (root.as_object_mut(), extra) {
            root.extend(extra);
        }
        glb(&root, &self.bin)
    }
}

/// An (n + 1) x (n + 1) vertex grid over [-1, 1]^2 at z = 0 with a height bump, so that its
/// triangles face different ways (row-major vertices).
pub fn bumpy_grid(n: usize) -> Vec<[f32; 3]> {
    let mut v = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (
                2.0 * i as f32 / n as f32 - 1.0,
                2.0 * j as f32 / n as f32 - 1.0,
            );
            v.push([x, y, 0.3 * (3.0 * x).sin() * (2.0 * y).cos()]);
        }
    }
    v
}

/// The triangles of [`bumpy_grid`]`(n)`, two per cell, counter-clockwise seen from +z.
pub fn grid_indices(n: usize) -> Vec<u32> {
    let mut indices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = (j * (n + 1) + i) as u32;
            let c = a + (n + 1) as u32;
            indices.extend([a, a + 1, c + 1, a, c + 1, c]);
        }
    }
    indices
}

/// A grey single-sided material, so that a triangle's winding shows.
fn grey() -> Value {
    json!({"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.5, 0.4, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.5}})
}

/// TRIANGLE_STRIP and TRIANGLE_FAN: a bumpy grid as one strip per row of cells and a bumpy
/// disc as a fan, against the same triangles listed with the winding of glTF 2.0 section 3.7.2.1.
pub fn strips_and_fans() -> (Vec<u8>, Vec<u8>) {
    let n = 6;
    let grid = bumpy_grid(n);
    let strips: Vec<Vec<u32>> = (0..n)
        .map(|j| {
            (0..=n)
                .flat_map(|i| [(j * (n + 1) + i) as u32, ((j + 1) * (n + 1) + i) as u32])
                .collect()
        })
        .collect();
    let mut disc = vec![[0.0, 0.0, 0.5f32]];
    for k in 0..=12 {
        let a = k as f32 / 12.0 * std::f32::consts::TAU;
        disc.push([0.4 * a.cos(), 0.4 * a.sin(), 0.2 + 0.1 * (3.0 * a).sin()]);
    }
    let fan: Vec<u32> = (0..disc.len() as u32).collect();
    let strip_list = |v: &[u32]| -> Vec<u32> {
        (0..v.len() - 2)
            .flat_map(|i| [v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]])
            .collect()
    };
    let fan_list = |v: &[u32]| -> Vec<u32> {
        (0..v.len() - 2)
            .flat_map(|i| [v[i + 1], v[i + 2], v[0]])
            .collect()
    };
    let write = |listed: bool| {
        let mut doc = Doc::default();
        let grid_pos = doc.floats(&grid);
        let disc_pos = doc.floats(&disc);
        let mut grid_prims = Vec::new();
        for s in &strips {
            let (indices, mode) = if listed {
                (strip_list(s), 4)
            } else {
                (s.clone(), 5)
            };
            let i = doc.indices(&indices);
            grid_prims.push(json!({"attributes": {"POSITION": grid_pos}, "indices": i, "mode": mode, "material": 0}));
        }
        let (indices, mode) = if listed {
            (fan_list(&fan), 4)
        } else {
            (fan.clone(), 6)
        };
        let i = doc.indices(&indices);
        let disc_prims = vec![
            json!({"attributes": {"POSITION": disc_pos}, "indices": i, "mode": mode, "material": 0}),
        ];
        doc.glb(
            vec![json!(grid_prims), json!(disc_prims)],
            vec![json!({}), json!({})],
            json!({"materials": [grey()]}),
        )
    };
    (write(false), write(true))
}

/// Positions, normals, UVs and indices of a mesh.
pub type Arrays = (Vec<[f32; 3]>, Vec<[f32; 3]>, Vec<[f32; 2]>, Vec<u32>);

/// A flat quad over [-1, 1]^2 facing +Z: positions, normals, UVs (v down, as glTF's) and indices.
pub fn quad() -> Arrays {
    (
        vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        vec![[0.0, 0.0, 1.0]; 4],
        vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]],
        vec![0, 1, 2, 0, 2, 3],
    )
}

/// The same file with its `asset.version` replaced (a 1.0 or 3.0 asset must be refused).
pub fn with_version(version: &str) -> Vec<u8> {
    let (p, n, _, i) = quad();
    let mut doc = Doc::default();
    let (p, n, i) = (doc.floats(&p), doc.floats(&n), doc.indices(&i));
    let prims = vec![json!({"attributes": {"POSITION": p, "NORMAL": n}, "indices": i})];
    let mut root_extra = json!({});
    root_extra["asset"] = json!({"version": version});
    doc.glb(vec![json!(prims)], vec![json!({})], root_extra)
}

/// A PNG of `w` x `h` RGBA8 pixels.
pub fn png(w: u32, h: u32, pixels: Vec<u8>) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    image::RgbaImage::from_raw(w, h, pixels)
        .expect("w * h * 4 bytes")
        .write_to(&mut out, image::ImageFormat::Png)
        .expect("PNG encodes");
    out.into_inner()
}

/// A 4 x 4 checker of two colours (RGBA8).
pub fn checker() -> (u32, u32, Vec<u8>) {
    let mut px = Vec::new();
    for y in 0..4 {
        for x in 0..4 {
            let c: [u8; 4] = if (x + y) % 2 == 0 {
                [230, 40, 30, 255]
            } else {
                [20, 90, 220, 255]
            };
            px.extend(c);
        }
    }
    (4, 4, px)
}

/// A textured quad as a .gltf whose buffer and image are files beside it: (the JSON, the files
/// it names as (relative path, bytes)): `scene.bin` and `textures/checker.png`.
pub fn with_separate_files() -> (String, Vec<(String, Vec<u8>)>) {
    let (p, n, uv, i) = quad();
    let mut doc = Doc::default();
    let (p, n, uv, i) = (
        doc.floats(&p),
        doc.floats(&n),
        doc.floats(&uv),
        doc.indices(&i),
    );
    let (w, h, px) = checker();
    let prims = vec![
        json!({"attributes": {"POSITION": p, "NORMAL": n, "TEXCOORD_0": uv}, "indices": i, "material": 0}),
    ];
    let glb_bytes = doc.glb(
        vec![json!(prims)],
        vec![json!({})],
        json!({
            "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}}],
            "textures": [{"source": 0}],
            "images": [{"uri": "textures/checker.png"}],
        }),
    );
    let (mut root, bin) = split_glb(&glb_bytes);
    root["buffers"][0]["uri"] = json!("scene.bin");
    let json = serde_json::to_string_pretty(&root).expect("JSON serialises");
    (
        json,
        vec![
            ("scene.bin".into(), bin),
            ("textures/checker.png".into(), png(w, h, px)),
        ],
    )
}

/// Writes the [`with_separate_files`] scene under `root` as `scene/scene.gltf` (with
/// `scene/scene.bin` and `scene/textures/checker.png`), beside an empty folder `other/` and a
/// symlink `link` to `scene/`: every way a user names a scene. Returns `scene/`.
pub fn write_scene_folders(root: &std::path::Path) -> std::io::Result<std::path::PathBuf> {
    let scene_dir = root.join("scene");
    std::fs::create_dir_all(scene_dir.join("textures"))?;
    std::fs::create_dir_all(root.join("other"))?;
    let (json, files) = with_separate_files();
    std::fs::write(scene_dir.join("scene.gltf"), json)?;
    for (name, bytes) in files {
        std::fs::write(scene_dir.join(name), bytes)?;
    }
    std::os::unix::fs::symlink(&scene_dir, root.join("link"))?;
    Ok(scene_dir)
}

/// The JSON and the binary chunk of a .glb written by [`glb`].
pub fn split_glb(bytes: &[u8]) -> (Value, Vec<u8>) {
    let u32_at =
        |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().expect("4 bytes")) as usize;
    let json_len = u32_at(12);
    let json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).expect("the GLB's JSON");
    let bin_start = 20 + json_len + 8;
    let bin_len = u32_at(20 + json_len);
    (json, bytes[bin_start..bin_start + bin_len].to_vec())
}

/// A .glb of `bytes` (one [`glb`] wrote) with its JSON changed by `edit`: a file made bad in
/// one place, for the loader's errors.
pub fn edited_glb(bytes: &[u8], edit: impl FnOnce(&mut Value)) -> Vec<u8> {
    let (mut json, bin) = split_glb(bytes);
    edit(&mut json);
    glb(&json, &bin)
}

/// A closed 2-unit room, [-1, 1]^3 with inward faces and an emissive ceiling, whose vertices an
/// exporter baked at `offset` (added to every coordinate in f64, then stored as f32: exact for
/// these corners up to 1.6e7), seen from inside (the camera at offset + (0, 0, 0.9)).
pub fn baked_room(offset: f64) -> Vec<u8> {
    let c = |x: f64, y: f64, z: f64| {
        [
            (x + offset) as f32,
            (y + offset) as f32,
            (z + offset) as f32,
        ]
    };
    // Each face: four corners counter-clockwise seen from outside the room.
    let faces = [
        [
            c(-1., -1., -1.),
            c(1., -1., -1.),
            c(1., -1., 1.),
            c(-1., -1., 1.),
        ], // floor
        [
            c(-1., 1., -1.),
            c(-1., 1., 1.),
            c(1., 1., 1.),
            c(1., 1., -1.),
        ], // ceiling
        [
            c(-1., -1., -1.),
            c(-1., 1., -1.),
            c(1., 1., -1.),
            c(1., -1., -1.),
        ], // back
        [
            c(-1., -1., 1.),
            c(1., -1., 1.),
            c(1., 1., 1.),
            c(-1., 1., 1.),
        ], // front
        [
            c(-1., -1., -1.),
            c(-1., -1., 1.),
            c(-1., 1., 1.),
            c(-1., 1., -1.),
        ], // left
        [
            c(1., -1., -1.),
            c(1., 1., -1.),
            c(1., 1., 1.),
            c(1., -1., 1.),
        ], // right
    ];
    let mut doc = Doc::default();
    let mut prims = Vec::new();
    for (k, f) in faces.iter().enumerate() {
        let p = doc.floats(f);
        // The corners run clockwise seen from inside: the faces' fronts face into the room.
        let i = doc.indices(&[0, 2, 1, 0, 3, 2]);
        let material = match k {
            1 => 1,
            4 => 2,
            _ => 0,
        };
        prims.push(json!({"attributes": {"POSITION": p}, "indices": i, "material": material}));
    }
    doc.glb_seen_from(
        [offset, offset, offset + 0.9],
        vec![json!(prims)],
        vec![json!({})],
        json!({"materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.6}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0], "metallicFactor": 0.0}, "emissiveFactor": [1.0, 1.0, 1.0]},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.2, 1.0], "metallicFactor": 0.3, "roughnessFactor": 0.3}},
        ]}),
    )
}

/// A 4 x 4 texture whose every texel differs (so a flipped, shifted or rotated lookup shows).
pub fn map_texture() -> (u32, u32, Vec<u8>) {
    let mut px = Vec::new();
    for y in 0..4u8 {
        for x in 0..4u8 {
            px.extend([40 + 60 * x, 30 + 50 * y, 200 - 40 * x + 10 * y, 255]);
        }
    }
    (4, 4, px)
}

/// A material JSON whose base colour is texture 0 read through `texture_info` (an object with
/// at least "index"), with a sampler that repeats.
fn textured(texture_info: Value) -> Value {
    json!({"pbrMetallicRoughness": {"baseColorTexture": texture_info, "metallicFactor": 0.0, "roughnessFactor": 0.7}})
}

fn texture_root(image: usize, materials: Value, extensions_used: &[&str]) -> Value {
    let mut root = json!({
        "materials": materials,
        "textures": [{"source": image, "sampler": 0}],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}],
    });
    if !extensions_used.is_empty() {
        root["extensionsUsed"] = json!(extensions_used);
    }
    root
}

/// A quad of grid cells whose UVs are `uv` of each vertex, with TEXCOORD_0 set to `uv0` and
/// TEXCOORD_1 (when given) to `uv1`.
fn uv_quad(doc: &mut Doc, uv0: &[[f32; 2]], uv1: Option<&[[f32; 2]]>, material: usize) -> Value {
    let (p, n, _, i) = quad();
    let (p, n, i) = (doc.floats(&p), doc.floats(&n), doc.indices(&i));
    let mut attributes = json!({"POSITION": p, "NORMAL": n, "TEXCOORD_0": doc.floats(uv0)});
    if let Some(uv1) = uv1 {
        attributes["TEXCOORD_1"] = json!(doc.floats(uv1));
    }
    json!([{"attributes": attributes, "indices": i, "material": material}])
}

/// COLOR_0 of a constant colour, stored as `component` (FLOAT RGB, or normalized UNSIGNED_BYTE
/// or UNSIGNED_SHORT RGBA), against the same colour as baseColorFactor.
pub fn vertex_colors(component: u32) -> (Vec<u8>, Vec<u8>) {
    let colour = [0.8f64, 0.4, 0.2];
    let write = |with_colors: bool| {
        let mut doc = Doc::default();
        let (p, n, _, i) = quad();
        let (p, n, i) = (doc.floats(&p), doc.floats(&n), doc.indices(&i));
        let mut attributes = json!({"POSITION": p, "NORMAL": n});
        let factor = if with_colors {
            let c = match component {
                FLOAT => doc.accessor(&[colour.map(f64::from); 4], FLOAT, false),
                UNSIGNED_BYTE => {
                    let q = colour.map(|c| (c * 255.0).round());
                    doc.accessor(&[[q[0], q[1], q[2], 255.0]; 4], UNSIGNED_BYTE, true)
                }
                _ => {
                    let q = colour.map(|c| (c * 65535.0).round());
                    doc.accessor(&[[q[0], q[1], q[2], 65535.0]; 4], UNSIGNED_SHORT, true)
                }
            };
            attributes["COLOR_0"] = json!(c);
            [1.0, 1.0, 1.0, 1.0]
        } else {
            [colour[0], colour[1], colour[2], 1.0]
        };
        let prims = vec![json!({"attributes": attributes, "indices": i, "material": 0})];
        doc.glb(
            vec![json!(prims)],
            vec![json!({})],
            json!({"materials": [{"pbrMetallicRoughness": {"baseColorFactor": factor, "metallicFactor": 0.0}}]}),
        )
    };
    (write(true), write(false))
}

/// KHR_texture_transform (offset, rotation, scale, and a texCoord override onto TEXCOORD_1,
/// with TEXCOORD_0 left at zero) against TEXCOORD_0 holding the UVs already transformed.
pub fn texture_transform() -> (Vec<u8>, Vec<u8>) {
    let (offset, rotation, scale) = ([0.1f32, -0.2], 0.3f32, [1.5f32, 0.8]);
    let (_, _, uv, _) = quad();
    let (s, c) = rotation.sin_cos();
    let transformed: Vec<[f32; 2]> = uv
        .iter()
        .map(|[u, v]| {
            let (u, v) = (u * scale[0], v * scale[1]);
            [c * u + s * v + offset[0], -s * u + c * v + offset[1]]
        })
        .collect();
    let (w, h, px) = map_texture();
    let image = png(w, h, px);
    let with = {
        let mut doc = Doc::default();
        let zeros = vec![[0.0f32; 2]; uv.len()];
        let prims = uv_quad(&mut doc, &zeros, Some(&uv), 0);
        let img = doc.image(&image, "image/png");
        let info = json!({"index": 0, "extensions": {"KHR_texture_transform":
            {"offset": offset, "rotation": rotation, "scale": scale, "texCoord": 1}}});
        doc.glb(
            vec![prims],
            vec![json!({})],
            texture_root(img, json!([textured(info)]), &["KHR_texture_transform"]),
        )
    };
    let without = {
        let mut doc = Doc::default();
        let prims = uv_quad(&mut doc, &transformed, None, 0);
        let img = doc.image(&image, "image/png");
        doc.glb(
            vec![prims],
            vec![json!({})],
            texture_root(img, json!([textured(json!({"index": 0}))]), &[]),
        )
    };
    (with, without)
}

/// KHR_materials_pbrSpecularGlossiness against the core material it describes: a red quad of
/// specular colour 0.04 (the core dielectric's f0 at ior 1.5) and glossiness 0.3 (roughness
/// 0.7). `textured`: the specular colour and glossiness come from a 2 x 2 texture with factors
/// of 1 (sRGB 56 is linear 0.0395; alpha 230 a glossiness of 0.902, roughness 0.098).
pub fn spec_gloss(textured: bool) -> (Vec<u8>, Vec<u8>) {
    let diffuse = [0.8, 0.2, 0.2, 1.0];
    let with = {
        let mut doc = Doc::default();
        let (_, _, uv, _) = quad();
        let prims = uv_quad(&mut doc, &uv, None, 0);
        let mut sg = json!({"diffuseFactor": diffuse, "specularFactor": [0.04, 0.04, 0.04],
            "glossinessFactor": 0.3});
        let mut root = json!({});
        if textured {
            let img = doc.image(&png(2, 2, [56, 56, 56, 230].repeat(4)), "image/png");
            sg = json!({"diffuseFactor": diffuse, "specularGlossinessTexture": {"index": 0}});
            root = texture_root(img, json!([]), &[]);
        }
        root["materials"] = json!([{
            "pbrMetallicRoughness": {"baseColorFactor": [0.0, 1.0, 0.0, 1.0]},
            "extensions": {"KHR_materials_pbrSpecularGlossiness": sg},
        }]);
        root["extensionsUsed"] = json!(["KHR_materials_pbrSpecularGlossiness"]);
        doc.glb(vec![prims], vec![json!({})], root)
    };
    let without = {
        let mut doc = Doc::default();
        let (_, _, uv, _) = quad();
        let prims = uv_quad(&mut doc, &uv, None, 0);
        let roughness = if textured { 1.0 - 230.0 / 255.0 } else { 0.7 };
        doc.glb(
            vec![prims],
            vec![json!({})],
            json!({"materials": [{"pbrMetallicRoughness": {"baseColorFactor": diffuse,
                "metallicFactor": 0.0, "roughnessFactor": roughness}}]}),
        )
    };
    (with, without)
}

/// A base colour texture read at TEXCOORD_1 (TEXCOORD_0 holding other UVs) against the same
/// UVs in TEXCOORD_0.
pub fn second_uv_set() -> (Vec<u8>, Vec<u8>) {
    let (_, _, uv, _) = quad();
    let other: Vec<[f32; 2]> = uv.iter().map(|[u, v]| [v * 0.5, u * 0.25]).collect();
    let (w, h, px) = map_texture();
    let image = png(w, h, px);
    let write = |second: bool| {
        let mut doc = Doc::default();
        let prims = if second {
            uv_quad(&mut doc, &other, Some(&uv), 0)
        } else {
            uv_quad(&mut doc, &uv, Some(&other), 0)
        };
        let img = doc.image(&image, "image/png");
        let info = json!({"index": 0, "texCoord": if second { 1 } else { 0 }});
        doc.glb(
            vec![prims],
            vec![json!({})],
            texture_root(img, json!([textured(info)]), &[]),
        )
    };
    (write(true), write(false))
}

/// The same textured quad with its image as lossless WebP (EXT_texture_webp, required, with no
/// fallback) and as PNG.
pub fn webp_texture() -> (Vec<u8>, Vec<u8>) {
    let (_, _, uv, _) = quad();
    let (w, h, px) = map_texture();
    let mut webp = std::io::Cursor::new(Vec::new());
    image::RgbaImage::from_raw(w, h, px.clone())
        .expect("w * h * 4 bytes")
        .write_to(&mut webp, image::ImageFormat::WebP)
        .expect("WebP encodes");
    let as_webp = {
        let mut doc = Doc::default();
        let prims = uv_quad(&mut doc, &uv, None, 0);
        let img = doc.image(webp.get_ref(), "image/webp");
        let mut root = texture_root(
            img,
            json!([textured(json!({"index": 0}))]),
            &["EXT_texture_webp"],
        );
        root["textures"] =
            json!([{"sampler": 0, "extensions": {"EXT_texture_webp": {"source": img}}}]);
        root["extensionsRequired"] = json!(["EXT_texture_webp"]);
        doc.glb(vec![prims], vec![json!({})], root)
    };
    let as_png = {
        let mut doc = Doc::default();
        let prims = uv_quad(&mut doc, &uv, None, 0);
        let img = doc.image(&png(w, h, px), "image/png");
        doc.glb(
            vec![prims],
            vec![json!({})],
            texture_root(img, json!([textured(json!({"index": 0}))]), &[]),
        )
    };
    (as_webp, as_png)
}

/// KHR_mesh_quantization as gltfpack writes it: a textured bumpy grid with SHORT positions
/// (1/1000 units, the node scaling them back), normalized SHORT normals and normalized
/// UNSIGNED_SHORT UVs, beside a flat quad with normalized BYTE normals and UNSIGNED_BYTE UVs;
/// against the float file.
pub fn quantized() -> (Vec<u8>, Vec<u8>) {
    let n = 8;
    let grid = bumpy_grid(n);
    let normals: Vec<[f32; 3]> = grid
        .iter()
        .map(|&[x, y, _]| {
            // The height field z = 0.3 sin(3x) cos(2y): its normal (-dz/dx, -dz/dy, 1).
            let dx = 0.9 * (3.0 * x).cos() * (2.0 * y).cos();
            let dy = -0.6 * (3.0 * x).sin() * (2.0 * y).sin();
            let l = (dx * dx + dy * dy + 1.0f32).sqrt();
            [-dx / l, -dy / l, 1.0 / l]
        })
        .collect();
    let uvs: Vec<[f32; 2]> = grid
        .iter()
        .map(|&[x, y, _]| [(x + 1.0) * 0.5, (1.0 - y) * 0.5])
        .collect();
    let indices = grid_indices(n);
    let (qp, qn, quv, qi) = quad();
    let small: Vec<[f32; 3]> = qp
        .iter()
        .map(|p| [p[0] * 0.3 + 0.6, p[1] * 0.3 - 0.6, 0.6])
        .collect();
    let (w, h, px) = map_texture();
    let image = png(w, h, px);
    let write = |quantize: bool| {
        let mut doc = Doc::default();
        let (grid_attr, quad_attr, scale) = if quantize {
            let q = |v: f32, s: f64| (v as f64 * s).round();
            let p: Vec<[f64; 3]> = grid.iter().map(|v| v.map(|c| q(c, 1000.0))).collect();
            let nn: Vec<[f64; 3]> = normals.iter().map(|v| v.map(|c| q(c, 32767.0))).collect();
            let t: Vec<[f64; 2]> = uvs.iter().map(|v| v.map(|c| q(c, 65535.0))).collect();
            let sp: Vec<[f64; 3]> = small.iter().map(|v| v.map(|c| q(c, 1000.0))).collect();
            let sn: Vec<[f64; 3]> = qn.iter().map(|v| v.map(|c| q(c, 127.0))).collect();
            let st: Vec<[f64; 2]> = quv.iter().map(|v| v.map(|c| q(c, 255.0))).collect();
            (
                json!({"POSITION": doc.accessor(&p, SHORT, false), "NORMAL": doc.accessor(&nn, SHORT, true),
                       "TEXCOORD_0": doc.accessor(&t, UNSIGNED_SHORT, true)}),
                json!({"POSITION": doc.accessor(&sp, SHORT, false), "NORMAL": doc.accessor(&sn, BYTE, true),
                       "TEXCOORD_0": doc.accessor(&st, UNSIGNED_BYTE, true)}),
                0.001,
            )
        } else {
            (
                json!({"POSITION": doc.floats(&grid), "NORMAL": doc.floats(&normals), "TEXCOORD_0": doc.floats(&uvs)}),
                json!({"POSITION": doc.floats(&small), "NORMAL": doc.floats(&qn), "TEXCOORD_0": doc.floats(&quv)}),
                1.0,
            )
        };
        let (gi, si) = (doc.indices(&indices), doc.indices(&qi));
        let img = doc.image(&image, "image/png");
        let mut root = texture_root(img, json!([textured(json!({"index": 0}))]), &[]);
        if quantize {
            root["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
            root["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
        }
        doc.glb(
            vec![
                json!([{"attributes": grid_attr, "indices": gi, "material": 0}]),
                json!([{"attributes": quad_attr, "indices": si, "material": 0}]),
            ],
            vec![
                json!({"scale": [scale, scale, scale]}),
                json!({"scale": [scale, scale, scale]}),
            ],
            root,
        )
    };
    (write(true), write(false))
}

/// Emissive quads seen by an orthographic camera (xmag = ymag = 1 at (0, 0, 3)): one over
/// [-0.5, 0.5]^2 at depth `z`, black elsewhere. Its image is the middle half of the view in each
/// direction whatever `z` is (a perspective view would shrink it with distance).
pub fn orthographic(z: f64) -> Vec<u8> {
    let mut doc = Doc::default();
    let (p, n, _, i) = quad();
    let half: Vec<[f32; 3]> = p.iter().map(|v| [v[0] * 0.5, v[1] * 0.5, 0.0]).collect();
    let prims = vec![
        json!({"attributes": {"POSITION": doc.floats(&half), "NORMAL": doc.floats(&n)},
        "indices": doc.indices(&i), "material": 0}),
    ];
    let mut bytes_root = json!({"materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0]},
        "emissiveFactor": [1.0, 1.0, 1.0]}]});
    bytes_root["cameras"] = json!([{"type": "orthographic", "orthographic":
        {"xmag": 1.0, "ymag": 1.0, "znear": 0.01, "zfar": 100.0}}]);
    doc.glb(
        vec![json!(prims)],
        vec![json!({"translation": [0.0, 0.0, z]})],
        bytes_root,
    )
}

/// A quad of alphaMode BLEND with `alpha`, emitting `front`, one unit in front of a wider
/// opaque quad emitting `back` (both black, so the image is their emission alone).
pub fn blended(alpha: f32, front: [f32; 3], back: [f32; 3]) -> Vec<u8> {
    let mut doc = Doc::default();
    let (p, n, _, i) = quad();
    let (p, n, i) = (doc.floats(&p), doc.floats(&n), doc.indices(&i));
    let prim = |m: usize| json!([{"attributes": {"POSITION": p, "NORMAL": n}, "indices": i, "material": m}]);
    doc.glb(
        vec![prim(0), prim(1)],
        vec![json!({"translation": [0.0, 0.0, 1.0], "scale": [0.5, 0.5, 1.0]}), json!({"scale": [3.0, 3.0, 1.0]})],
        json!({"materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, alpha]}, "emissiveFactor": front, "alphaMode": "BLEND"},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0]}, "emissiveFactor": back},
        ]}),
    )
}

/// A KHR_materials_unlit quad of base colour `colour` (times its vertex colours: white here)
/// filling the middle of the view.
pub fn unlit(colour: [f32; 3]) -> Vec<u8> {
    let mut doc = Doc::default();
    let (p, n, _, i) = quad();
    let prims = vec![
        json!({"attributes": {"POSITION": doc.floats(&p), "NORMAL": doc.floats(&n)},
        "indices": doc.indices(&i), "material": 0}),
    ];
    doc.glb(
        vec![json!(prims)],
        vec![json!({"scale": [0.5, 0.5, 1.0]})],
        json!({
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [colour[0], colour[1], colour[2], 1.0]},
                "extensions": {"KHR_materials_unlit": {}}}],
            "extensionsUsed": ["KHR_materials_unlit"],
        }),
    )
}

/// KHR_materials_variants: an unlit quad (it shows its base colour exactly) whose own material is
/// grey (0.5), mapped to red (1, 0, 0) by the variant "red" and to blue (0, 0, 1) by "blue"; the
/// variant "plain" maps nothing, so the quad keeps its own material.
pub fn variants() -> Vec<u8> {
    let mut doc = Doc::default();
    let (p, n, _, i) = quad();
    let prims = vec![json!({
        "attributes": {"POSITION": doc.floats(&p), "NORMAL": doc.floats(&n)},
        "indices": doc.indices(&i), "material": 0,
        "extensions": {"KHR_materials_variants": {"mappings": [
            {"material": 1, "variants": [0]},
            {"material": 2, "variants": [1]},
        ]}},
    })];
    let unlit = |c: [f32; 3]| {
        json!({"pbrMetallicRoughness": {"baseColorFactor": [c[0], c[1], c[2], 1.0]},
            "extensions": {"KHR_materials_unlit": {}}})
    };
    doc.glb(
        vec![json!(prims)],
        vec![json!({"scale": [0.5, 0.5, 1.0]})],
        json!({
            "materials": [unlit([0.5; 3]), unlit([1.0, 0.0, 0.0]), unlit([0.0, 0.0, 1.0])],
            "extensions": {"KHR_materials_variants": {"variants": [
                {"name": "red"}, {"name": "blue"}, {"name": "plain"},
            ]}},
            "extensionsUsed": ["KHR_materials_unlit", "KHR_materials_variants"],
        }),
    )
}

/// Morph targets: a bumpy grid with two position-and-normal targets, posed at weights
/// (0.6, 0.3) by the node's weights over the mesh's (1, 1) (`animated`: by a LINEAR weights
/// animation from (0, 0) at 0 s to (1.2, 0.6) at 1 s, to be posed at 0.5 s); against the grid
/// with those displacements baked into its vertices.
pub fn morphed(animated: bool) -> (Vec<u8>, Vec<u8>) {
    let n = 6;
    let grid = bumpy_grid(n);
    let normals = vec![[0.0f32, 0.0, 1.0]; grid.len()];
    let d0: Vec<[f32; 3]> = grid.iter().map(|p| [0.0, 0.0, 0.4 * p[0]]).collect();
    let d1: Vec<[f32; 3]> = grid
        .iter()
        .map(|p| [0.1 * p[1], 0.0, -0.3 * p[1] * p[1]])
        .collect();
    let dn0: Vec<[f32; 3]> = grid.iter().map(|_| [-0.3, 0.0, 0.0]).collect();
    let dn1: Vec<[f32; 3]> = grid.iter().map(|p| [0.0, 0.5 * p[1], 0.0]).collect();
    let indices = grid_indices(n);
    let (w0, w1) = (0.6f32, 0.3f32);
    let with = {
        let mut doc = Doc::default();
        let (p, nn, i) = (
            doc.floats(&grid),
            doc.floats(&normals),
            doc.indices(&indices),
        );
        let targets = json!([
            {"POSITION": doc.floats(&d0), "NORMAL": doc.floats(&dn0)},
            {"POSITION": doc.floats(&d1), "NORMAL": doc.floats(&dn1)},
        ]);
        let prims = json!([{"attributes": {"POSITION": p, "NORMAL": nn}, "indices": i, "material": 0, "targets": targets}]);
        let mut extra = json!({"materials": [grey()]});
        let node = if animated {
            let times = doc.floats(&[[0.0f32], [1.0]]);
            let values = doc.floats(&[[0.0f32], [0.0], [2.0 * w0], [2.0 * w1]]);
            extra["animations"] = json!([{"channels": [{"sampler": 0, "target": {"node": 1, "path": "weights"}}],
                "samplers": [{"input": times, "output": values, "interpolation": "LINEAR"}]}]);
            json!({})
        } else {
            json!({"weights": [w0, w1]})
        };
        let mut bytes = doc.glb(vec![prims], vec![node], extra);
        // The mesh's own default weights, which the node's (or the animation's) replace.
        let (mut root, bin) = split_glb(&bytes);
        root["meshes"][0]["weights"] = json!([1.0, 1.0]);
        bytes = glb(&root, &bin);
        bytes
    };
    let baked = {
        let mut doc = Doc::default();
        let moved: Vec<[f32; 3]> = (0..grid.len())
            .map(|k| std::array::from_fn(|c| grid[k][c] + w0 * d0[k][c] + w1 * d1[k][c]))
            .collect();
        let bent: Vec<[f32; 3]> = (0..grid.len())
            .map(|k| {
                let v: [f32; 3] =
                    std::array::from_fn(|c| normals[k][c] + w0 * dn0[k][c] + w1 * dn1[k][c]);
                let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                v.map(|c| c / l)
            })
            .collect();
        let (p, nn, i) = (doc.floats(&moved), doc.floats(&bent), doc.indices(&indices));
        let prims =
            json!([{"attributes": {"POSITION": p, "NORMAL": nn}, "indices": i, "material": 0}]);
        doc.glb(vec![prims], vec![json!({})], json!({"materials": [grey()]}))
    };
    (with, baked)
}

/// EXT_mesh_gpu_instancing: a small bumpy grid drawn three times by a node's instance
/// attributes (translation, rotation, scale), against three child nodes with those transforms.
pub fn gpu_instancing() -> (Vec<u8>, Vec<u8>) {
    let t = [[-0.6f32, 0.4, 0.0], [0.5, 0.3, 0.2], [0.0, -0.5, -0.3]];
    let r = [
        [0.0f32, 0.0, 0.0, 1.0],
        [0.0, 0.0, 0.382_683_4, 0.923_879_5],
        [0.258_819, 0.0, 0.0, 0.965_925_8],
    ];
    let s = [[0.3f32; 3], [0.25, 0.4, 0.3], [0.35; 3]];
    let (grid, indices) = (bumpy_grid(4), grid_indices(4));
    let write = |extension: bool| {
        let mut doc = Doc::default();
        let (p, i) = (doc.floats(&grid), doc.indices(&indices));
        let prims = json!([{"attributes": {"POSITION": p}, "indices": i, "material": 0}]);
        let mut extra = json!({"materials": [grey()]});
        let parent = if extension {
            extra["extensionsUsed"] = json!(["EXT_mesh_gpu_instancing"]);
            json!({"translation": [0.0, 0.0, 0.1], "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {
                "TRANSLATION": doc.floats(&t), "ROTATION": doc.floats(&r), "SCALE": doc.floats(&s)}}}})
        } else {
            json!({"translation": [0.0, 0.0, 0.1]})
        };
        let bytes = doc.glb(vec![prims], vec![parent], extra);
        if extension {
            return bytes;
        }
        // The explicit twin: the mesh moves from the parent onto three children.
        let (mut root, bin) = split_glb(&bytes);
        let nodes = root["nodes"].as_array_mut().expect("nodes");
        let parent = nodes.len() - 1;
        nodes[parent].as_object_mut().expect("node").remove("mesh");
        let first = nodes.len();
        for k in 0..3 {
            nodes.push(json!({"mesh": 0, "translation": t[k], "rotation": r[k], "scale": s[k]}));
        }
        nodes[parent]["children"] = json!([first, first + 1, first + 2]);
        glb(&root, &bin)
    };
    (write(true), write(false))
}

/// A quad textured by two texels, red | blue, with magFilter NEAREST (`nearest`) or LINEAR.
pub fn magnified(nearest: bool) -> Vec<u8> {
    let (_, _, uv, _) = quad();
    let mut doc = Doc::default();
    let prims = uv_quad(&mut doc, &uv, None, 0);
    let img = doc.image(
        &png(2, 1, vec![255, 0, 0, 255, 0, 0, 255, 255]),
        "image/png",
    );
    let mut root = texture_root(img, json!([textured(json!({"index": 0}))]), &[]);
    root["samplers"][0]["magFilter"] = json!(if nearest { 9728 } else { 9729 });
    doc.glb(vec![prims], vec![json!({})], root)
}

//! glTF 2.0 loader (.gltf with external or embedded buffers, .glb). Errors name the file and
//! the problem; unsupported optional features become warnings kept on the scene.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gltf::Gltf;

use crate::animation::{Animation, Channel, Interpolation, Property};
use crate::error::{Error, Result};
use crate::scene::*;

/// Extensions that platoon implements; a file that *requires* any other is refused.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_ior",
];

pub fn load(path: &Path) -> Result<Scene> {
    let bytes =
        std::fs::read(path).map_err(|e| Error::file(path, format!("cannot read scene: {e}")))?;
    let unvalidated = Gltf::from_slice_without_validation(&bytes)
        .map_err(|e| Error::file(path, format!("not a valid glTF file: {e}")))?;
    for ext in unvalidated.extensions_required() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            return Err(Error::file(
                path,
                format!("requires the unsupported glTF extension {ext}"),
            ));
        }
    }
    let gltf =
        Gltf::from_slice(&bytes).map_err(|e| Error::file(path, format!("invalid glTF: {e}")))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let doc = gltf.document;
    for buffer in doc.buffers() {
        if let gltf::buffer::Source::Uri(uri) = buffer.source() {
            check_external(path, base, uri, "buffer")?;
        }
    }
    let buffers = gltf::import_buffers(&doc, Some(base), gltf.blob)
        .map_err(|e| Error::file(path, format!("cannot load buffers: {e}")))?;
    for image in doc.images() {
        if let gltf::image::Source::Uri { uri, .. } = image.source() {
            check_external(path, base, uri, "texture")?;
        }
    }
    let images = gltf::import_images(&doc, Some(base), &buffers)
        .map_err(|e| Error::file(path, format!("cannot load textures: {e}")))?;

    let mut scene = Scene {
        source: Some(path.to_path_buf()),
        ..Default::default()
    };
    scene.textures = doc
        .textures()
        .map(|t| texture(&t, &images[t.source().index()]))
        .collect();
    scene.materials = doc
        .materials()
        .map(|m| material(&m, &mut scene.warnings))
        .collect();
    // Primitives without a material use the glTF default material, appended last when needed.
    let default_material = scene.materials.len() as u32;
    if doc
        .meshes()
        .flat_map(|m| m.primitives())
        .any(|p| p.material().index().is_none())
    {
        scene.materials.push(Material::default());
    }
    for mesh in doc.meshes() {
        let m = load_mesh(
            path,
            &mesh,
            &buffers,
            default_material,
            &scene.materials,
            &mut scene.warnings,
        )?;
        scene.meshes.push(Arc::new(m));
    }
    load_nodes(path, &doc, &buffers, &mut scene)?;
    Ok(scene)
}

fn check_external(gltf: &Path, base: &Path, uri: &str, what: &str) -> Result<()> {
    if uri.starts_with("data:") {
        return Ok(());
    }
    let decoded = percent_decode(uri);
    let file = base.join(&decoded);
    if !file.is_file() {
        return Err(Error::file(
            gltf,
            format!("missing {what} file {}", file.display()),
        ));
    }
    Ok(())
}

fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            if let Ok(v) = u8::from_str_radix(&s[i + 1..i + 3], 16) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn wrap(mode: gltf::texture::WrappingMode) -> Wrap {
    match mode {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    }
}

fn texture(t: &gltf::Texture, data: &gltf::image::Data) -> Texture {
    use gltf::image::Format::*;
    let px = &data.pixels;
    let n = (data.width * data.height) as usize;
    let mut rgba = Vec::with_capacity(n * 4);
    // 16-bit formats keep their high byte (little-endian: the second of each pair).
    for i in 0..n {
        let texel: [u8; 4] = match data.format {
            R8 => [px[i], px[i], px[i], 255],
            R8G8 => [px[2 * i], px[2 * i + 1], 0, 255],
            R8G8B8 => [px[3 * i], px[3 * i + 1], px[3 * i + 2], 255],
            R8G8B8A8 => [px[4 * i], px[4 * i + 1], px[4 * i + 2], px[4 * i + 3]],
            R16 => [px[2 * i + 1], px[2 * i + 1], px[2 * i + 1], 255],
            R16G16 => [px[4 * i + 1], px[4 * i + 3], 0, 255],
            R16G16B16 => [px[6 * i + 1], px[6 * i + 3], px[6 * i + 5], 255],
            R16G16B16A16 => [px[8 * i + 1], px[8 * i + 3], px[8 * i + 5], px[8 * i + 7]],
            R32G32B32FLOAT | R32G32B32A32FLOAT => {
                let ch = if data.format == R32G32B32FLOAT { 3 } else { 4 };
                let f = |k: usize| {
                    let o = (ch * i + k) * 4;
                    let v = f32::from_le_bytes([px[o], px[o + 1], px[o + 2], px[o + 3]]);
                    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
                };
                [f(0), f(1), f(2), if ch == 4 { f(3) } else { 255 }]
            }
        };
        rgba.extend_from_slice(&texel);
    }
    let sampler = t.sampler();
    Texture {
        name: t.name().or(t.source().name()).unwrap_or("").to_string(),
        width: data.width,
        height: data.height,
        rgba8: rgba,
        wrap_s: wrap(sampler.wrap_s()),
        wrap_t: wrap(sampler.wrap_t()),
    }
}

fn tex_ref(
    info: Option<gltf::texture::Info>,
    what: &str,
    warnings: &mut Vec<String>,
) -> Option<TextureRef> {
    let info = info?;
    if info.tex_coord() != 0 {
        warnings.push(format!(
            "{what} uses TEXCOORD_{}; platoon reads TEXCOORD_0",
            info.tex_coord()
        ));
    }
    Some(TextureRef {
        texture: info.texture().index() as u32,
    })
}

fn material(m: &gltf::Material, warnings: &mut Vec<String>) -> Material {
    let pbr = m.pbr_metallic_roughness();
    let name = m.name().unwrap_or("").to_string();
    let mut mat = Material {
        name: name.clone(),
        base_color: Vec4::from_array(pbr.base_color_factor()),
        base_color_texture: tex_ref(pbr.base_color_texture(), "baseColorTexture", warnings),
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: tex_ref(
            pbr.metallic_roughness_texture(),
            "metallicRoughnessTexture",
            warnings,
        ),
        normal_texture: None,
        normal_scale: 1.0,
        emissive: Vec3::from_array(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
        emissive_texture: tex_ref(m.emissive_texture(), "emissiveTexture", warnings),
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => {
                warnings.push(format!(
                    "material '{name}': alpha mode BLEND is rendered as OPAQUE"
                ));
                AlphaMode::Blend
            }
        },
        double_sided: m.double_sided(),
        ior: m.ior().unwrap_or(1.5),
        ..Material::default()
    };
    if let Some(n) = m.normal_texture() {
        mat.normal_scale = n.scale();
        mat.normal_texture = Some(TextureRef {
            texture: n.texture().index() as u32,
        });
    }
    if let Some(s) = m.specular() {
        mat.specular = s.specular_factor();
        mat.specular_texture = tex_ref(s.specular_texture(), "specularTexture", warnings);
        mat.specular_color = Vec3::from_array(s.specular_color_factor());
        mat.specular_color_texture =
            tex_ref(s.specular_color_texture(), "specularColorTexture", warnings);
    }
    if let Some(t) = m.transmission() {
        mat.transmission = t.transmission_factor();
        mat.transmission_texture =
            tex_ref(t.transmission_texture(), "transmissionTexture", warnings);
    }
    mat
}

fn load_mesh(
    path: &Path,
    mesh: &gltf::Mesh,
    buffers: &[gltf::buffer::Data],
    default_material: u32,
    materials: &[Material],
    warnings: &mut Vec<String>,
) -> Result<Mesh> {
    let name = mesh.name().unwrap_or("").to_string();
    let mut out = Mesh {
        name: name.clone(),
        ..Default::default()
    };
    let mut any_normals = false;
    let mut any_tangents = false;
    let mut any_uvs = false;
    let mut any_skin = false;
    let mut parts = Vec::new();
    for prim in mesh.primitives() {
        if prim.mode() != gltf::mesh::Mode::Triangles {
            warnings.push(format!(
                "mesh '{name}': primitive mode {:?} skipped (triangles only)",
                prim.mode()
            ));
            continue;
        }
        let reader = prim.reader(|b| Some(&buffers[b.index()]));
        let Some(positions) = reader.read_positions() else {
            return Err(Error::file(
                path,
                format!("mesh '{name}' has a primitive without POSITION"),
            ));
        };
        let positions: Vec<Vec3> = positions.map(Vec3::from_array).collect();
        let n = positions.len();
        let normals: Option<Vec<Vec3>> = reader
            .read_normals()
            .map(|it| it.map(Vec3::from_array).collect());
        let tangents: Option<Vec<Vec4>> = reader
            .read_tangents()
            .map(|it| it.map(Vec4::from_array).collect());
        let uvs: Option<Vec<Vec2>> = reader
            .read_tex_coords(0)
            .map(|it| it.into_f32().map(Vec2::from_array).collect());
        let joints: Option<Vec<[u16; 4]>> = reader.read_joints(0).map(|it| it.into_u16().collect());
        let weights: Option<Vec<Vec4>> = reader
            .read_weights(0)
            .map(|it| it.into_f32().map(Vec4::from_array).collect());
        let indices: Vec<u32> = match reader.read_indices() {
            Some(it) => it.into_u32().collect(),
            None => (0..n as u32).collect(),
        };
        if indices.iter().any(|&i| i as usize >= n) {
            return Err(Error::file(
                path,
                format!("mesh '{name}' has an index out of range"),
            ));
        }
        any_normals |= normals.is_some();
        any_tangents |= tangents.is_some();
        any_uvs |= uvs.is_some();
        any_skin |= joints.is_some() && weights.is_some();
        let material = prim
            .material()
            .index()
            .map(|i| i as u32)
            .unwrap_or(default_material);
        parts.push((
            positions, normals, tangents, uvs, joints, weights, indices, material,
        ));
    }
    for (positions, normals, tangents, uvs, joints, weights, indices, material) in parts {
        let base = out.positions.len() as u32;
        let n = positions.len();
        out.positions.extend(positions);
        if any_normals {
            out.normals
                .extend(normals.unwrap_or_else(|| vec![Vec3::ZERO; n]));
        }
        if any_tangents {
            out.tangents
                .extend(tangents.unwrap_or_else(|| vec![Vec4::ZERO; n]));
        }
        if any_uvs {
            out.uvs.extend(uvs.unwrap_or_else(|| vec![Vec2::ZERO; n]));
        }
        if any_skin {
            out.joints.extend(joints.unwrap_or_else(|| vec![[0; 4]; n]));
            out.weights
                .extend(weights.unwrap_or_else(|| vec![Vec4::ZERO; n]));
        }
        for t in indices.chunks_exact(3) {
            out.indices.push([t[0] + base, t[1] + base, t[2] + base]);
            out.triangle_materials.push(material);
        }
    }
    let normal_mapped = out
        .triangle_materials
        .iter()
        .any(|&m| materials[m as usize].normal_texture.is_some());
    if normal_mapped && !any_tangents && any_uvs {
        out.tangents =
            crate::tangents::generate(&out.positions, &out.normals, &out.uvs, &out.indices);
    }
    Ok(out)
}

fn load_nodes(
    path: &Path,
    doc: &gltf::Document,
    buffers: &[gltf::buffer::Data],
    scene: &mut Scene,
) -> Result<()> {
    let gscene = doc.default_scene().or_else(|| doc.scenes().next());
    let mut map: HashMap<usize, usize> = HashMap::new();
    // Breadth-first from the roots, so a parent always precedes its children.
    let mut queue: std::collections::VecDeque<(gltf::Node, Option<usize>)> = gscene
        .iter()
        .flat_map(|s| s.nodes())
        .map(|n| (n, None))
        .collect();
    while let Some((gn, parent)) = queue.pop_front() {
        if map.contains_key(&gn.index()) {
            return Err(Error::file(
                path,
                format!("node {} appears twice in the hierarchy", gn.index()),
            ));
        }
        let idx = scene.nodes.len();
        map.insert(gn.index(), idx);
        let (t, r, s) = gn.transform().decomposed();
        let mut node = Node::new(gn.name().unwrap_or(""));
        node.parent = parent;
        node.translation = Vec3::from_array(t);
        node.rotation = Quat::from_array(r);
        node.scale = Vec3::from_array(s);
        node.mesh = gn.mesh().map(|m| m.index());
        node.skin = gn.skin().map(|s| s.index());
        if let Some(c) = gn.camera() {
            match c.projection() {
                gltf::camera::Projection::Perspective(p) => {
                    node.camera = Some(scene.cameras.len());
                    scene.cameras.push(CameraModel {
                        name: c.name().unwrap_or("").into(),
                        yfov: p.yfov(),
                        aspect_ratio: p.aspect_ratio(),
                    });
                }
                gltf::camera::Projection::Orthographic(_) => scene.warnings.push(format!(
                    "camera '{}': orthographic cameras are skipped",
                    c.name().unwrap_or("")
                )),
            }
        }
        if let Some(l) = gn.light() {
            node.light = Some(scene.lights.len());
            use gltf::khr_lights_punctual::Kind;
            scene.lights.push(PunctualLight {
                name: l.name().unwrap_or("").into(),
                kind: match l.kind() {
                    Kind::Point => LightKind::Point,
                    Kind::Directional => LightKind::Directional,
                    Kind::Spot {
                        inner_cone_angle,
                        outer_cone_angle,
                    } => LightKind::Spot {
                        inner_cone: inner_cone_angle,
                        outer_cone: outer_cone_angle,
                    },
                },
                color: Vec3::from_array(l.color()),
                intensity: l.intensity(),
                range: l.range().unwrap_or(0.0),
            });
        }
        scene.nodes.push(node);
        for child in gn.children() {
            queue.push_back((child, Some(idx)));
        }
    }
    for skin in doc.skins() {
        let reader = skin.reader(|b| Some(&buffers[b.index()]));
        let ibm: Vec<Mat4> = reader
            .read_inverse_bind_matrices()
            .map(|it| it.map(|m| Mat4::from_cols_array_2d(&m)).collect())
            .unwrap_or_default();
        let joints = skin
            .joints()
            .filter_map(|j| map.get(&j.index()).copied())
            .collect::<Vec<_>>();
        scene.skins.push(Skin {
            name: skin.name().unwrap_or("").into(),
            joints,
            inverse_bind_matrices: ibm,
        });
    }
    for anim in doc.animations() {
        let mut channels = Vec::new();
        for ch in anim.channels() {
            let Some(&node) = map.get(&ch.target().node().index()) else {
                continue;
            };
            let reader = ch.reader(|b| Some(&buffers[b.index()]));
            let times: Vec<f32> = reader
                .read_inputs()
                .map(|it| it.collect())
                .unwrap_or_default();
            use gltf::animation::util::ReadOutputs;
            let (property, values): (Property, Vec<f32>) = match reader.read_outputs() {
                Some(ReadOutputs::Translations(it)) => {
                    (Property::Translation, it.flatten().collect())
                }
                Some(ReadOutputs::Scales(it)) => (Property::Scale, it.flatten().collect()),
                Some(ReadOutputs::Rotations(it)) => {
                    (Property::Rotation, it.into_f32().flatten().collect())
                }
                Some(ReadOutputs::MorphTargetWeights(it)) => {
                    (Property::Weights, it.into_f32().collect())
                }
                None => continue,
            };
            let interpolation = match ch.sampler().interpolation() {
                gltf::animation::Interpolation::Step => Interpolation::Step,
                gltf::animation::Interpolation::Linear => Interpolation::Linear,
                gltf::animation::Interpolation::CubicSpline => Interpolation::CubicSpline,
            };
            let per_key = match property {
                Property::Translation | Property::Scale => 3,
                Property::Rotation => 4,
                Property::Weights => 1,
            } * if interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            if property != Property::Weights && values.len() < times.len() * per_key {
                return Err(Error::file(
                    path,
                    format!(
                        "animation '{}' has too few output values",
                        anim.name().unwrap_or("")
                    ),
                ));
            }
            channels.push(Channel {
                node,
                property,
                interpolation,
                times,
                values,
            });
        }
        scene.animations.push(Animation {
            name: anim.name().unwrap_or("").into(),
            channels,
        });
    }
    Ok(())
}

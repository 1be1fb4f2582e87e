//! A prepared scene as a Mitsuba 3 scene (XML, PLY meshes, PNG textures): so that the bench
//! renders the very geometry, camera, lights and materials platoon renders, whatever the glTF
//! features of the source (skins and morphs posed, instances placed).
//!
//! What maps one to one: world-space triangles with their shading normals and UVs, the
//! perspective camera, point, spot and directional lights (platoon reads glTF intensities as
//! radiometric, as Mitsuba's `intensity` and `irradiance` are), emissive triangles as area
//! emitters, the constant sky and the environment map (turned to platoon's longitude origin).
//! Materials: a Lambertian one (dielectric, KHR_materials_specular factor 0) as `diffuse`, the
//! rest as the `principled` BSDF (base colour and its texture, metallic, roughness, the
//! transmission factor and the IOR), under Mitsuba's `mask` where glTF's alpha lets light through
//! (MASK as an opacity of 0 or 1 by the cutoff, BLEND as the alpha: both renderers then pass a
//! ray through with the same probability); Mitsuba has no match for the specular colour, normal
//! maps or texture transforms, so those are left out: the exported scene is the same work for
//! the renderer, not the same image.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context as _, Result};
use glam::{Mat3, Vec3};
use platoon::core::scene::environment::Environment;
use platoon::core::scene::{AlphaMode, LightKind, Material, Texture};
use platoon::Prepared;

/// What the render is: its size, samples and path length.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Path segments (Mitsuba's max_depth, platoon's --max-depth); `None` unbounded.
    pub max_depth: Option<u32>,
    /// The depth Russian roulette starts at (platoon's rr_depth).
    pub rr_depth: u32,
}

fn rgb(v: Vec3) -> String {
    format!("{:.6}, {:.6}, {:.6}", v.x, v.y, v.z)
}

fn point(name: &str, v: Vec3) -> String {
    format!(
        r#"<point name="{name}" x="{:.6}" y="{:.6}" z="{:.6}"/>"#,
        v.x, v.y, v.z
    )
}

/// A Lambertian material as platoon's built-in box has: no specular lobe at all.
fn is_lambertian(m: &Material) -> bool {
    m.metallic == 0.0
        && m.specular == 0.0
        && m.specular_texture.is_none()
        && m.transmission == 0.0
        && m.metallic_roughness_texture.is_none()
}

/// The BSDF of material `m` (`texture`: its base colour texture's file, when it has one).
fn bsdf(m: &Material, texture: Option<&str>) -> String {
    let colour = |name: &str| match texture {
        Some(file) => format!(
            r#"<texture type="bitmap" name="{name}"><string name="filename" value="{file}"/></texture>"#
        ),
        None => format!(
            r#"<rgb name="{name}" value="{}"/>"#,
            rgb(m.base_color.truncate())
        ),
    };
    if is_lambertian(m) {
        return format!(
            r#"<bsdf type="twosided"><bsdf type="diffuse">{}</bsdf></bsdf>"#,
            colour("reflectance")
        );
    }
    let principled = format!(
        r#"<bsdf type="principled">{}<float name="metallic" value="{}"/><float name="roughness" value="{}"/><float name="spec_trans" value="{}"/><float name="eta" value="{}"/></bsdf>"#,
        colour("base_color"),
        m.metallic,
        m.roughness,
        m.transmission,
        m.ior.max(1.0001)
    );
    // A transmitting BSDF has two sides of its own; an opaque one shades its back as its front,
    // as platoon does.
    if m.transmission > 0.0 {
        principled
    } else {
        format!(r#"<bsdf type="twosided">{principled}</bsdf>"#)
    }
}

/// The chance that a ray meets `m`'s surface, as a grey image of `texture`'s alpha (times the
/// base colour's): thresholded at the cutoff for MASK, as it is for BLEND; `None` for an opaque
/// material or one without a texture (then [`opacity_constant`]).
fn opacity_image(m: &Material, texture: &Texture) -> Option<image::GrayImage> {
    let cutoff = match m.alpha_mode {
        AlphaMode::Opaque => return None,
        AlphaMode::Mask(c) => Some(c),
        AlphaMode::Blend => None,
    };
    let pixels = texture
        .rgba8
        .chunks_exact(4)
        .map(|p| {
            let alpha = m.base_color.w * p[3] as f32 / 255.0;
            let coverage = match cutoff {
                Some(c) => (alpha >= c) as u8 as f32,
                None => alpha,
            };
            (coverage * 255.0).round() as u8
        })
        .collect();
    image::GrayImage::from_raw(texture.width, texture.height, pixels)
}

/// The opacity of an untextured material whose alpha lets light through, or `None`.
fn opacity_constant(m: &Material) -> Option<f32> {
    match m.alpha_mode {
        AlphaMode::Opaque => None,
        AlphaMode::Mask(c) => Some((m.base_color.w >= c) as u8 as f32),
        AlphaMode::Blend => Some(m.base_color.w),
    }
}

/// `inner` under Mitsuba's `mask` of the given opacity (an image file or a constant).
fn masked(inner: String, image: Option<&str>, constant: Option<f32>) -> String {
    let opacity = match (image, constant) {
        (Some(file), _) => format!(
            r#"<texture type="bitmap" name="opacity"><string name="filename" value="{file}"/><boolean name="raw" value="true"/></texture>"#
        ),
        (None, Some(c)) if c < 1.0 => format!(r#"<float name="opacity" value="{c}"/>"#),
        _ => return inner,
    };
    format!(r#"<bsdf type="mask">{opacity}{inner}</bsdf>"#)
}

/// One mesh's triangles in world space: positions, normals, UVs and corner indices.
#[derive(Default)]
struct Ply {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<[f32; 2]>,
    faces: Vec<[u32; 3]>,
}

impl Ply {
    fn bytes(&self) -> Vec<u8> {
        let mut out = format!(
            "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
            self.positions.len(),
            self.faces.len()
        )
        .into_bytes();
        for ((p, n), uv) in self.positions.iter().zip(&self.normals).zip(&self.uvs) {
            for f in [p.x, p.y, p.z, n.x, n.y, n.z, uv[0], uv[1]] {
                out.extend(f.to_le_bytes());
            }
        }
        for f in &self.faces {
            out.push(3);
            for &i in f {
                out.extend((i as i32).to_le_bytes());
            }
        }
        out
    }
}

/// Writes `prepared` as `dir/scene.xml` (with `meshes/` and `textures/` beside it) for a render
/// of `settings`; returns the XML's path.
pub fn export(prepared: &Prepared, settings: &Settings, dir: &Path) -> Result<PathBuf> {
    let (scene, posed, camera) = (&prepared.scene, &prepared.posed, &prepared.camera);
    if camera.orthographic.is_some() {
        bail!("orthographic cameras are not exported to Mitsuba");
    }
    std::fs::create_dir_all(dir.join("meshes"))?;
    std::fs::create_dir_all(dir.join("textures"))?;
    let mut xml = String::from("<scene version=\"3.0.0\">\n");
    let depth = settings.max_depth.map_or(-1, |d| d as i64);
    writeln!(
        xml,
        r#"<integrator type="path"><integer name="max_depth" value="{depth}"/><integer name="rr_depth" value="{}"/></integrator>"#,
        settings.rr_depth.max(1)
    )?;
    let b = camera.basis(settings.width, settings.height);
    writeln!(
        xml,
        r#"<sensor type="perspective"><string name="fov_axis" value="y"/><float name="fov" value="{}"/><transform name="to_world"><lookat origin="{}" target="{}" up="{}"/></transform><sampler type="independent"><integer name="sample_count" value="{}"/></sampler><film type="hdrfilm"><integer name="width" value="{}"/><integer name="height" value="{}"/><rfilter type="box"/></film></sensor>"#,
        camera.yfov.to_degrees(),
        rgb(b.origin),
        rgb(b.origin + b.forward),
        rgb(b.up),
        settings.spp,
        settings.width,
        settings.height
    )?;

    // Base colour textures, written once each.
    let mut texture_files = vec![None; scene.textures.len()];
    for (i, m) in scene.materials.iter().enumerate() {
        if let Some(t) = m.base_color_texture {
            let k = t.texture as usize;
            if texture_files[k].is_none() {
                let tex = &scene.textures[k];
                let name = format!("textures/{k}.png");
                let img = image::RgbaImage::from_raw(tex.width, tex.height, tex.rgba8.clone())
                    .with_context(|| format!("texture {k} of material {i}"))?;
                img.save(dir.join(&name))?;
                texture_files[k] = Some(name);
            }
        }
    }
    for (i, m) in scene.materials.iter().enumerate() {
        let texture = m
            .base_color_texture
            .and_then(|t| texture_files[t.texture as usize].as_deref());
        let opacity = match m.base_color_texture {
            Some(t) => match opacity_image(m, &scene.textures[t.texture as usize]) {
                Some(img) => {
                    let name = format!("textures/opacity{i}.png");
                    img.save(dir.join(&name))?;
                    Some(name)
                }
                None => None,
            },
            None => None,
        };
        let constant = opacity_constant(m).filter(|_| m.base_color_texture.is_none());
        let b = masked(bsdf(m, texture), opacity.as_deref(), constant);
        // The id sits on the outermost BSDF.
        let b = b.replacen("<bsdf ", &format!(r#"<bsdf id="m{i}" "#), 1);
        writeln!(xml, "{b}")?;
    }

    // Every instance in world space, a PLY per (instance, material).
    let mut files = 0;
    for inst in &posed.instances {
        let mesh = &posed.meshes[inst.mesh];
        let normal_matrix = Mat3::from_mat4(inst.object_to_world).inverse().transpose();
        let mirrored = inst.object_to_world.determinant() < 0.0;
        let mut by_material: Vec<(u32, Ply, Vec<u32>)> = Vec::new();
        for (t, tri) in mesh.indices.iter().enumerate() {
            let material = mesh.triangle_materials.get(t).copied().unwrap_or(0);
            let slot = match by_material.iter().position(|e| e.0 == material) {
                Some(s) => s,
                None => {
                    by_material.push((
                        material,
                        Ply::default(),
                        vec![u32::MAX; mesh.positions.len()],
                    ));
                    by_material.len() - 1
                }
            };
            let (_, ply, remap) = &mut by_material[slot];
            let mut face = [0u32; 3];
            for (c, &v) in face.iter_mut().zip(tri) {
                let v = v as usize;
                if remap[v] == u32::MAX {
                    remap[v] = ply.positions.len() as u32;
                    ply.positions
                        .push(inst.object_to_world.transform_point3(mesh.positions[v]));
                    let n = mesh
                        .normals
                        .get(v)
                        .map_or(Vec3::ZERO, |n| (normal_matrix * *n).normalize_or_zero());
                    ply.normals.push(n);
                    ply.uvs
                        .push(mesh.uvs.get(v).map_or([0.0; 2], |uv| uv.to_array()));
                }
                *c = remap[v];
            }
            if mirrored {
                face.swap(1, 2);
            }
            ply.faces.push(face);
        }
        for (material, ply, _) in by_material {
            let name = format!("meshes/{files}.ply");
            files += 1;
            std::fs::write(dir.join(&name), ply.bytes())?;
            // Flat-shaded meshes have no normals: Mitsuba then uses the face normals.
            let flat = ply.normals.iter().all(|n| *n == Vec3::ZERO);
            let m = &scene.materials[material as usize];
            let emitter = if m.is_emissive() {
                format!(
                    r#"<emitter type="area"><rgb name="radiance" value="{}"/></emitter>"#,
                    rgb(m.emissive)
                )
            } else {
                String::new()
            };
            writeln!(
                xml,
                r#"<shape type="ply"><string name="filename" value="{name}"/><boolean name="face_normals" value="{flat}"/><ref id="m{material}"/>{emitter}</shape>"#
            )?;
        }
    }

    for placed in &posed.lights {
        let l = &scene.lights[placed.light];
        let power = l.color * l.intensity;
        let line = match l.kind {
            LightKind::Point => format!(
                r#"<emitter type="point">{}<rgb name="intensity" value="{}"/></emitter>"#,
                point("position", placed.position),
                rgb(power)
            ),
            LightKind::Spot {
                inner_cone,
                outer_cone,
            } => format!(
                r#"<emitter type="spot"><transform name="to_world"><lookat origin="{}" target="{}"/></transform><rgb name="intensity" value="{}"/><float name="cutoff_angle" value="{}"/><float name="beam_width" value="{}"/></emitter>"#,
                rgb(placed.position),
                rgb(placed.position + placed.direction),
                rgb(power),
                outer_cone.to_degrees(),
                inner_cone.to_degrees()
            ),
            LightKind::Directional => format!(
                r#"<emitter type="directional"><vector name="direction" x="{}" y="{}" z="{}"/><rgb name="irradiance" value="{}"/></emitter>"#,
                placed.direction.x,
                placed.direction.y,
                placed.direction.z,
                rgb(power)
            ),
        };
        writeln!(xml, "{line}")?;
    }
    match &scene.environment {
        Some(Environment::Constant(c)) => writeln!(
            xml,
            r#"<emitter type="constant"><rgb name="radiance" value="{}"/></emitter>"#,
            rgb(*c)
        )?,
        // Mitsuba's longitude starts half a turn from platoon's (u = atan(x, -z) / 2pi + 1/2).
        Some(Environment::Map(map)) => writeln!(
            xml,
            r#"<emitter type="envmap"><string name="filename" value="{}"/><transform name="to_world"><rotate y="1" angle="180"/></transform></emitter>"#,
            std::fs::canonicalize(&map.path)?.display()
        )?,
        None => {}
    }
    xml.push_str("</scene>\n");
    let path = dir.join("scene.xml");
    std::fs::write(&path, xml)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    fn leaf(mode: AlphaMode, factor: f32) -> (Material, Texture) {
        let m = Material {
            base_color: Vec4::new(1.0, 1.0, 1.0, factor),
            alpha_mode: mode,
            ..Default::default()
        };
        // Alphas 0, 100, 200, 255 in a 4 x 1 image.
        let t = Texture {
            name: "leaf".into(),
            width: 4,
            height: 1,
            rgba8: [0u8, 100, 200, 255]
                .iter()
                .flat_map(|&a| [10, 200, 10, a])
                .collect(),
            wrap_s: platoon::core::scene::Wrap::Repeat,
            wrap_t: platoon::core::scene::Wrap::Repeat,
            nearest: false,
            mips: Vec::new(),
        };
        (m, t)
    }

    #[test]
    fn a_masked_material_becomes_mitsubas_mask_of_its_cutoff() {
        let (m, t) = leaf(AlphaMode::Mask(0.5), 1.0);
        let img = opacity_image(&m, &t).unwrap();
        assert_eq!(img.as_raw(), &vec![0, 0, 255, 255]);
        // The base colour's alpha multiplies the texture's before the cutoff.
        let (m, t) = leaf(AlphaMode::Mask(0.5), 0.5);
        assert_eq!(opacity_image(&m, &t).unwrap().as_raw(), &vec![0, 0, 0, 255]);
        let (m, t) = leaf(AlphaMode::Blend, 1.0);
        assert_eq!(
            opacity_image(&m, &t).unwrap().as_raw(),
            &vec![0, 100, 200, 255]
        );
        let (m, t) = leaf(AlphaMode::Opaque, 0.2);
        assert!(opacity_image(&m, &t).is_none() && opacity_constant(&m).is_none());
        let b = masked(bsdf(&m, None), Some("textures/opacity4.png"), None);
        assert!(b.starts_with(r#"<bsdf type="mask"><texture type="bitmap" name="opacity">"#));
        assert!(b.contains(r#"<string name="filename" value="textures/opacity4.png"/>"#));
        // Nothing to mask: the BSDF as it was.
        assert_eq!(masked(bsdf(&m, None), None, Some(1.0)), bsdf(&m, None));
        let half = masked(bsdf(&m, None), None, Some(0.5));
        assert!(half.starts_with(r#"<bsdf type="mask"><float name="opacity" value="0.5"/>"#));
    }
}

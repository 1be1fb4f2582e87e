//! A glTF mesh (its triangle primitives merged) as one platoon mesh. Every accessor is checked
//! (validate::accessor) before the crate's reader decodes it.

use glam::{DVec3, Vec2, Vec3, Vec4};
use gltf::accessor::Dimensions;
use gltf::mesh::Semantic;

use super::attributes;
use super::validate::{self, Check, Expect};
use crate::*;

/// The accessor expectations of each vertex attribute platoon reads: floats, or the integer
/// types KHR_mesh_quantization allows.
fn expectation(semantic: &Semantic, dims: Dimensions) -> Option<Expect> {
    let (what, types, dims) = match semantic {
        Semantic::Positions => ("POSITION", validate::NORM_OR_FLOAT, Dimensions::Vec3),
        Semantic::Normals => ("NORMAL", validate::SNORM_OR_FLOAT, Dimensions::Vec3),
        Semantic::Tangents => ("TANGENT", validate::SNORM_OR_FLOAT, Dimensions::Vec4),
        Semantic::TexCoords(0) => ("TEXCOORD_0", validate::NORM_OR_FLOAT, Dimensions::Vec2),
        Semantic::TexCoords(1) => ("TEXCOORD_1", validate::NORM_OR_FLOAT, Dimensions::Vec2),
        // RGB or RGBA.
        Semantic::Colors(0) => (
            "COLOR_0",
            validate::UNORM_OR_FLOAT,
            if dims == Dimensions::Vec3 {
                Dimensions::Vec3
            } else {
                Dimensions::Vec4
            },
        ),
        Semantic::Joints(0) => ("JOINTS_0", validate::JOINT, Dimensions::Vec4),
        Semantic::Weights(0) => ("WEIGHTS_0", validate::UNORM_OR_FLOAT, Dimensions::Vec4),
        _ => return None,
    };
    Some(Expect { what, types, dims })
}

/// One triangle primitive's vertex streams, all of the POSITION count.
struct Primitive {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    tangents: Option<Vec<Vec4>>,
    uvs: Option<Vec<Vec2>>,
    uvs1: Option<Vec<Vec2>>,
    colors: Option<Vec<Vec4>>,
    joints: Option<Vec<[u16; 4]>>,
    weights: Option<Vec<Vec4>>,
    targets: Vec<MorphTarget>,
    indices: Vec<u32>,
    material: u32,
}

/// A primitive's morph targets, every attribute checked and of the POSITION count (or absent).
fn read_targets(
    name: &str,
    prim: &gltf::Primitive,
    buffers: &[Vec<u8>],
    n: usize,
) -> Check<Vec<MorphTarget>> {
    let read = |a: Option<gltf::Accessor>, what: &'static str, types| -> Check<Vec<Vec3>> {
        let Some(a) = a else {
            return Ok(Vec::new());
        };
        validate::accessor(
            &a,
            &Expect {
                what,
                types,
                dims: Dimensions::Vec3,
            },
        )?;
        let v = attributes::read_as(Some(a), buffers, Vec3::from_array)?.unwrap_or_default();
        if v.len() != n {
            return Err(format!(
                "mesh '{name}': a morph target's {what} has {} entries for {n} vertices",
                v.len()
            ));
        }
        Ok(v)
    };
    prim.morph_targets()
        .map(|t| {
            Ok(MorphTarget {
                positions: read(t.positions(), "morph POSITION", validate::NORM_OR_FLOAT)?,
                normals: read(t.normals(), "morph NORMAL", validate::SNORM_OR_FLOAT)?,
                tangents: read(t.tangents(), "morph TANGENT", validate::SNORM_OR_FLOAT)?,
            })
        })
        .collect()
}

/// KHR_materials_variants: the chosen variant's index (None: the default look) and how many
/// the file names.
#[derive(Clone, Copy, Debug, Default)]
pub struct Variant {
    pub chosen: Option<u32>,
    pub count: u32,
}

/// The material a primitive takes: the one its KHR_materials_variants mapping gives the chosen
/// variant, else its own, else the default material. Every mapping is checked, whichever variant
/// is chosen.
fn primitive_material(
    name: &str,
    prim: &gltf::Primitive,
    default_material: u32,
    variant: Variant,
) -> Check<u32> {
    let mut mapped = None;
    for m in prim.mappings() {
        let material = m.material().index().ok_or(format!(
            "mesh '{name}': a KHR_materials_variants mapping names a material the file lacks"
        ))? as u32;
        for &v in m.variants() {
            if v >= variant.count {
                return Err(format!(
                    "mesh '{name}': a KHR_materials_variants mapping names variant {v}; the \
                     file has {}",
                    variant.count
                ));
            }
            if Some(v) == variant.chosen {
                mapped.get_or_insert(material);
            }
        }
    }
    Ok(mapped
        .or(prim.material().index().map(|i| i as u32))
        .unwrap_or(default_material))
}

fn read_primitive(
    name: &str,
    prim: &gltf::Primitive,
    buffers: &[Vec<u8>],
    default_material: u32,
    variant: Variant,
) -> Check<Primitive> {
    for (semantic, accessor) in prim.attributes() {
        if let Some(expect) = expectation(&semantic, accessor.dimensions()) {
            validate::accessor(&accessor, &expect)?;
        }
    }
    if let Some(indices) = prim.indices() {
        validate::accessor(
            &indices,
            &Expect {
                what: "index",
                types: validate::INDEX,
                dims: Dimensions::Scalar,
            },
        )?;
    }
    let attribute = |semantic: Semantic| prim.get(&semantic);
    let read3 = |s| attributes::read_as(attribute(s), buffers, Vec3::from_array);
    let read2 = |s| attributes::read_as(attribute(s), buffers, Vec2::from_array);
    let read4 = |s| attributes::read_as(attribute(s), buffers, Vec4::from_array);
    let positions = read3(Semantic::Positions)?
        .ok_or_else(|| format!("mesh '{name}' has a primitive without POSITION"))?;
    let n = positions.len();
    let same_count = |what: &str, len: usize| -> Check<()> {
        if len == n {
            Ok(())
        } else {
            Err(format!(
                "mesh '{name}': {what} has {len} entries for {n} vertices"
            ))
        }
    };
    // RGB colours get alpha 1.
    let colors = match attribute(Semantic::Colors(0)) {
        Some(a) if a.dimensions() == Dimensions::Vec3 => {
            attributes::read_as(Some(a), buffers, |c| Vec3::from_array(c).extend(1.0))?
        }
        _ => read4(Semantic::Colors(0))?,
    };
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let p = Primitive {
        targets: read_targets(name, prim, buffers, n)?,
        normals: read3(Semantic::Normals)?,
        tangents: read4(Semantic::Tangents)?,
        uvs: read2(Semantic::TexCoords(0))?,
        uvs1: read2(Semantic::TexCoords(1))?,
        colors,
        joints: reader.read_joints(0).map(|it| it.into_u16().collect()),
        weights: read4(Semantic::Weights(0))?,
        indices: match (prim.indices(), reader.read_indices()) {
            (None, _) => (0..n as u32).collect(),
            (Some(_), Some(it)) => it.into_u32().collect(),
            (Some(a), None) => {
                return Err(format!(
                    "mesh '{name}': index accessor {} cannot be read",
                    a.index()
                ))
            }
        },
        material: primitive_material(name, prim, default_material, variant)?,
        positions,
    };
    let lengths = [
        ("NORMAL", p.normals.as_ref().map(Vec::len)),
        ("TANGENT", p.tangents.as_ref().map(Vec::len)),
        ("TEXCOORD_0", p.uvs.as_ref().map(Vec::len)),
        ("TEXCOORD_1", p.uvs1.as_ref().map(Vec::len)),
        ("COLOR_0", p.colors.as_ref().map(Vec::len)),
        ("JOINTS_0", p.joints.as_ref().map(Vec::len)),
        ("WEIGHTS_0", p.weights.as_ref().map(Vec::len)),
    ];
    for (what, len) in lengths {
        if let Some(len) = len {
            same_count(what, len)?;
        }
    }
    if p.indices.iter().any(|&i| i as usize >= n) {
        return Err(format!("mesh '{name}' has an index out of range"));
    }
    Ok(p)
}

/// The triangles of a primitive's index sequence as a list, three indices each, with the winding
/// glTF 2.0 (3.7.2.1) defines: strip triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}), fan triangle i
/// is (v_{i+1}, v_{i+2}, v_0). A list's trailing indices that make no triangle are dropped.
fn triangle_list(mode: gltf::mesh::Mode, v: &[u32]) -> Vec<u32> {
    use gltf::mesh::Mode;
    let triangles = v.len().saturating_sub(2);
    match mode {
        Mode::TriangleStrip => (0..triangles)
            .flat_map(|i| [v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]])
            .collect(),
        Mode::TriangleFan => (0..triangles)
            .flat_map(|i| [v[i + 1], v[i + 2], v[0]])
            .collect(),
        _ => v[..v.len() / 3 * 3].to_vec(),
    }
}

/// Moves a mesh whose vertices lie far from its object's origin (by more than eight times its
/// own half-size) onto its bounds' centre, computed and subtracted in f64: an exporter that bakes
/// world coordinates into the vertices leaves a 2-unit room at 1e6, where f32 world coordinates
/// are 1/16 apart. The offset goes into the instances' transforms (`Mesh::offset`), which the
/// floating origin composes in f64 as it does node translations.
fn recentre(mesh: &mut Mesh) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for p in &mesh.positions {
        if crate::placeable::placeable(*p) {
            lo = lo.min(p.as_dvec3());
            hi = hi.max(p.as_dvec3());
        }
    }
    if lo.x > hi.x {
        return;
    }
    let centre = (lo + hi) * 0.5;
    let half = ((hi - lo) * 0.5).max_element();
    if centre.abs().max_element() <= 8.0 * half {
        return;
    }
    for p in &mut mesh.positions {
        if crate::placeable::placeable(*p) {
            *p = (p.as_dvec3() - centre).as_vec3();
        }
    }
    mesh.offset = centre;
}

pub fn load_mesh(
    mesh: &gltf::Mesh,
    buffers: &[Vec<u8>],
    default_material: u32,
    variant: Variant,
    materials: &[Material],
    warnings: &mut Vec<String>,
) -> Check<Mesh> {
    let name = mesh.name().unwrap_or("").to_string();
    let mut out = Mesh {
        name: name.clone(),
        ..Default::default()
    };
    let mut parts = Vec::new();
    for prim in mesh.primitives() {
        use gltf::mesh::Mode;
        if !matches!(
            prim.mode(),
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            warnings.push(format!(
                "mesh '{name}': primitive mode {:?} skipped (points and lines have no area)",
                prim.mode()
            ));
            continue;
        }
        for (semantic, _) in prim.attributes() {
            let ignored = match semantic {
                Semantic::TexCoords(n) if n >= 2 => Some(format!("TEXCOORD_{n}")),
                Semantic::Colors(n) if n >= 1 => Some(format!("COLOR_{n}")),
                Semantic::Joints(n) | Semantic::Weights(n) if n >= 1 => Some(format!(
                    "JOINTS_{n}/WEIGHTS_{n} (over four joint influences)"
                )),
                _ => None,
            };
            if let Some(what) = ignored {
                let warning = format!("mesh '{name}': {what} is ignored");
                if !warnings.contains(&warning) {
                    warnings.push(warning);
                }
            }
        }
        let mut p = read_primitive(&name, &prim, buffers, default_material, variant)?;
        p.indices = triangle_list(prim.mode(), &p.indices);
        parts.push(p);
    }
    let any_normals = parts.iter().any(|p| p.normals.is_some());
    let any_tangents = parts.iter().any(|p| p.tangents.is_some());
    let any_uvs = parts.iter().any(|p| p.uvs.is_some());
    let any_uvs1 = parts.iter().any(|p| p.uvs1.is_some());
    let any_colors = parts.iter().any(|p| p.colors.is_some());
    let target_count = parts.iter().map(|p| p.targets.len()).max().unwrap_or(0);
    if parts.iter().any(|p| p.targets.len() != target_count) {
        return Err(format!(
            "mesh '{name}': its primitives have different numbers of morph targets"
        ));
    }
    out.targets = vec![MorphTarget::default(); target_count];
    // Which attributes some primitive displaces, per target (the others' vertices get zeros).
    let displaced: Vec<[bool; 3]> = (0..target_count)
        .map(|t| {
            let any = |f: fn(&MorphTarget) -> bool| parts.iter().any(|p| f(&p.targets[t]));
            [
                any(|m| !m.positions.is_empty()),
                any(|m| !m.normals.is_empty()),
                any(|m| !m.tangents.is_empty()),
            ]
        })
        .collect();
    out.morph_weights = mesh.weights().map(<[f32]>::to_vec).unwrap_or_default();
    out.morph_weights.resize(target_count, 0.0);
    let any_skin = parts
        .iter()
        .any(|p| p.joints.is_some() && p.weights.is_some());
    for p in parts {
        let base = out.positions.len() as u32;
        let n = p.positions.len();
        for ((into, from), d) in out.targets.iter_mut().zip(p.targets).zip(&displaced) {
            let fill = |v: Vec<Vec3>| if v.is_empty() { vec![Vec3::ZERO; n] } else { v };
            if d[0] {
                into.positions.extend(fill(from.positions));
            }
            if d[1] {
                into.normals.extend(fill(from.normals));
            }
            if d[2] {
                into.tangents.extend(fill(from.tangents));
            }
        }
        out.positions.extend(p.positions);
        if any_normals {
            out.normals
                .extend(p.normals.unwrap_or_else(|| vec![Vec3::ZERO; n]));
        }
        if any_tangents {
            out.tangents
                .extend(p.tangents.unwrap_or_else(|| vec![Vec4::ZERO; n]));
        }
        if any_uvs {
            out.uvs.extend(p.uvs.unwrap_or_else(|| vec![Vec2::ZERO; n]));
        }
        if any_uvs1 {
            out.uvs1
                .extend(p.uvs1.unwrap_or_else(|| vec![Vec2::ZERO; n]));
        }
        // A primitive without COLOR_0 multiplies its base colour by one.
        if any_colors {
            out.colors
                .extend(p.colors.unwrap_or_else(|| vec![Vec4::ONE; n]));
        }
        if any_skin {
            out.joints
                .extend(p.joints.unwrap_or_else(|| vec![[0; 4]; n]));
            out.weights
                .extend(p.weights.unwrap_or_else(|| vec![Vec4::ZERO; n]));
        }
        for t in p.indices.chunks_exact(3) {
            out.indices.push([t[0] + base, t[1] + base, t[2] + base]);
            out.triangle_materials.push(p.material);
        }
    }
    // A skinned mesh is placed by its joints from the bind-pose positions as they are.
    if !any_skin {
        recentre(&mut out);
    }
    let unplaceable = out
        .positions
        .iter()
        .filter(|p| !crate::placeable::placeable(**p))
        .count();
    if unplaceable > 0 {
        warnings.push(format!(
            "mesh '{name}': {unplaceable} vertices are not finite or beyond {:e}; their triangles are not drawn",
            crate::placeable::MAX_COORDINATE
        ));
    }
    // A normal map (the base's or the coat's) or an anisotropic lobe needs a tangent frame.
    let uses = |f: fn(&Material) -> bool| {
        out.triangle_materials
            .iter()
            .any(|&m| f(&materials[m as usize]))
    };
    let anisotropic = uses(Material::has_anisotropy);
    let framed =
        anisotropic || uses(|m| m.normal_texture.is_some() || m.clearcoat_normal_texture.is_some());
    if framed && !any_tangents && any_uvs {
        out.tangents =
            crate::tangents::generate(&out.positions, &out.normals, &out.uvs, &out.indices);
    }
    if anisotropic && !any_tangents && !any_uvs {
        warnings.push(format!(
            "mesh '{name}': an anisotropic material without TANGENT or TEXCOORD_0 to make them from: its anisotropy follows an arbitrary direction"
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use gltf::mesh::Mode;

    #[test]
    fn strips_and_fans_triangulate_with_the_specs_winding() {
        let v = [10, 11, 12, 13, 14];
        assert_eq!(
            triangle_list(Mode::TriangleStrip, &v),
            [10, 11, 12, 11, 13, 12, 12, 13, 14]
        );
        assert_eq!(
            triangle_list(Mode::TriangleFan, &v),
            [11, 12, 10, 12, 13, 10, 13, 14, 10]
        );
        assert_eq!(triangle_list(Mode::Triangles, &v), [10, 11, 12]);
        assert!(triangle_list(Mode::TriangleStrip, &v[..2]).is_empty());
    }

    #[test]
    fn a_mesh_baked_far_away_is_recentred_exactly_and_a_centred_one_is_left() {
        let mut far = Mesh {
            positions: vec![Vec3::splat(1e6 - 1.0), Vec3::splat(1e6 + 1.0)],
            ..Default::default()
        };
        recentre(&mut far);
        assert_eq!(far.offset, DVec3::splat(1e6));
        assert_eq!(far.positions, [Vec3::splat(-1.0), Vec3::splat(1.0)]);
        let mut near = Mesh {
            positions: vec![Vec3::new(0.5, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0)],
            ..Default::default()
        };
        recentre(&mut near);
        assert_eq!(near.offset, DVec3::ZERO);
        assert_eq!(near.positions[0], Vec3::new(0.5, 0.0, 0.0));
    }
}

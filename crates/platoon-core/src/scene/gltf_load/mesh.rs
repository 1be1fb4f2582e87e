//! A glTF mesh (its triangle primitives merged) as one platoon mesh. Every accessor is checked
//! (validate::accessor) before the crate's reader decodes it.

use glam::{Vec2, Vec3, Vec4};
use gltf::accessor::Dimensions;
use gltf::mesh::Semantic;

use super::validate::{self, Check, Expect};
use crate::scene::*;

/// The accessor expectations of each vertex attribute platoon reads.
fn expectation(semantic: &Semantic) -> Option<Expect> {
    let (what, types, dims) = match semantic {
        Semantic::Positions => ("POSITION", validate::FLOAT, Dimensions::Vec3),
        Semantic::Normals => ("NORMAL", validate::FLOAT, Dimensions::Vec3),
        Semantic::Tangents => ("TANGENT", validate::FLOAT, Dimensions::Vec4),
        Semantic::TexCoords(0) => ("TEXCOORD_0", validate::UNORM_OR_FLOAT, Dimensions::Vec2),
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
    joints: Option<Vec<[u16; 4]>>,
    weights: Option<Vec<Vec4>>,
    indices: Vec<u32>,
    material: u32,
}

fn read_primitive(
    name: &str,
    prim: &gltf::Primitive,
    buffers: &[Vec<u8>],
    default_material: u32,
) -> Check<Primitive> {
    for (semantic, accessor) in prim.attributes() {
        if let Some(expect) = expectation(&semantic) {
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
    let reader = prim.reader(|b| buffers.get(b.index()).map(Vec::as_slice));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or_else(|| format!("mesh '{name}' has a primitive without POSITION"))?
        .map(Vec3::from_array)
        .collect();
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
    let p = Primitive {
        normals: reader
            .read_normals()
            .map(|it| it.map(Vec3::from_array).collect()),
        tangents: reader
            .read_tangents()
            .map(|it| it.map(Vec4::from_array).collect()),
        uvs: reader
            .read_tex_coords(0)
            .map(|it| it.into_f32().map(Vec2::from_array).collect()),
        joints: reader.read_joints(0).map(|it| it.into_u16().collect()),
        weights: reader
            .read_weights(0)
            .map(|it| it.into_f32().map(Vec4::from_array).collect()),
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
        material: prim
            .material()
            .index()
            .map(|i| i as u32)
            .unwrap_or(default_material),
        positions,
    };
    if let Some(v) = &p.normals {
        same_count("NORMAL", v.len())?;
    }
    if let Some(v) = &p.tangents {
        same_count("TANGENT", v.len())?;
    }
    if let Some(v) = &p.uvs {
        same_count("TEXCOORD_0", v.len())?;
    }
    if let Some(v) = &p.joints {
        same_count("JOINTS_0", v.len())?;
    }
    if let Some(v) = &p.weights {
        same_count("WEIGHTS_0", v.len())?;
    }
    if p.indices.iter().any(|&i| i as usize >= n) {
        return Err(format!("mesh '{name}' has an index out of range"));
    }
    Ok(p)
}

pub fn load_mesh(
    mesh: &gltf::Mesh,
    buffers: &[Vec<u8>],
    default_material: u32,
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
        if prim.mode() != gltf::mesh::Mode::Triangles {
            warnings.push(format!(
                "mesh '{name}': primitive mode {:?} skipped (triangles only)",
                prim.mode()
            ));
            continue;
        }
        parts.push(read_primitive(&name, &prim, buffers, default_material)?);
    }
    let any_normals = parts.iter().any(|p| p.normals.is_some());
    let any_tangents = parts.iter().any(|p| p.tangents.is_some());
    let any_uvs = parts.iter().any(|p| p.uvs.is_some());
    let any_skin = parts
        .iter()
        .any(|p| p.joints.is_some() && p.weights.is_some());
    for p in parts {
        let base = out.positions.len() as u32;
        let n = p.positions.len();
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
    let unplaceable = out
        .positions
        .iter()
        .filter(|p| !crate::flatten::bvh::placeable(**p))
        .count();
    if unplaceable > 0 {
        warnings.push(format!(
            "mesh '{name}': {unplaceable} vertices are not finite or beyond {:e}; their triangles are not drawn",
            crate::flatten::bvh::MAX_COORDINATE
        ));
    }
    let normal_mapped = out
        .triangle_materials
        .iter()
        .any(|&m| materials[m as usize].normal_texture.is_some());
    if normal_mapped && !any_tangents && any_uvs {
        out.tangents =
            crate::scene::tangents::generate(&out.positions, &out.normals, &out.uvs, &out.indices);
    }
    Ok(out)
}

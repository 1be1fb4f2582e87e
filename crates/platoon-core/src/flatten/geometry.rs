//! The geometry of a posed scene: per-mesh bottom levels (vertices, triangles in leaf order,
//! BVH nodes with global items) and the top level over the placed instances.

use std::sync::Arc;
use std::time::Duration;

use super::bvh::{self, FlatBvh};
use super::layout::{GpuTriangle, GpuVertex};
use super::GpuScene;
use crate::error::{Error, Result};
use crate::scene::{Instance, Mesh, Posed, Scene};

/// The meshes some instance uses; the others are left empty (a skinned mesh's bind pose is
/// replaced by its pose).
pub fn used_meshes(posed: &Posed) -> Vec<Arc<Mesh>> {
    let mut used = vec![false; posed.meshes.len()];
    for i in &posed.instances {
        used[i.mesh] = true;
    }
    posed
        .meshes
        .iter()
        .zip(&used)
        .map(|(m, &u)| if u { m.clone() } else { Default::default() })
        .collect()
}

/// Where each mesh landed in the global arrays.
pub(super) struct BottomLevel {
    /// The root item of each mesh's BVH.
    pub blas_root: Vec<u32>,
    /// The first global triangle of each mesh.
    pub tri_base: Vec<u32>,
}

/// Appends every mesh's vertices, triangles (in leaf order, with their emissive-light indices)
/// and BVH nodes to `g`, each mesh's nodes padded to its `node_capacity`.
pub(super) fn bottom_level(
    scene: &Scene,
    meshes: &[Arc<Mesh>],
    mesh_bvhs: &[FlatBvh],
    node_capacity: &[usize],
    g: &mut GpuScene,
) -> Result<BottomLevel> {
    let mut blas_root = Vec::with_capacity(meshes.len());
    let mut tri_base = Vec::with_capacity(meshes.len());
    for ((mesh, flat), &capacity) in meshes.iter().zip(mesh_bvhs).zip(node_capacity) {
        let vbase = g.vertices.len() as u32;
        let tbase = g.triangles.len() as u32;
        let nbase = g.blas_nodes.len() as u32;
        tri_base.push(tbase);
        for (i, p) in mesh.positions.iter().enumerate() {
            let uv = mesh.uvs.get(i).copied().unwrap_or_default();
            let n = mesh.normals.get(i).copied().unwrap_or_default();
            let t = mesh.tangents.get(i).copied().unwrap_or_default();
            g.vertices.push(GpuVertex {
                position_u: [p.x, p.y, p.z, uv.x],
                normal_v: [n.x, n.y, n.z, uv.y],
                tangent: t.to_array(),
            });
        }
        let mut local_light = 0u32;
        for &orig in &flat.order {
            let tri = mesh.indices[orig as usize];
            let material = mesh.triangle_materials[orig as usize];
            for &v in &tri {
                let p = mesh.positions[v as usize];
                g.triangle_positions.push([p.x, p.y, p.z, 0.0]);
            }
            g.triangles.push(GpuTriangle {
                v: tri.map(|v| v + vbase),
                material,
            });
            if scene.materials[material as usize].is_emissive() {
                g.triangle_lights.push(local_light);
                local_light += 1;
            } else {
                g.triangle_lights.push(u32::MAX);
            }
        }
        let too_large = || {
            Error::Invalid(format!(
                "more than {} triangles or BVH nodes: too large for the kernel's node items",
                bvh::MAX_ITEM_INDEX
            ))
        };
        for n in &flat.nodes {
            g.blas_nodes
                .push(n.rebased(nbase, tbase).ok_or_else(too_large)?);
        }
        let padding = capacity.saturating_sub(flat.nodes.len());
        g.blas_nodes
            .extend(std::iter::repeat_n(bvh::BvhNode::default(), padding));
        blas_root.push(bvh::rebase_item(flat.root, nbase, tbase).ok_or_else(too_large)?);
    }
    g.triangle_count = g.triangles.len();
    Ok(BottomLevel {
        blas_root,
        tri_base,
    })
}

/// The top level over the instances of non-empty meshes whose world box is placeable: its
/// nodes, root and the scene radius go into `g`; returns the BVH (its `order` indexes the
/// returned instances), the instances and the build time.
pub(super) fn top_level<'a>(
    posed: &'a Posed,
    mesh_bvhs: &[FlatBvh],
    g: &mut GpuScene,
) -> (FlatBvh, Vec<&'a Instance>, Duration) {
    let (live, boxes): (Vec<&Instance>, Vec<obvhs::aabb::Aabb>) = posed
        .instances
        .iter()
        .filter(|i| !mesh_bvhs[i.mesh].is_empty())
        .map(|i| {
            let b = bvh::transform_bounds(&i.object_to_world, mesh_bvhs[i.mesh].bounds());
            (i, b)
        })
        .filter(|(_, b)| bvh::placeable(b.min.into()) && bvh::placeable(b.max.into()))
        .unzip();
    let (tlas, time) = bvh::timed(|| bvh::build_instance_bvh(&boxes));
    g.tlas_nodes = tlas.nodes.clone();
    g.tlas_root = tlas.root;
    let (lo, hi) = tlas.bounds();
    g.scene_radius = ((hi.as_dvec3() - lo.as_dvec3()).length() * 0.5).max(1e-3);
    (tlas, live, time)
}

//! The geometry of a posed scene: per-mesh bottom levels (vertices, triangles in leaf order,
//! BVH nodes with global items) and the top level over the placed instances.

use std::sync::Arc;
use std::time::Duration;

use super::bvh::{self, FlatBvh};
use super::gpu_scene::{GpuScene, MeshRegion};
use super::layout::{GpuTriangle, GpuVertex, GpuVertexExtra, CORNER_ALPHA_TESTED};
use platoon_scene::error::{Error, Result};
use platoon_scene::{AlphaMode, Instance, Mesh, Posed, Scene};

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

/// Appends every mesh's vertices, triangles (in leaf order, with their emissive-light indices)
/// and BVH nodes to `g`, each mesh's nodes padded to its `node_capacity`, and records where.
pub(super) fn bottom_level(
    scene: &Scene,
    meshes: &[Arc<Mesh>],
    mesh_bvhs: &[&FlatBvh],
    node_capacity: &[usize],
    g: &mut GpuScene,
) -> Result<()> {
    g.regions.clear();
    // Whenever the kernel may read them (vertex colours, or a texture at TEXCOORD_1).
    let extras = scene
        .meshes
        .iter()
        .any(|m| !m.colors.is_empty() || !m.uvs1.is_empty())
        || scene
            .materials
            .iter()
            .any(|m| m.textures().any(|t| t.tex_coord == 1));
    for ((mesh, flat), &capacity) in meshes.iter().zip(mesh_bvhs).zip(node_capacity) {
        let region = MeshRegion {
            vertex_base: g.vertices.len() as u32,
            vertex_count: mesh.positions.len() as u32,
            triangle_base: g.triangles.len() as u32,
            triangle_count: flat.order.len() as u32,
            node_base: g.blas_nodes.len() as u32,
            node_capacity: capacity.max(flat.nodes.len()) as u32,
            root: 0,
        };
        g.vertices.resize(
            g.vertices.len() + region.vertex_count as usize,
            Default::default(),
        );
        if extras {
            g.vertex_extras.resize(g.vertices.len(), Default::default());
        }
        let triangles = region.triangle_count as usize;
        g.triangle_positions
            .resize(g.triangle_positions.len() + 3 * triangles, [0.0; 4]);
        g.triangles
            .resize(g.triangles.len() + triangles, Default::default());
        g.triangle_lights
            .resize(g.triangle_lights.len() + triangles, u32::MAX);
        g.blas_nodes.resize(
            g.blas_nodes.len() + region.node_capacity as usize,
            Default::default(),
        );
        g.regions.push(region);
        write_mesh(scene, g.regions.len() - 1, mesh, flat, g)?;
    }
    g.triangle_count = g.triangles.len();
    Ok(())
}

/// Writes `mesh` and its BVH `flat` into region `index` of `g` (whose counts it must match,
/// its nodes fitting the region's capacity): the whole of a mesh's data, in place.
pub(super) fn write_mesh(
    scene: &Scene,
    index: usize,
    mesh: &Mesh,
    flat: &FlatBvh,
    g: &mut GpuScene,
) -> Result<()> {
    let r = g.regions[index];
    check_fits(index, r, mesh, flat)?;
    write_vertices(mesh, r, g);
    let (tbase, vbase) = (r.triangle_base as usize, r.vertex_base);
    let mut local_light = 0u32;
    for (k, &orig) in flat.order.iter().enumerate() {
        let tri = mesh.indices[orig as usize];
        let material = mesh.triangle_materials[orig as usize];
        g.triangles[tbase + k] = GpuTriangle {
            v: tri.map(|v| v + vbase),
            material,
        };
        g.triangle_lights[tbase + k] = if scene.materials[material as usize].is_emissive() {
            local_light += 1;
            local_light - 1
        } else {
            u32::MAX
        };
    }
    let triangles = g.triangles.len();
    g.hit_names.set_mesh(mesh, tbase, &flat.order, triangles);
    write_corners(scene, mesh, &flat.order, r, g);
    write_nodes(index, flat, g)
}

/// Writes `flat`'s nodes over region `index`'s node capacity (the slots past them cleared) and
/// its root: all a new tree over the triangles in place needs, when it keeps their order.
pub(super) fn write_nodes(index: usize, flat: &FlatBvh, g: &mut GpuScene) -> Result<()> {
    let r = g.regions[index];
    if !tree_fits(r, flat) {
        return Err(no_longer_fits(index));
    }
    let too_large = || {
        Error::Invalid(format!(
            "more than {} triangles or BVH nodes: too large for the kernel's node items",
            bvh::MAX_ITEM_INDEX
        ))
    };
    let nodes = &mut g.blas_nodes[r.node_base as usize..][..r.node_capacity as usize];
    for (slot, n) in nodes.iter_mut().enumerate() {
        *n = match flat.nodes.get(slot) {
            Some(n) => n
                .rebased(r.node_base, r.triangle_base)
                .ok_or_else(too_large)?,
            None => Default::default(),
        };
    }
    g.regions[index].root =
        bvh::rebase_item(flat.root, r.node_base, r.triangle_base).ok_or_else(too_large)?;
    Ok(())
}

/// Rewrites region `index` of `g` after its mesh deformed and its BVH `flat` was refitted (the
/// triangle order and the nodes' shape unchanged since the region was written): the vertices,
/// the triangles' `corners` (in leaf order, three each) and the nodes' boxes, nothing else.
pub(super) fn write_refitted(
    index: usize,
    mesh: &Mesh,
    flat: &FlatBvh,
    corners: &[[f32; 4]],
    g: &mut GpuScene,
) -> Result<()> {
    let r = g.regions[index];
    check_fits(index, r, mesh, flat)?;
    if corners.len() != 3 * flat.order.len() {
        return Err(Error::Invalid(format!(
            "mesh {index}: {} corners for {} triangles",
            corners.len(),
            flat.order.len()
        )));
    }
    write_vertices(mesh, r, g);
    // The positions only: w keeps what the whole write put there (the refit does not know the
    // materials).
    let slots = &mut g.triangle_positions[3 * r.triangle_base as usize..][..corners.len()];
    for (slot, c) in slots.iter_mut().zip(corners) {
        slot[..3].copy_from_slice(&c[..3]);
    }
    let nodes = &mut g.blas_nodes[r.node_base as usize..][..flat.nodes.len()];
    for (n, f) in nodes.iter_mut().zip(&flat.nodes) {
        // The items stay as rebased when the region was written whole.
        n.min0 = f.min0;
        n.max0 = f.max0;
        n.min1 = f.min1;
        n.max1 = f.max1;
    }
    Ok(())
}

/// Whether `mesh` and its BVH `flat` fit region `r` (mesh `index`): the same vertex and triangle
/// counts, the nodes within its capacity.
fn check_fits(index: usize, r: MeshRegion, mesh: &Mesh, flat: &FlatBvh) -> Result<()> {
    if r.vertex_count as usize != mesh.positions.len() || !tree_fits(r, flat) {
        return Err(no_longer_fits(index));
    }
    Ok(())
}

/// Whether BVH `flat` fits region `r`: over as many triangles, its nodes within the capacity.
fn tree_fits(r: MeshRegion, flat: &FlatBvh) -> bool {
    r.triangle_count as usize == flat.order.len() && flat.nodes.len() <= r.node_capacity as usize
}

fn no_longer_fits(index: usize) -> Error {
    Error::Invalid(format!(
        "mesh {index} no longer fits its region (vertices, triangles or BVH nodes changed)"
    ))
}

fn write_vertices(mesh: &Mesh, r: MeshRegion, g: &mut GpuScene) {
    if !g.vertex_extras.is_empty() {
        let extras = &mut g.vertex_extras[r.vertex_base as usize..][..r.vertex_count as usize];
        let unorm16 = |a: f32, b: f32| {
            let q = |c: f32| (c.clamp(0.0, 1.0) * 65535.0).round() as u32;
            q(a) | q(b) << 16
        };
        for (i, e) in extras.iter_mut().enumerate() {
            let uv1 = mesh.uvs1.get(i).copied().unwrap_or_default();
            let c = mesh.colors.get(i).copied().unwrap_or(glam::Vec4::ONE);
            *e = GpuVertexExtra {
                uv1: uv1.to_array(),
                color: [unorm16(c.x, c.y), unorm16(c.z, c.w)],
            };
        }
    }
    let vertices = &mut g.vertices[r.vertex_base as usize..][..r.vertex_count as usize];
    for (i, (v, p)) in vertices.iter_mut().zip(&mesh.positions).enumerate() {
        let uv = mesh.uvs.get(i).copied().unwrap_or_default();
        let n = mesh.normals.get(i).copied().unwrap_or_default();
        let t = mesh.tangents.get(i).copied().unwrap_or_default();
        *v = GpuVertex {
            position_u: [p.x, p.y, p.z, uv.x],
            normal_v: [n.x, n.y, n.z, uv.y],
            tangent: t.to_array(),
        };
    }
}

/// Each triangle's three corners, in leaf `order` (what the kernel intersects), the first one's
/// w [`CORNER_ALPHA_TESTED`] where the triangle's material lets light through by its alpha.
fn write_corners(scene: &Scene, mesh: &Mesh, order: &[u32], r: MeshRegion, g: &mut GpuScene) {
    let corners = &mut g.triangle_positions[3 * r.triangle_base as usize..][..3 * order.len()];
    for (slot, &orig) in corners.chunks_exact_mut(3).zip(order) {
        for (c, &v) in slot.iter_mut().zip(&mesh.indices[orig as usize]) {
            let p = mesh.positions[v as usize];
            *c = [p.x, p.y, p.z, 0.0];
        }
        let material = &scene.materials[mesh.triangle_materials[orig as usize] as usize];
        if material.alpha_mode != AlphaMode::Opaque {
            slot[0][3] = CORNER_ALPHA_TESTED;
        }
    }
}

/// The top level over the instances of non-empty meshes whose world box is placeable: its
/// nodes, root and the scene radius go into `g`; returns the BVH (its `order` indexes the
/// returned instances), the instances and the build time.
pub(super) fn top_level<'a>(
    posed: &'a Posed,
    mesh_bvhs: &[&FlatBvh],
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
    let (tlas, time) = bvh::timed(|| super::instance_bvh::build_instance_bvh(&boxes));
    g.tlas_nodes = tlas.nodes.clone();
    g.tlas_root = tlas.root;
    let (lo, hi) = tlas.bounds();
    g.scene_radius = ((hi.as_dvec3() - lo.as_dvec3()).length() * 0.5).max(1e-3);
    g.scene_center = ((lo.as_dvec3() + hi.as_dvec3()) * 0.5).as_vec3().to_array();
    (tlas, live, time)
}

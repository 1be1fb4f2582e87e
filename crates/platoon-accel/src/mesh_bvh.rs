//! A mesh's BVH at the quality its size calls for: obvhs' builds ([`super::bvh`]) or the binned
//! SAH's ([`super::binned_sah`]) behind one call, so that neither builder's module imports the
//! other.

use obvhs::triangle::Triangle;
use rayon::prelude::*;

use super::bvh::STATIC_COLLAPSE_TRAVERSAL_COST;
use super::bvh::{build_bvh2, flatten_mesh, placeable_triangles, BuildQuality, FlatBvh};
use platoon_scene::Mesh;

/// The BVH of a mesh's triangles, built once ([`BuildQuality::for_static`]). Triangles with an
/// unplaceable corner (NaN or Inf from a file or from skinning) are left out of it, so they are
/// never drawn.
pub fn build_mesh_bvh(mesh: &Mesh) -> FlatBvh {
    build_mesh_bvh_at(mesh, None)
}

/// [`build_mesh_bvh`] at `quality` (None: by the size rule).
pub fn build_mesh_bvh_at(mesh: &Mesh, quality: Option<BuildQuality>) -> FlatBvh {
    let quality = quality.unwrap_or(BuildQuality::for_static(mesh.indices.len()));
    if quality == BuildQuality::Quick {
        // A big mesh: no array of its triangles beside the build's own.
        return super::binned_sah::build_mesh(
            &mesh.positions,
            &mesh.indices,
            STATIC_COLLAPSE_TRAVERSAL_COST,
        );
    }
    let (tris, original) = placeable_triangles(mesh);
    if tris.is_empty() {
        return FlatBvh::default();
    }
    build_flat(&tris, &original, quality)
}

/// The flattened BVH of `tris` (mesh triangles `original`) at `quality`.
pub fn build_flat(tris: &[Triangle], original: &[u32], quality: BuildQuality) -> FlatBvh {
    match quality {
        BuildQuality::Quick => {
            let mut flat = super::binned_sah::build(tris, STATIC_COLLAPSE_TRAVERSAL_COST);
            for o in &mut flat.order {
                *o = original[*o as usize];
            }
            flat
        }
        _ => flatten_mesh(&build_bvh2(tris, quality), original),
    }
}

/// Per-mesh BVHs at `quality` (None: each by the size rule), built in parallel on the CPU
/// threads.
pub fn build_mesh_bvhs(
    meshes: &[std::sync::Arc<Mesh>],
    quality: Option<BuildQuality>,
) -> Vec<FlatBvh> {
    meshes
        .par_iter()
        .map(|m| build_mesh_bvh_at(m, quality))
        .collect()
}

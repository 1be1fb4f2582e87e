//! Which points a BVH can hold: the loader warns about the others, the scene's bounds leave them
//! out, and the BVH builders drop the triangles that touch them (`flatten::bvh`).

use glam::Vec3;

/// Largest coordinate magnitude a triangle may have to enter a BVH. Far beyond it, box extents
/// and surface areas overflow f32 and the builder's arithmetic turns to NaN (obvhs asserts on
/// NaN bounds); a vertex at 1e30 still renders.
pub const MAX_COORDINATE: f32 = 1e32;

/// Whether a point can be placed in a BVH: finite and within [`MAX_COORDINATE`].
pub fn placeable(p: Vec3) -> bool {
    p.is_finite() && p.abs().max_element() <= MAX_COORDINATE
}

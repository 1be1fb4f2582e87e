//! Per-vertex tangents from UVs, for normal-mapped meshes that ship without TANGENT.
//! Accumulates per-triangle tangents (Lengyel's method), not MikkTSpace: close for smooth UV
//! layouts, can differ from the baker's tangent frame at UV seams.

use glam::{Vec2, Vec3, Vec4};

pub fn generate(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[[u32; 3]],
) -> Vec<Vec4> {
    let n = positions.len();
    let mut tan = vec![Vec3::ZERO; n];
    let mut bit = vec![Vec3::ZERO; n];
    for tri in indices {
        let [a, b, c] = tri.map(|i| i as usize);
        let (e1, e2) = (positions[b] - positions[a], positions[c] - positions[a]);
        let (d1, d2) = (uvs[b] - uvs[a], uvs[c] - uvs[a]);
        let det = d1.x * d2.y - d2.x * d1.y;
        if det.abs() < 1e-20 {
            continue;
        }
        let r = 1.0 / det;
        let t = (e1 * d2.y - e2 * d1.y) * r;
        let bt = (e2 * d1.x - e1 * d2.x) * r;
        for v in [a, b, c] {
            tan[v] += t;
            bit[v] += bt;
        }
    }
    (0..n)
        .map(|v| {
            let nrm = normals.get(v).copied().unwrap_or(Vec3::Z);
            let t = (tan[v] - nrm * nrm.dot(tan[v])).normalize_or_zero();
            let t = if t == Vec3::ZERO {
                nrm.any_orthonormal_vector()
            } else {
                t
            };
            let w = if nrm.cross(t).dot(bit[v]) < 0.0 {
                -1.0
            } else {
                1.0
            };
            t.extend(w)
        })
        .collect()
}

//! Per-vertex tangents for meshes that ship without TANGENT but need a tangent frame (a normal
//! map, the coat's own, or an anisotropic material): MikkTSpace, the frame glTF prescribes and
//! bakers write normal maps in, through `bevy_mikktspace` (a safe port that reproduces the
//! reference implementation). MikkTSpace gives every face corner a tangent; corners that share a
//! vertex share its attributes, which MikkTSpace welds, so they get the same one. Vertices no
//! face reaches keep a vector orthogonal to their normal.

use bevy_mikktspace::{Geometry, TangentSpace};
use glam::{Vec2, Vec3, Vec4};

/// A mesh's triangles as MikkTSpace reads them, and the tangents it writes.
struct Corners<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    indices: &'a [[u32; 3]],
    tangents: Vec<Vec4>,
}

impl Corners<'_> {
    fn vertex(&self, face: usize, corner: usize) -> usize {
        self.indices[face][corner] as usize
    }
}

impl Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.vertex(face, vert)].to_array()
    }

    /// The vertex normal; a flat-shaded mesh (no normals) its face's.
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        match self.normals.get(self.vertex(face, vert)) {
            Some(n) => n.to_array(),
            None => {
                let [a, b, c] = self.indices[face].map(|i| self.positions[i as usize]);
                (b - a).cross(c - a).normalize_or_zero().to_array()
            }
        }
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.uvs[self.vertex(face, vert)].to_array()
    }

    fn set_tangent(&mut self, tangent_space: Option<TangentSpace>, face: usize, vert: usize) {
        if let Some(t) = tangent_space {
            let v = self.vertex(face, vert);
            self.tangents[v] = Vec4::from_array(t.tangent_encoded());
        }
    }
}

/// The MikkTSpace tangent of every vertex (xyz, w = the bitangent's sign: glTF's bitangent is
/// cross(normal, tangent) * w), from the UVs.
pub fn generate(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[[u32; 3]],
) -> Vec<Vec4> {
    let mut corners = Corners {
        positions,
        normals,
        uvs,
        indices,
        tangents: vec![Vec4::ZERO; positions.len()],
    };
    // It fails only on a mesh without faces, which has no corners to write either.
    let _ = bevy_mikktspace::generate_tangents(&mut corners);
    corners
        .tangents
        .into_iter()
        .enumerate()
        .map(|(v, t)| {
            if t.truncate().length_squared() > 0.0 {
                t
            } else {
                let n = normals.get(v).copied().unwrap_or(Vec3::Z);
                n.any_orthonormal_vector().extend(1.0)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit quad in the xy plane facing +z, UVs (u(x), y).
    fn quad_tangents(u: impl Fn(f32) -> f32) -> Vec<Vec4> {
        let positions =
            [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| Vec3::new(x, y, 0.0));
        let uvs = positions.map(|p| Vec2::new(u(p.x), p.y));
        generate(&positions, &[Vec3::Z; 4], &uvs, &[[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn the_tangent_follows_u_and_the_sign_the_uvs_handedness() {
        for t in quad_tangents(|x| x) {
            assert!((t - Vec4::new(1.0, 0.0, 0.0, 1.0)).length() < 1e-5, "{t}");
        }
        // Mirrored in u: the tangent turns to -x and the bitangent (along +v, +y) must be
        // cross(+z, -x) * w = -y * w, so w = -1.
        for t in quad_tangents(|x| 1.0 - x) {
            assert!((t - Vec4::new(-1.0, 0.0, 0.0, -1.0)).length() < 1e-5, "{t}");
        }
    }

    #[test]
    fn a_spheres_tangents_are_unit_and_orthogonal_to_its_normals() {
        let (rings, segments) = (12, 24);
        let mut positions = Vec::new();
        let mut uvs = Vec::new();
        for r in 0..=rings {
            for s in 0..=segments {
                let (theta, phi) = (
                    std::f32::consts::PI * r as f32 / rings as f32,
                    std::f32::consts::TAU * s as f32 / segments as f32,
                );
                positions.push(Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    -theta.sin() * phi.sin(),
                ));
                uvs.push(Vec2::new(
                    s as f32 / segments as f32,
                    r as f32 / rings as f32,
                ));
            }
        }
        let row = segments + 1;
        let mut indices = Vec::new();
        for r in 0..rings {
            for s in 0..segments {
                let a = r * row + s;
                indices.push([a, a + row, a + row + 1]);
                indices.push([a, a + row + 1, a + 1]);
            }
        }
        let tangents = generate(&positions, &positions, &uvs, &indices);
        for (t, n) in tangents.iter().zip(&positions) {
            assert!((t.truncate().length() - 1.0).abs() < 1e-4, "{t}");
            assert!(t.truncate().dot(*n).abs() < 1e-4, "{t} against {n}");
            assert!(t.w.abs() == 1.0);
        }
    }
}

//! Midpoint subdivision (1:4): the same surfaces with more vertices, for methods that carry
//! light at vertices (vertex links' tessellation sweep). Every attribute at an edge's midpoint
//! is the mean of its ends, which is what interpolation across the triangle gave there, so the
//! image stays the same: flat faces stay flat, and shading normals, tangents, UVs and colours
//! interpolate as before (a normal is left unnormalised for that reason: the kernel normalises
//! after interpolating). Skinned and morphed meshes are left as they are: their vertices move by
//! weights that a midpoint's mean would not reproduce.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

use super::{Mesh, Scene};

impl Mesh {
    /// Each triangle cut into four at its edges' midpoints (a midpoint shared by the triangles
    /// of its edge); None for a skinned or morphed mesh.
    pub fn subdivided(&self) -> Option<Mesh> {
        if !self.joints.is_empty() || !self.targets.is_empty() {
            return None;
        }
        let mut m = Mesh {
            indices: Vec::with_capacity(4 * self.indices.len()),
            triangle_materials: Vec::with_capacity(4 * self.triangle_materials.len()),
            ..self.clone()
        };
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |m: &mut Mesh, a: u32, b: u32| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (i, j) = (a.min(b) as usize, a.max(b) as usize);
                mean_into(&mut m.positions, i, j, |p, q| (p + q) * 0.5);
                mean_into(&mut m.normals, i, j, |p: Vec3, q| (p + q) * 0.5);
                mean_into(&mut m.tangents, i, j, |p: Vec4, q: Vec4| {
                    ((p.truncate() + q.truncate()) * 0.5).extend(p.w)
                });
                mean_into(&mut m.uvs, i, j, |p: Vec2, q| (p + q) * 0.5);
                mean_into(&mut m.uvs1, i, j, |p: Vec2, q| (p + q) * 0.5);
                mean_into(&mut m.colors, i, j, |p: Vec4, q| (p + q) * 0.5);
                (m.positions.len() - 1) as u32
            })
        };
        for (t, &[a, b, c]) in self.indices.iter().enumerate() {
            let (ab, bc, ca) = (
                midpoint(&mut m, a, b),
                midpoint(&mut m, b, c),
                midpoint(&mut m, c, a),
            );
            m.indices
                .extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
            let material = self.triangle_materials.get(t).copied().unwrap_or(0);
            m.triangle_materials.extend([material; 4]);
        }
        Some(m)
    }
}

/// Appends the mean of `v[i]` and `v[j]` to an attribute that is present (empty: absent).
fn mean_into<T: Copy>(v: &mut Vec<T>, i: usize, j: usize, mean: impl Fn(T, T) -> T) {
    if !v.is_empty() {
        let m = mean(v[i], v[j]);
        v.push(m);
    }
}

impl Scene {
    /// Every mesh that can be subdivided (`Mesh::subdivided`) subdivided `levels` times; how
    /// many were.
    pub fn subdivide(&mut self, levels: u32) -> usize {
        let mut count = 0;
        for mesh in &mut self.meshes {
            let mut m = (**mesh).clone();
            let mut done = false;
            for _ in 0..levels {
                match m.subdivided() {
                    Some(s) => {
                        m = s;
                        done = true;
                    }
                    None => break,
                }
            }
            if done {
                *mesh = Arc::new(m);
                count += 1;
            }
        }
        count
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed tetrahedron with normals and UVs.
    fn tetrahedron() -> Mesh {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        Mesh {
            normals: positions.iter().map(|p| *p - Vec3::splat(0.25)).collect(),
            uvs: positions.iter().map(|p| p.truncate()).collect(),
            positions,
            indices: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
            triangle_materials: vec![0, 1, 2, 3],
            ..Default::default()
        }
    }

    fn area(m: &Mesh) -> f32 {
        m.indices
            .iter()
            .map(|&[a, b, c]| {
                let p = |i: u32| m.positions[i as usize];
                0.5 * (p(b) - p(a)).cross(p(c) - p(a)).length()
            })
            .sum()
    }

    #[test]
    fn a_closed_mesh_stays_closed_with_its_surface_and_its_interpolation() {
        let t = tetrahedron();
        let s = t.subdivided().unwrap();
        // 4 + 6 edge midpoints; 4 x 4 triangles; Euler characteristic 2 kept (V - E + F).
        assert_eq!((s.positions.len(), s.indices.len()), (10, 16));
        let edges = 3 * s.indices.len() / 2;
        assert_eq!(s.positions.len() + s.indices.len() - edges, 2);
        assert!((area(&s) - area(&t)).abs() < 1e-6);
        // Materials follow their triangle; attributes are their ends' means.
        assert_eq!(&s.triangle_materials[4..8], &[1; 4]);
        for (k, &[a, b, c]) in t.indices.iter().enumerate() {
            let [_, ab, _] = s.indices[4 * k];
            let (a, b, ab) = (a as usize, b as usize, ab as usize);
            assert_eq!(s.positions[ab], (t.positions[a] + t.positions[b]) * 0.5);
            assert_eq!(s.normals[ab], (t.normals[a] + t.normals[b]) * 0.5);
            assert_eq!(s.uvs[ab], (t.uvs[a] + t.uvs[b]) * 0.5);
            let _ = c;
        }
        // Twice: 16 x 4 triangles, the same area.
        let mut scene = Scene {
            meshes: vec![Arc::new(t.clone())],
            ..Default::default()
        };
        assert_eq!(scene.subdivide(2), 1);
        assert_eq!(scene.meshes[0].indices.len(), 64);
        assert!((area(&scene.meshes[0]) - area(&t)).abs() < 1e-5);
    }

    #[test]
    fn skinned_meshes_are_left_as_they_are() {
        let mut t = tetrahedron();
        t.joints = vec![[0; 4]; 4];
        t.weights = vec![Vec4::X; 4];
        assert!(t.subdivided().is_none());
        let mut scene = Scene {
            meshes: vec![Arc::new(t)],
            ..Default::default()
        };
        assert_eq!(scene.subdivide(1), 0);
    }
}

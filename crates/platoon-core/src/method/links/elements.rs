//! Elements: the vertices radiance is solved at. glTF splits a vertex wherever an attribute
//! changes (a UV seam, a hard edge's normals), so a mesh's vertices are welded first: vertices
//! at the same position whose normals lie within the feature angle are one element (a seam
//! disappears, a crease stays two elements, one per side). The element's normal is the
//! normalised sum of its vertices'. Welding runs in vertex order, so the elements are a pure
//! function of the mesh.

use std::collections::HashMap;

use glam::Vec3;

use super::gather::Rings;

/// A mesh's vertices welded into elements, with each element's one-ring (the elements it shares
/// a triangle with, in order of first appearance) for smoothing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Welded {
    pub element_of_vertex: Vec<u32>,
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub rings: Rings,
}

/// Welds the vertices (`positions`, `normals`) of the `triangles` that sit at the same position
/// (bit for bit: exporters duplicate a seam's vertices exactly) with normals within the feature
/// angle (n . n' > `cos_feature`) of the first vertex of an element.
pub fn weld(
    positions: &[Vec3],
    normals: &[Vec3],
    triangles: &[[u32; 3]],
    cos_feature: f32,
) -> Welded {
    assert_eq!(positions.len(), normals.len());
    let mut w = Welded::default();
    // The elements at each position, and the normal of the first vertex of each.
    let mut at: HashMap<[u32; 3], Vec<u32>> = HashMap::new();
    let mut first_normal: Vec<Vec3> = Vec::new();
    let mut sums: Vec<Vec3> = Vec::new();
    for (&p, &n) in positions.iter().zip(normals) {
        let key = p.to_array().map(f32::to_bits);
        let here = at.entry(key).or_default();
        let element = match here
            .iter()
            .find(|&&e| first_normal[e as usize].dot(n) > cos_feature)
        {
            Some(&e) => e,
            None => {
                let e = w.positions.len() as u32;
                here.push(e);
                w.positions.push(p);
                first_normal.push(n);
                sums.push(Vec3::ZERO);
                e
            }
        };
        sums[element as usize] += n;
        w.element_of_vertex.push(element);
    }
    w.normals = sums.iter().map(|s| s.normalize_or_zero()).collect();
    w.rings = rings(&w.element_of_vertex, w.positions.len(), triangles);
    w
}

/// Each element's neighbours across the triangles, in order of first appearance.
fn rings(element_of_vertex: &[u32], elements: usize, triangles: &[[u32; 3]]) -> Rings {
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); elements];
    for t in triangles {
        let e = t.map(|v| element_of_vertex[v as usize]);
        for i in 0..3 {
            for j in 0..3 {
                if e[i] != e[j] && !lists[e[i] as usize].contains(&e[j]) {
                    lists[e[i] as usize].push(e[j]);
                }
            }
        }
    }
    let mut rings = Rings {
        offsets: vec![0],
        neighbours: Vec::new(),
    };
    for l in lists {
        rings.neighbours.extend(l);
        rings.offsets.push(rings.neighbours.len() as u32);
    }
    rings
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Two triangles of a unit quad facing +z, the shared edge's vertices written twice (a
    /// seam): positions, normals, triangles.
    pub(in super::super) fn seamed_quad() -> (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>) {
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::X,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::Y,
        ];
        (p, vec![Vec3::Z; 6], vec![[0, 1, 2], [3, 4, 5]])
    }

    /// A unit cube as exporters write it: four vertices a face, each with the face's normal.
    fn cube() -> (Vec<Vec3>, Vec<Vec3>, Vec<[u32; 3]>) {
        let (mut p, mut n, mut t) = (Vec::new(), Vec::new(), Vec::new());
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let mut normal = Vec3::ZERO;
                normal[axis] = sign;
                let (u, v) = (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3]);
                let base = p.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    p.push(normal * 0.5 + u * 0.5 * a + v * 0.5 * b);
                    n.push(normal);
                }
                t.push([base, base + 1, base + 2]);
                t.push([base, base + 2, base + 3]);
            }
        }
        (p, n, t)
    }

    #[test]
    fn a_cubes_creases_are_kept_within_the_feature_angle_and_welded_past_it() {
        let (p, n, t) = cube();
        let sharp = weld(&p, &n, &t, 30f32.to_radians().cos());
        assert_eq!(sharp.positions.len(), 24);
        // A face's corner sees the face's three other corners only.
        assert_eq!(sharp.rings.offsets[1] - sharp.rings.offsets[0], 3);
        let round = weld(&p, &n, &t, 100f32.to_radians().cos());
        assert_eq!(round.positions.len(), 8);
        // A corner of the cube: three faces meet, its normal the diagonal; it shares a
        // triangle with three edge neighbours and the three faces' diagonal corners.
        let corner = round.normals[0];
        assert!((corner.abs() - Vec3::splat(1.0 / 3f32.sqrt())).length() < 1e-6);
        assert_eq!(round.rings.offsets[1] - round.rings.offsets[0], 6);
    }

    #[test]
    fn a_uv_seams_duplicated_vertices_become_one_element() {
        let (p, n, t) = seamed_quad();
        let w = weld(&p, &n, &t, 0.9);
        assert_eq!(w.element_of_vertex, [0, 1, 2, 1, 3, 2]);
        assert_eq!(w.rings.offsets, [0, 2, 5, 8, 10]);
        assert_eq!(w.rings.neighbours, [1, 2, 0, 2, 3, 0, 1, 3, 1, 2]);
    }
}

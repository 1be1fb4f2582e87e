//! The directions of spherical layered hit buffers (Yu's thesis, chapter 3): one buffer per
//! direction, each answering rays that travel along it. The thesis' default is the face
//! directions of an icosahedron subdivided twice (20 * 4^L: 20, 80, 320, 1280); it also measures
//! the octahedron's (8 * 4^L: 8, 32, 128) and Halton points (any count). Face directions come
//! from subdividing the solid's triangles with midpoints pushed onto the sphere and taking each
//! face's normalised centroid, so every set covers the sphere evenly and is symmetric.

use std::collections::HashMap;
use std::fmt;

use glam::DVec3;

use crate::error::{Error, Result};

/// A set of buffer directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DirectionSet {
    /// The faces of an icosahedron subdivided L times: 20 * 4^L directions.
    Icosahedral(u32),
    /// The faces of an octahedron subdivided L times: 8 * 4^L directions.
    Octahedral(u32),
    /// The first N points of the Halton sequence in bases 2 and 3, uniform on the sphere.
    Halton(u32),
}

/// The most directions a set may have (buffers are built per direction).
pub const MAX_DIRECTIONS: usize = 5120;

impl Default for DirectionSet {
    /// The thesis' 320 directions.
    fn default() -> Self {
        DirectionSet::Icosahedral(2)
    }
}

impl fmt::Display for DirectionSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DirectionSet::Icosahedral(l) => write!(f, "ico{}", 20 * 4u64.pow(*l)),
            DirectionSet::Octahedral(l) => write!(f, "oct{}", 8 * 4u64.pow(*l)),
            DirectionSet::Halton(n) => write!(f, "halton{n}"),
        }
    }
}

impl DirectionSet {
    /// `ico20|80|320|1280|5120`, `oct8|32|128|512|2048`, `haltonN`.
    pub fn parse(s: &str) -> Result<DirectionSet> {
        let count = |rest: &str| rest.parse::<u64>().ok();
        let level = |n: u64, base: u64| (0..6).find(|&l| base * 4u64.pow(l) == n);
        let set = if let Some(n) = s.strip_prefix("ico").and_then(count) {
            level(n, 20).map(DirectionSet::Icosahedral)
        } else if let Some(n) = s.strip_prefix("oct").and_then(count) {
            level(n, 8).map(DirectionSet::Octahedral)
        } else {
            s.strip_prefix("halton")
                .and_then(count)
                .filter(|&n| n > 0)
                .map(|n| DirectionSet::Halton(n as u32))
        };
        let set = set.ok_or_else(|| {
            Error::Invalid(format!(
                "lhb: {s:?} is no direction set (ico20, ico80, ico320, ico1280, oct8, oct32, \
                 oct128, haltonN)"
            ))
        })?;
        if set.count() > MAX_DIRECTIONS {
            return Err(Error::Invalid(format!(
                "lhb: {s} has {} directions, more than {MAX_DIRECTIONS}",
                set.count()
            )));
        }
        Ok(set)
    }

    pub fn count(self) -> usize {
        match self {
            DirectionSet::Icosahedral(l) => 20 * 4usize.pow(l),
            DirectionSet::Octahedral(l) => 8 * 4usize.pow(l),
            DirectionSet::Halton(n) => n as usize,
        }
    }

    /// The unit directions, in a fixed order (buffer i is direction i).
    pub fn directions(self) -> Vec<DVec3> {
        match self {
            DirectionSet::Icosahedral(l) => faces(icosahedron(), l),
            DirectionSet::Octahedral(l) => faces(octahedron(), l),
            DirectionSet::Halton(n) => (1..=n as u64).map(halton_direction).collect(),
        }
    }
}

type Solid = (Vec<DVec3>, Vec<[usize; 3]>);

/// The icosahedron: the 12 cyclic permutations of (0, +-1, +-t), its faces the triples of
/// vertices at the edge length (2) from each other, turned to face outwards.
fn icosahedron() -> Solid {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v = Vec::new();
    for (a, b) in [(1.0, t), (1.0, -t), (-1.0, t), (-1.0, -t)] {
        v.extend([
            DVec3::new(0.0, a, b),
            DVec3::new(a, b, 0.0),
            DVec3::new(b, 0.0, a),
        ]);
    }
    let edge = |i: usize, j: usize| (v[i].distance(v[j]) - 2.0).abs() < 1e-9;
    let mut faces = Vec::new();
    for a in 0..v.len() {
        for b in a + 1..v.len() {
            for c in b + 1..v.len() {
                if edge(a, b) && edge(b, c) && edge(c, a) {
                    let outwards = (v[b] - v[a]).cross(v[c] - v[a]).dot(v[a] + v[b] + v[c]) > 0.0;
                    faces.push(if outwards { [a, b, c] } else { [a, c, b] });
                }
            }
        }
    }
    debug_assert_eq!(faces.len(), 20);
    (v.iter().map(|p| p.normalize()).collect(), faces)
}

fn octahedron() -> Solid {
    let v = vec![
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    let mut faces = Vec::new();
    for (x, sx) in [(0, 1.0), (1, -1.0)] {
        for (y, sy) in [(2, 1.0), (3, -1.0)] {
            for (z, sz) in [(4, 1.0), (5, -1.0)] {
                // Counter-clockwise seen from outside.
                faces.push(if sx * sy * sz > 0.0 {
                    [x, y, z]
                } else {
                    [x, z, y]
                });
            }
        }
    }
    (v, faces)
}

/// The normalised centroids of `solid`'s faces after `levels` subdivisions (midpoints on the
/// sphere).
fn faces((mut vertices, mut tris): Solid, levels: u32) -> Vec<DVec3> {
    for _ in 0..levels {
        let mut mid: HashMap<(usize, usize), usize> = HashMap::new();
        let mut midpoint = |a: usize, b: usize, v: &mut Vec<DVec3>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                v.push((v[a] + v[b]).normalize());
                v.len() - 1
            })
        };
        let mut next = Vec::with_capacity(4 * tris.len());
        for &[a, b, c] in &tris {
            let ab = midpoint(a, b, &mut vertices);
            let bc = midpoint(b, c, &mut vertices);
            let ca = midpoint(c, a, &mut vertices);
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        tris = next;
    }
    tris.iter()
        .map(|&[a, b, c]| (vertices[a] + vertices[b] + vertices[c]).normalize())
        .collect()
}

/// The radical inverse of `i` in `base`.
fn radical_inverse(mut i: u64, base: u64) -> f64 {
    let (mut r, mut f) = (0.0, 1.0 / base as f64);
    while i > 0 {
        r += (i % base) as f64 * f;
        i /= base;
        f /= base as f64;
    }
    r
}

/// Halton point `i` (bases 2, 3) mapped to the sphere by equal areas (z uniform).
fn halton_direction(i: u64) -> DVec3 {
    let z = 1.0 - 2.0 * radical_inverse(i, 2);
    let phi = std::f64::consts::TAU * radical_inverse(i, 3);
    let r = (1.0 - z * z).max(0.0).sqrt();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sets_have_their_counts_cover_the_sphere_and_parse_back() {
        for set in [
            DirectionSet::Icosahedral(0),
            DirectionSet::Icosahedral(2),
            DirectionSet::Octahedral(1),
            DirectionSet::Halton(144),
        ] {
            let d = set.directions();
            assert_eq!(d.len(), set.count(), "{set}");
            assert!(d.iter().all(|v| (v.length() - 1.0).abs() < 1e-12));
            assert_eq!(DirectionSet::parse(&set.to_string()).unwrap(), set);
            // Every direction has a neighbour closer than the sets' coarsest spacing, and no
            // two coincide.
            for (i, a) in d.iter().enumerate() {
                let nearest = d
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, b)| a.dot(*b))
                    .fold(-1.0, f64::max);
                assert!(nearest < 1.0 - 1e-9 && nearest > 0.0, "{set}: {nearest}");
            }
        }
        assert_eq!(icosahedron().1.len(), 20);
        // The polyhedral sets are symmetric: their directions sum to zero.
        for set in [DirectionSet::Icosahedral(2), DirectionSet::Octahedral(2)] {
            let sum: DVec3 = set.directions().iter().sum();
            assert!(sum.length() < 1e-9, "{set}: {sum}");
        }
        assert!(DirectionSet::parse("ico100").is_err());
        assert!(DirectionSet::parse("halton0").is_err());
        assert!(DirectionSet::parse("oct8192").is_err());
    }
}

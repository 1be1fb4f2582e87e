//! The directional map: any direction to its nearest buffer direction in O(1) (the thesis'
//! lat-long index texture). A texel of a lat-long grid cannot hold one index exactly (a Voronoi
//! edge between two directions crosses it), so each texel lists the few directions that can be
//! nearest anywhere in it: every d with angle(d, c) <= angle(best(c), c) + 2 rho, where c is the
//! texel's centre direction and rho bounds the angle from c to any point of the texel (for x
//! within rho of c, the nearest direction to x is within angle(best(c), x) + rho of c, at most
//! angle(best(c), c) + 2 rho). A lookup takes the candidate of largest dot product, ties to the
//! lowest index, which is exactly what a search over every direction gives.

use glam::{DVec3, Vec3};

/// Candidates per texel and their ranges.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalMap {
    pub width: u32,
    pub height: u32,
    /// Per texel (row-major, rows from the pole at +z down): (first candidate, count).
    pub ranges: Vec<[u32; 2]>,
    pub candidates: Vec<u32>,
    /// The directions as the lookups compare them (f32, as on the devices).
    pub directions: Vec<Vec3>,
}

/// The texel of the lat-long grid `width` x `height` that `d` falls in: theta from +z (rows),
/// phi about z from +x (columns).
pub fn texel(d: Vec3, width: u32, height: u32) -> (u32, u32) {
    let theta = d.z.clamp(-1.0, 1.0).acos();
    let phi = d.y.atan2(d.x).rem_euclid(std::f32::consts::TAU);
    let column = ((phi / std::f32::consts::TAU) * width as f32) as u32;
    let row = ((theta / std::f32::consts::PI) * height as f32) as u32;
    (column.min(width - 1), row.min(height - 1))
}

/// The direction of index `i` nearest `d` by a search over all (largest dot, lowest index).
pub fn nearest_brute_force(directions: &[Vec3], d: Vec3) -> u32 {
    nearest_among(directions, 0..directions.len() as u32, d)
}

/// Of the `candidates` (ascending indices into `directions`), the one nearest `d`: largest
/// dot product, a tie to the lowest index.
fn nearest_among(directions: &[Vec3], candidates: impl IntoIterator<Item = u32>, d: Vec3) -> u32 {
    let mut best = (f32::NEG_INFINITY, u32::MAX);
    for i in candidates {
        let dot = directions[i as usize].dot(d);
        if dot > best.0 {
            best = (dot, i);
        }
    }
    best.1
}

fn spherical(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

impl DirectionalMap {
    /// The map of `directions` on a `width` x `height` grid (a few texels per direction:
    /// 2 * sqrt(n) x sqrt(n) keeps the lists short).
    pub fn new(directions: &[DVec3], width: u32, height: u32) -> DirectionalMap {
        let (w, h) = (width as f64, height as f64);
        let mut map = DirectionalMap {
            width,
            height,
            ranges: Vec::with_capacity((width * height) as usize),
            candidates: Vec::new(),
            directions: directions.iter().map(|d| d.as_vec3()).collect(),
        };
        for row in 0..height {
            let (t0, t1) = (
                row as f64 / h * std::f64::consts::PI,
                (row + 1) as f64 / h * std::f64::consts::PI,
            );
            for column in 0..width {
                let (p0, p1) = (
                    column as f64 / w * std::f64::consts::TAU,
                    (column + 1) as f64 / w * std::f64::consts::TAU,
                );
                let c = spherical(0.5 * (t0 + t1), 0.5 * (p0 + p1));
                // The texel's corners and edge midpoints bound its extent from the centre; the
                // margin covers the edges' bulge between them and f32 rounding.
                let mut rho = 0.0f64;
                for t in [t0, 0.5 * (t0 + t1), t1] {
                    for p in [p0, 0.5 * (p0 + p1), p1] {
                        rho = rho.max(c.dot(spherical(t, p)).clamp(-1.0, 1.0).acos());
                    }
                }
                let rho = rho * 1.05 + 1e-4;
                let best = directions
                    .iter()
                    .map(|d| d.dot(c).clamp(-1.0, 1.0).acos())
                    .fold(f64::INFINITY, f64::min);
                let first = map.candidates.len() as u32;
                for (i, d) in directions.iter().enumerate() {
                    if d.dot(c).clamp(-1.0, 1.0).acos() <= best + 2.0 * rho {
                        map.candidates.push(i as u32);
                    }
                }
                map.ranges
                    .push([first, map.candidates.len() as u32 - first]);
            }
        }
        map
    }

    /// A grid of about two texels per direction, twice as wide as high.
    pub fn for_directions(directions: &[DVec3]) -> DirectionalMap {
        let height = ((directions.len() as f64).sqrt().ceil() as u32).max(4);
        DirectionalMap::new(directions, 2 * height, height)
    }

    /// The nearest direction to unit `d` (what the kernels' lookup computes).
    pub fn nearest(&self, d: Vec3) -> u32 {
        let (column, row) = texel(d, self.width, self.height);
        let [first, count] = self.ranges[(row * self.width + column) as usize];
        let candidates = &self.candidates[first as usize..(first + count) as usize];
        nearest_among(&self.directions, candidates.iter().copied(), d)
    }

    /// The longest candidate list (the lookup's worst case).
    pub fn longest(&self) -> u32 {
        self.ranges.iter().map(|r| r[1]).max().unwrap_or(0)
    }
}

#[cfg(test)]
mod tests {
    use super::super::directions::DirectionSet;
    use super::*;

    /// 1e5 random unit directions (a fixed xorshift, uniform on the sphere).
    fn random_directions(n: usize) -> Vec<Vec3> {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| {
                let z = 1.0 - 2.0 * next();
                let phi = std::f64::consts::TAU * next();
                let r = (1.0 - z * z).sqrt();
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
                    .as_vec3()
                    .normalize()
            })
            .collect()
    }

    #[test]
    fn the_map_finds_the_nearest_direction_as_a_search_over_all_does() {
        let probes = random_directions(100_000);
        for set in [
            DirectionSet::Icosahedral(0),
            DirectionSet::Icosahedral(1),
            DirectionSet::Icosahedral(2),
            DirectionSet::Icosahedral(3),
            DirectionSet::Octahedral(0),
            DirectionSet::Octahedral(2),
            DirectionSet::Halton(144),
            DirectionSet::Halton(320),
        ] {
            let map = DirectionalMap::for_directions(&set.directions());
            let wrong = probes
                .iter()
                .filter(|&&d| map.nearest(d) != nearest_brute_force(&map.directions, d))
                .count();
            assert_eq!(wrong, 0, "{set}: {wrong} of 1e5 lookups differ");
            // Short lists: the lookup is O(1) in practice.
            assert!(map.longest() <= 16, "{set}: {} candidates", map.longest());
        }
        // The poles and the seam at phi = 0 included.
        let map = DirectionalMap::for_directions(&DirectionSet::default().directions());
        for d in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(1.0, -1e-7, 0.0).normalize(),
        ] {
            assert_eq!(
                map.nearest(d),
                nearest_brute_force(&map.directions, d),
                "{d}"
            );
        }
    }
}

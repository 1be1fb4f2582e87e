//! A ray answered by the buffers instead of a traversal (the thesis' indirect rays): snap the
//! ray's direction to the nearest buffer direction (the directional map), project the ray's
//! origin into that buffer, move by the cone jitter within the texel grid, and take the first
//! surface the texel lists beyond the origin's depth whose front faces the ray; the hit lies on
//! the texel's centre line at that depth. What shaders/lhb/lookup.glsl computes (it orders
//! ties by placed triangle and gives up after 8 backs). Direct light stays exact; only
//! indirect rays go here.

use glam::Vec3;

use super::directional_map::DirectionalMap;
use super::directions::DirectionSet;
use super::frame::{BufferFrame, View};
use super::oracle::{buffer_by_rays, Layer};
use crate::flatten::GpuScene;

/// Every direction's buffer of one scene.
pub struct Buffers {
    pub frame: BufferFrame,
    pub resolution: u32,
    pub views: Vec<View>,
    pub map: DirectionalMap,
    /// Per direction, per texel (row-major), the layers in depth order.
    pub texels: Vec<Vec<Vec<Layer>>>,
    /// Each placed triangle's geometric normal in render space (not normalised), by
    /// (instance, triangle): which side of it a ray meets.
    pub normals: std::collections::HashMap<(u32, u32), Vec3>,
}

/// What a lookup found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookupHit {
    pub instance: u32,
    pub triangle: u32,
    /// The surface's point: on the buffer direction's line through the looked-up texel
    /// position, at the layer's depth.
    pub point: Vec3,
    /// Which buffer answered.
    pub direction: u32,
}

impl Buffers {
    /// The buffers of `g` built by rays (`oracle`): what the rasterizer's must equal.
    pub fn by_rays(g: &GpuScene, set: DirectionSet, resolution: u32, margin: f32) -> Buffers {
        let directions = set.directions();
        let frame = BufferFrame::of_scene(g, margin);
        let views: Vec<View> = directions.iter().map(|&d| View::along(d)).collect();
        let normals = g
            .placed_triangles()
            .map(|(instance, t)| {
                let [a, b, c] = g.placed_corners(instance, t);
                ((instance, t), (b - a).cross(c - a))
            })
            .collect();
        Buffers {
            texels: views
                .iter()
                .map(|v| buffer_by_rays(g, &frame, v, resolution))
                .collect(),
            normals,
            map: DirectionalMap::for_directions(&directions),
            views,
            frame,
            resolution,
        }
    }

    /// The first surface beyond `x` (by more than `eps`) facing `dir` that the buffer of the
    /// direction nearest unit `dir` lists at `x`'s texel moved by `jitter` texels; None where
    /// it lists none (the ray leaves the scene) or the texel is off the buffer.
    pub fn lookup(&self, x: Vec3, dir: Vec3, jitter: (f32, f32), eps: f32) -> Option<LookupHit> {
        let i = self.map.nearest(dir);
        let view = &self.views[i as usize];
        let r = self.resolution;
        let (u, v, z) = self.frame.project(view, x, r);
        let (u, v) = (u + jitter.0, v + jitter.1);
        if !(u >= 0.0 && v >= 0.0 && u < r as f32 && v < r as f32) {
            return None;
        }
        let texel = (v as u32 * r + u as u32) as usize;
        let layer = self.texels[i as usize][texel].iter().find(|l| {
            l.depth > z + eps && self.normals[&(l.instance, l.triangle)].dot(dir) < 0.0
        })?;
        let texel_size = 2.0 * self.frame.radius / r as f32;
        let (cu, cv) = (u.floor() + 0.5, v.floor() + 0.5);
        let point = self.frame.centre
            + view.right * (cu * texel_size - self.frame.radius)
            + view.up * (cv * texel_size - self.frame.radius)
            + view.forward * (layer.depth - self.frame.radius);
        Some(LookupHit {
            instance: layer.instance,
            triangle: layer.triangle,
            point,
            direction: i,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flatten::queries::QueryScene;
    use crate::scene::cornell::push_grid;
    use crate::scene::Mesh;

    /// A closed cube of side 2 about the origin, its faces 2 x 2 quads turned inwards: every
    /// point inside is free space and every ray from it meets a face from the front.
    fn inward_cube() -> GpuScene {
        let mut mesh = Mesh::default();
        let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let faces = [
            [
                p(-1., -1., -1.),
                p(-1., -1., 1.),
                p(1., -1., 1.),
                p(1., -1., -1.),
            ],
            [
                p(-1., 1., -1.),
                p(1., 1., -1.),
                p(1., 1., 1.),
                p(-1., 1., 1.),
            ],
            [
                p(-1., -1., 1.),
                p(-1., 1., 1.),
                p(1., 1., 1.),
                p(1., -1., 1.),
            ],
            [
                p(-1., -1., -1.),
                p(1., -1., -1.),
                p(1., 1., -1.),
                p(-1., 1., -1.),
            ],
            [
                p(1., -1., -1.),
                p(1., -1., 1.),
                p(1., 1., 1.),
                p(1., 1., -1.),
            ],
            [
                p(-1., -1., -1.),
                p(-1., 1., -1.),
                p(-1., 1., 1.),
                p(-1., -1., 1.),
            ],
        ];
        for f in faces {
            push_grid(&mut mesh, f, 0, 2);
        }
        super::super::one_mesh(mesh)
    }

    /// A fixed stream of numbers in [0, 1).
    fn stream(seed: u64) -> impl FnMut() -> f32 {
        let mut s = seed;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    #[test]
    fn along_a_buffer_direction_from_a_texel_centre_every_lookup_finds_the_closest_hit() {
        let g = inward_cube();
        let q = QueryScene::new(&g);
        let b = Buffers::by_rays(&g, DirectionSet::Icosahedral(1), 32, 0.0);
        let mut next = stream(7);
        let (mut asked, mut agreed) = (0, 0);
        for (i, view) in b.views.iter().enumerate() {
            for _ in 0..40 {
                let (tx, ty) = ((next() * 32.0) as u32, (next() * 32.0) as u32);
                let (origin, dir) = b.frame.texel_ray(view, tx, ty, 32);
                // A point inside the cube on the texel's centre ray, if the ray crosses it.
                let Some(enter) = q.closest_hit(origin, dir, f32::INFINITY) else {
                    continue;
                };
                let x = origin + dir * (enter.t + 0.3);
                if x.abs().max_element() >= 0.99 {
                    continue;
                }
                let hit = q.closest_hit(x, dir, f32::INFINITY).expect("a closed cube");
                let found = b.lookup(x, dir, (0.0, 0.0), 1e-4).expect("listed");
                assert_eq!(found.direction, i as u32);
                asked += 1;
                let expected = x + dir * hit.t;
                if (found.point - expected).length() < 1e-4 {
                    agreed += 1;
                }
            }
        }
        assert!(asked > 1000, "{asked}");
        assert_eq!(
            agreed,
            asked,
            "{} of {asked} lookups missed",
            asked - agreed
        );
    }

    /// Away from buffer directions and texel centres the lookups approximate: the share that
    /// lands within a tenth of the cube's side of the closest hit rises with the directions
    /// and with the resolution.
    #[test]
    fn agreement_rises_with_directions_and_resolution() {
        let g = inward_cube();
        let q = QueryScene::new(&g);
        let agreement = |set: DirectionSet, r: u32| {
            let b = Buffers::by_rays(&g, set, r, 0.0);
            let mut next = stream(11);
            let mut agreed = 0;
            let n = 4000;
            for _ in 0..n {
                let x = Vec3::new(next(), next(), next()) * 1.6 - 0.8;
                let z = 1.0 - 2.0 * next();
                let phi = std::f32::consts::TAU * next();
                let s = (1.0 - z * z).max(0.0).sqrt();
                let dir = Vec3::new(s * phi.cos(), s * phi.sin(), z);
                let hit = q.closest_hit(x, dir, f32::INFINITY).expect("a closed cube");
                if let Some(found) = b.lookup(x, dir, (0.0, 0.0), 1e-4) {
                    if (found.point - (x + dir * hit.t)).length() < 0.2 {
                        agreed += 1;
                    }
                }
            }
            agreed as f64 / n as f64
        };
        let coarse = agreement(DirectionSet::Icosahedral(0), 16);
        let more_directions = agreement(DirectionSet::Icosahedral(2), 16);
        let finer = agreement(DirectionSet::Icosahedral(2), 64);
        println!("agreement: ico20 16^2 {coarse:.3}, ico320 16^2 {more_directions:.3}, ico320 64^2 {finer:.3}");
        assert!(
            more_directions > coarse + 0.1,
            "{coarse} -> {more_directions}"
        );
        assert!(finer >= more_directions, "{more_directions} -> {finer}");
    }
}

//! Buffers built by rays, the rasterizer's oracle: for every texel of direction d's buffer, the
//! ray from the texel's centre along d and every triangle whose front it meets (a face whose
//! geometric normal opposes d: a buffer answers rays travelling along d, so it keeps only the
//! surfaces they can hit). Each triangle is tested against the texel centres its projection's
//! bounding box covers, by a ray-triangle intersection in f64, independently of the
//! rasterizer's edge functions.

use glam::DVec3;

use super::frame::{BufferFrame, View};
use crate::flatten::GpuScene;

/// One surface in a texel's list.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// Distance along the view from the buffer's entry plane.
    pub depth: f32,
    pub instance: u32,
    /// Scene-global triangle index (`GpuScene::triangles`).
    pub triangle: u32,
}

/// The buffer of `view` at resolution `r`: per texel (row-major, rows along `up`), its layers
/// sorted by depth, ties by instance and triangle.
pub fn buffer_by_rays(g: &GpuScene, frame: &BufferFrame, view: &View, r: u32) -> Vec<Vec<Layer>> {
    let mut texels = vec![Vec::new(); (r * r) as usize];
    let forward = view.forward.as_dvec3();
    for (instance, t) in g.placed_triangles() {
        let corners = g.placed_corners(instance, t);
        let [a, b, c] = corners.map(|p| p.as_dvec3());
        if (b - a).cross(c - a).dot(forward) >= 0.0 {
            continue; // seen from behind or edge-on
        }
        let projected = corners.map(|p| frame.project(view, p, r));
        let lo = |k: fn(&(f32, f32, f32)) -> f32| {
            projected
                .iter()
                .map(k)
                .fold(f32::INFINITY, f32::min)
                .floor()
                .max(0.0) as u32
        };
        let hi = |k: fn(&(f32, f32, f32)) -> f32| {
            (projected
                .iter()
                .map(k)
                .fold(f32::NEG_INFINITY, f32::max)
                .ceil() as i64)
                .clamp(0, r as i64) as u32
        };
        let (x0, x1, y0, y1) = (lo(|p| p.0), hi(|p| p.0), lo(|p| p.1), hi(|p| p.1));
        for j in y0..y1 {
            for i in x0..x1 {
                let (origin, dir) = frame.texel_ray(view, i, j, r);
                if let Some(depth) = intersect(origin.as_dvec3(), dir.as_dvec3(), a, b, c) {
                    texels[(j * r + i) as usize].push(Layer {
                        depth: depth as f32,
                        instance,
                        triangle: t,
                    });
                }
            }
        }
    }
    for list in &mut texels {
        list.sort_by(|p, q| {
            p.depth
                .total_cmp(&q.depth)
                .then(p.instance.cmp(&q.instance))
                .then(p.triangle.cmp(&q.triangle))
        });
    }
    texels
}

/// Möller and Trumbore's ray-triangle test: the distance along unit `dir` where the ray from
/// `origin` meets triangle abc (edges and corners included), if it does ahead of the origin.
fn intersect(origin: DVec3, dir: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some(t)
}

/// Whether texel (i, j)'s centre lies within 1e-3 texels of an edge of one of `layers`'
/// triangles (where the oracle and the rasterizer may rightly differ: the oracle counts an edge
/// point in both triangles, the top-left rule in one).
pub fn on_an_edge(
    g: &GpuScene,
    frame: &BufferFrame,
    view: &View,
    r: u32,
    layers: &[Layer],
    (i, j): (u32, u32),
) -> bool {
    let p = (i as f32 + 0.5, j as f32 + 0.5);
    layers.iter().any(|l| {
        let [a, b, c] = g
            .placed_corners(l.instance, l.triangle)
            .map(|p| frame.project(view, p, r));
        [(a, b), (b, c), (c, a)].iter().any(|&(e0, e1)| {
            let (dx, dy) = (e1.0 - e0.0, e1.1 - e0.1);
            let e = (p.0 - e0.0) * dy - (p.1 - e0.1) * dx;
            e.abs() / (dx * dx + dy * dy).sqrt().max(1e-12) < 1e-3
        })
    })
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::scene::cornell::push_quad;
    use crate::scene::Mesh;

    /// Two squares of side 2 across z (at z = 0 facing -z and at z = 1 facing -z, the second
    /// half the size) and one at z = 2 facing +z; seen along +z.
    fn stacked() -> GpuScene {
        let mut mesh = Mesh::default();
        let v = Vec3::new;
        let facing_minus_z = |s: f32, z: f32| [v(-s, -s, z), v(-s, s, z), v(s, s, z), v(s, -s, z)];
        push_quad(&mut mesh, facing_minus_z(1.0, 0.0), 0);
        push_quad(&mut mesh, facing_minus_z(0.5, 1.0), 0);
        let [a, b, c, d] = facing_minus_z(1.0, 2.0);
        push_quad(&mut mesh, [a, d, c, b], 0);
        super::super::one_mesh(mesh)
    }

    #[test]
    fn a_texel_lists_the_fronts_its_ray_meets_in_depth_order() {
        let g = stacked();
        let frame = BufferFrame::of_scene(&g, 0.0);
        let view = View::along(DVec3::Z);
        let r = 32;
        let buffer = buffer_by_rays(&g, &frame, &view, r);
        let at = |p: Vec3| {
            let (x, y, _) = frame.project(&view, p, r);
            &buffer[(y as u32 * r + x as u32) as usize]
        };
        // Through both squares facing the rays (away from their diagonals, where a texel's
        // centre may meet both triangles of a square): two layers, the nearer first, 1 apart;
        // the square facing away is not listed.
        let centre = at(Vec3::new(0.3, -0.15, 0.0));
        assert_eq!(centre.len(), 2, "{centre:?}");
        assert!((centre[1].depth - centre[0].depth - 1.0).abs() < 1e-5);
        let (_, _, z0) = frame.project(&view, Vec3::ZERO, r);
        assert!((centre[0].depth - z0).abs() < 1e-5);
        // Outside the small square: one layer; outside both: none.
        assert_eq!(at(Vec3::new(0.85, 0.5, 0.0)).len(), 1);
        assert!(at(Vec3::new(1.3, 0.0, 0.0)).is_empty());
        // Seen the other way, only the square at z = 2.
        let back_view = View::along(-DVec3::Z);
        let back = buffer_by_rays(&g, &frame, &back_view, r);
        let (_, _, z2) = frame.project(&back_view, Vec3::new(0.0, 0.0, 2.0), r);
        assert!(back.iter().flatten().all(|l| (l.depth - z2).abs() < 1e-5));
        assert!(back.iter().filter(|l| !l.is_empty()).count() > 0);
        // The layers cover the squares' areas: texels of the big square and of the small one
        // (a quarter of it), within the texels along their edges.
        let texel = 2.0 * frame.radius / r as f32;
        let layers: usize = buffer.iter().map(|l| l.len()).sum();
        let expected = (4.0 + 1.0) / (texel * texel);
        assert!(
            (layers as f32 - expected).abs() < 0.15 * expected,
            "{layers} layers, {expected} expected"
        );
    }
}

//! The buffers' rasterizer on the CPU: the algorithm the compute kernel will run, in its f32
//! operations. Each front-facing triangle is projected into the buffer; each texel centre its
//! box covers is tested with the three edge functions (a centre on an edge belongs to the
//! triangle to its right or below, the top-left rule, so triangles sharing an edge list a centre
//! on it once), and its depth is the triangle's plane through the projected corners. Each covered
//! texel appends a layer; past `capacity` layers a texel counts the rest as overflow (lost, as
//! the thesis' fixed-capacity lists), or, in the variant without a limit, a counting pass and a
//! prefix sum place every layer.

use super::frame::{BufferFrame, View};
use super::oracle::Layer;
use crate::flatten::GpuScene;

/// A buffer as the rasterizer leaves it: each texel's layers in the order they were appended,
/// and the layers lost past the capacity.
pub struct Rasterized {
    pub texels: Vec<Vec<Layer>>,
    pub overflow: u64,
}

/// Whether an edge from `a` to `b` is a top or left edge of a triangle wound clockwise in the
/// buffer's (u, v) plane (a front face: its normal opposes the view).
fn top_left(a: (f32, f32), b: (f32, f32)) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    (dy == 0.0 && dx > 0.0) || dy < 0.0
}

/// Rasterizes `g` into the buffer of `view` at resolution `r`, `capacity` layers a texel.
pub fn rasterize(
    g: &GpuScene,
    frame: &BufferFrame,
    view: &View,
    r: u32,
    capacity: usize,
) -> Rasterized {
    let mut out = Rasterized {
        texels: vec![Vec::new(); (r * r) as usize],
        overflow: 0,
    };
    cover(g, frame, view, r, |texel, layer| {
        let list = &mut out.texels[texel];
        if list.len() < capacity {
            list.push(layer);
        } else {
            out.overflow += 1;
        }
    });
    out
}

/// A buffer without a capacity (the thesis' count, prefix-sum, fill variant): texel k's layers
/// are `layers[offsets[k]..offsets[k + 1]]`, in the order they were covered.
pub struct Exact {
    pub offsets: Vec<u32>,
    pub layers: Vec<Layer>,
}

/// The buffer with every layer: a pass counting each texel's layers, their prefix sum, and a
/// pass filling them in.
pub fn rasterize_exact(g: &GpuScene, frame: &BufferFrame, view: &View, r: u32) -> Exact {
    let mut counts = vec![0u32; (r * r) as usize];
    cover(g, frame, view, r, |texel, _| counts[texel] += 1);
    let mut offsets = Vec::with_capacity(counts.len() + 1);
    offsets.push(0u32);
    for c in &counts {
        offsets.push(offsets.last().expect("starts with 0") + c);
    }
    let mut next: Vec<u32> = offsets[..counts.len()].to_vec();
    let mut layers = vec![
        Layer {
            depth: 0.0,
            instance: 0,
            triangle: 0,
        };
        *offsets.last().expect("starts with 0") as usize
    ];
    cover(g, frame, view, r, |texel, layer| {
        layers[next[texel] as usize] = layer;
        next[texel] += 1;
    });
    Exact { offsets, layers }
}

/// Calls `visit(texel, layer)` for every texel centre a front-facing triangle of `g` covers in
/// the buffer of `view` at resolution `r`.
fn cover(
    g: &GpuScene,
    frame: &BufferFrame,
    view: &View,
    r: u32,
    mut visit: impl FnMut(usize, Layer),
) {
    for (instance, t) in g.placed_triangles() {
        let [a, b, c] = g
            .placed_corners(instance, t)
            .map(|p| frame.project(view, p, r));
        // Twice the signed area in (u, v): negative for a front face (clockwise).
        let area = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        if area >= 0.0 {
            continue;
        }
        let x0 = a.0.min(b.0).min(c.0).floor().max(0.0) as u32;
        let y0 = a.1.min(b.1).min(c.1).floor().max(0.0) as u32;
        let x1 = (a.0.max(b.0).max(c.0).ceil() as i64).clamp(0, r as i64) as u32;
        let y1 = (a.1.max(b.1).max(c.1).ceil() as i64).clamp(0, r as i64) as u32;
        let edges = [(a, b), (b, c), (c, a)];
        for j in y0..y1 {
            for i in x0..x1 {
                let p = (i as f32 + 0.5, j as f32 + 0.5);
                let mut w = [0.0f32; 3];
                let mut inside = true;
                for (k, &(e0, e1)) in edges.iter().enumerate() {
                    // Positive inside a clockwise triangle.
                    let e = (p.0 - e0.0) * (e1.1 - e0.1) - (p.1 - e0.1) * (e1.0 - e0.0);
                    inside &= e > 0.0 || (e == 0.0 && top_left((e0.0, e0.1), (e1.0, e1.1)));
                    w[k] = e;
                }
                if !inside {
                    continue;
                }
                // Barycentrics from the edge functions: w[1] is a's weight (the edge bc),
                // w[2] b's, w[0] c's.
                let sum = w[0] + w[1] + w[2];
                let depth = (w[1] * a.2 + w[2] * b.2 + w[0] * c.2) / sum;
                visit(
                    (j * r + i) as usize,
                    Layer {
                        depth,
                        instance,
                        triangle: t,
                    },
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::super::directions::DirectionSet;
    use super::super::oracle::{buffer_by_rays, on_an_edge};
    use super::*;
    use crate::scene::cornell;

    #[test]
    fn the_rasterizer_lists_what_the_rays_find() {
        let scene = cornell::tessellated(3);
        let g = GpuScene::build(&scene, &scene.pose(0.0), None).unwrap();
        let frame = BufferFrame::of_scene(&g, 0.05);
        let r = 48;
        let (mut compared, mut exempt, mut overflow) = (0, 0, 0);
        for d in DirectionSet::Icosahedral(1).directions().iter().step_by(7) {
            let view = View::along(*d);
            let oracle = buffer_by_rays(&g, &frame, &view, r);
            let raster = rasterize(&g, &frame, &view, r, 16);
            overflow += raster.overflow;
            for (k, (want, got)) in oracle.iter().zip(&raster.texels).enumerate() {
                let texel = (k as u32 % r, k as u32 / r);
                let mut got = got.clone();
                got.sort_by(|p, q| {
                    p.depth
                        .total_cmp(&q.depth)
                        .then(p.instance.cmp(&q.instance))
                        .then(p.triangle.cmp(&q.triangle))
                });
                let same = want.len() == got.len()
                    && want.iter().zip(&got).all(|(w, g)| {
                        (w.instance, w.triangle) == (g.instance, g.triangle)
                            && (w.depth - g.depth).abs() <= 1e-5 * w.depth.abs().max(1.0)
                    });
                if same {
                    compared += 1;
                } else if on_an_edge(&g, &frame, &view, r, want, texel) {
                    exempt += 1;
                } else {
                    panic!("direction {d}, texel {texel:?}: rays {want:?}, raster {got:?}");
                }
            }
        }
        println!("{compared} texels the same, {exempt} on edges");
        assert_eq!(overflow, 0);
        assert!(exempt * 50 < compared, "{exempt} of {compared} on edges");
    }

    #[test]
    fn layers_past_the_capacity_are_counted_not_kept() {
        let scene = cornell::tessellated(2);
        let g = GpuScene::build(&scene, &scene.pose(0.0), None).unwrap();
        let frame = BufferFrame::of_scene(&g, 0.05);
        let view = View::along(DVec3::new(0.3, -0.2, 1.0).normalize());
        let full = rasterize(&g, &frame, &view, 32, 64);
        let kept: usize = full.texels.iter().map(|l| l.len()).sum();
        let capped = rasterize(&g, &frame, &view, 32, 1);
        assert_eq!(full.overflow, 0);
        assert!(capped.texels.iter().all(|l| l.len() <= 1));
        let capped_kept: usize = capped.texels.iter().map(|l| l.len()).sum();
        assert!(capped.overflow > 0);
        assert_eq!(capped_kept as u64 + capped.overflow, kept as u64);
        // Without a capacity: every layer, each texel's in the same order as a large capacity.
        let exact = rasterize_exact(&g, &frame, &view, 32);
        assert_eq!(exact.layers.len(), kept);
        for (k, list) in full.texels.iter().enumerate() {
            let range = exact.offsets[k] as usize..exact.offsets[k + 1] as usize;
            assert_eq!(&exact.layers[range], list.as_slice(), "texel {k}");
        }
    }
}

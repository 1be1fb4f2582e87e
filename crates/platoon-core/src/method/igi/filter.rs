//! The filters of IGI's accelerations, run once on the assembled frame. Both need neighbouring
//! pixels, which a band's edge does not have: rather than have each device render halo lines
//! (gather pixels of the neighbours' bands, traced twice, and a halo as wide as the filter times
//! the downsampling factor), the devices leave irradiance and a G-buffer per pixel and the
//! filters run here, after assembly, on the whole frame. The image is then the same bits for any
//! split, no ray is traced twice, and the cost is one CPU pass over the frame (measured with the
//! render: `tradeoff` adds it to the device time).
//!
//! - discontinuity buffer (Keller and Heidrich 2001, as in Wald et al.'s interactive IGI): each
//!   gather pixel saw one VPL subset; it takes the mean irradiance of the m x n window of gather
//!   pixels around it (one of each subset) over the neighbours on the same surface (depth and
//!   normal within thresholds);
//! - joint bilateral upsampling (Kopf et al. 2007): a pixel's irradiance is the weighted mean of
//!   the 3 x 3 gather pixels around its cell, weighed by distance in the image and by how alike
//!   the full-resolution normals (cosine) and depths are.

use glam::Vec3;

use super::{Grid, IgiOptions, IgiTexel, DEPTH_THRESHOLD, NORMAL_THRESHOLD};
use crate::frame::{Band, FrameParams};

/// A gather pixel's surface and irradiance, averaged over its samples.
#[derive(Clone, Copy, Debug, Default)]
struct Sample {
    irradiance: Vec3,
    normal: Vec3,
    depth: f32,
    /// Some sample of the pixel hit a diffuse surface.
    valid: bool,
}

impl Sample {
    fn of(t: &IgiTexel) -> Sample {
        if t.diffuse_samples <= 0.0 {
            return Sample::default();
        }
        let n = 1.0 / t.diffuse_samples;
        Sample {
            irradiance: Vec3::from(t.irradiance) * n,
            normal: Vec3::from(t.normal).normalize_or_zero(),
            depth: t.depth * n,
            valid: true,
        }
    }

    /// Whether `other` lies on the same surface (the discontinuity test).
    fn alike(&self, other: &Sample) -> bool {
        other.valid
            && (other.depth - self.depth).abs() <= DEPTH_THRESHOLD * self.depth
            && self.normal.dot(other.normal) >= NORMAL_THRESHOLD
    }
}

/// Adds the filtered indirect light to the bands' sums: what the IGI kernel leaves undone when
/// its options are `filtered()`. Every band carries its texels (`Band::per_pixel`); a pixel
/// whose band left none (or unreadable ones) is a pixel without a diffuse hit.
pub fn finish_bands(options: &IgiOptions, params: &FrameParams, bands: &mut [Band]) {
    if !options.filtered() {
        return;
    }
    let (w, h) = (params.width, params.height);
    let mut texels = vec![IgiTexel::default(); w as usize * h as usize];
    for b in bands.iter() {
        let start = (b.span.begin as usize).min(texels.len());
        let theirs = b.per_pixel.records::<IgiTexel>().unwrap_or_default();
        let n = theirs
            .len()
            .min(b.span.len() as usize)
            .min(texels.len() - start);
        texels[start..start + n].copy_from_slice(&theirs[..n]);
    }
    let indirect = indirect_radiance(options, w, h, &texels);
    for b in bands.iter_mut() {
        let start = b.span.begin as usize;
        for (i, s) in b.sums.iter_mut().enumerate() {
            let add = indirect[start + i];
            for c in 0..3 {
                s[c] += add[c];
            }
        }
    }
}

/// Per pixel, the sum over its samples of the indirect radiance: reflectance sums times the
/// filtered irradiance.
pub fn indirect_radiance(
    options: &IgiOptions,
    width: u32,
    height: u32,
    texels: &[IgiTexel],
) -> Vec<[f32; 3]> {
    let grid = options.grid(width, height);
    let (cw, ch) = grid.cells();
    let coarse: Vec<Sample> = (0..ch)
        .flat_map(|j| (0..cw).map(move |i| (i, j)))
        .map(|(i, j)| {
            let (x, y) = grid.pixel(i, j);
            Sample::of(&texels[(y * width + x) as usize])
        })
        .collect();
    let coarse = discontinuity_buffer(options.interleave, cw, ch, &coarse);
    let mut out = vec![[0.0f32; 3]; texels.len()];
    for y in 0..height {
        for x in 0..width {
            let t = &texels[(y * width + x) as usize];
            if t.diffuse_samples <= 0.0 {
                continue;
            }
            let e = if grid.k == 1 {
                coarse[(y * width + x) as usize].irradiance
            } else {
                upsample(&grid, &coarse, x, y, &Sample::of(t))
            };
            out[(y * width + x) as usize] = (Vec3::from(t.reflectance) * e).to_array();
        }
    }
    out
}

/// The mean over the m x n window (one pixel of each VPL subset) of the neighbours on the same
/// surface; the identity for a 1 x 1 tile.
fn discontinuity_buffer(tile: [u32; 2], cw: u32, ch: u32, coarse: &[Sample]) -> Vec<Sample> {
    if tile == [1, 1] {
        return coarse.to_vec();
    }
    let (m, n) = (tile[0] as i64, tile[1] as i64);
    let mut out = coarse.to_vec();
    for j in 0..ch as i64 {
        for i in 0..cw as i64 {
            let me = coarse[(j * cw as i64 + i) as usize];
            if !me.valid {
                continue;
            }
            let (mut sum, mut count) = (Vec3::ZERO, 0u32);
            for dy in -(n - 1) / 2..=n / 2 {
                for dx in -(m - 1) / 2..=m / 2 {
                    let (x, y) = (i + dx, j + dy);
                    if x < 0 || y < 0 || x >= cw as i64 || y >= ch as i64 {
                        continue;
                    }
                    let other = &coarse[(y * cw as i64 + x) as usize];
                    if (dx == 0 && dy == 0) || me.alike(other) {
                        sum += other.irradiance;
                        count += 1;
                    }
                }
            }
            out[(j * cw as i64 + i) as usize].irradiance = sum / count as f32;
        }
    }
    out
}

/// Joint bilateral upsampling of the gather grid at pixel (x, y), whose own surface is `me`.
fn upsample(grid: &Grid, coarse: &[Sample], x: u32, y: u32, me: &Sample) -> Vec3 {
    let (cw, ch) = grid.cells();
    let (ci, cj) = ((x / grid.k) as i64, (y / grid.k) as i64);
    let sigma = grid.k as f32 * 0.5;
    let (mut sum, mut weights) = (Vec3::ZERO, 0.0f32);
    let mut best = (0.0f32, Vec3::ZERO);
    for j in cj - 1..=cj + 1 {
        for i in ci - 1..=ci + 1 {
            if i < 0 || j < 0 || i >= cw as i64 || j >= ch as i64 {
                continue;
            }
            let s = &coarse[(j * cw as i64 + i) as usize];
            if !s.valid {
                continue;
            }
            let (px, py) = grid.pixel(i as u32, j as u32);
            let d2 = (px as f32 - x as f32).powi(2) + (py as f32 - y as f32).powi(2);
            let spatial = (-d2 / (2.0 * sigma * sigma)).exp();
            let cos = me.normal.dot(s.normal).max(0.0);
            let depth = (s.depth - me.depth) / (DEPTH_THRESHOLD * me.depth.max(1e-6));
            let range = cos.powi(8) * (-depth * depth).exp();
            let w = spatial * range;
            sum += s.irradiance * w;
            weights += w;
            if range > best.0 {
                best = (range, s.irradiance);
            }
        }
    }
    // Far from every neighbour in the image (weights underflow): the most alike one.
    if weights > 1e-12 {
        sum / weights
    } else {
        best.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texel(e: f32, normal: [f32; 3], depth: f32) -> IgiTexel {
        IgiTexel {
            irradiance: [e; 3],
            diffuse_samples: 1.0,
            reflectance: [1.0; 3],
            depth,
            normal,
            _pad: 0.0,
        }
    }

    /// A 12 x 12 frame, left half a wall facing +z at depth 1 with irradiance `left` at its
    /// gather pixels, right half a floor facing +y at depth 3 with `right`.
    fn two_surfaces(options: &IgiOptions, left: f32, right: f32) -> Vec<IgiTexel> {
        let grid = options.grid(12, 12);
        let (cw, ch) = grid.cells();
        let mut t: Vec<IgiTexel> = (0..144)
            .map(|p| {
                if p % 12 < 6 {
                    texel(0.0, [0.0, 0.0, 1.0], 1.0)
                } else {
                    texel(0.0, [0.0, 1.0, 0.0], 3.0)
                }
            })
            .collect();
        for j in 0..ch {
            for i in 0..cw {
                let (x, y) = grid.pixel(i, j);
                let p = (y * 12 + x) as usize;
                t[p].irradiance = [if x < 6 { left } else { right }; 3];
            }
        }
        t
    }

    #[test]
    fn filters_keep_a_constant_irradiance_and_do_not_blur_across_surfaces() {
        for options in [
            IgiOptions {
                downsample: 3,
                ..Default::default()
            },
            IgiOptions {
                interleave: [3, 3],
                ..Default::default()
            },
            IgiOptions {
                downsample: 2,
                interleave: [2, 3],
                ..Default::default()
            },
        ] {
            let t = two_surfaces(&options, 2.0, 2.0);
            let out = indirect_radiance(&options, 12, 12, &t);
            assert!(out.iter().all(|p| (p[0] - 2.0).abs() < 1e-5), "{options:?}");
            let t = two_surfaces(&options, 1.0, 5.0);
            let out = indirect_radiance(&options, 12, 12, &t);
            for (p, v) in out.iter().enumerate() {
                let want = if p % 12 < 6 { 1.0 } else { 5.0 };
                assert!((v[0] - want).abs() < 1e-3, "{options:?} pixel {p}: {v:?}");
            }
        }
    }

    #[test]
    fn the_discontinuity_buffer_averages_the_subsets_of_one_surface() {
        // A 3 x 3 tile whose pixels saw 9, 0, 0, ... : the mean over the tile is 1.
        let options = IgiOptions {
            interleave: [3, 3],
            ..Default::default()
        };
        let mut t: Vec<IgiTexel> = (0..81).map(|_| texel(0.0, [0.0, 0.0, 1.0], 1.0)).collect();
        for y in (0..9).step_by(3) {
            for x in (0..9).step_by(3) {
                t[y * 9 + x].irradiance = [9.0; 3];
            }
        }
        let out = indirect_radiance(&options, 9, 9, &t);
        // The centre of each tile sees exactly one tile's worth of subsets.
        for (x, y) in [(1, 1), (4, 4), (7, 4)] {
            assert!(
                (out[y * 9 + x][0] - 1.0).abs() < 1e-5,
                "{x},{y}: {:?}",
                out[y * 9 + x]
            );
        }
    }

    #[test]
    fn pixels_without_a_diffuse_hit_get_nothing() {
        let options = IgiOptions {
            downsample: 2,
            ..Default::default()
        };
        let mut t = two_surfaces(&options, 1.0, 1.0);
        t[0] = IgiTexel::default();
        let out = indirect_radiance(&options, 12, 12, &t);
        assert_eq!(out[0], [0.0; 3]);
        assert!(out[1][0] > 0.0);
    }
}

//! The edge-avoiding à-trous wavelet filter (Dammertz et al. 2010, "Edge-Avoiding À-Trous
//! Wavelet Transform for fast Global Illumination Filtering"), with the edge-stopping functions
//! of SVGF (Schied et al. 2017) for what a single frame has: the 5 x 5 B3-spline kernel applied
//! five times with holes of 1, 2, 4, 8 and 16 pixels, each tap weighed by how alike the two
//! pixels' normals (cosine to the power 128), depths (against the depth gradient times the
//! distance), albedos and radiance (against the local standard deviation, estimated in a 3 x 3
//! window since one frame has no history, and in log space, so an emitter's edge holds) are;
//! the albedo weight keeps texture edges. Radiance is not divided by the albedo (SVGF's demodulation): a constant image under
//! varying albedo must stay constant. A tap never crosses between a surface and the background
//! (infinite depth).

use rayon::prelude::*;

use super::Guides;
use platoon_image::Film;

/// The B3-spline kernel's 1D weights.
const KERNEL: [f32; 5] = [1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0];
/// Holes 1, 2, 4, 8, 16.
const ITERATIONS: u32 = 5;
/// The normal weight is the cosine to the power 2^7 = 128 (seven squarings: `powf` was the
/// filter's costliest step).
const NORMAL_POWER_LOG2: u32 = 7;
const DEPTH_SIGMA: f32 = 1.0;
const LUMINANCE_SIGMA: f32 = 2.0;
const ALBEDO_SIGMA: f32 = 0.1;
const LOG_LUMINANCE_SIGMA: f32 = 1.0;

/// `film` filtered with the guides of the same frame.
pub fn filter(film: &Film, guides: &Guides) -> Film {
    let (w, h) = (film.width as usize, film.height as usize);
    let n = w * h;
    let mut colour = film.pixels.clone();
    let gradient = depth_gradient(&guides.depth, w, h);
    let mut variance = spatial_variance(&colour, w, h);
    // The history's estimate where it has one (SVGF): a shadow's or a texture's edge is not
    // noise, which the window's estimate takes it for.
    if let Some(given) = &guides.variance {
        for (v, g) in variance.iter_mut().zip(given) {
            if !g.is_nan() {
                *v = *g;
            }
        }
    }
    for i in 0..ITERATIONS {
        let step = 1usize << i;
        let sd: Vec<f32> = blurred(&variance, w, h).iter().map(|v| v.sqrt()).collect();
        let lum = Luminance::of(&colour);
        let next: Vec<([f32; 3], f32)> = (0..n)
            .into_par_iter()
            .map(|p| {
                tap_sum(
                    p, step, w, h, &colour, &lum, &variance, &sd, &gradient, guides,
                )
            })
            .collect();
        colour = next.iter().map(|c| c.0).collect();
        variance = next.iter().map(|c| c.1).collect();
    }
    Film {
        width: film.width,
        height: film.height,
        pixels: colour,
    }
}

/// The filtered radiance and variance of pixel `p` for holes of `step` pixels.
#[allow(clippy::too_many_arguments)]
fn tap_sum(
    p: usize,
    step: usize,
    w: usize,
    h: usize,
    colour: &[[f32; 3]],
    lum: &Luminance,
    variance: &[f32],
    sd: &[f32],
    gradient: &[f32],
    g: &Guides,
) -> ([f32; 3], f32) {
    let (px, py) = ((p % w) as isize, (p / w) as isize);
    let (mut sum, mut var, mut weights) = ([0.0f32; 3], 0.0f32, 0.0f32);
    for (ky, hy) in KERNEL.iter().enumerate() {
        for (kx, hx) in KERNEL.iter().enumerate() {
            let qx = px + (kx as isize - 2) * step as isize;
            let qy = py + (ky as isize - 2) * step as isize;
            if qx < 0 || qy < 0 || qx >= w as isize || qy >= h as isize {
                continue;
            }
            let q = qy as usize * w + qx as usize;
            let weight = if q == p {
                hx * hy
            } else {
                let distance = ((qx - px).pow(2) + (qy - py).pow(2)) as f32;
                hx * hy * edge_weight(p, q, distance.sqrt(), lum, sd[p], gradient[p], g)
            };
            for c in 0..3 {
                sum[c] += weight * colour[q][c];
            }
            var += weight * weight * variance[q];
            weights += weight;
        }
    }
    // The centre tap always counts: weights > 0.
    (sum.map(|s| s / weights), var / (weights * weights))
}

/// How much pixel `q` may stand in for `p`: 0 across a normal, depth or albedo edge, or where
/// their radiance differs by many standard deviations.
#[allow(clippy::too_many_arguments)]
fn edge_weight(
    p: usize,
    q: usize,
    distance: f32,
    lum: &Luminance,
    sd: f32,
    gradient: f32,
    g: &Guides,
) -> f32 {
    let (zp, zq) = (g.depth[p], g.depth[q]);
    if zp.is_finite() != zq.is_finite() {
        return 0.0;
    }
    let np = g.normal[p];
    let nq = g.normal[q];
    let cos = np[0] * nq[0] + np[1] * nq[1] + np[2] * nq[2];
    let w_normal = if zp.is_finite() {
        (0..NORMAL_POWER_LOG2).fold(cos.max(0.0), |x, _| x * x)
    } else {
        1.0
    };
    let w_depth = if zp.is_finite() {
        -(zp - zq).abs() / (DEPTH_SIGMA * gradient * distance + 1e-6)
    } else {
        0.0
    };
    let (ap, aq) = (g.albedo[p], g.albedo[q]);
    let da = (0..3).map(|c| (ap[c] - aq[c]).powi(2)).sum::<f32>();
    let w_albedo = -da / (ALBEDO_SIGMA * ALBEDO_SIGMA);
    // In log space as well: an emitter's edge (radiance 20 beside 1) stops the filter even
    // where the window's spread is large.
    let w_luminance = -(lum.linear[p] - lum.linear[q]).abs() / (LUMINANCE_SIGMA * sd + 1e-6)
        - (lum.log[p] - lum.log[q]).abs() / LOG_LUMINANCE_SIGMA;
    w_normal * (w_depth + w_albedo + w_luminance).exp()
}

fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

/// Each pixel's luminance and ln(1 + luminance), once per iteration rather than per tap.
struct Luminance {
    linear: Vec<f32>,
    log: Vec<f32>,
}

impl Luminance {
    fn of(colour: &[[f32; 3]]) -> Luminance {
        let linear: Vec<f32> = colour.iter().map(|c| luminance(*c)).collect();
        let log = linear.iter().map(|l| l.ln_1p()).collect();
        Luminance { linear, log }
    }
}

/// The larger of the depth's central differences in x and y (0 at the background).
fn depth_gradient(depth: &[f32], w: usize, h: usize) -> Vec<f32> {
    let at = |x: usize, y: usize| depth[y * w + x];
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let d = |a: f32, b: f32| {
                if a.is_finite() && b.is_finite() {
                    (a - b).abs()
                } else {
                    0.0
                }
            };
            let gx = d(at((x + 1).min(w - 1), y), at(x.saturating_sub(1), y)) * 0.5;
            let gy = d(at(x, (y + 1).min(h - 1)), at(x, y.saturating_sub(1))) * 0.5;
            gx.max(gy)
        })
        .collect()
}

/// The variance of the luminance in each pixel's 3 x 3 window.
fn spatial_variance(colour: &[[f32; 3]], w: usize, h: usize) -> Vec<f32> {
    window_3x3(
        w,
        h,
        |i| luminance(colour[i]),
        |values| {
            let n = values.len() as f32;
            let mean = values.iter().sum::<f32>() / n;
            values.iter().map(|v| (v - mean) * (v - mean)).sum::<f32>() / n
        },
    )
}

/// The variance blurred by a 3 x 3 box (SVGF's prefilter before the luminance weight).
fn blurred(variance: &[f32], w: usize, h: usize) -> Vec<f32> {
    window_3x3(
        w,
        h,
        |i| variance[i],
        |values| values.iter().sum::<f32>() / values.len() as f32,
    )
}

fn window_3x3(
    w: usize,
    h: usize,
    value: impl Fn(usize) -> f32 + Sync,
    reduce: impl Fn(&[f32]) -> f32 + Sync,
) -> Vec<f32> {
    (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            let (mut values, mut n) = ([0.0f32; 9], 0);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (qx, qy) = (x + dx, y + dy);
                    if qx >= 0 && qy >= 0 && qx < w as isize && qy < h as isize {
                        values[n] = value(qy as usize * w + qx as usize);
                        n += 1;
                    }
                }
            }
            reduce(&values[..n])
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::denoise::test_frames::{assert_smoothed_not_across_the_edge, two_faces};

    #[test]
    fn a_constant_image_stays_constant() {
        let (film, mut guides) = two_faces(24, 16, 0.7, 0.7, 0.0);
        // Guides that vary: the filter must still average equal values to themselves.
        for (i, a) in guides.albedo.iter_mut().enumerate() {
            *a = [0.2 + 0.01 * (i % 7) as f32; 3];
        }
        let out = filter(&film, &guides);
        for p in &out.pixels {
            for c in p {
                assert!((c - 0.7).abs() < 1e-5, "{c}");
            }
        }
    }

    #[test]
    fn noise_is_smoothed_but_not_across_a_normal_edge() {
        assert_smoothed_not_across_the_edge(32, 16, 0.01, filter);
    }
}

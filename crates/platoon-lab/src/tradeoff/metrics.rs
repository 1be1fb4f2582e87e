//! Error of a render against a reference, both linear radiance of the same size.
//!
//! - RMSE over every pixel and channel: Bikker's measure (appendix D), dominated by the
//!   brightest pixels.
//! - Relative MSE, (x - r)^2 / (r^2 + 0.01) averaged over pixels and channels (pbrt's and
//!   Mitsuba's habit): every pixel counts for its relative error, so dark regions matter too.
//!
//! - LDR-FLIP (Andersson et al. 2020, NVIDIA's reference implementation through the `nv-flip`
//!   crate): the mean perceived difference, 0 to 1, between the two images as platoon's PNGs
//!   show them (the same tone curve), at the default 67 pixels per degree. A perceptual metric
//!   sees a noise pattern and a darkened caustic for what they look like, where the two MSEs
//!   weigh one pixel's error alone. HDR-FLIP would skip the tone curve; the crate offers LDR.
//!
//! Efficiency is 1 / (MSE x seconds): a technique twice as fast at the same error, or with half
//! the variance at the same time, is twice as efficient (Veach; the fair single number).

use platoon_core::output::Film;

/// Added to r^2 in the relative MSE so that black pixels do not divide by zero.
const REL_EPSILON: f64 = 0.01;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Errors {
    pub rmse: f64,
    pub relmse: f64,
    /// Mean LDR-FLIP error in [0, 1].
    pub flip: f64,
}

/// Errors of `film` against `reference` (same size: the caller checks).
pub fn errors(film: &Film, reference: &Film) -> Errors {
    let (mut se, mut rel) = (0.0f64, 0.0f64);
    for (p, r) in film.pixels.iter().zip(&reference.pixels) {
        for k in 0..3 {
            let (x, r) = (p[k] as f64, r[k] as f64);
            let d2 = (x - r) * (x - r);
            se += d2;
            rel += d2 / (r * r + REL_EPSILON);
        }
    }
    let n = (3 * film.pixels.len().max(1)) as f64;
    Errors {
        rmse: (se / n).sqrt(),
        relmse: rel / n,
        flip: flip(film, reference),
    }
}

/// Mean LDR-FLIP of `film` against `reference`, both tone-mapped as platoon's PNGs are.
pub fn flip(film: &Film, reference: &Film) -> f64 {
    let image = |f: &Film| nv_flip::FlipImageRgb8::with_data(f.width, f.height, &f.srgb8());
    let map = nv_flip::flip(
        image(reference),
        image(film),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    nv_flip::FlipPool::from_image(&map).mean() as f64
}

/// The relative squared bias of an estimator from independent realisations of it (2 or more):
/// (mean - r)^2 less the mean's variance (the realisations' sample variance over their count),
/// over r^2 + 0.01 as the relative MSE, averaged over pixels and channels. What is left of a
/// technique's relative MSE when its noise is averaged away; a noisy reference adds its own
/// variance to it.
pub fn relative_squared_bias(realisations: &[&Film], reference: &Film) -> f64 {
    let k = realisations.len() as f64;
    assert!(k >= 2.0, "the bias needs two realisations at least");
    let mut sum = 0.0f64;
    for (i, r) in reference.pixels.iter().enumerate() {
        for c in 0..3 {
            let values = realisations.iter().map(|f| f.pixels[i][c] as f64);
            let mean = values.clone().sum::<f64>() / k;
            let variance = values.map(|x| (x - mean) * (x - mean)).sum::<f64>() / (k - 1.0);
            let r = r[c] as f64;
            sum += ((mean - r) * (mean - r) - variance / k) / (r * r + REL_EPSILON);
        }
    }
    sum / (3 * reference.pixels.len().max(1)) as f64
}

/// 1 / (RMSE^2 x seconds).
pub fn efficiency(rmse: f64, seconds: f64) -> f64 {
    let cost = rmse * rmse * seconds;
    if cost > 0.0 {
        1.0 / cost
    } else {
        f64::INFINITY
    }
}

/// Least-squares slope of log(y) against log(x): how an error falls with samples.
pub fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    let n = logs.len() as f64;
    let (mx, my) = (
        logs.iter().map(|p| p.0).sum::<f64>() / n,
        logs.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film(v: &[f32]) -> Film {
        Film {
            width: v.len() as u32,
            height: 1,
            pixels: v.iter().map(|&x| [x; 3]).collect(),
        }
    }

    #[test]
    fn errors_match_their_definitions() {
        let e = errors(&film(&[1.0, 0.0]), &film(&[0.0, 0.0]));
        assert!((e.rmse - (0.5f64).sqrt()).abs() < 1e-12);
        assert!((e.relmse - 0.5 / REL_EPSILON).abs() < 1e-9);
        assert_eq!(errors(&film(&[2.0]), &film(&[2.0])).rmse, 0.0);
        assert_eq!(errors(&film(&[2.0]), &film(&[2.0])).flip, 0.0);
        // A black pixel where the reference is white is a large perceived error.
        let (black, white) = (film(&[0.0; 16]), film(&[1.0; 16]));
        assert!(flip(&black, &white) > 0.5);
        assert_eq!(efficiency(0.5, 2.0), 2.0);
        let slope = log_log_slope(&[(4.0, 0.5), (16.0, 0.25), (64.0, 0.125)]);
        assert!((slope + 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_squared_bias_is_what_the_mean_keeps_once_its_noise_is_taken_out() {
        // 64 realisations of 256 pixels of uniform noise in [-0.5, 0.5] about 1 (an LCG's).
        let mut state = 12345u64;
        let mut noise = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f64 / (1u64 << 24) as f64 - 0.5
        };
        let reference = film(&[1.0; 256]);
        let realisations = |offset: f64, noise: &mut dyn FnMut() -> f64| -> Vec<Film> {
            (0..64)
                .map(|_| {
                    let v: Vec<f32> = (0..256).map(|_| (1.0 + offset + noise()) as f32).collect();
                    film(&v)
                })
                .collect()
        };
        let unbiased = realisations(0.0, &mut noise);
        let b = relative_squared_bias(&unbiased.iter().collect::<Vec<_>>(), &reference);
        // The mean's own error, 1/12/64 over 1.01 a pixel, is taken out.
        assert!(b.abs() < 4e-4, "{b}");
        let shifted = realisations(0.2, &mut noise);
        let b = relative_squared_bias(&shifted.iter().collect::<Vec<_>>(), &reference);
        assert!((b - 0.04 / 1.01).abs() < 1e-3, "{b}");
    }
}

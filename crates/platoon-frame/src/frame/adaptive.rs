//! A frame's samples taken in batches, each continuing the sums of the ones before it (bit for
//! bit one longer render, `FrameParams::accumulated`), for what needs to look at the pixels on
//! the way:
//! - adaptive sampling, Cycles' scheme: each round's samples are taken in two halves, the first
//!   also summed into a half buffer; after a minimum of samples, and after each round, a pixel's
//!   error is the difference between its full and half estimates against the square root of its
//!   brightness, a pixel converges when its error and its 8 neighbours' errors are below the
//!   threshold (the dilation keeps a converged region's border sampling as long as its neighbour
//!   does), and converged pixels take no more samples (`FrameParams::converged`). The rounds end
//!   at fixed sample counts and the mask is computed from the assembled sums, so any split
//!   between devices gives the same bits;
//! - the variance AOV: the variance of each pixel's mean estimated from its batch means.

use std::sync::Arc;

use super::FrameParams;
use crate::output::Film;

/// Adaptive sampling's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Adaptive {
    /// The noise threshold: a pixel converges when its error estimate is below it (Cycles'
    /// "Noise Threshold"; 0.01 is a clean image, 0.1 a preview).
    pub threshold: f32,
    /// Samples every pixel takes before any may converge (`None`: `default_min_spp`).
    pub min_spp: Option<u32>,
}

impl Adaptive {
    /// The minimum when none is given: a sixteenth of the samples, at least 16 (and at most all).
    pub fn default_min_spp(spp: u32) -> u32 {
        (spp / 16).max(16).min(spp)
    }

    pub fn min_spp(&self, spp: u32) -> u32 {
        self.min_spp
            .unwrap_or_else(|| Self::default_min_spp(spp))
            .clamp(2, spp.max(2))
    }

    /// What is wrong with sampling a frame of `spp` samples rendered by `method` adaptively:
    /// the rules, once (the request's and the batched render's checks call this).
    pub fn validate(&self, spp: u32, method: &crate::method::Method) -> Result<(), String> {
        if !(self.threshold.is_finite() && self.threshold > 0.0) {
            return Err("the adaptive threshold must be a positive number".into());
        }
        if spp < 2 || self.min_spp == Some(0) {
            return Err("adaptive sampling needs at least 2 samples per pixel".into());
        }
        if !method.unit().skips_converged_pixels() {
            return Err(refused_by(method));
        }
        Ok(())
    }

    /// Why sampling `spp` samples a pixel adaptively would change nothing, when it would:
    /// every pixel takes its minimum before any may stop.
    pub fn idle(&self, spp: u32) -> Option<String> {
        let min = self.min_spp(spp);
        (min >= spp).then(|| {
            format!(
                "adaptive sampling does nothing at {spp} samples a pixel: every pixel takes its \
                 minimum of {min} before any may stop (give more samples, or a lower minimum)"
            )
        })
    }
}

/// How a frame's samples are batched.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Batching {
    pub adaptive: Option<Adaptive>,
    /// Keep what the variance AOV needs.
    pub variance: bool,
}

/// One batch: the samples [begin, end) of every pixel still sampling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Batch {
    pub begin: u32,
    pub end: u32,
    /// The first half of a round: its samples are also summed into the half buffer.
    pub half: bool,
    /// The mask is updated after it (the end of a round at or past the minimum).
    pub check: bool,
}

impl Batching {
    pub fn is_some(&self) -> bool {
        self.adaptive.is_some() || self.variance
    }

    /// The batches of a frame of `spp` samples rendered `per_pass` samples a kernel pass.
    pub fn batches(&self, spp: u32, per_pass: u32) -> Vec<Batch> {
        let mut out = Vec::new();
        let mut push = |begin: u32, end: u32, half: bool, check: bool| {
            if end > begin {
                out.push(Batch {
                    begin,
                    end,
                    half,
                    check,
                });
            }
        };
        match self.adaptive {
            Some(a) => {
                // Rounds of two passes after the minimum, each round in two halves.
                let step = 2 * per_pass.max(1);
                let mut begin = 0;
                let mut end = a.min_spp(spp).min(spp);
                while begin < spp {
                    let mid = begin + (end - begin) / 2;
                    push(begin, mid, true, false);
                    push(mid, end, false, end < spp);
                    begin = end;
                    end = (end + step).min(spp);
                }
            }
            None => {
                // At least 8 batches when the passes allow, for the batch means' variance.
                let size = (spp / 8).clamp(1, per_pass.max(1));
                let mut begin = 0;
                while begin < spp {
                    let end = (begin + size).min(spp);
                    push(begin, end, false, false);
                    begin = end;
                }
            }
        }
        out
    }
}

/// The sums of a frame rendered in batches and what each pixel's samples say of its noise.
pub struct Batched {
    width: u32,
    height: u32,
    sums: Arc<[[f32; 3]]>,
    half: Vec<[f32; 3]>,
    half_samples: Vec<u32>,
    samples: Vec<u32>,
    /// Per pixel: the batches its samples came in, and the sum of n_b m_b^2 over them (n_b
    /// samples of mean m_b), for the batch means' variance.
    batches: Vec<u32>,
    batch_squares: Vec<[f64; 3]>,
    converged: Arc<[bool]>,
}

impl Batched {
    pub fn new(width: u32, height: u32) -> Batched {
        let n = width as usize * height as usize;
        Batched {
            width,
            height,
            sums: vec![[0.0; 3]; n].into(),
            half: vec![[0.0; 3]; n],
            half_samples: vec![0; n],
            samples: vec![0; n],
            batches: vec![0; n],
            batch_squares: vec![[0.0; 3]; n],
            converged: vec![false; n].into(),
        }
    }

    /// The frame rendering `batch` of `base`: its samples, continuing the sums, the converged
    /// pixels left out.
    pub fn params(&self, base: &FrameParams, batch: &Batch) -> FrameParams {
        let mut p = base.clone();
        p.first_sample = base.first_sample.wrapping_add(batch.begin);
        p.spp = batch.end - batch.begin;
        p.film.accumulated = (batch.begin > 0).then(|| self.sums.clone());
        p.film.converged = self
            .converged
            .iter()
            .any(|&c| c)
            .then(|| self.converged.clone());
        p
    }

    /// Takes in the sums after `batch` (they continue the earlier ones).
    pub fn join(&mut self, batch: &Batch, sums: Vec<[f32; 3]>) {
        let n = (batch.end - batch.begin) as f64;
        for (i, new) in sums.iter().enumerate() {
            if self.converged[i] {
                continue;
            }
            let old = self.sums[i];
            let delta = [0, 1, 2].map(|c| new[c] - old[c]);
            if batch.half {
                for (h, d) in self.half[i].iter_mut().zip(delta) {
                    *h += d;
                }
                self.half_samples[i] += batch.end - batch.begin;
            }
            for (sq, d) in self.batch_squares[i].iter_mut().zip(delta) {
                let mean = d as f64 / n;
                *sq += n * mean * mean;
            }
            self.batches[i] += 1;
            self.samples[i] += batch.end - batch.begin;
        }
        self.sums = sums.into();
    }

    /// Marks the pixels whose error and neighbours' errors are below the threshold converged.
    pub fn check(&mut self, threshold: f32) {
        let (w, h) = (self.width as i64, self.height as i64);
        let noisy: Vec<bool> = (0..self.sums.len())
            .map(|i| !self.converged[i] && self.error(i) >= threshold)
            .collect();
        let mut converged = self.converged.to_vec();
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                if converged[i] {
                    continue;
                }
                let mut quiet = true;
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let (nx, ny) = (x + dx, y + dy);
                        if nx >= 0 && ny >= 0 && nx < w && ny < h {
                            quiet &= !noisy[(ny * w + nx) as usize];
                        }
                    }
                }
                converged[i] = quiet;
            }
        }
        self.converged = converged.into();
    }

    /// Cycles' per-pixel error: the L1 difference of the full and half estimates over the
    /// square root of the brightness (so the threshold is relative, gentler on dark pixels).
    fn error(&self, i: usize) -> f32 {
        if self.half_samples[i] == 0 || self.samples[i] == 0 {
            return f32::INFINITY;
        }
        let full = self.sums[i].map(|v| v / self.samples[i] as f32);
        let half = self.half[i].map(|v| v / self.half_samples[i] as f32);
        let diff: f32 = (0..3).map(|c| (full[c] - half[c]).abs()).sum();
        let brightness: f32 = full.iter().sum();
        diff / (1e-4 + brightness.max(0.0).sqrt())
    }

    /// The frame's mean radiance (as `assemble` computes it, so a frame of one sample count
    /// has the bits of an unbatched render).
    pub fn film(&self) -> Film {
        Film {
            width: self.width,
            height: self.height,
            pixels: self
                .sums
                .iter()
                .zip(&self.samples)
                .map(|(s, &n)| {
                    let inv = 1.0 / n.max(1) as f32;
                    s.map(|v| v * inv)
                })
                .collect(),
        }
    }

    pub fn sums(&self) -> Vec<[f32; 3]> {
        self.sums.to_vec()
    }

    /// Samples each pixel took.
    pub fn samples(&self) -> &[u32] {
        &self.samples
    }

    /// The variance of each pixel's mean, per channel, from its batch means (with n_b samples
    /// of mean m_b, N in all of mean m: sum n_b (m_b - m)^2 / (B - 1) / N); +inf for a pixel of
    /// one batch.
    pub fn variance(&self) -> Vec<[f32; 3]> {
        (0..self.sums.len())
            .map(|i| {
                let b = self.batches[i];
                let n = self.samples[i] as f64;
                if b < 2 {
                    return [f32::INFINITY; 3];
                }
                [0, 1, 2].map(|c| {
                    let mean = self.sums[i][c] as f64 / n;
                    let spread = (self.batch_squares[i][c] - n * mean * mean).max(0.0);
                    (spread / (b - 1) as f64 / n) as f32
                })
            })
            .collect()
    }
}

/// Why adaptive sampling is refused to `method`: its kernels render every pixel's samples
/// (`RenderMethod::skips_converged_pixels`).
fn refused_by(method: &crate::method::Method) -> String {
    format!(
        "adaptive sampling: method {}'s kernels render every pixel's samples, skipping no \
         converged pixel",
        method.unit().name()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn adaptive(min: u32) -> Batching {
        Batching {
            adaptive: Some(Adaptive {
                threshold: 0.01,
                min_spp: Some(min),
            }),
            variance: false,
        }
    }

    #[test]
    fn rounds_halve_and_check_at_fixed_counts() {
        let b = adaptive(16).batches(64, 16);
        let ends: Vec<(u32, bool, bool)> = b.iter().map(|b| (b.end, b.half, b.check)).collect();
        assert_eq!(
            ends,
            vec![
                (8, true, false),
                (16, false, true),
                (32, true, false),
                (48, false, true),
                (56, true, false),
                (64, false, false)
            ]
        );
        assert!(b.windows(2).all(|w| w[0].end == w[1].begin));
        let plain = Batching {
            adaptive: None,
            variance: true,
        };
        assert_eq!(plain.batches(64, 16).len(), 8);
        assert_eq!(plain.batches(3, 16).len(), 3);
    }

    /// A pixel whose halves agree converges; one whose halves differ does not, nor do its
    /// neighbours (the dilation), while pixels two away do.
    #[test]
    fn converges_where_the_halves_agree_and_dilates_the_noisy_ones() {
        let (w, h) = (5u32, 1u32);
        let mut b = Batched::new(w, h);
        let first = Batch {
            begin: 0,
            end: 2,
            half: true,
            check: false,
        };
        let second = Batch {
            begin: 2,
            end: 4,
            half: false,
            check: true,
        };
        b.join(&first, vec![[2.0; 3]; 5]);
        let mut after = vec![[4.0; 3]; 5];
        after[0] = [10.0; 3];
        b.join(&second, after);
        b.check(0.01);
        assert_eq!(&*b.converged, &[false, false, true, true, true]);
        assert_eq!(b.samples(), &[4, 4, 4, 4, 4]);
        // Converged pixels keep their sums and counts through the next batch.
        let p = b.params(&FrameParams::new(w, h, 8, camera()), &second);
        assert_eq!(p.film.converged.as_deref().unwrap().len(), 5);
        let third = Batch {
            begin: 4,
            end: 8,
            half: true,
            check: false,
        };
        let mut next = b.sums();
        next[0] = [20.0; 3];
        next[1] = [8.0; 3];
        b.join(&third, next);
        assert_eq!(b.samples(), &[8, 8, 4, 4, 4]);
        assert_eq!(b.film().pixels[2], [1.0; 3]);
        assert_eq!(b.film().pixels[0], [2.5; 3]);
    }

    #[test]
    fn batch_means_give_the_variance_of_the_mean() {
        // Two batches of 2 samples with means 1 and 3: sample variance 2 * ((1-2)^2 + (3-2)^2)
        // / 1 = 4 per sample, 1 for the mean of 4.
        let mut b = Batched::new(1, 1);
        let batch = |begin, end| Batch {
            begin,
            end,
            half: false,
            check: false,
        };
        b.join(&batch(0, 2), vec![[2.0; 3]]);
        b.join(&batch(2, 4), vec![[8.0; 3]]);
        assert_eq!(b.variance()[0], [1.0; 3]);
    }

    fn camera() -> crate::scene::camera::Camera {
        crate::scene::camera::Camera::look_at(glam::Vec3::ZERO, glam::Vec3::NEG_Z, 1.0)
    }
}

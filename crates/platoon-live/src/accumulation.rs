//! The film a game's frames converge in (Bikker 7.3.5): `C = C_prev (1 - f) + C_new f`, carried
//! out as the frame's [`Join`] says. While the view is still the film keeps radiance sums and
//! the frames continue them (the tracers add each sample onto the sums in sample order), so k
//! frames of s samples are bit for bit one render of k s samples; a blend keeps a mean.

use std::sync::Arc;

use super::plan::Join;
use platoon_core::output::Film;

pub struct Accumulation {
    width: u32,
    height: u32,
    /// The sums of every sample since the last restart, while the film is exact.
    sums: Option<Arc<[[f32; 3]]>>,
    /// Samples per pixel in `sums`.
    samples: u32,
    /// What the film shows.
    mean: Vec<[f32; 3]>,
}

impl Accumulation {
    pub fn new(width: u32, height: u32) -> Accumulation {
        Accumulation {
            width,
            height,
            sums: None,
            samples: 0,
            mean: vec![[0.0; 3]; width as usize * height as usize],
        }
    }

    /// The sums a frame joining with `join` continues (the tracers start from them).
    pub fn continued(&self, join: Join) -> Option<Arc<[[f32; 3]]>> {
        match join {
            Join::Sum => self.sums.clone(),
            Join::Restart | Join::Blend { .. } => None,
        }
    }

    /// Joins a frame: `sums` are its radiance sums (continuing [`Accumulation::continued`]
    /// when it was given), `spp` the samples per pixel the frame added.
    pub fn join(&mut self, join: Join, sums: Vec<[f32; 3]>, spp: u32) {
        let spp = spp.max(1);
        match join {
            Join::Restart => self.keep_sums(sums, spp),
            Join::Sum if self.sums.is_some() => self.keep_sums(sums, self.samples + spp),
            // A sum over a film that holds a mean cannot be exact; the plan never asks for
            // one, and if it did the frame restarts the sums.
            Join::Sum => self.keep_sums(sums, spp),
            Join::Blend { f } => {
                let inv = 1.0 / spp as f32;
                for (m, s) in self.mean.iter_mut().zip(&sums) {
                    for k in 0..3 {
                        m[k] = m[k] * (1.0 - f) + s[k] * inv * f;
                    }
                }
                self.sums = None;
                self.samples = 0;
            }
        }
    }

    /// Joins a frame rendered at a reduced resolution (`size`): its mean, upscaled bilinearly
    /// to the film's size, restarts the film or is blended in (an upscaled frame is a mean, never
    /// exact sums).
    pub fn join_upscaled(&mut self, join: Join, sums: &[[f32; 3]], size: (u32, u32), spp: u32) {
        let inv = 1.0 / spp.max(1) as f32;
        let mean = upscale(sums, size, (self.width, self.height));
        let f = match join {
            Join::Restart => 1.0,
            Join::Blend { f } => f,
            // The plan blends converging upscaled frames; a sum here would be a mistake, so it
            // restarts.
            Join::Sum => 1.0,
        };
        for (m, s) in self.mean.iter_mut().zip(&mean) {
            for k in 0..3 {
                m[k] = m[k] * (1.0 - f) + s[k] * inv * f;
            }
        }
        self.sums = None;
        self.samples = 0;
    }

    fn keep_sums(&mut self, sums: Vec<[f32; 3]>, samples: u32) {
        // The same arithmetic as the offline film (`frame::assemble`), for the same bits.
        let inv = 1.0 / samples as f32;
        for (m, s) in self.mean.iter_mut().zip(&sums) {
            *m = s.map(|v| v * inv);
        }
        self.samples = samples;
        self.sums = Some(sums.into());
    }

    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Samples per pixel behind the film while it holds exact sums, else None (a blend).
    pub fn samples(&self) -> Option<u32> {
        self.sums.as_ref().map(|_| self.samples)
    }

    pub fn film(&self) -> Film {
        Film {
            width: self.width,
            height: self.height,
            pixels: self.mean.clone(),
        }
    }
}

/// Bilinear resampling of a `from`-sized image to `to`, pixel centres aligned.
pub(super) fn upscale(pixels: &[[f32; 3]], from: (u32, u32), to: (u32, u32)) -> Vec<[f32; 3]> {
    let (fw, fh) = (from.0.max(1) as usize, from.1.max(1) as usize);
    let at = |x: usize, y: usize| pixels.get(y * fw + x).copied().unwrap_or([0.0; 3]);
    // Position of a target pixel's centre in source pixels, and its two neighbours' weights.
    let axis = |i: u32, t: u32, f: usize| -> (usize, usize, f32) {
        let p = ((i as f32 + 0.5) * f as f32 / t.max(1) as f32 - 0.5).max(0.0);
        let i0 = (p.floor() as usize).min(f - 1);
        (i0, (i0 + 1).min(f - 1), p - i0 as f32)
    };
    let mut out = Vec::with_capacity(to.0 as usize * to.1 as usize);
    for y in 0..to.1 {
        let (y0, y1, ty) = axis(y, to.1, fh);
        for x in 0..to.0 {
            let (x0, x1, tx) = axis(x, to.0, fw);
            let (a, b, c, d) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
            out.push(std::array::from_fn(|k| {
                let top = a[k] + (b[k] - a[k]) * tx;
                let bottom = c[k] + (d[k] - c[k]) * tx;
                top + (bottom - top) * ty
            }));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_upscaled_frame_is_its_mean_resampled_and_blends_like_one() {
        let mut a = Accumulation::new(4, 2);
        // 2x1 pixels of 2 samples: sums 0 and 4 -> means 0 and 2.
        a.join_upscaled(Join::Restart, &[[0.0; 3], [4.0; 3]], (2, 1), 2);
        let row: Vec<f32> = a.film().pixels[..4].iter().map(|p| p[0]).collect();
        // Pixel centres 0.5..3.5 of 4 fall at -0.25, 0.25, 0.75, 1.25 of 2: clamped at the
        // edges, linear between.
        assert_eq!(row, vec![0.0, 0.5, 1.5, 2.0]);
        assert_eq!(a.film().pixels[4..], a.film().pixels[..4]);
        assert_eq!(a.samples(), None);
        assert!(a.continued(Join::Sum).is_none());
        a.join_upscaled(Join::Blend { f: 0.5 }, &[[2.0; 3], [2.0; 3]], (2, 1), 2);
        assert_eq!(a.film().pixels[0], [0.5; 3]);
    }

    #[test]
    fn sums_continue_and_blends_mix_means() {
        let mut a = Accumulation::new(1, 1);
        a.join(Join::Restart, vec![[2.0, 4.0, 6.0]], 2);
        assert_eq!(a.film().pixels, vec![[1.0, 2.0, 3.0]]);
        assert_eq!(
            a.continued(Join::Sum).as_deref(),
            Some(&[[2.0, 4.0, 6.0]][..])
        );
        assert!(a.continued(Join::Restart).is_none());
        // The frame's sums include the earlier ones: 2 + 2 samples.
        a.join(Join::Sum, vec![[4.0, 4.0, 4.0]], 2);
        assert_eq!(
            (a.film().pixels[0], a.samples()),
            ([1.0, 1.0, 1.0], Some(4))
        );
        a.join(Join::Blend { f: 0.25 }, vec![[10.0, 10.0, 10.0]], 2);
        assert_eq!(a.film().pixels[0], [2.0, 2.0, 2.0]);
        assert_eq!(a.samples(), None);
    }
}

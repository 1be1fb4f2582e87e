//! Distant lighting: a constant colour or an equirectangular HDR map (EXR or Radiance .hdr),
//! with the piecewise-constant 2D distribution used to importance-sample it.

use std::f32::consts::PI;
use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::error::{Error, Result};

#[derive(Clone, Debug)]
pub enum Environment {
    Constant(Vec3),
    Map(EnvMap),
}

/// Equirectangular map: u = phi / 2pi with phi measured around +Y from +X towards -Z... see
/// `direction_to_uv` in shaders/environment.glsl, the single definition both sides follow.
#[derive(Clone, Debug)]
pub struct EnvMap {
    pub path: PathBuf,
    pub width: u32,
    pub height: u32,
    /// Linear RGB radiance, row-major from the top row (theta = 0, +Y).
    pub texels: Vec<[f32; 3]>,
}

/// Sampling tables for an environment map: the marginal CDF over rows and one conditional CDF
/// per row, both of length n+1 and starting at 0, built on luminance * sin(theta).
pub struct EnvDistribution {
    pub marginal_cdf: Vec<f32>,
    pub conditional_cdf: Vec<f32>,
    /// Integral of the (unnormalised) function over `[0,1]^2`.
    pub integral: f32,
}

/// Rec. 709 luminance, the weighting used for light power and importance sampling (the kernel's
/// `luminance` in shaders/scene.glsl uses the same weights).
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

fn cdf_of(f: impl Iterator<Item = f32>, n: usize) -> (Vec<f32>, f32) {
    let mut cdf = Vec::with_capacity(n + 1);
    cdf.push(0.0f64);
    let mut sum = 0.0f64;
    for v in f {
        sum += v as f64 / n as f64;
        cdf.push(sum);
    }
    let total = sum;
    let cdf = if total > 0.0 {
        cdf.iter().map(|c| (c / total) as f32).collect()
    } else {
        (0..=n).map(|i| i as f32 / n as f32).collect()
    };
    (cdf, total as f32)
}

impl EnvMap {
    pub fn load(path: &Path) -> Result<EnvMap> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        crate::input::regular_file(path)
            .map_err(|e| Error::file(path, format!("cannot read environment map: {e}")))?;
        let (width, height, texels) = match ext.as_str() {
            "exr" => {
                use exr::prelude::*;
                let image = read_first_rgba_layer_from_file(
                    path,
                    |res, _| (res.width(), vec![[0.0f32; 3]; res.width() * res.height()]),
                    |(w, px), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
                        px[pos.y() * *w + pos.x()] = [r, g, b]
                    },
                )
                .map_err(|e| {
                    crate::Error::file(path, format!("cannot read EXR environment map: {e}"))
                })?;
                let size = image.layer_data.size;
                (
                    size.width() as u32,
                    size.height() as u32,
                    image.layer_data.channel_data.pixels.1,
                )
            }
            "hdr" => {
                let img = image::open(path).map_err(|e| {
                    Error::file(path, format!("cannot read HDR environment map: {e}"))
                })?;
                let rgb = img.to_rgb32f();
                let texels = rgb.pixels().map(|p| p.0).collect();
                (rgb.width(), rgb.height(), texels)
            }
            _ => return Err(Error::file(path, "environment map must be .exr or .hdr")),
        };
        if width == 0 || height == 0 {
            return Err(Error::file(path, "environment map is empty"));
        }
        let mut texels: Vec<[f32; 3]> = texels;
        // Non-finite or negative radiance would poison the sampling tables and the film.
        for t in &mut texels {
            for c in t.iter_mut() {
                if !c.is_finite() || *c < 0.0 {
                    *c = 0.0;
                }
            }
        }
        Ok(EnvMap {
            path: path.to_path_buf(),
            width,
            height,
            texels,
        })
    }

    /// Turns the map about +Y by `degrees`, counter-clockwise seen from above (right-handed):
    /// what was at azimuth phi (`direction_to_uv`'s, from -Z towards +X) is then at phi -
    /// degrees. By whole columns of texels (a 2048-wide map's step is 0.18 degrees), so the
    /// map's texels, and with them its sampling, are the unrotated map's moved.
    pub fn rotate(&mut self, degrees: f32) {
        let w = self.width as i64;
        let shift = ((degrees as f64 / 360.0 * w as f64).round() as i64).rem_euclid(w) as usize;
        if shift == 0 {
            return;
        }
        for row in self.texels.chunks_exact_mut(self.width as usize) {
            row.rotate_left(shift);
        }
    }

    pub fn distribution(&self) -> EnvDistribution {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut conditional_cdf = Vec::with_capacity(h * (w + 1));
        let mut row_integrals = Vec::with_capacity(h);
        for y in 0..h {
            let sin_theta = (PI * (y as f32 + 0.5) / h as f32).sin();
            let row = &self.texels[y * w..(y + 1) * w];
            let (cdf, integral) = cdf_of(
                row.iter()
                    .map(|t| luminance(Vec3::from_array(*t)) * sin_theta),
                w,
            );
            conditional_cdf.extend(cdf);
            row_integrals.push(integral);
        }
        let (marginal_cdf, integral) = cdf_of(row_integrals.iter().copied(), h);
        EnvDistribution {
            marginal_cdf,
            conditional_cdf,
            integral,
        }
    }

    /// Mean radiance over the sphere (solid-angle weighted), for light power estimates.
    pub fn mean_radiance(&self) -> Vec3 {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut sum = [0.0f64; 3];
        let mut wsum = 0.0f64;
        for y in 0..h {
            let s = (PI * (y as f32 + 0.5) / h as f32).sin() as f64;
            for x in 0..w {
                let t = self.texels[y * w + x];
                for k in 0..3 {
                    sum[k] += t[k] as f64 * s;
                }
                wsum += s;
            }
        }
        Vec3::new(
            (sum[0] / wsum) as f32,
            (sum[1] / wsum) as f32,
            (sum[2] / wsum) as f32,
        )
    }
}

impl Environment {
    pub fn mean_radiance(&self) -> Vec3 {
        match self {
            Environment::Constant(c) => *c,
            Environment::Map(m) => m.mean_radiance(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdfs_are_monotone_and_normalised() {
        let map = EnvMap {
            path: "x".into(),
            width: 4,
            height: 2,
            texels: vec![
                [1.0, 1.0, 1.0],
                [0.0; 3],
                [2.0, 2.0, 2.0],
                [0.0; 3],
                [0.0; 3],
                [0.0; 3],
                [0.0; 3],
                [0.0; 3],
            ],
        };
        let d = map.distribution();
        assert_eq!(d.marginal_cdf.len(), 3);
        assert_eq!(*d.marginal_cdf.last().unwrap(), 1.0);
        assert_eq!(
            &d.conditional_cdf[..5],
            &[0.0, 1.0 / 3.0, 1.0 / 3.0, 1.0, 1.0]
        );
        // An all-black row still has a valid (uniform) CDF.
        assert_eq!(&d.conditional_cdf[5..], &[0.0, 0.25, 0.5, 0.75, 1.0]);
        assert!(d.marginal_cdf.windows(2).all(|w| w[0] <= w[1]));
    }
}

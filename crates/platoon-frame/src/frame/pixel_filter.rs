//! The pixel filter: how much a sample counts for the pixel it is taken for, by its offset from
//! the pixel's centre. Camera rays leave the pixel at an offset drawn from the filter itself
//! (filter importance sampling, as Cycles does), so every sample weighs one and a pixel's
//! estimate is its own samples' mean: the same bits for any split of the frame between
//! devices. Separable: the two axes' offsets are drawn apart, each from the 1D filter.

use std::fmt;

/// The filter, with its standard width (a kernel define each, `method::variant`; the sampling
/// in `shaders/path/pixel_filter.glsl`).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum PixelFilter {
    /// Uniform over the pixel (1 px): the sharpest, aliasing the most.
    #[default]
    Box,
    /// Gaussian of standard deviation 0.5 px (Mitsuba's default), cut at 3 of them (1.5 px
    /// from the centre).
    Gaussian,
    /// Blackman-Harris over 1.5 px (Cycles' default filter).
    BlackmanHarris,
}

/// The Gaussian's standard deviation and the distance it is cut at, in pixels.
pub const GAUSSIAN_SIGMA: f64 = 0.5;
pub const GAUSSIAN_RADIUS: f64 = 1.5;
/// Blackman-Harris' width (its whole support), in pixels, and its four coefficients.
pub const BLACKMAN_HARRIS_WIDTH: f64 = 1.5;
pub const BLACKMAN_HARRIS: [f64; 4] = [0.35875, 0.48829, 0.14128, 0.01168];

impl PixelFilter {
    pub const NAMES: [&'static str; 3] = ["box", "gaussian", "blackman-harris"];

    pub fn name(self) -> &'static str {
        match self {
            PixelFilter::Box => "box",
            PixelFilter::Gaussian => "gaussian",
            PixelFilter::BlackmanHarris => "blackman-harris",
        }
    }

    pub fn parse(name: &str) -> Result<PixelFilter, String> {
        match name {
            "box" => Ok(PixelFilter::Box),
            "gaussian" => Ok(PixelFilter::Gaussian),
            "blackman-harris" => Ok(PixelFilter::BlackmanHarris),
            _ => Err(format!(
                "unknown pixel filter {name:?} (known: {})",
                Self::NAMES.join(", ")
            )),
        }
    }

    /// The 1D filter's value at `x` pixels from the centre, unnormalised (0 outside).
    pub fn weight(self, x: f64) -> f64 {
        match self {
            PixelFilter::Box => f64::from(x.abs() <= 0.5),
            PixelFilter::Gaussian if x.abs() <= GAUSSIAN_RADIUS => {
                (-x * x / (2.0 * GAUSSIAN_SIGMA * GAUSSIAN_SIGMA)).exp()
            }
            PixelFilter::BlackmanHarris if x.abs() <= 0.5 * BLACKMAN_HARRIS_WIDTH => {
                let [a0, a1, a2, a3] = BLACKMAN_HARRIS;
                let v = 2.0 * std::f64::consts::PI * (x / BLACKMAN_HARRIS_WIDTH + 0.5);
                a0 - a1 * v.cos() + a2 * (2.0 * v).cos() - a3 * (3.0 * v).cos()
            }
            _ => 0.0,
        }
    }

    /// What the output's metadata says of it.
    pub fn describe(self) -> String {
        match self {
            PixelFilter::Box => "box, 1 px".into(),
            PixelFilter::Gaussian => {
                format!("gaussian, sigma {GAUSSIAN_SIGMA} px, cut at {GAUSSIAN_RADIUS} px")
            }
            PixelFilter::BlackmanHarris => format!("blackman-harris, {BLACKMAN_HARRIS_WIDTH} px"),
        }
    }
}

impl fmt::Display for PixelFilter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

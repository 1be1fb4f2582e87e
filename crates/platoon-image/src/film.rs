//! What the writers write: a rendered frame (linear RGB radiance) and the layers beside it.

use crate::colour::View;

/// A rendered frame: linear RGB radiance, row-major from the top row.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl Film {
    pub fn mean(&self) -> [f64; 3] {
        let mut s = [0.0f64; 3];
        for p in &self.pixels {
            for k in 0..3 {
                s[k] += p[k] as f64;
            }
        }
        s.map(|v| v / self.pixels.len().max(1) as f64)
    }
    /// The image as 8-bit sRGB under the default view, three bytes a pixel.
    pub fn srgb8(&self) -> Vec<u8> {
        self.srgb8_viewed(&View::default())
    }

    /// The image as 16-bit sRGB under `view`, three values a pixel.
    pub fn srgb16_viewed(&self, view: &View) -> Vec<u16> {
        self.pixels.iter().flat_map(|&p| view.srgb16(p)).collect()
    }

    /// The image as 8-bit sRGB under `view`, three bytes a pixel (a PNG's pixels).
    pub fn srgb8_viewed(&self, view: &View) -> Vec<u8> {
        self.pixels.iter().flat_map(|&p| view.srgb8(p)).collect()
    }

    /// The colour with `alpha` divided back out (straight alpha, what PNG and TIFF hold): the
    /// film's colour is premultiplied by its coverage. Black where nothing covers the pixel.
    pub fn unpremultiplied(&self, alpha: &[f32]) -> Film {
        let pixels = (self.pixels.iter().zip(alpha))
            .map(|(p, &a)| match a > 0.0 {
                true => p.map(|c| c / a),
                false => [0.0; 3],
            })
            .collect();
        Film { pixels, ..*self }
    }

    pub fn count_non_finite(&self) -> usize {
        self.pixels
            .iter()
            .filter(|p| p.iter().any(|v| !v.is_finite()))
            .count()
    }
}

/// A layer of an output image: named channels, each a plane of `width * height` values.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    pub name: String,
    pub channels: Vec<(String, Vec<f32>)>,
    /// Header attributes the layer brings, written as they are (Cryptomatte's manifest).
    pub attributes: Vec<(String, String)>,
    /// Written as 32-bit floats whatever the file's sample type: values whose bits matter
    /// (Cryptomatte's ids, hashes stored as floats).
    pub full_float: bool,
}

impl Layer {
    /// The channel `name` of the layer.
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }
}

impl Film {
    /// Its 8-bit display samples under `view`: RGB, or given a transparent film's `alpha` RGBA
    /// of straight alpha (the colour divided by it first): what a PNG or TIFF holds.
    pub(super) fn display8(&self, alpha: Option<&[f32]>, view: &View) -> Vec<u8> {
        self.display(alpha, u8::MAX as u32, |f| f.srgb8_viewed(view))
    }

    /// ... its 16-bit ones.
    pub(super) fn display16(&self, alpha: Option<&[f32]>, view: &View) -> Vec<u16> {
        self.display(alpha, u16::MAX as u32, |f| f.srgb16_viewed(view))
    }

    fn display<T: Copy + TryFrom<u32>>(
        &self,
        alpha: Option<&[f32]>,
        max: u32,
        rgb: impl Fn(&Film) -> Vec<T>,
    ) -> Vec<T> {
        match alpha {
            None => rgb(self),
            Some(a) => with_alpha(&rgb(&self.unpremultiplied(a)), a, max),
        }
    }
}

/// Display samples of three channels a pixel (`rgb`) with a fourth, the alpha `alpha` at the
/// same bits (`max`: the largest sample, 255 or 65535).
fn with_alpha<T: Copy + TryFrom<u32>>(rgb: &[T], alpha: &[f32], max: u32) -> Vec<T> {
    let a = |v: f32| -> T {
        let q = (v.clamp(0.0, 1.0) * max as f32).round() as u32;
        T::try_from(q.min(max))
            .ok()
            .expect("within the sample's range")
    };
    rgb.chunks(3)
        .zip(alpha)
        .flat_map(|(c, &v)| [c[0], c[1], c[2], a(v)])
        .collect()
}

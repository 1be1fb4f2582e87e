//! What guides a denoiser: the frame's albedo, normal and depth AOVs, pixel by pixel.

use crate::aov::Layer;

/// A frame's albedo, normal and depth, pixel by pixel.
#[derive(Clone, Debug)]
pub struct Guides {
    pub albedo: Vec<[f32; 3]>,
    pub normal: Vec<[f32; 3]>,
    /// Along the view axis; infinite where the pixel sees no surface.
    pub depth: Vec<f32>,
    /// The variance of each pixel's luminance as the image holds it, from its history's
    /// moments (SVGF's temporal estimate, `denoise::temporal`); NaN where the history is too
    /// short, and None for a single frame: the filter estimates those in a 3 x 3 window.
    pub variance: Option<Vec<f32>>,
}

impl Guides {
    /// The guides from the frame's layers (None unless albedo, normal and depth are there).
    pub fn from_layers(layers: &[Layer]) -> Option<Guides> {
        let plane = |name: &str, channels: [&str; 3]| -> Option<Vec<[f32; 3]>> {
            let l = layers.iter().find(|l| l.name == name)?;
            let [a, b, c] = channels.map(|ch| l.channel(ch));
            let (a, b, c) = (a?, b?, c?);
            Some((0..a.len()).map(|i| [a[i], b[i], c[i]]).collect())
        };
        Some(Guides {
            albedo: plane("albedo", ["R", "G", "B"])?,
            normal: plane("normal", ["X", "Y", "Z"])?,
            depth: layers
                .iter()
                .find(|l| l.name == "depth")?
                .channel("Z")?
                .to_vec(),
            variance: None,
        })
    }
}

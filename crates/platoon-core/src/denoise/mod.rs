//! Denoising a frame after assembly (so the image is the same whatever the split between
//! devices), guided by its albedo, normal and depth AOVs (`frame::aov`). Denoising is an
//! approximation (biased): the raw image is always kept beside the denoised one.

pub mod atrous;

use crate::frame::aov::{Aov, Layer};
use crate::output::Film;

/// Which denoiser `--denoise` names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Denoiser {
    #[default]
    None,
    /// The edge-avoiding à-trous wavelet filter ([`atrous`]).
    Atrous,
}

impl std::str::FromStr for Denoiser {
    type Err = String;
    fn from_str(s: &str) -> Result<Denoiser, String> {
        match s {
            "none" => Ok(Denoiser::None),
            "atrous" => Ok(Denoiser::Atrous),
            _ => Err(format!("unknown denoiser {s:?}: none or atrous")),
        }
    }
}

impl Denoiser {
    /// What the metadata's approximations say of it (None when it is off).
    pub fn describe(self) -> Option<&'static str> {
        match self {
            Denoiser::None => None,
            Denoiser::Atrous => Some(
                "denoised by the edge-avoiding a-trous filter (Dammertz et al. 2010; 5 \
                 iterations, guided by albedo, normal and depth)",
            ),
        }
    }

    /// The AOVs it is guided by.
    pub const GUIDES: [Aov; 3] = [Aov::Albedo, Aov::Normal, Aov::Depth];

    /// `film` denoised with `guides` (`film` itself when off).
    pub fn apply(self, film: &Film, guides: &Guides) -> Film {
        match self {
            Denoiser::None => film.clone(),
            Denoiser::Atrous => atrous::filter(film, guides),
        }
    }
}

/// A frame's albedo, normal and depth, pixel by pixel.
#[derive(Clone, Debug)]
pub struct Guides {
    pub albedo: Vec<[f32; 3]>,
    pub normal: Vec<[f32; 3]>,
    /// Along the view axis; infinite where the pixel sees no surface.
    pub depth: Vec<f32>,
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
        })
    }
}

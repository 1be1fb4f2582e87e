//! What a rendered frame writes: the image (denoised when asked, the raw one kept beside it as
//! `NAME.noisy.EXT`), with the AOV layers asked for.

use std::path::{Path, PathBuf};

use anyhow::Result;
use platoon::core::denoise::{Denoiser, Guides};
use platoon::core::flatten::GpuScene;
use platoon::core::frame::aov::{Aov, Layer};
use platoon::core::frame::FrameParams;
use platoon::core::output::{write_image_with_layers, Film};
use platoon::{Rendered, Tracers};

/// A frame's files before writing.
pub struct Outputs {
    image: Film,
    layers: Vec<Layer>,
    /// The raw image, when `image` is denoised.
    raw: Option<Film>,
    denoiser: Denoiser,
}

impl Outputs {
    /// The AOVs `aovs` and the denoiser's guides rendered on `tracers` for the frame, and the
    /// image denoised.
    pub fn of(
        tracers: &mut Tracers,
        scene: &GpuScene,
        params: &FrameParams,
        rendered: &Rendered,
        aovs: &[Aov],
        denoiser: Denoiser,
        origin: glam::DVec3,
    ) -> Result<Outputs> {
        let mut wanted = aovs.to_vec();
        if denoiser != Denoiser::None {
            for g in Denoiser::GUIDES {
                if !wanted.contains(&g) {
                    wanted.push(g);
                }
            }
        }
        let mut layers = if wanted.is_empty() {
            Vec::new()
        } else {
            platoon::aov::render_layers(tracers, scene, params, &wanted, origin)?
        };
        let (image, raw) = match denoiser {
            Denoiser::None => (rendered.film.clone(), None),
            _ => {
                let guides = Guides::from_layers(&layers).expect("the guides were rendered");
                (
                    denoiser
                        .apply(&rendered.film, &guides)
                        .map_err(anyhow::Error::msg)?,
                    Some(rendered.film.clone()),
                )
            }
        };
        layers.extend(platoon::aov::batch_layers(rendered, aovs)?);
        layers.retain(|l| aovs.iter().any(|a| a.name() == l.name));
        layers.sort_by_key(|l| aovs.iter().position(|a| a.name() == l.name));
        Ok(Outputs {
            image,
            layers,
            raw,
            denoiser,
        })
    }

    /// Writes the image to `path` (and the raw one beside it), each with `meta`, atomically.
    pub fn write(&self, path: &Path, meta: &[(String, String)]) -> Result<()> {
        if let Some(raw) = &self.raw {
            write_image_with_layers(&noisy_path(path), raw, &self.layers, meta)?;
        }
        let mut meta = meta.to_vec();
        if let Some(d) = self.denoiser.describe() {
            meta.push((
                "denoiser".into(),
                format!("{:?}", self.denoiser).to_lowercase(),
            ));
            for (k, v) in &mut meta {
                if k == "approximations" {
                    *v = format!("{v}; {d}");
                }
            }
        }
        write_image_with_layers(path, &self.image, &self.layers, &meta)?;
        Ok(())
    }
}

/// Where the raw image of a denoised `path` goes: `NAME.noisy.EXT`.
pub fn noisy_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    let ext = path.extension().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}.noisy.{ext}"))
}

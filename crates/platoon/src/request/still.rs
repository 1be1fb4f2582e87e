//! A still: a frame's outputs (the image, denoised when asked, the raw one kept; the AOV
//! layers; the metadata), made after its render on the tracers that rendered it
//! ([`Request::outputs`]), and a request rendered as one in this process
//! ([`Request::render`]).

use anyhow::Result;
use glam::DVec3;
use platoon_core::denoise::{Denoiser, Guides};
use platoon_core::flatten::GpuScene;
use platoon_core::frame::aov::{Aov, Layer};
use platoon_core::frame::motion::PreviousFrame;
use platoon_core::frame::FrameParams;
use platoon_core::output::Film;

use super::form::Request;
use crate::{Rendered, Tracers};

/// A rendered frame's outputs.
pub struct Still {
    /// The image: denoised when a denoiser was asked for (then `raw` is the render).
    pub image: Film,
    /// A transparent film's alpha per pixel (the image's colour is premultiplied by it).
    pub alpha: Option<Vec<f32>>,
    pub raw: Option<Film>,
    /// The AOV layers asked for, in the order asked.
    pub layers: Vec<Layer>,
    /// The image's metadata (`with_metadata`).
    pub metadata: Vec<(String, String)>,
    /// The raw image's: the same without the denoiser's entries.
    pub raw_metadata: Vec<(String, String)>,
    pub rendered: Rendered,
    denoiser: Denoiser,
    aovs: Vec<Aov>,
}

/// The scene a frame was rendered from, as its outputs read it: flattened (`gpu`), its render
/// space centred on the world point `origin`, and the frame before (motion vectors; None when
/// not asked for).
#[derive(Clone, Copy)]
pub(crate) struct FrameScene<'a> {
    pub gpu: &'a GpuScene,
    pub origin: DVec3,
    pub previous: Option<&'a PreviousFrame>,
}

impl Still {
    /// The outputs of `rendered`, the frame `params` of `scene` on `tracers`: the AOVs `aovs`
    /// and the denoiser's guides rendered on the same tracers (so their bits do not depend on
    /// the split), and the image denoised. The metadata is empty until `with_metadata`.
    pub(crate) fn of(
        tracers: &mut Tracers,
        scene: &FrameScene,
        params: &FrameParams,
        rendered: Rendered,
        aovs: &[Aov],
        denoiser: Denoiser,
    ) -> Result<Still> {
        let FrameScene {
            gpu,
            origin,
            previous,
        } = *scene;
        let scene = gpu;
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
            crate::aov::render_layers(tracers, scene, params, &wanted, origin, previous)?
        };
        let alpha = match params.options.transparent_film {
            true => Some(crate::aov::render_alpha(
                tracers,
                scene,
                params,
                rendered.spp,
            )?),
            false => None,
        };
        let (image, raw) = match denoiser {
            Denoiser::None => (rendered.film.clone(), None),
            _ => {
                let guides = Guides::from_layers(&layers).expect("the guides were rendered");
                (
                    denoiser
                        .apply_on(&rendered.film, &guides, tracers)
                        .map_err(anyhow::Error::msg)?,
                    Some(rendered.film.clone()),
                )
            }
        };
        layers.extend(crate::aov::batch_layers(&rendered, aovs)?);
        layers.retain(|l| aovs.iter().any(|a| a.owns_layer(&l.name)));
        layers.sort_by_key(|l| aovs.iter().position(|a| a.owns_layer(&l.name)));
        Ok(Still {
            image,
            alpha,
            raw,
            layers,
            metadata: Vec::new(),
            raw_metadata: Vec::new(),
            rendered,
            denoiser,
            aovs: aovs.to_vec(),
        })
    }

    /// Sets the metadata from the render's (`crate::metadata`): the AOV layers named, and for
    /// the image the denoiser and its approximation.
    pub fn with_metadata(mut self, mut meta: Vec<(String, String)>) -> Still {
        if !self.aovs.is_empty() {
            let names: Vec<&str> = self.aovs.iter().map(|a| a.name()).collect();
            meta.push(("aovs".into(), names.join(",")));
        }
        self.raw_metadata = meta.clone();
        if let Some(d) = self.denoiser.describe() {
            meta.push(("denoiser".into(), self.denoiser.name().into()));
            for (k, v) in &mut meta {
                if k == "approximations" {
                    *v = format!("{v}; {d}");
                }
            }
        }
        self.metadata = meta;
        self
    }
}

impl Request {
    /// Renders the request as a still in this process, on its devices: validated, the scene
    /// loaded and prepared (its warnings and notes logged), the frame rendered in the batches
    /// its outputs need, its AOVs and denoiser run; `progress` hears the samples done (one
    /// device; several render on their own threads). Its steps are the request's calls of
    /// `steps.rs`, which the CLI takes one by one.
    pub fn render(&self, progress: &mut dyn FnMut(u32)) -> Result<Still> {
        self.validate()?;
        self.refuse_frame_to_frame()?;
        let mut prepared = self.load_and_prepare()?;
        let mut tracers = self.still_tracers(&mut prepared.gpu, None)?;
        let params = self.frame_params(self.camera_in(&prepared));
        let rendered = self.render_frame(&mut tracers, &prepared.gpu, &params, progress)?;
        let shown = prepared.shown(self.frame_interval);
        self.outputs(&mut tracers, &shown, &params, rendered, Vec::new())
    }
}

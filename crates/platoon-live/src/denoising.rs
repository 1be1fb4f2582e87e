//! Denoising a game's frames on the render thread ([`DriverOptions::denoise`]): the frame's own
//! samples, its geometry from the AOV kernel passes (rendered again only when something moved)
//! with where each hit was in the frame before when the scene moved (its hit geometry then and
//! now, `frame::hit_geometry`: moving objects keep their history), and the denoiser's temporal
//! history (`denoise::temporal`). The film stays the raw, unbiased one; the denoised image
//! comes beside it.
//!
//! [`DriverOptions::denoise`]: super::DriverOptions::denoise

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::accumulation::upscale;
use super::plan::FramePlan;
use platoon_core::denoise::temporal::{GBuffer, Temporal};
use platoon_core::denoise::Denoiser;
use platoon_core::error::{Error, Result};
use platoon_core::frame::aov::AovPass;
use platoon_core::frame::aov_params::aov_pass_params;
use platoon_core::frame::hit_geometry::HitGeometry;
use platoon_core::frame::motion::hits_before;
use platoon_core::frame::{BandTracer, FrameParams};
use platoon_core::output::Film;
use platoon_schedule::renderer::{Renderer, TracerFailure};

/// What denoising a frame did and cost.
#[derive(Clone, Debug)]
pub struct DenoiseStats {
    pub denoiser: Denoiser,
    /// Rendering the guides; None when the last ones were kept (nothing moved).
    pub guides: Option<Duration>,
    /// Reprojection, accumulation and the spatial filter.
    pub filter: Duration,
    /// Pixels that found their history in the previous frame, over all pixels.
    pub reused: f32,
    /// Samples behind the mean pixel of the history the filter read.
    pub history_samples: f32,
}

/// The render thread's denoiser.
pub(super) struct FrameDenoiser {
    temporal: Temporal,
    /// The last frame's geometry, kept while nothing moves.
    geometry: Option<GBuffer>,
    /// The scene's hit geometry as the last frame had it.
    hits: Arc<HitGeometry>,
}

/// A frame as the denoiser sees it: what it rendered and how it joined the film.
pub(super) struct RenderedFrame<'a> {
    pub params: &'a FrameParams,
    pub plan: &'a FramePlan,
    /// The frame's radiance sums, continuing `before` when it continued the film's.
    pub sums: &'a [[f32; 3]],
    pub before: Option<&'a [[f32; 3]]>,
    /// The film's size (the frame may have rendered fewer pixels: `plan.resolution`).
    pub film_size: (u32, u32),
    /// The camera or the scene changed since the previous frame.
    pub moved: bool,
    /// The scene's new hit geometry, when the scene changed.
    pub hits: Option<Arc<HitGeometry>>,
}

impl FrameDenoiser {
    /// `first`: the hit geometry of the scene the first frame renders.
    pub fn new(denoiser: Denoiser, first: HitGeometry) -> FrameDenoiser {
        FrameDenoiser {
            temporal: Temporal::new(denoiser),
            geometry: None,
            hits: Arc::new(first),
        }
    }

    /// The frame denoised with its history; the guide passes' failures join `failures`.
    pub fn denoise<T: BandTracer + Send + 'static>(
        &mut self,
        renderer: &mut Renderer<T>,
        frame: RenderedFrame,
        failures: &mut Vec<TracerFailure>,
    ) -> Result<(Film, DenoiseStats)> {
        let (w, h) = frame.film_size;
        let start = Instant::now();
        // The scene moved: hits are carried back from its geometry now to the one before.
        let before = frame
            .hits
            .clone()
            .map(|now| std::mem::replace(&mut self.hits, now));
        let kept = self
            .geometry
            .take()
            .filter(|g| !frame.moved && g.position.len() == (w * h) as usize);
        let (geometry, guides) = match kept {
            Some(g) => (g, None),
            None => (
                render_geometry(renderer, frame.params, (w, h), &self.hits, before, failures)?,
                Some(start.elapsed()),
            ),
        };
        let start = Instant::now();
        let own = own_mean(&frame);
        self.geometry = Some(geometry.clone());
        let out = self
            .temporal
            .filter(
                &own,
                frame.plan.spp,
                geometry,
                frame.params.camera,
                frame.moved,
                renderer,
            )
            .map_err(|e| Error::Invalid(format!("denoising the frame: {e}")))?;
        Ok((
            out.film,
            DenoiseStats {
                denoiser: self.temporal.denoiser(),
                guides,
                filter: start.elapsed(),
                reused: out.reused,
                history_samples: out.mean_samples,
            },
        ))
    }
}

/// The mean of the frame's own samples at the film's size: its sums less the ones it
/// continued, upscaled when it rendered fewer pixels.
fn own_mean(frame: &RenderedFrame) -> Film {
    let inv = 1.0 / frame.plan.spp.max(1) as f32;
    let mut mean: Vec<[f32; 3]> = match frame.before {
        Some(before) => frame
            .sums
            .iter()
            .zip(before)
            .map(|(s, b)| std::array::from_fn(|k| (s[k] - b[k]) * inv))
            .collect(),
        None => frame.sums.iter().map(|s| s.map(|v| v * inv)).collect(),
    };
    let size = (frame.params.width, frame.params.height);
    if size != frame.film_size {
        mean = upscale(&mean, size, frame.film_size);
    }
    Film {
        width: frame.film_size.0,
        height: frame.film_size.1,
        pixels: mean,
    }
}

/// Samples a pixel of the guide passes: one, as a game's G-buffer (the albedo and normal passes
/// at the beauty's spp took two thirds of the denoiser's time in `bench game`, 12 of 18 ms).
const GUIDE_SPP: u32 = 1;

/// The geometry of the frame `params` renders, at the film's size: the AOV kernel passes, on
/// the same tracers, in the beauty's bands and without the balancer learning from them. Its
/// surfaces are named by object (`hits`: the scene's hit geometry now), not by instance, so
/// that a history outlives a change of the instances' order (an object added, or split out of
/// the merged static geometry when it starts to move); where `before` (the hit geometry of
/// the frame before) says the scene moved, with where each hit was then.
fn render_geometry<T: BandTracer + Send + 'static>(
    renderer: &mut Renderer<T>,
    params: &FrameParams,
    (width, height): (u32, u32),
    hits: &HitGeometry,
    before: Option<Arc<HitGeometry>>,
    failures: &mut Vec<TracerFailure>,
) -> Result<GBuffer> {
    let mut films = Vec::new();
    for pass in GBuffer::PASSES {
        let mut p = aov_pass_params(params, pass, GUIDE_SPP);
        p.width = width;
        p.height = height;
        let rendered = renderer
            .render_side_pass(&p)
            .map_err(|e| Error::Invalid(e.to_string()))?;
        failures.extend(rendered.failures);
        films.push((pass, rendered.film));
    }
    let film = |pass| {
        films
            .iter()
            .find(|(p, _)| *p == pass)
            .map(|(_, f)| f.clone())
            .expect("every pass rendered")
    };
    let mut geometry = GBuffer::from_passes(&film, &params.camera);
    let ids = film(AovPass::Ids);
    for (key, id) in geometry.instance.iter_mut().zip(&ids.pixels) {
        *key = if id[0] == 0.0 {
            0.0
        } else {
            hits.object_key(id[0] as u32 - 1)
        };
    }
    if let Some(before) = before {
        let position = film(AovPass::Position);
        geometry.before = Some(hits_before(&position, &ids, hits, &before));
    }
    Ok(geometry)
}

//! A frame's AOVs beside its beauty (`platoon_core::frame::aov`): each kernel pass they need
//! rendered on the same tracers as the beauty, with its random numbers, so the layers have the
//! same bits whatever the split between devices; the sample count and variance from the
//! beauty's batches (`crate::batched`).

use anyhow::Result;
use glam::DVec3;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::aov::{self, Aov, Layer};
use platoon_core::frame::aov_params::aov_pass_params;
use platoon_core::frame::motion::PreviousFrame;
use platoon_core::frame::FrameParams;
use platoon_core::output::Film;

use crate::{Rendered, Tracers};

/// The layers of `aovs` for the frame `params` renders (its camera, samples and seed) of
/// `scene`, whose render space is centred on the world point `origin`; motion vectors measure
/// against `previous`, the frame before.
pub fn render_layers(
    tracers: &mut Tracers,
    scene: &GpuScene,
    params: &FrameParams,
    aovs: &[Aov],
    origin: DVec3,
    previous: Option<&PreviousFrame>,
) -> Result<Vec<Layer>> {
    let context = aov::Context {
        scene: Some(scene),
        previous,
        crop: params.image_crop(),
    };
    render_layers_with(
        &mut |p| Ok(tracers.render(scene, p, &mut |_| {})?.film),
        params,
        aovs,
        origin,
        &context,
    )
}

/// The same with each pass's frame rendered by `render` (a bare tracer's, for the lab), the
/// layers that read more than films reading `context`.
pub fn render_layers_with(
    render: &mut dyn FnMut(&FrameParams) -> Result<Film>,
    params: &FrameParams,
    aovs: &[Aov],
    origin: DVec3,
    context: &aov::Context,
) -> Result<Vec<Layer>> {
    if aovs.contains(&Aov::Motion) && (context.previous.is_none() || context.scene.is_none()) {
        anyhow::bail!("motion vectors need the frame before and the flattened scene");
    }
    let mut films: Vec<(aov::AovPass, Film)> = Vec::new();
    for pass in aov::passes(aovs) {
        let p = aov_pass_params(params, pass, pass.spp(params.spp));
        films.push((pass, render(&p)?));
    }
    let film = |pass| {
        films
            .iter()
            .find(|(p, _)| *p == pass)
            .map(|(_, f)| f.clone())
            .expect("every pass rendered")
    };
    Ok(aov::layers(aovs, &film, &params.camera, origin, context))
}

/// A transparent film's alpha for the frame `params` (its film transparent) rendered at
/// `spp`: the share of the beauty's camera rays of each pixel that find a surface.
pub fn render_alpha(
    tracers: &mut Tracers,
    scene: &GpuScene,
    params: &FrameParams,
    spp: u32,
) -> Result<Vec<f32>> {
    let p = aov_pass_params(params, aov::AovPass::Alpha, spp);
    let film = tracers.render(scene, &p, &mut |_| {})?.film;
    Ok(film.pixels.iter().map(|p| p[0]).collect())
}

/// The layers of `aovs` that come from the beauty's batches (sample count, variance) of the
/// frame `rendered`: a frame not rendered in batches took its `spp` in every pixel.
pub fn batch_layers(rendered: &Rendered, aovs: &[Aov]) -> Result<Vec<Layer>> {
    let pixels = rendered.film.pixels.len();
    let uniform;
    let (samples, variance) = match &rendered.batched {
        Some(b) => (&b.samples[..], b.variance.as_deref()),
        None => {
            uniform = vec![rendered.spp; pixels];
            (&uniform[..], None)
        }
    };
    if aovs.contains(&Aov::Variance) && variance.is_none() {
        anyhow::bail!("the variance AOV needs the frame rendered in batches that keep it");
    }
    Ok(aov::batch_layers(aovs, samples, variance))
}

//! A method's work before its frames (`RenderMethod::prepare`: vertex links' update), run on
//! the tracers that will render them: one tracer's bands, or split by the renderer's balancer
//! (a tracer lost midway is replaced as in frames).

use anyhow::{Context as _, Result};
use platoon_core::flatten::GpuScene;
use platoon_core::frame::{assemble, BandTracer, FrameParams, Span};
use platoon_core::method::render_method::DeviceFrame;
use platoon_schedule::renderer::Renderer;
use platoon_tracer::Tracer;

/// `params` with its method's preparation done on `tracer` (the scene `g` being the one the
/// tracer holds); `params` as they are when the method needs none.
pub fn on_tracer(tracer: &mut Tracer, g: &GpuScene, params: &FrameParams) -> Result<FrameParams> {
    let method = params.method.unit();
    let prepared = method
        .prepare(g, params, &mut |p| {
            let mut band = tracer
                .render_span(p, Span::lines(p.width, 0, p.height), &mut |_| {})
                .map_err(|e| e.to_string())?;
            let film = assemble(p, std::slice::from_ref(&band)).pixels;
            Ok(DeviceFrame {
                film,
                per_pixel: std::mem::take(&mut band.per_pixel),
                gpu_time: band.gpu_time,
            })
        })
        .with_context(|| format!("preparing {} failed", method.name()))?;
    Ok(with_method(params, prepared))
}

/// `params` with its method's preparation done over the renderer's tracers.
pub fn on_renderer<T: BandTracer + Send + 'static>(
    renderer: &mut Renderer<T>,
    g: &GpuScene,
    params: &FrameParams,
) -> Result<FrameParams> {
    let (prepared, failures) = platoon_live::gi::prepare_on(renderer, g, params)?;
    for f in &failures {
        log::warn!(
            "tracer {} failed while preparing the frame and was dropped; the others \
             did its part: {}",
            f.tracer,
            f.message
        );
    }
    Ok(prepared)
}

fn with_method(params: &FrameParams, method: Option<platoon_core::Method>) -> FrameParams {
    let mut p = params.clone();
    if let Some(m) = method {
        p.method = m;
    }
    p
}

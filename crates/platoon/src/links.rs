//! Vertex links' update before the frames that read it (platoon_core::method::links::solve):
//! a frame asking for vertex links without a solution is solved on the same tracers that will
//! render it, one tracer's bands or the renderer's split.

use std::sync::Arc;

use anyhow::{Context as _, Result};
use platoon_core::flatten::GpuScene;
use platoon_core::frame::renderer::Renderer;
use platoon_core::frame::{assemble, BandTracer, FrameParams, Span};
use platoon_core::method::links::solve::{solve, DeviceFrame};
use platoon_core::method::links::{Job, Links};
use platoon_core::Method;
use platoon_tracer::Tracer;

/// The options of a vertex-links frame still to be solved; None for any other frame.
fn unsolved(params: &FrameParams) -> Option<&Links> {
    params.method.links().filter(|l| l.job.is_none())
}

/// `params` with `job` in place of the unsolved one.
fn with_job(params: &FrameParams, links: &Links, job: Job) -> FrameParams {
    let mut p = params.clone();
    p.method = Method::Links(Links {
        options: links.options,
        job: Some(job),
    });
    p
}

/// `params` solved on `tracer` when it asks for vertex links without a solution (the scene
/// `g` being the one the tracer holds); else `params` as they are.
pub fn solve_on_tracer(
    tracer: &mut Tracer,
    g: &GpuScene,
    params: &FrameParams,
) -> Result<FrameParams> {
    let Some(links) = unsolved(params) else {
        return Ok(params.clone());
    };
    let solution = solve(g, &links.options, params, &mut |p| {
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
    .context("vertex links' update failed")?;
    Ok(with_job(params, links, Job::Render(Arc::new(solution))))
}

/// `params` solved over the renderer's tracers (split by its balancer; a tracer lost midway
/// is replaced as in frames) when it asks for vertex links without a solution.
pub fn solve_on_renderer<T: BandTracer + Send + 'static>(
    renderer: &mut Renderer<T>,
    g: &GpuScene,
    params: &FrameParams,
) -> Result<FrameParams> {
    let Some(links) = unsolved(params) else {
        return Ok(params.clone());
    };
    let solution = solve(g, &links.options, params, &mut |p| {
        let frame = renderer.render_frame(p).map_err(|e| e.to_string())?;
        for f in &frame.failures {
            eprintln!(
                "warning: tracer {} failed in the links update and was dropped; the others shot its part: {}",
                f.tracer, f.message
            );
        }
        Ok(DeviceFrame {
            gpu_time: frame.tracers.iter().map(|t| t.gpu_time).sum(),
            film: frame.film.pixels,
            per_pixel: frame.per_pixel,
        })
    })
    .context("vertex links' update failed")?;
    Ok(with_job(params, links, Job::Render(Arc::new(solution))))
}

//! The frame driver's render thread: it takes each frame the game thread planned (`FrameJob`),
//! brings the tracers to its generation, prepares a method that needs it, renders, joins the
//! frame to the film, denoises it and trains the world cache, and sends back the finished frame.

use std::sync::mpsc::{Receiver, SyncSender};
use std::sync::Arc;
use std::time::Instant;

use super::accumulation::Accumulation;
use super::denoising::{FrameDenoiser, RenderedFrame};
use super::finished::{FinishedFrame, FrameStats};
use super::gi::{self, GiStats, PreparedMethod};
use super::plan::FramePlan;
use super::UpdateTimes;
use platoon_core::balance::Balancer;
use platoon_core::error::{Error, Result};
use platoon_core::flatten::commit::Commit;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::hit_geometry::HitGeometry;
use platoon_core::frame::{BandTracer, FrameParams};
use platoon_core::method::learning::FrameLearning;
use platoon_schedule::renderer::Renderer;

pub(super) struct FrameJob {
    pub frame: u32,
    pub commit: Option<Arc<Commit>>,
    /// The scene's generation (counting the ones that changed it) and, when it is new and a
    /// synchronous preparation reads it, its flattened scene.
    pub generation: u64,
    pub scene: Option<Arc<GpuScene>>,
    /// What carries its hits back to the frame before, when the scene changed and the frame
    /// is denoised.
    pub hits: Option<Arc<HitGeometry>>,
    /// The lighting the game thread chose for the frame (asynchronous preparation).
    pub gi: Option<GiStats>,
    pub update: UpdateTimes,
    pub params: FrameParams,
    pub plan: FramePlan,
    /// The camera or the scene changed since the previous frame.
    pub moved: bool,
}

pub(super) enum Job {
    Frame(Box<FrameJob>),
    Balancer(Box<dyn Balancer>),
}

/// What the render thread keeps for a method's synchronous preparation: the newest scene
/// and the last result.
pub(super) struct Synchronous {
    /// The generation being rendered, when the generations carry their scenes.
    pub scene: Arc<GpuScene>,
    pub prepared: Option<PreparedMethod>,
    /// Whether finished frames carry it (`DriverOptions::keep_frame_scenes`).
    pub keep_frame_scenes: bool,
}

pub(super) fn render_loop<T: BandTracer + Send + 'static>(
    mut renderer: Renderer<T>,
    mut film: Accumulation,
    mut denoiser: Option<FrameDenoiser>,
    mut learning: Option<Box<dyn FrameLearning>>,
    mut sync: Synchronous,
    inbox: Receiver<Job>,
    outbox: SyncSender<Result<FinishedFrame>>,
) {
    for job in inbox {
        let result = match job {
            Job::Balancer(b) => {
                renderer.set_balancer(b);
                continue;
            }
            Job::Frame(job) => render_one(
                &mut renderer,
                &mut film,
                denoiser.as_mut(),
                &mut learning,
                &mut sync,
                *job,
            ),
        };
        if outbox.send(result).is_err() {
            return;
        }
    }
}

fn render_one<T: BandTracer + Send + 'static>(
    renderer: &mut Renderer<T>,
    film: &mut Accumulation,
    denoiser: Option<&mut FrameDenoiser>,
    learning: &mut Option<Box<dyn FrameLearning>>,
    sync: &mut Synchronous,
    job: FrameJob,
) -> Result<FinishedFrame> {
    let FrameJob {
        frame,
        commit,
        generation,
        scene,
        hits,
        mut gi,
        update,
        mut params,
        plan,
        moved,
    } = job;
    let start = Instant::now();
    let failed = |e: platoon_schedule::renderer::RenderError| Error::Invalid(e.to_string());
    let mut failures = Vec::new();
    let commit_bytes = match &commit {
        Some(c) => {
            let before = renderer.failures().len();
            let uploaded = renderer.apply_commit(c, frame).map_err(failed)?;
            failures.extend_from_slice(&renderer.failures()[before..]);
            uploaded.first().map_or(0, |u| u.1)
        }
        None => 0,
    };
    let commit_time = start.elapsed();
    if let Some(scene) = scene {
        sync.scene = scene;
    }
    if !params.method.unit().ready() {
        gi = Some(gi::prepare_synchronously(
            renderer,
            &mut sync.prepared,
            &sync.scene,
            generation,
            &mut params,
            &mut failures,
        )?);
    }
    let render_start = Instant::now();
    params.film.accumulated = film.continued(plan.join);
    let lights = commit.as_ref().map(|c| c.header.lights as usize);
    if let Some(l) = learning.as_mut() {
        l.give(&mut params.method, lights);
    }
    let mut rendered = renderer
        .render_frame_planned(&params, plan.rebalance)
        .map_err(failed)?;
    let render = render_start.elapsed();
    failures.extend(std::mem::take(&mut rendered.failures));
    // The records of every band, in pixel order: the same cache and reservoirs for any split.
    let learned = (learning.as_mut())
        .map(|l| l.learn(&rendered.per_pixel, &params, frame))
        .transpose()
        .map_err(Error::Invalid)?;
    let (denoised, denoise) = match denoiser {
        Some(d) => {
            let frame = RenderedFrame {
                params: &params,
                plan: &plan,
                sums: &rendered.sums,
                before: params.film.accumulated.as_deref(),
                film_size: film.size(),
                moved,
                hits,
            };
            let (image, stats) = d.denoise(renderer, frame, &mut failures)?;
            (Some(image), Some(stats))
        }
        None => (None, None),
    };
    if plan.resolution < 1.0 {
        film.join_upscaled(
            plan.join,
            &rendered.sums,
            (params.width, params.height),
            plan.spp,
        );
    } else {
        film.join(plan.join, rendered.sums, plan.spp);
    }
    let film_now = film.film();
    Ok(FinishedFrame {
        film: film_now,
        denoised,
        camera: params.camera,
        scene: sync.keep_frame_scenes.then(|| Arc::clone(&sync.scene)),
        stats: FrameStats {
            frame,
            weight: plan.join.weight(plan.frames_joined),
            plan,
            film_samples: film.samples(),
            busy: start.elapsed(),
            render,
            commit: commit_time,
            commit_bytes,
            update,
            idle_fraction: rendered.idle_fraction,
            tracers: rendered.tracers,
            line_rays: rendered.line_rays,
            failures,
            rejected_samples: rendered.rejected_samples,
            device_messages: renderer.with_tracers(|t| t.messages()).concat(),
            gi,
            denoise,
            learned,
        },
    })
}

//! A method's preparation in the game loop (vertex links' update), following the living
//! scene's generations. Synchronously, the render thread prepares the method before the first
//! frame of each new generation, on that generation's scene: the frame waits, and is lit by its
//! own geometry. Asynchronously (the paper's way), a worker thread with tracers of its own
//! prepares it on the newest generation there is whenever it is free, while the frames render
//! with the newest finished result; each update works on one snapshot (its tracers take the
//! generations' commits only between updates), and a new result joins the film as moving
//! objects do. Either way an update starts from the last result (`RenderMethod::renewal`: what
//! vertex links revalidate or relight from), and each frame reports the generation its lighting
//! was prepared on and how many generations the scene has moved on since.

use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use platoon_core::balance::Balancer;
use platoon_core::error::{Error, Result};
use platoon_core::flatten::commit::Commit;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::{BandTracer, FrameParams};
use platoon_core::method::render_method::DeviceFrame;
use platoon_core::method::Method;
use platoon_schedule::renderer::{Renderer, TracerFailure};

/// Where the game loop prepares a method whose frames need it (vertex links' update).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GiUpdate {
    /// On the render thread, before the first frame of each new generation.
    #[default]
    Synchronous,
    /// On a worker thread with tracers of its own, while the frames render.
    Asynchronous,
}

/// The prepared method frames render with, and the scene generation it was prepared on.
#[derive(Clone)]
pub(super) struct PreparedMethod {
    pub method: Method,
    pub generation: u64,
    /// The preparation's wall time.
    pub took: Duration,
}

/// What a frame's lighting was prepared on.
#[derive(Clone, Debug)]
pub struct GiStats {
    /// The scene generation (the driver's count of generations that changed the scene).
    pub generation: u64,
    /// Generations the frame's scene had moved on since (0: its own).
    pub age: u64,
    /// Wall time of the preparation this frame was the first to use; zero when an earlier
    /// frame's.
    pub update: Duration,
    /// The preparation's metadata (vertex links: `links_update`).
    pub metadata: Vec<(String, String)>,
    /// The prepared method the frame rendered with (vertex links: with the solution).
    pub method: Method,
}

impl GiStats {
    pub(super) fn of(p: &PreparedMethod, generation: u64, fresh: bool) -> GiStats {
        GiStats {
            generation: p.generation,
            age: generation - p.generation,
            update: if fresh { p.took } else { Duration::ZERO },
            metadata: p.method.unit().metadata(),
            method: p.method.clone(),
        }
    }
}

/// `params` with its method prepared on `g` (the scene the renderer's tracers hold) through
/// the renderer's frames, split by its balancer (a tracer lost midway is replaced as in
/// frames); `params` as they are when the method needs nothing. With the tracers lost.
pub fn prepare_on<T: BandTracer + Send + 'static>(
    renderer: &mut Renderer<T>,
    g: &GpuScene,
    params: &FrameParams,
) -> Result<(FrameParams, Vec<TracerFailure>)> {
    let method = params.method.unit();
    let mut failures = Vec::new();
    let prepared = method
        .prepare(g, params, &mut |p| {
            let frame = renderer.render_frame(p).map_err(|e| e.to_string())?;
            failures.extend(frame.failures);
            Ok(DeviceFrame {
                gpu_time: frame.tracers.iter().map(|t| t.gpu_time).sum(),
                film: frame.film.pixels,
                per_pixel: frame.per_pixel,
            })
        })
        .map_err(|e| Error::Invalid(format!("preparing {} failed: {e}", method.name())))?;
    let mut p = params.clone();
    if let Some(m) = prepared {
        p.method = m;
    }
    Ok((p, failures))
}

/// The frames' method (`params`) prepared on `scene` of `generation`, starting from the last
/// result's renewal (or the method itself at first), with random numbers of frame 0 and sample
/// 0 so that a generation's preparation is the same whenever it runs; with the tracers lost.
fn prepare_after<T: BandTracer + Send + 'static>(
    renderer: &mut Renderer<T>,
    last: Option<&PreparedMethod>,
    scene: &GpuScene,
    generation: u64,
    params: &FrameParams,
) -> Result<(PreparedMethod, Vec<TracerFailure>)> {
    let mut p = params.clone();
    p.frame = 0;
    p.first_sample = 0;
    p.film.accumulated = None;
    p.method = last
        .and_then(|l| l.method.unit().renewal())
        .unwrap_or_else(|| params.method.clone());
    let start = Instant::now();
    let (prepared, lost) = prepare_on(renderer, scene, &p)?;
    Ok((
        PreparedMethod {
            method: prepared.method,
            generation,
            took: start.elapsed(),
        },
        lost,
    ))
}

/// Prepares the method on the render thread when `generation` is newer than the last
/// preparation (synchronous updates); the frame's params get the prepared method.
pub(super) fn prepare_synchronously<T: BandTracer + Send + 'static>(
    renderer: &mut Renderer<T>,
    last: &mut Option<PreparedMethod>,
    scene: &GpuScene,
    generation: u64,
    params: &mut FrameParams,
    failures: &mut Vec<TracerFailure>,
) -> Result<GiStats> {
    let fresh = last.as_ref().is_none_or(|p| p.generation < generation);
    if fresh {
        let (prepared, lost) = prepare_after(renderer, last.as_ref(), scene, generation, params)?;
        failures.extend(lost);
        *last = Some(prepared);
    }
    let p = last.as_ref().expect("prepared above");
    params.method = p.method.clone();
    Ok(GiStats::of(p, generation, fresh))
}

/// One generation for the worker: its commit (what the worker's tracers apply), its scene,
/// and the params of the frames (what the preparation reads).
pub(super) struct WorkerJob {
    pub commit: Option<Arc<Commit>>,
    pub scene: Arc<GpuScene>,
    pub generation: u64,
    pub params: FrameParams,
}

/// The asynchronous updates' thread.
pub(super) struct Worker {
    jobs: Option<Sender<WorkerJob>>,
    results: Receiver<Result<PreparedMethod>>,
    thread: Option<JoinHandle<()>>,
}

impl Worker {
    /// Starts the worker with `tracers` (holding the first generation) under `balancer`.
    pub fn start<T: BandTracer + Send + 'static>(
        tracers: Vec<T>,
        balancer: Box<dyn Balancer>,
    ) -> Result<Worker> {
        let renderer = Renderer::new(tracers, balancer);
        let (jobs, inbox) = mpsc::channel();
        let (outbox, results) = mpsc::channel();
        let thread = std::thread::Builder::new()
            .name("platoon gi update".into())
            .spawn(move || worker_loop(renderer, inbox, outbox))
            .map_err(|e| Error::Invalid(format!("starting the update thread: {e}")))?;
        Ok(Worker {
            jobs: Some(jobs),
            results,
            thread: Some(thread),
        })
    }

    /// Hands the worker a generation (every one, in order: its tracers apply each commit).
    pub fn submit(&mut self, job: WorkerJob) -> Result<()> {
        self.jobs
            .as_ref()
            .and_then(|j| j.send(job).ok())
            .ok_or_else(|| Error::Invalid("the update thread ended".into()))
    }

    /// The newest finished preparation, if one came since the last call; waits for one when
    /// `wait`.
    pub fn newest(&mut self, wait: bool) -> Result<Option<PreparedMethod>> {
        let mut newest = None;
        if wait {
            newest = Some(
                self.results
                    .recv()
                    .map_err(|_| Error::Invalid("the update thread ended".into()))??,
            );
        }
        loop {
            match self.results.try_recv() {
                Ok(r) => newest = Some(r?),
                Err(mpsc::TryRecvError::Empty) => return Ok(newest),
                Err(mpsc::TryRecvError::Disconnected) => {
                    return Err(Error::Invalid("the update thread ended".into()))
                }
            }
        }
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.jobs = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn worker_loop<T: BandTracer + Send + 'static>(
    mut renderer: Renderer<T>,
    inbox: Receiver<WorkerJob>,
    outbox: Sender<Result<PreparedMethod>>,
) {
    let mut last: Option<PreparedMethod> = None;
    while let Ok(first) = inbox.recv() {
        // Every commit in order (the tracers follow the scene), then the newest generation.
        let mut job = first;
        let mut result = apply(&mut renderer, &job);
        while let Ok(next) = inbox.try_recv() {
            job = next;
            result = result.and_then(|()| apply(&mut renderer, &job));
        }
        let result = result.and_then(|()| {
            prepare_after(
                &mut renderer,
                last.as_ref(),
                &job.scene,
                job.generation,
                &job.params,
            )
            .map(|(prepared, _lost)| prepared)
        });
        if let Ok(p) = &result {
            last = Some(p.clone());
        }
        if outbox.send(result).is_err() {
            return;
        }
    }
}

fn apply<T: BandTracer + Send + 'static>(
    renderer: &mut Renderer<T>,
    job: &WorkerJob,
) -> Result<()> {
    if let Some(c) = &job.commit {
        renderer
            .apply_commit(c, job.generation as u32)
            .map_err(|e| Error::Invalid(format!("the update's tracers: {e}")))?;
    }
    Ok(())
}

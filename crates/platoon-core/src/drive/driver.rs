//! The frame driver: a game's one call per frame. It owns the living scene's updater (through
//! the [`Pipeline`]), the tracers (each on its persistent thread, under the balancer) and the
//! film, on a render thread of their own, so that frame N renders while the game simulates
//! frame N + 1 and the updater builds its scene:
//!
//! ```text
//! game:     edits N+1 ─ frame() ─ edits N+2 ─ frame() ...
//! render:   ──── render N ───────┴── render N+1 ─────┴ ...
//! updater:  ──── build N+1 ──────┴── build N+2 ──────┴ ...
//! ```
//!
//! Each call hands over the camera and the edits made since the previous call, and gives back
//! the previous finished frame with its statistics. What each frame renders and how it joins
//! the film is decided by [`super::plan`] alone; the driver carries it out.

use std::sync::mpsc::{self, Receiver, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::accumulation::Accumulation;
use super::denoising::{DenoiseStats, FrameDenoiser, RenderedFrame};
use super::gi::{self, GiStats, GiUpdate, PreparedMethod, Worker, WorkerJob};
use super::plan::{FramePlan, Join, Motion, Planner};
use super::scaling::{BelowOneSample, Workload, WorkloadScaler};
use super::{Pipeline, QueryScene, UpdateTimes};
use crate::balance::Balancer;
use crate::denoise::Denoiser;
use crate::error::{Error, Result};
use crate::flatten::commit::Commit;
use crate::flatten::GpuScene;
use crate::frame::hit_geometry::HitGeometry;
use crate::frame::renderer::{Renderer, TracerFailure, TracerStats};
use crate::frame::world_cache::{CacheUpdate, WorldCache, WorldCacheOptions};
use crate::frame::{BandTracer, FrameParams, DEFAULT_MAX_DEPTH, DEFAULT_SAMPLES_PER_PASS};
use crate::output::Film;
use crate::scene::camera::Camera;

/// How the driver renders.
#[derive(Clone, Debug)]
pub struct DriverOptions {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel per frame: fixed, or the first count when `target` is set.
    pub spp: u32,
    /// Frame time to hold by scaling the samples per frame (Bikker 7.3.7); None: fixed spp.
    pub target: Option<Duration>,
    /// How a held frame time goes below one sample a frame (Russian-roulette survival,
    /// render resolution); neither by default.
    pub below_one: BelowOneSample,
    /// Smallest weight of a frame in the film while objects move (see [`super::plan`]).
    pub blend_floor: f32,
    pub seed: u32,
    /// The pixel filter every frame's camera rays are drawn from.
    pub filter: crate::frame::PixelFilter,
    pub max_depth: u32,
    pub rr_depth: u32,
    pub samples_per_pass: u32,
    /// The rendering method (`crate::method`). With instant global illumination a still
    /// view's frames each gather a VPL set of their own, so the film averages over sets.
    pub method: crate::method::Method,
    /// Keep a [`QueryScene`] of the generation being rendered, for the game's ray queries.
    pub queries: bool,
    /// Where a method whose frames need a preparation (vertex links' update) prepares them as
    /// the scene changes: asynchronously it needs tracers of its own
    /// ([`FrameDriver::with_update_tracers`]).
    pub gi_update: GiUpdate,
    /// Denoise each frame with its history reprojected (`denoise::temporal`), beside the raw
    /// film ([`FinishedFrame::denoised`]); none by default.
    pub denoise: Denoiser,
    /// A change of the scene restarts the film, as a moved camera does (an editor's viewport:
    /// the still view that follows converges to exact sums), instead of blending the new
    /// samples in (a game's: moving objects keep the history). Off by default.
    pub restart_on_change: bool,
    /// Next-event estimation resamples this many candidate lights toward their unshadowed
    /// contribution ([`FrameParams::set_resampled_light`]); None: one drawn by power.
    pub resampled_light: Option<u32>,
    /// The path tracer's bounces after the first read a world cache trained as the frames go
    /// (`frame::world_cache`; biased); None by default.
    pub world_cache: Option<WorldCacheOptions>,
}

/// Candidate lights of a game's resampled direct light ([`DriverOptions::realtime`]): most of
/// the gain in the many-light hall (tests/kernel/estimators.rs) for a few evaluations of the BSDF.
pub const REALTIME_CANDIDATES: u32 = 8;

/// [`DriverOptions::realtime`]'s rule on a resampled-light and a denoiser setting (for front
/// ends that validate them before any driver exists).
pub fn realtime(resampled_light: Option<u32>, denoise: Denoiser) -> (Option<u32>, Denoiser) {
    let denoise = match denoise {
        Denoiser::None => Denoiser::Atrous,
        d => d,
    };
    (resampled_light.or(Some(REALTIME_CANDIDATES)), denoise)
}

impl DriverOptions {
    /// A game's real-time settings where these options leave them open: resampled direct light
    /// over [`REALTIME_CANDIDATES`] lights and the à-trous denoiser over the history (biased by
    /// the denoiser, reported as such).
    pub fn realtime(&mut self) {
        (self.resampled_light, self.denoise) = realtime(self.resampled_light, self.denoise);
    }

    /// A frame's params of `width` x `height` at `spp` from `camera` with these options' seed,
    /// depths, samples per pass and method (what every frame and a method's preparation share).
    fn frame_params(&self, width: u32, height: u32, spp: u32, camera: Camera) -> FrameParams {
        let mut p = FrameParams::new(width, height, spp, camera);
        p.seed = self.seed;
        p.filter = self.filter;
        p.max_depth = self.max_depth;
        p.rr_depth = self.rr_depth;
        p.samples_per_pass = self.samples_per_pass;
        p.method = self.method.clone();
        p.set_resampled_light(self.resampled_light);
        p
    }

    pub fn new(width: u32, height: u32) -> DriverOptions {
        DriverOptions {
            width,
            height,
            spp: 1,
            target: None,
            below_one: BelowOneSample::default(),
            blend_floor: 0.2,
            seed: 0,
            filter: crate::frame::PixelFilter::Box,
            max_depth: DEFAULT_MAX_DEPTH,
            rr_depth: 3,
            samples_per_pass: DEFAULT_SAMPLES_PER_PASS,
            method: crate::method::Method::path_tracing(),
            resampled_light: None,
            world_cache: None,
            queries: false,
            gi_update: GiUpdate::default(),
            denoise: Denoiser::None,
            restart_on_change: false,
        }
    }
}

/// What one frame was and cost.
#[derive(Clone, Debug)]
pub struct FrameStats {
    /// The game frame (counting calls from 0).
    pub frame: u32,
    pub plan: FramePlan,
    /// The weight f of this frame's samples in the film.
    pub weight: f32,
    /// Samples per pixel behind the film when it holds exact sums (None after a blend).
    pub film_samples: Option<u32>,
    /// The render thread's whole time for the frame: commit, a synchronous preparation
    /// (`gi`), render, film.
    pub busy: Duration,
    pub render: Duration,
    /// Applying the scene's commit on the tracers.
    pub commit: Duration,
    /// Bytes each tracer took from the commit.
    pub commit_bytes: u64,
    /// The updater's times for the generation this frame rendered (zero if none was new).
    pub update: UpdateTimes,
    pub idle_fraction: f64,
    pub tracers: Vec<TracerStats>,
    /// Rays traced in each line: the frame's cost map as the balancer saw it.
    pub line_rays: Vec<u64>,
    pub failures: Vec<TracerFailure>,
    pub rejected_samples: u64,
    /// Every warning and error the devices have reported so far (validation layer).
    pub device_messages: Vec<String>,
    /// What the frame's lighting was prepared on, for a method with a preparation (vertex
    /// links).
    pub gi: Option<GiStats>,
    /// What denoising the frame did and cost ([`DriverOptions::denoise`]).
    pub denoise: Option<DenoiseStats>,
    /// What the frame's training paths did to the world cache ([`DriverOptions::world_cache`]).
    pub world_cache: Option<CacheUpdate>,
}

impl FrameStats {
    /// Seconds each line took, when one tracer rendered the whole frame: its band's time spread
    /// over the lines in proportion to their rays (what `bench balance` replays). None with
    /// several tracers, whose times are in different devices' units.
    pub fn line_seconds(&self) -> Option<Vec<f64>> {
        let [tracer] = self.tracers.as_slice() else {
            return None;
        };
        let rays = self.line_rays.iter().sum::<u64>().max(1) as f64;
        let seconds = tracer.wall_time.as_secs_f64();
        Some(
            self.line_rays
                .iter()
                .map(|&r| r as f64 / rays * seconds)
                .collect(),
        )
    }
}

pub struct FinishedFrame {
    /// The film after this frame joined it (linear radiance).
    pub film: Film,
    /// The frame denoised with its history, when [`DriverOptions::denoise`] asks.
    pub denoised: Option<Film>,
    pub stats: FrameStats,
}

/// What the game gets back from a call.
pub struct FrameOutput {
    /// The previous call's frame (None on the first call).
    pub finished: Option<FinishedFrame>,
    /// The time this call waited: for the previous frame to finish, and on the updater.
    pub waited_render: Duration,
    pub waited_update: Duration,
}

struct FrameJob {
    frame: u32,
    commit: Option<Arc<Commit>>,
    /// The scene's generation (counting the ones that changed it) and, when it is new and a
    /// synchronous preparation reads it, its flattened scene.
    generation: u64,
    scene: Option<Arc<GpuScene>>,
    /// What carries its hits back to the frame before, when the scene changed and the frame
    /// is denoised.
    hits: Option<Arc<HitGeometry>>,
    /// The lighting the game thread chose for the frame (asynchronous preparation).
    gi: Option<GiStats>,
    update: UpdateTimes,
    params: FrameParams,
    plan: FramePlan,
    /// The camera or the scene changed since the previous frame.
    moved: bool,
}

enum Job {
    Frame(Box<FrameJob>),
    Balancer(Box<dyn Balancer>),
}

pub struct FrameDriver {
    pipeline: Pipeline,
    jobs: Option<SyncSender<Job>>,
    done: Receiver<Result<FinishedFrame>>,
    render: Option<JoinHandle<()>>,
    in_flight: bool,
    options: DriverOptions,
    planner: Planner,
    scaler: Option<WorkloadScaler>,
    queries: Option<QueryScene>,
    frame: u32,
    /// The frame of the last restart: the random numbers' frame key while the view converges.
    epoch: u32,
    last_camera: Option<Camera>,
    balancer: &'static str,
    /// Generations taken that changed the scene.
    generation: u64,
    /// Asynchronous preparation: its worker, the newest result, and the first scene (handed
    /// to the worker with the first frame's params).
    worker: Option<Worker>,
    prepared: Option<PreparedMethod>,
    first_scene: Option<Arc<GpuScene>>,
}

impl FrameDriver {
    /// Starts the render thread with `tracers` holding the pipeline's first generation
    /// (`first`, as [`Pipeline::new`] returned it).
    pub fn new<T: BandTracer + Send + 'static>(
        pipeline: Pipeline,
        first: &GpuScene,
        tracers: Vec<T>,
        balancer: Box<dyn Balancer>,
        options: DriverOptions,
    ) -> Result<FrameDriver> {
        FrameDriver::with_update_tracers(pipeline, first, tracers, Vec::new(), balancer, options)
    }

    /// The same, with `update_tracers` (holding `first` too) for a method's asynchronous
    /// preparation ([`GiUpdate::Asynchronous`]), split by a balancer of the same name.
    pub fn with_update_tracers<T: BandTracer + Send + 'static>(
        mut pipeline: Pipeline,
        first: &GpuScene,
        tracers: Vec<T>,
        update_tracers: Vec<T>,
        balancer: Box<dyn Balancer>,
        options: DriverOptions,
    ) -> Result<FrameDriver> {
        if options.width == 0 || options.height == 0 {
            return Err(Error::Invalid(format!(
                "the frame size {}x{} is empty",
                options.width, options.height
            )));
        }
        if tracers.is_empty() {
            return Err(Error::Invalid("a frame driver needs a tracer".into()));
        }
        options.denoise.available().map_err(Error::Invalid)?;
        let name = balancer.name();
        let first_scene = Arc::new(first.clone());
        let prepares = !options.method.unit().ready();
        let worker = match (prepares, options.gi_update) {
            (true, GiUpdate::Asynchronous) => {
                if update_tracers.is_empty() {
                    return Err(Error::Invalid(format!(
                        "the asynchronous update of {} needs tracers of its own \
                         (FrameDriver::with_update_tracers)",
                        options.method.unit().name()
                    )));
                }
                let balancer = crate::balance::by_name(name)
                    .ok_or_else(|| Error::Invalid(format!("no balancer named {name}")))?;
                Some(Worker::start(update_tracers, balancer)?)
            }
            _ => None,
        };
        if prepares {
            pipeline.keep_scenes();
        }
        if options.denoise != Denoiser::None {
            pipeline.keep_hit_geometry();
        }
        let renderer = Renderer::new(tracers, balancer);
        let film = Accumulation::new(options.width, options.height);
        let denoiser = (options.denoise != Denoiser::None)
            .then(|| FrameDenoiser::new(options.denoise, HitGeometry::of_flattened(first)));
        let cache = match options.world_cache {
            Some(o) => {
                if !options.method.is_path_tracing() {
                    return Err(Error::Invalid(
                        "the world cache is the path tracer's: another method was chosen".into(),
                    ));
                }
                Some(WorldCache::new(o, first.header().scene_sphere[3]).map_err(Error::Invalid)?)
            }
            None => None,
        };
        // One frame queued at most: the game is never more than a frame ahead.
        let (jobs, inbox) = mpsc::sync_channel::<Job>(1);
        let (outbox, done) = mpsc::sync_channel(1);
        let scene = first_scene.clone();
        let render = std::thread::Builder::new()
            .name("platoon render".into())
            .spawn(move || render_loop(renderer, film, denoiser, cache, scene, inbox, outbox))
            .map_err(|e| Error::Invalid(format!("starting the render thread: {e}")))?;
        Ok(FrameDriver {
            pipeline,
            jobs: Some(jobs),
            done,
            render: Some(render),
            in_flight: false,
            planner: Planner::new(options.blend_floor),
            scaler: options
                .target
                .map(|target| scaler(target, options.spp, options.below_one)),
            queries: options.queries.then(|| QueryScene::new(first)),
            options,
            frame: 0,
            epoch: 0,
            last_camera: None,
            balancer: name,
            generation: 0,
            first_scene: worker.is_some().then_some(first_scene),
            worker,
            prepared: None,
        })
    }

    /// The scene's edit calls (placements, instances, materials, lights, time...): what is
    /// edited before a [`FrameDriver::frame`] call is built while that frame renders and
    /// rendered by the next.
    pub fn scene(&mut self) -> &mut Pipeline {
        &mut self.pipeline
    }

    /// The generation being rendered, for the game's CPU ray queries (with
    /// [`DriverOptions::queries`]).
    pub fn queries(&self) -> Option<&QueryScene> {
        self.queries.as_ref()
    }

    /// Samples the next frame will take.
    pub fn spp(&self) -> u32 {
        self.workload().spp
    }

    /// The next frame's work.
    pub fn workload(&self) -> Workload {
        self.scaler
            .as_ref()
            .map_or(Workload::samples(self.options.spp), |s| s.workload())
    }

    /// Holds `target` from the next frame on (None: keep the current spp fixed).
    pub fn set_target(&mut self, target: Option<Duration>) {
        let spp = self.spp();
        self.options.spp = spp;
        self.options.target = target;
        self.scaler = target.map(|t| scaler(t, spp, self.options.below_one));
    }

    pub fn options(&self) -> &DriverOptions {
        &self.options
    }

    pub fn balancer_name(&self) -> &'static str {
        self.balancer
    }

    /// Cuts the frames from the next one on with `balancer`.
    pub fn set_balancer(&mut self, balancer: Box<dyn Balancer>) -> Result<()> {
        self.balancer = balancer.name();
        self.send(Job::Balancer(balancer))
    }

    /// One game frame: starts rendering the view from `camera` of the scene as edited up to
    /// the previous call, hands this call's edits to the updater, and returns the previous
    /// frame. Errors: an edit the updater refused, or every tracer lost.
    pub fn frame(&mut self, camera: Camera) -> Result<FrameOutput> {
        let wait = Instant::now();
        let finished = self.finish()?;
        let waited_render = wait.elapsed();
        if let (Some(f), Some(scaler)) = (&finished, self.scaler.as_mut()) {
            scaler.observe(f.stats.busy, f.stats.plan.rate);
        }

        let wait = Instant::now();
        let generation = if self.pipeline.has_submitted() {
            Some(self.pipeline.take()?)
        } else {
            None
        };
        if self.pipeline.has_pending() {
            self.pipeline.submit()?;
        }
        let waited_update = wait.elapsed();
        if let (Some(q), Some(g)) = (self.queries.as_mut(), &generation) {
            q.apply_commit(&g.commit);
        }

        let changed = generation.as_ref().is_some_and(|g| !g.commit.is_empty());
        if changed {
            self.generation += 1;
        }
        let gi_arrived = self.follow_asynchronously(generation.as_ref(), camera)?;
        let motion = Motion {
            camera: self.last_camera != Some(camera) || (changed && self.options.restart_on_change),
            // A new result of the asynchronous update joins the film as moving objects do.
            scene: changed || gi_arrived,
        };
        self.last_camera = Some(camera);
        let last_idle = finished.as_ref().map(|f| f.stats.idle_fraction);
        let plan = self.planner.plan(motion, self.workload(), last_idle);
        if plan.join == Join::Restart {
            self.epoch = self.frame;
        }
        let o = &self.options;
        let (width, height) = render_size(o.width, o.height, plan.resolution);
        let mut params = o.frame_params(width, height, plan.spp, camera);
        params.frame = self.epoch;
        params.first_sample = plan.first_sample;
        params.rr_survival = plan.rr_survival;
        if plan.rr_survival < 1.0 {
            // Scaled roulette saves time only where it plays: from the first bounce on.
            params.rr_depth = params.rr_depth.min(1);
        }
        let gi = self.prepared.as_ref().map(|p| {
            params.method = p.method.clone();
            GiStats::of(p, self.generation, gi_arrived)
        });
        let (commit, update, scene, hits) = match generation {
            Some(g) if !g.commit.is_empty() => (Some(g.commit), g.times, g.scene, g.hits),
            Some(g) => (None, g.times, None, None),
            None => (None, UpdateTimes::default(), None, None),
        };
        self.send(Job::Frame(Box::new(FrameJob {
            frame: self.frame,
            commit,
            generation: self.generation,
            scene: if self.worker.is_none() { scene } else { None },
            hits,
            gi,
            update,
            params,
            plan,
            moved: motion.camera || motion.scene,
        })))?;
        self.in_flight = true;
        self.frame += 1;
        Ok(FrameOutput {
            finished,
            waited_render,
            waited_update,
        })
    }

    /// Asynchronous preparation: hands the worker the new generation (and the first scene with
    /// the first frame), and takes its newest result, waiting for the first; whether one came.
    fn follow_asynchronously(
        &mut self,
        generation: Option<&super::Generation>,
        camera: Camera,
    ) -> Result<bool> {
        let Some(worker) = self.worker.as_mut() else {
            return Ok(false);
        };
        let o = &self.options;
        let params = |scene| WorkerJob {
            commit: None,
            scene,
            generation: self.generation,
            params: o.frame_params(o.width, o.height, 1, camera),
        };
        if let Some(first) = self.first_scene.take() {
            worker.submit(params(first))?;
        }
        if let Some(g) = generation.filter(|g| !g.commit.is_empty()) {
            let scene = g.scene.clone().ok_or_else(|| {
                Error::Invalid("a generation came without the scene the update reads".into())
            })?;
            worker.submit(WorkerJob {
                commit: Some(g.commit.clone()),
                ..params(scene)
            })?;
        }
        match worker.newest(self.prepared.is_none())? {
            Some(p) => {
                self.prepared = Some(p);
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// Waits for the frame in flight, if any (at the end of a game, for its last frame).
    pub fn finish(&mut self) -> Result<Option<FinishedFrame>> {
        if !self.in_flight {
            return Ok(None);
        }
        self.in_flight = false;
        match self.done.recv() {
            Ok(result) => result.map(Some),
            Err(_) => Err(Error::Invalid("the render thread ended".into())),
        }
    }

    fn send(&self, job: Job) -> Result<()> {
        self.jobs
            .as_ref()
            .and_then(|j| j.send(job).ok())
            .ok_or_else(|| Error::Invalid("the render thread ended".into()))
    }
}

impl Drop for FrameDriver {
    fn drop(&mut self) {
        self.jobs = None;
        // Drain a frame in flight so the render thread can end.
        while self.done.recv().is_ok() {}
        if let Some(render) = self.render.take() {
            let _ = render.join();
        }
    }
}

/// What the render thread keeps for a method's synchronous preparation: the newest scene
/// and the last result.
struct Synchronous {
    scene: Arc<GpuScene>,
    prepared: Option<PreparedMethod>,
}

fn render_loop<T: BandTracer + Send + 'static>(
    mut renderer: Renderer<T>,
    mut film: Accumulation,
    mut denoiser: Option<FrameDenoiser>,
    mut cache: Option<WorldCache>,
    scene: Arc<GpuScene>,
    inbox: Receiver<Job>,
    outbox: SyncSender<Result<FinishedFrame>>,
) {
    let mut sync = Synchronous {
        scene,
        prepared: None,
    };
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
                cache.as_mut(),
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
    cache: Option<&mut WorldCache>,
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
    let failed = |e: crate::frame::renderer::RenderError| Error::Invalid(e.to_string());
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
    params.world_cache = cache.as_ref().map(|c| c.table());
    let mut rendered = renderer
        .render_frame_planned(&params, plan.rebalance)
        .map_err(failed)?;
    let render = render_start.elapsed();
    failures.extend(std::mem::take(&mut rendered.failures));
    // The records of every band, in pixel order: the same cache for any split.
    let world_cache = cache.map(|c| c.update(&rendered.per_pixel, frame));
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
            world_cache,
        },
    })
}

fn scaler(target: Duration, spp: u32, below_one: BelowOneSample) -> WorkloadScaler {
    let mut s = WorkloadScaler::new(target, spp);
    s.below_one = below_one;
    s
}

/// The size a frame renders at: the film's scaled by `resolution` per axis, at least a pixel.
pub fn render_size(width: u32, height: u32, resolution: f32) -> (u32, u32) {
    if resolution >= 1.0 {
        return (width, height);
    }
    let scale = |n: u32| ((n as f32 * resolution).round() as u32).clamp(1, n.max(1));
    (scale(width), scale(height))
}

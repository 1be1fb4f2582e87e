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
use super::denoising::FrameDenoiser;
use super::finished::{FinishedFrame, FrameOutput};
use super::gi::{GiStats, GiUpdate, PreparedMethod, Worker, WorkerJob};
use super::plan::{Join, Motion, Planner};
use super::render_thread::{render_loop, FrameJob, Job, Synchronous};
use super::scaling::{BelowOneSample, Workload, WorkloadScaler};
use super::{Pipeline, QueryScene, UpdateTimes};
use platoon_core::balance::Balancer;
use platoon_core::denoise::Denoiser;
use platoon_core::error::{Error, Result};
use platoon_core::flatten::GpuScene;
use platoon_core::frame::hit_geometry::HitGeometry;
use platoon_core::frame::{BandTracer, FrameParams, PathLoop, DEFAULT_SAMPLES_PER_PASS};
use platoon_core::method::Method;
use platoon_core::scene::camera::Camera;
use platoon_schedule::renderer::Renderer;

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
    /// The options every frame takes as they are: the seed, the pixel filter its camera rays are drawn
    /// from, a transparent film (a game request refuses one: its frames are opaque), the AO
    /// distance (`FrameOptions`).
    pub options: platoon_core::frame::FrameOptions,
    /// The path loop every frame's kernels run: depth, Russian roulette, clamp, light
    /// selection (`frame::PathLoop`; the frame driver's roulette scaling lowers its survival
    /// below one sample a frame).
    pub path_loop: PathLoop,
    pub samples_per_pass: u32,
    /// The rendering method (`platoon_core::method`). With instant global illumination a still
    /// view's frames each gather a VPL set of their own, so the film averages over sets.
    pub method: Method,
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
    /// Each finished frame carries its generation's flattened scene
    /// ([`FinishedFrame::scene`]): what a still render of the same frame needs, to measure the
    /// game's error against (`bench game`). A copy of the scene per changed generation.
    pub keep_frame_scenes: bool,
}

/// [`DriverOptions::realtime`]'s rule on a method and a denoiser (for front ends that
/// validate them before any driver exists): the method's own real-time settings where its
/// options leave them open (`RenderMethod::realtime`: the path tracer's resampled light over
/// `REALTIME_CANDIDATES` lights); the à-trous denoiser where none is chosen.
pub fn realtime(method: &mut Method, denoise: Denoiser) -> Denoiser {
    if let Some(m) = method.unit().realtime() {
        *method = m;
    }
    match denoise {
        Denoiser::None => Denoiser::Atrous,
        d => d,
    }
}

impl DriverOptions {
    /// A game's real-time settings where these options leave them open: the method's (the
    /// path tracer's resampled direct light) and the à-trous denoiser over
    /// the history (biased by the denoiser, reported as such).
    pub fn realtime(&mut self) {
        self.denoise = realtime(&mut self.method, self.denoise);
    }

    /// A frame's params of `width` x `height` at `spp` from `camera` with these options' seed,
    /// depths, samples per pass and method (what every frame and a method's preparation share).
    fn frame_params(&self, width: u32, height: u32, spp: u32, camera: Camera) -> FrameParams {
        let mut p = FrameParams::new(width, height, spp, camera);
        p.options = self.options;
        p.path_loop = self.path_loop.clone();
        p.samples_per_pass = self.samples_per_pass;
        p.method = self.method.clone();
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
            options: Default::default(),
            path_loop: PathLoop::default(),
            samples_per_pass: DEFAULT_SAMPLES_PER_PASS,
            method: platoon_core::method::Method::path_tracing(),
            keep_frame_scenes: false,
            queries: false,
            gi_update: GiUpdate::default(),
            denoise: Denoiser::None,
            restart_on_change: false,
        }
    }
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
                let balancer = platoon_core::balance::by_name(name)
                    .ok_or_else(|| Error::Invalid(format!("no balancer named {name}")))?;
                Some(Worker::start(update_tracers, balancer)?)
            }
            _ => None,
        };
        if prepares || options.keep_frame_scenes {
            pipeline.keep_scenes();
        }
        if options.denoise != Denoiser::None {
            pipeline.keep_hit_geometry();
        }
        let renderer = Renderer::new(tracers, balancer);
        let film = Accumulation::new(options.width, options.height);
        let denoiser = (options.denoise != Denoiser::None)
            .then(|| FrameDenoiser::new(options.denoise, HitGeometry::of_flattened(first)));
        // What the method learns over the frames (the path tracer's world cache, light reuse).
        let learning = (options.method.unit())
            .learning(first.header().scene_sphere[3])
            .map_err(Error::Invalid)?;
        // One frame queued at most: the game is never more than a frame ahead.
        let (jobs, inbox) = mpsc::sync_channel::<Job>(1);
        let (outbox, done) = mpsc::sync_channel(1);
        let sync = Synchronous {
            scene: first_scene.clone(),
            prepared: None,
            keep_frame_scenes: options.keep_frame_scenes,
        };
        let render = std::thread::Builder::new()
            .name("platoon render".into())
            .spawn(move || render_loop(renderer, film, denoiser, learning, sync, inbox, outbox))
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
        // The scaling's survival on the options' own (1 unless a caller lowered it).
        params.path_loop.rr_survival *= plan.rr_survival;
        if plan.rr_survival < 1.0 {
            // Scaled roulette saves time only where it plays: from the first bounce on.
            params.path_loop.rr_depth = params.path_loop.rr_depth.min(1);
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

#[cfg(test)]
mod tests {
    use super::*;
    use platoon_core::method::path::REALTIME_CANDIDATES;

    #[test]
    fn every_frame_runs_the_options_path_loop_and_method() {
        let mut options = DriverOptions::new(8, 6);
        options.path_loop.max_depth = 3;
        options.path_loop.clamp_indirect = Some(2.5);
        options.realtime();
        let camera = Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0);
        let p = options.frame_params(8, 6, 1, camera);
        assert_eq!(p.path_loop, options.path_loop);
        assert_eq!(p.method, options.method);
        let light = p.method.path().resampled_light.unwrap();
        assert_eq!(light.candidates, REALTIME_CANDIDATES);
        assert_eq!(options.denoise, Denoiser::Atrous);
    }
}

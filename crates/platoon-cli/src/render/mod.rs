//! `platoon render`: one frame of a scene to an EXR or PNG, with a progress bar; with
//! `--frames`, an animation to numbered files ([`frames`]), optionally a video ([`video`]).

mod batching;
mod farm;
mod frames;
mod outputs;
mod video;

use std::path::PathBuf;
use std::rc::Rc;

use anyhow::{bail, Result};
use clap::ValueEnum;
use glam::Vec3;
use indicatif::{ProgressBar, ProgressStyle};
use platoon::core::balance;
use platoon::core::denoise::Denoiser;
use platoon::core::frame::adaptive::{Adaptive, Batching};
use platoon::core::frame::aov::Aov;
use platoon::core::frame::FrameParams;
use platoon::devices::DeviceSpec;
use platoon::distributed::Session;
use platoon::tracer::Sampling;
use platoon::{PrepareOptions, Tracers};

use crate::method_args::MethodArgs;
use crate::scene_args::SceneArgs;
use outputs::Outputs;

#[derive(Clone, Copy, ValueEnum)]
pub enum MemoryArg {
    Auto,
    TexelBuffers,
    StorageBuffers,
    DeviceAddress,
}

#[derive(Clone, Copy, ValueEnum)]
pub enum SamplingArg {
    Mis,
    Bsdf,
    Light,
}

#[derive(clap::Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    method: MethodArgs,
    #[arg(long, default_value_t = 64)]
    spp: u32,
    /// Stop at the last complete pass within this many seconds (then --spp is an upper
    /// bound; the spp reached goes into the metadata). One device only.
    #[arg(long)]
    time_limit: Option<f64>,
    #[arg(long, default_value_t = 512)]
    width: u32,
    #[arg(long, default_value_t = 512)]
    height: u32,
    /// Longest path in segments (1: emitters only, 2: direct light). Default: effectively unbounded.
    #[arg(long)]
    max_depth: Option<u32>,
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Index of the scene camera; the scene is framed from its bounds when it has none.
    #[arg(long)]
    camera: Option<usize>,
    /// Thin-lens aperture radius in scene units (0: pinhole).
    #[arg(long, default_value_t = 0.0)]
    aperture: f32,
    /// Distance to the plane in focus (default: the scene centre).
    #[arg(long)]
    focus_distance: Option<f32>,
    /// Devices: `all`, indices like `0,1` (see `platoon devices`), or `lavapipe:T1,T2,...`
    /// (one software tracer per entry, with Ti threads each).
    #[arg(long, default_value = "0")]
    devices: DeviceSpec,
    /// How lines are split between devices: none, robin-hood, perfect, perfect-smooth,
    /// cycles, cost-aware.
    #[arg(long, default_value = "cost-aware", value_parser = parse_balancer)]
    balancer: String,
    /// Estimator: MIS of light and BSDF sampling (default), or either alone.
    #[arg(long, value_enum, default_value = "mis")]
    sampling: SamplingArg,
    /// Enable the Khronos validation layer.
    #[arg(long)]
    validation: bool,
    /// How the kernel reads scene arrays: auto is texel buffers on CPU devices (lavapipe) and
    /// storage buffers on GPUs, each where the array fits the device's limits, else device
    /// addresses; the others force one path where it fits. Same image on every path.
    #[arg(long, value_enum, default_value = "auto")]
    memory: MemoryArg,
    #[arg(long, short, default_value = "render.png")]
    out: PathBuf,
    /// AOVs written as layers of the EXR beside the beauty, comma-separated: albedo, normal
    /// (Cycles' denoising conventions), depth, position, instance-id, material-id,
    /// primitive-id, variance (of each pixel's mean, from batches of its samples),
    /// sample-count.
    #[arg(long, value_parser = parse_aovs)]
    aov: Option<AovList>,
    /// Denoise the image after assembly, guided by its albedo, normal and depth: none, atrous
    /// (the edge-avoiding a-trous filter) or oidn (Intel Open Image Denoise, in a build with
    /// `--features oidn`); biased. The raw image is written beside it as NAME.noisy.EXT.
    #[arg(long, default_value = "none")]
    denoise: Denoiser,
    /// Adaptive sampling (Cycles' scheme): a pixel stops taking samples once its noise
    /// estimate is below this threshold (0.01 clean, 0.1 a preview); --spp is then the most a
    /// pixel takes. An EXR output gets the sample-count layer. Path tracing only.
    #[arg(long)]
    adaptive_threshold: Option<f32>,
    /// Samples every pixel takes before adaptive sampling may stop it (default: spp / 16, at
    /// least 16).
    #[arg(long, requires = "adaptive_threshold")]
    adaptive_min_spp: Option<u32>,
    /// Split each frame between the ranks of an MPI job: `mpirun -n N platoon render ...
    /// --mpi`, in a build with `--features mpi`. Every rank loads the scene and renders on its
    /// own --devices; rank 0 cuts frames between the ranks with --balancer and writes the
    /// image (docs/DISTRIBUTED.md).
    #[arg(long)]
    mpi: bool,
    #[command(flatten)]
    frames: frames::FrameArgs,
}

#[derive(Clone, Debug)]
pub struct AovList(pub Vec<Aov>);

fn parse_aovs(s: &str) -> Result<AovList, String> {
    Aov::parse_list(s).map(AovList)
}

fn parse_balancer(s: &str) -> Result<String, String> {
    match balance::by_name(s) {
        Some(_) => Ok(s.to_string()),
        None => Err(format!(
            "unknown balancer {s}: one of {}",
            balance::NAMES.join(", ")
        )),
    }
}

/// What a render needs besides the camera: the scene loaded, how to prepare it, the frame's
/// parameters and the tracers' options.
struct Setup {
    scene: platoon::core::Scene,
    options: PrepareOptions,
    params: FrameParams,
    tracers: Vec<platoon::tracer::TracerOptions>,
    balancer: String,
    sampling: &'static str,
    aovs: Vec<Aov>,
    denoiser: Denoiser,
    /// Adaptive sampling and the variance AOV's batches.
    batching: Batching,
    /// The job's ranks, with --mpi or --mpi-frames.
    session: Option<Rc<dyn Session>>,
    /// --mpi-frames: each rank renders whole frames on its own devices.
    farm: bool,
}

impl Setup {
    /// The tracers of this process holding `scene`: over the job's ranks with --mpi.
    fn tracers(&self, scene: &platoon::core::flatten::GpuScene) -> Result<Tracers> {
        match &self.session {
            Some(s) if !self.farm => {
                Tracers::over_ranks(&self.tracers, &self.balancer, scene, s.clone())
            }
            _ => Tracers::new(&self.tracers, &self.balancer, scene),
        }
    }

    /// Whether this process writes and reports (rank 0 of a job, or a process alone).
    fn speaks(&self) -> bool {
        self.session.as_ref().is_none_or(|s| s.rank() == 0)
    }
}

/// Runs `body`; in a job of several ranks an error on one ends them all (MPI_Abort), since
/// the others would wait for it in their next exchange.
fn on_every_rank(
    session: Option<Rc<dyn Session>>,
    body: impl FnOnce() -> Result<()>,
) -> Result<()> {
    match (body(), session) {
        (Err(e), Some(s)) if s.size() > 1 => {
            use std::io::Write as _;
            let line = format!("error: rank {}: {e:#}\n", s.rank());
            let _ = std::io::stderr().write_all(line.as_bytes());
            s.abort(1)
        }
        (result, _) => result,
    }
}

fn setup(a: RenderArgs) -> Result<(Setup, PathBuf, frames::FrameArgs)> {
    let RenderArgs {
        scene,
        method,
        spp,
        time_limit,
        width,
        height,
        max_depth,
        seed,
        camera,
        aperture,
        focus_distance,
        devices,
        balancer,
        sampling,
        validation,
        memory,
        out,
        aov,
        denoise,
        adaptive_threshold,
        adaptive_min_spp,
        mpi,
        frames,
    } = a;
    let mut aovs = aov.map(|l| l.0).unwrap_or_default();
    denoise
        .available()
        .map_err(|e| anyhow::anyhow!("--denoise: {e}"))?;
    let kernel = method.kernel;
    let method = method.method()?;
    if width == 0 || height == 0 || spp == 0 {
        bail!("--width, --height and --spp must be positive");
    }
    let loaded = scene.load()?;
    let options = PrepareOptions {
        env: scene.env_choice(),
        time: scene.time,
        camera,
        aperture_radius: aperture,
        focus_distance,
        ..Default::default()
    };
    // The camera is the prepared scene's, or each frame's: set before rendering.
    let placeholder = platoon::core::scene::camera::Camera::look_at(Vec3::ZERO, Vec3::NEG_Z, 1.0);
    let mut params = FrameParams::new(width, height, spp, placeholder);
    params.seed = seed;
    params.method = method;
    params.kernel = kernel;
    if let Some(d) = max_depth {
        params.max_depth = d.max(1);
    }
    if let Some(t) = time_limit {
        if !(t.is_finite() && t > 0.0) {
            bail!("--time-limit must be a positive number of seconds");
        }
        params.time_limit = Some(std::time::Duration::from_secs_f64(t));
    }
    let (sampling, sampling_name) = match sampling {
        SamplingArg::Mis => (Sampling::Mis, "mis"),
        SamplingArg::Bsdf => (Sampling::Bsdf, "bsdf"),
        SamplingArg::Light => (Sampling::Light, "light"),
    };
    let mut tracers = platoon::devices::tracer_options(&devices, validation, sampling)?;
    for o in &mut tracers {
        o.memory = match memory {
            MemoryArg::Auto => platoon::tracer::MemoryPath::Auto,
            MemoryArg::TexelBuffers => platoon::tracer::MemoryPath::TexelBuffers,
            MemoryArg::StorageBuffers => platoon::tracer::MemoryPath::StorageBuffers,
            MemoryArg::DeviceAddress => platoon::tracer::MemoryPath::DeviceAddress,
        };
    }
    if mpi && time_limit.is_some() {
        bail!("--time-limit renders on one device: shares of a frame cut at different times on the ranks would break the image's independence from the split (--mpi-frames renders whole frames, each with the limit)");
    }
    if tracers.len() > 1 && time_limit.is_some() {
        bail!("--time-limit renders on one device: bands cut at different times would break the image's independence from the device split");
    }
    let farm = frames.mpi_frames.is_some();
    let session = if mpi || farm {
        Some(platoon::distributed::join()?)
    } else {
        None
    };
    let batching = batching::of(
        adaptive_threshold.map(|threshold| Adaptive {
            threshold,
            min_spp: adaptive_min_spp,
        }),
        &params,
        &out,
        &mut aovs,
    )?;
    let setup = Setup {
        scene: loaded,
        options,
        params,
        tracers,
        balancer,
        sampling: sampling_name,
        aovs,
        denoiser: denoise,
        batching,
        session,
        farm,
    };
    Ok((setup, out, frames))
}

pub fn run(a: RenderArgs) -> Result<()> {
    if a.frames.frames.is_some() || a.frames.mpi_frames.is_some() {
        return frames::run(a);
    }
    check_output(&a)?;
    let (setup, out, _) = setup(a)?;
    let session = setup.session.clone();
    on_every_rank(session, || still(setup, out))
}

/// The still render of `run`.
fn still(setup: Setup, out: PathBuf) -> Result<()> {
    let speaks = setup.speaks();
    let prepared = platoon::prepare(setup.scene.clone(), &setup.options)?;
    if speaks {
        for w in &prepared.scene.warnings {
            eprintln!("warning: {w}");
        }
        if let Some(note) = &prepared.note {
            eprintln!("note: {note}");
        }
    }
    let mut tracers = setup.tracers(&prepared.gpu)?;
    let Setup {
        mut params,
        sampling,
        aovs,
        denoiser,
        batching,
        ..
    } = setup;
    params.camera = prepared.camera;
    let rendered = render_frame(&mut tracers, &prepared.gpu, &params, &batching)?;
    let origin = prepared.posed.origin;
    let outputs = Outputs::of(
        &mut tracers,
        &prepared.gpu,
        &params,
        &rendered,
        &aovs,
        denoiser,
        origin,
    )?;
    if !speaks {
        return Ok(());
    }
    let mut meta = platoon::metadata(&prepared, &params, &rendered, sampling);
    meta.extend(aov_metadata(&aovs));
    outputs.write(&out, &meta)?;
    let secs = rendered.wall_time.as_secs_f64();
    let spp = match rendered.batched.as_ref().and_then(|b| b.adaptive) {
        Some(_) => format!(
            "{:.1} spp on average (adaptive, at most {})",
            rendered.mean_spp(),
            rendered.spp
        ),
        None => format!("{} spp", rendered.spp),
    };
    eprintln!(
        "{}: {}x{} at {spp} in {:.2} s on {} ({:.2} M samples/s, {:.2} M rays/s, {} rejected samples)",
        out.display(),
        params.width,
        params.height,
        secs,
        rendered.device,
        (params.width as f64 * params.height as f64 * rendered.mean_spp()) / secs / 1e6,
        rendered.rays() as f64 / secs / 1e6,
        rendered.rejected_samples()
    );
    report_method(&rendered);
    Ok(())
}

/// Refuses an output the render could not write, before it starts.
fn check_output(a: &RenderArgs) -> Result<()> {
    let format = platoon::core::output::check_image_path(&a.out)?;
    if a.aov.is_some() && !matches!(format, platoon::core::output::ImageFormat::Exr) {
        bail!(
            "{}: AOVs are written as layers of an EXR: the output must end in .exr",
            a.out.display()
        );
    }
    Ok(())
}

/// The metadata entry naming the AOV layers (none without AOVs).
fn aov_metadata(aovs: &[Aov]) -> Option<(String, String)> {
    let names: Vec<&str> = aovs.iter().map(|a| a.name()).collect();
    (!aovs.is_empty()).then(|| ("aovs".into(), names.join(",")))
}

/// Renders a frame with a progress bar over its samples (one tracer) or a spinner (several,
/// which render on their own threads), then prints the tracers' shares.
fn render_frame(
    tracers: &mut Tracers,
    scene: &platoon::core::flatten::GpuScene,
    params: &FrameParams,
    batching: &Batching,
) -> Result<platoon::Rendered> {
    let rendered = if tracers.rank() != 0 {
        tracers.render_batched(scene, params, batching, &mut |_| {})?
    } else if tracers.count() == 1 && tracers.ranks() == 1 {
        let bar = ProgressBar::new(params.spp as u64);
        bar.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} spp {msg}")
                .unwrap(),
        );
        let r = tracers.render_batched(scene, params, batching, &mut |done| {
            bar.set_position(done as u64)
        });
        bar.finish_and_clear();
        r?
    } else {
        let spinner = ProgressBar::new_spinner();
        spinner.set_message(match tracers.ranks() {
            1 => format!("rendering on {} tracers", tracers.count()),
            n => format!("rendering on {n} ranks"),
        });
        spinner.enable_steady_tick(std::time::Duration::from_millis(200));
        let r = tracers.render_batched(scene, params, batching, &mut |_| {});
        spinner.finish_and_clear();
        r?
    };
    if tracers.rank() != 0 {
        return Ok(rendered);
    }
    if let Some(report) = &rendered.ranks {
        report_ranks(report, params.width);
        return Ok(rendered);
    }
    for t in &rendered.tracers {
        eprintln!(
            "  tracer {}: lines {:.2}..{:.2} ({} pixels rendered), {:.3} s, idle {:.3} s",
            t.tracer,
            t.span.begin as f64 / params.width as f64,
            t.span.end as f64 / params.width as f64,
            t.pixels,
            t.wall_time.as_secs_f64(),
            t.idle.as_secs_f64()
        );
    }
    for m in &rendered.validation_messages {
        eprintln!("validation: {m}");
    }
    Ok(rendered)
}

/// Each rank's share and devices, and what crossed between the ranks.
fn report_ranks(report: &platoon::distributed::RanksReport, width: u32) {
    for p in &report.parts {
        eprintln!(
            "  rank {}: lines {:.2}..{:.2}, {:.3} s on {} device(s)",
            p.rank,
            p.span.begin as f64 / width as f64,
            p.span.end as f64 / width as f64,
            p.wall_time.as_secs_f64(),
            p.tracers.len()
        );
    }
    let c = &report.communication;
    eprintln!(
        "  {} ranks under {}: {} bytes sent, {} received, {:.1} ms in exchanges, {:.1} ms waiting \
         for the slowest rank (rank 0)",
        report.ranks,
        report.balancer,
        c.sent,
        c.received,
        c.time.as_secs_f64() * 1e3,
        c.waiting.as_secs_f64() * 1e3
    );
}

/// What the method's report says a user should see (layered hit buffers' build and losses).
fn report_method(rendered: &platoon::Rendered) {
    let entry = |key| platoon::core::frame::renderer::report_entry(&rendered.method_metadata, key);
    if let Some(build) = entry("lhb_build") {
        eprintln!("  layered hit buffers: {build}");
    }
    if let Some(lost) = entry("lhb_lost_layers").filter(|l| *l != "0") {
        eprintln!(
            "warning: {lost} layers did not fit the buffers' lists and are missing from the \
             lookups: raise --lhb-layers or use --lhb-variant exact"
        );
    }
}

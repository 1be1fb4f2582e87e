//! `platoon render`: one frame of a scene to an EXR or PNG, with a progress bar.

use std::path::PathBuf;

use anyhow::{bail, Result};
use clap::ValueEnum;
use indicatif::{ProgressBar, ProgressStyle};
use platoon::core::balance;
use platoon::core::frame::FrameParams;
use platoon::devices::DeviceSpec;
use platoon::tracer::Sampling;
use platoon::PrepareOptions;

use crate::method_args::MethodArgs;
use crate::scene_args::SceneArgs;

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

pub fn run(a: RenderArgs) -> Result<()> {
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
    } = a;
    platoon::core::output::check_image_path(&out)?;
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
    let prepared = platoon::prepare(loaded, &options)?;
    for w in &prepared.scene.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(note) = &prepared.note {
        eprintln!("note: {note}");
    }
    let mut params = FrameParams::new(width, height, spp, prepared.camera);
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
    let mut options = platoon::devices::tracer_options(&devices, validation, sampling)?;
    for o in &mut options {
        o.memory = match memory {
            MemoryArg::Auto => platoon::tracer::MemoryPath::Auto,
            MemoryArg::TexelBuffers => platoon::tracer::MemoryPath::TexelBuffers,
            MemoryArg::StorageBuffers => platoon::tracer::MemoryPath::StorageBuffers,
            MemoryArg::DeviceAddress => platoon::tracer::MemoryPath::DeviceAddress,
        };
    }
    if options.len() > 1 && time_limit.is_some() {
        bail!("--time-limit renders on one device: bands cut at different times would break the image's independence from the device split");
    }
    let rendered = if options.len() == 1 {
        let bar = ProgressBar::new(spp as u64);
        bar.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} spp {msg}")
                .unwrap(),
        );
        let r = platoon::render(&prepared, &options[0], &params, &mut |done| {
            bar.set_position(done as u64)
        })?;
        bar.finish_and_clear();
        r
    } else {
        let policy = balance::by_name(&balancer).expect("validated by clap");
        let tracers = platoon::devices::tracers_from_options(&options, &prepared.gpu)?;
        let mut renderer = platoon::core::frame::renderer::Renderer::new(tracers, policy);
        // Bands render on their own threads without per-sample progress: show that it runs.
        let spinner = ProgressBar::new_spinner();
        spinner.set_message(format!("rendering on {} tracers", options.len()));
        spinner.enable_steady_tick(std::time::Duration::from_millis(200));
        let r = platoon::method_update::on_renderer(&mut renderer, &prepared.gpu, &params)
            .and_then(|solved| platoon::render_frame(&mut renderer, &solved));
        spinner.finish_and_clear();
        let r = r?;
        for t in &r.tracers {
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
        r
    };
    for m in &rendered.validation_messages {
        eprintln!("validation: {m}");
    }
    let meta = platoon::metadata(&prepared, &params, &rendered, sampling_name);
    let spp = rendered.spp;
    platoon::core::output::write_image(&out, &rendered.film, &meta)?;
    let secs = rendered.wall_time.as_secs_f64();
    eprintln!(
        "{}: {}x{} at {} spp in {:.2} s on {} ({:.2} M samples/s, {:.2} M rays/s, {} rejected samples)",
        out.display(),
        width,
        height,
        spp,
        secs,
        rendered.device,
        (width as f64 * height as f64 * spp as f64) / secs / 1e6,
        rendered.rays() as f64 / secs / 1e6,
        rendered.rejected_samples()
    );
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
    Ok(())
}

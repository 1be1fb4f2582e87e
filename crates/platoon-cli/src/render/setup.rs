//! What `platoon render` makes of its arguments before rendering: the scene loaded, the frame's
//! parameters, the tracers' options, the job's ranks; the output refused early when it cannot be
//! written.

use std::path::PathBuf;
use std::rc::Rc;

use anyhow::{bail, Result};
use glam::Vec3;
use platoon::core::denoise::Denoiser;
use platoon::core::frame::adaptive::{Adaptive, Batching};
use platoon::core::frame::aov::Aov;
use platoon::core::frame::FrameParams;
use platoon::distributed::Session;
use platoon::tracer::Sampling;
use platoon::{PrepareOptions, Tracers};

use super::args::{FrameArgs, MemoryArg, RenderArgs, SamplingArg};
use super::batching;

/// What a render needs besides the camera: the scene loaded, how to prepare it, the frame's
/// parameters and the tracers' options.
pub(super) struct Setup {
    pub(super) scene: platoon::core::Scene,
    pub(super) options: PrepareOptions,
    pub(super) params: FrameParams,
    pub(super) tracers: Vec<platoon::tracer::TracerOptions>,
    pub(super) balancer: String,
    pub(super) sampling: &'static str,
    pub(super) aovs: Vec<Aov>,
    pub(super) denoiser: Denoiser,
    /// Adaptive sampling and the variance AOV's batches.
    pub(super) batching: Batching,
    /// The job's ranks, with --mpi or --mpi-frames.
    pub(super) session: Option<Rc<dyn Session>>,
    /// --mpi-frames: each rank renders whole frames on its own devices.
    pub(super) farm: bool,
}

impl Setup {
    /// The tracers of this process holding `scene`: over the job's ranks with --mpi.
    pub(super) fn tracers(&self, scene: &platoon::core::flatten::GpuScene) -> Result<Tracers> {
        match &self.session {
            Some(s) if !self.farm => {
                Tracers::over_ranks(&self.tracers, &self.balancer, scene, s.clone())
            }
            _ => Tracers::new(&self.tracers, &self.balancer, scene),
        }
    }

    /// Whether this process writes and reports (rank 0 of a job, or a process alone).
    pub(super) fn speaks(&self) -> bool {
        self.session.as_ref().is_none_or(|s| s.rank() == 0)
    }
}

/// Runs `body`; in a job of several ranks an error on one ends them all (MPI_Abort), since
/// the others would wait for it in their next exchange.
pub(super) fn on_every_rank(
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

pub(super) fn setup(a: RenderArgs) -> Result<(Setup, PathBuf, FrameArgs)> {
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

/// Refuses an output the render could not write, before it starts.
pub(super) fn check_output(a: &RenderArgs) -> Result<()> {
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
pub(super) fn aov_metadata(aovs: &[Aov]) -> Option<(String, String)> {
    let names: Vec<&str> = aovs.iter().map(|a| a.name()).collect();
    (!aovs.is_empty()).then(|| ("aovs".into(), names.join(",")))
}

//! What `platoon render` makes of its arguments before rendering: a request (`platoon::Request`,
//! which holds the rules), the scene it loads, the frame's parameters, the tracers' options, the
//! job's ranks; the output refused early when it cannot be written.

use std::path::PathBuf;
use std::rc::Rc;

use anyhow::{bail, Result};
use glam::Vec3;
use platoon::core::frame::aov::Aov;
use platoon::core::output::{image_format, ImageFormat};
use platoon::distributed::Session;
use platoon::tracer::MemoryPath;
use platoon::{CameraChoice, PrepareOptions, Request, SceneSource};

use crate::request_flags::{any_as_flags, as_flags};

use super::args::{FrameArgs, MemoryArg, RenderArgs};

/// What a render needs besides the camera: the request (what it asks for, and what the
/// frame's parameters, the batches, the AOVs and the denoiser are made from; its steps render
/// it), the scene it loaded, how to prepare it (at an animation frame's time) and the job's
/// ranks.
pub(super) struct Setup {
    /// The request the flags make, validated.
    pub(super) request: Request,
    pub(super) scene: platoon::core::Scene,
    pub(super) options: PrepareOptions,
    /// The job's ranks, with --mpi or --mpi-frames.
    pub(super) session: Option<Rc<dyn Session>>,
    /// --mpi-frames: each rank renders whole frames on its own devices.
    pub(super) farm: bool,
    /// When the command began (before the scene was read): what a render's time in all counts
    /// from.
    pub(super) started: std::time::Instant,
    /// How long reading the scene took.
    pub(super) load_time: std::time::Duration,
    /// How a PNG or a video shows the image.
    pub(super) image: platoon::core::output::ImageOptions,
}

/// The camera `--camera-position`, `--look-at` and `--fov` give, with the lens flags.
fn given_camera(
    eye: Vec3,
    target: Vec3,
    fov: f32,
    aperture: f32,
    focus_distance: Option<f32>,
) -> Result<platoon::core::scene::camera::Camera> {
    if !(fov > 0.0 && fov < 180.0) {
        bail!("--fov: a vertical field of view in degrees, above 0 and below 180, not {fov}");
    }
    if eye.distance(target) <= f32::EPSILON * eye.abs().max_element().max(1.0) {
        bail!("--look-at: the same point as --camera-position ({eye}): no direction to look in");
    }
    let mut c = platoon::core::scene::camera::Camera::look_at(eye, target, fov.to_radians());
    c.aperture_radius = aperture;
    if let Some(f) = focus_distance {
        c.focus_distance = f;
    }
    Ok(c)
}

impl Setup {
    /// The ranks a frame's bands are split between: the job's with --mpi (a farm's ranks each
    /// render whole frames on their own devices).
    pub(super) fn ranks(&self) -> Option<Rc<dyn Session>> {
        self.session.clone().filter(|_| !self.farm)
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
    let started = std::time::Instant::now();
    let RenderArgs {
        scene,
        method,
        options,
        resolution_percent,
        resume: _,
        camera,
        camera_position,
        look_at,
        fov,
        memory,
        device_memory_limit,
        out,
        aov,
        adaptive_min_spp,
        mpi,
        frames,
        display,
    } = a;
    let image = display.image(&out)?;
    let mut request = Request {
        scene: match &scene.scene {
            Some(path) => SceneSource::File(path.clone()),
            None => SceneSource::BuiltIn,
        },
        load: scene.load_options(),
        env: scene.env_choice(),
        env_light: scene.env_light(),
        time: scene.time,
        // A sequence's frames measure motion over their own interval (`Job::frame_interval`).
        frame_interval: platoon::request::DEFAULT_FRAME_INTERVAL,
        method: method.method()?,
        memory: match memory {
            MemoryArg::Auto => MemoryPath::Auto,
            MemoryArg::TexelBuffers => MemoryPath::TexelBuffers,
            MemoryArg::StorageBuffers => MemoryPath::StorageBuffers,
            MemoryArg::DeviceAddress => MemoryPath::DeviceAddress,
        },
        device_memory_limit,
        aovs: aov.map(|l| l.0).unwrap_or_default(),
        ..Default::default()
    };
    options.apply(&mut request)?;
    if let Some(a) = &mut request.adaptive {
        a.min_spp = adaptive_min_spp;
        // An adaptive render's EXR shows where it stopped: the sample-count layer.
        if matches!(image_format(&out)?, ImageFormat::Exr)
            && !request.aovs.contains(&Aov::SampleCount)
        {
            request.aovs.push(Aov::SampleCount);
        }
    }
    if request.frame.transparent_film && matches!(image_format(&out)?, ImageFormat::Jpeg) {
        bail!(
            "--film-transparent: {} is a JPEG, which has no alpha channel: write PNG, TIFF or EXR",
            out.display()
        );
    }
    (request.width, request.height) =
        at_percent(request.width, request.height, resolution_percent)?;
    request.camera = match (camera, camera_position.zip(look_at)) {
        (_, Some((eye, target))) => CameraChoice::Given(given_camera(
            eye,
            target,
            fov,
            request.aperture,
            request.focus_distance,
        )?),
        (None, None) => CameraChoice::Scene(None),
        (Some(c), None) => match c.parse::<usize>() {
            Ok(index) => CameraChoice::Scene(Some(index)),
            Err(_) => CameraChoice::Named(c),
        },
    };
    request.validate().map_err(as_flags)?;
    if mpi && request.frame.time_limit.is_some() {
        bail!("--time-limit renders on one device: shares of a frame cut at different times on the ranks would break the image's independence from the split (--mpi-frames renders whole frames, each with the limit)");
    }
    // Refused now, naming the flag: the tracers are made from it after the scene is read.
    request.tracer_options().map_err(any_as_flags)?;
    let loading = std::time::Instant::now();
    let loaded = super::stage::during("reading the scene", || request.load_scene())?;
    let load_time = loading.elapsed();
    let options = request.prepare_options(&loaded).map_err(any_as_flags)?;
    let farm = frames.mpi_frames.is_some();
    let session = if mpi || farm {
        Some(platoon::distributed::join()?)
    } else {
        None
    };
    let setup = Setup {
        request,
        started,
        load_time,
        image,
        scene: loaded,
        options,
        session,
        farm,
    };
    Ok((setup, out, frames))
}

/// Refuses an output the render could not write, before it starts.
pub(super) fn check_output(a: &RenderArgs) -> Result<()> {
    let format = platoon::core::output::check_image_path(&a.out)?;
    a.display.image(&a.out)?;
    if a.aov.is_some() && !matches!(format, platoon::core::output::ImageFormat::Exr) {
        bail!(
            "{}: AOVs are written as layers of an EXR: the output must end in .exr",
            a.out.display()
        );
    }
    Ok(())
}

/// `width` x `height` at `percent` (rounded, at least a pixel), as Blender's resolution %.
fn at_percent(width: u32, height: u32, percent: u32) -> Result<(u32, u32)> {
    if percent == 0 {
        bail!("--resolution-percent must be positive");
    }
    let scale = |v: u32| {
        let scaled = (v as u64 * percent as u64 + 50) / 100;
        // A zero stays zero: the request refuses it naming --width or --height.
        u32::try_from(if v == 0 { 0 } else { scaled.max(1) })
    };
    match (scale(width), scale(height)) {
        (Ok(w), Ok(h)) => Ok((w, h)),
        _ => bail!("--resolution-percent {percent}: {width}x{height} grows past what a size holds"),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_percentage_scales_both_sides_rounded() {
        assert_eq!(super::at_percent(1920, 1080, 25).unwrap(), (480, 270));
        assert_eq!(super::at_percent(512, 511, 100).unwrap(), (512, 511));
        assert_eq!(super::at_percent(3, 3, 10).unwrap(), (1, 1));
        assert_eq!(super::at_percent(100, 0, 50).unwrap(), (50, 0));
        assert!(super::at_percent(8, 8, 0).is_err());
        assert!(super::at_percent(u32::MAX, 8, 200).is_err());
    }
}

//! What makes an animation frame's image what it is, written into the frame's metadata as `job`
//! and read back by a rerun: a frame whose files hold its job is done (resume).

use std::fmt::Display;
use std::path::Path;
use std::time::UNIX_EPOCH;

use platoon::core::frame::FrameParams;
use platoon::{CameraChoice, EnvChoice, Request};

use super::args::FrameArgs;
use super::outputs::noisy_path;
use super::setup::Setup;

/// The settings of a job (the scene and environment files as they are now among them), said
/// as a person reads them.
pub(super) struct Job {
    settings: String,
    fps: f64,
    animated_seed: bool,
    /// A denoised frame's raw image is a file of the frame too (`NAME.noisy.EXT`).
    denoised: bool,
}

impl Job {
    pub(super) fn new(setup: &Setup, args: &FrameArgs) -> Job {
        let scene = match &setup.scene.source {
            Some(p) => file_stamp(p),
            None => "the built-in Cornell box".into(),
        };
        let o = &setup.options;
        let env = match &o.env {
            EnvChoice::Scene => "the scene's".to_string(),
            EnvChoice::File(p) => file_stamp(p),
            EnvChoice::Color(c) => format!("colour {},{},{}", c.x, c.y, c.z),
        };
        let env = format!("{env}{}", o.env_light.describe());
        let request = &setup.request;
        let camera = match &request.camera {
            CameraChoice::Given(c) => {
                let (p, f) = (c.position(), -c.camera_to_world.z_axis.truncate());
                format!(
                    "given at {},{},{} looking along {},{},{} over {} degrees",
                    p.x,
                    p.y,
                    p.z,
                    f.x,
                    f.y,
                    f.z,
                    c.yfov.to_degrees()
                )
            }
            _ => o
                .camera
                .map_or("the scene's".into(), |i| format!("number {i}")),
        };
        let aovs: Vec<&str> = request.aovs.iter().map(|a| a.name()).collect();
        let adaptive_min_spp = request
            .adaptive
            .map_or("none".into(), |a| or(a.min_spp, "its default"));
        // The request's options that change the image come from its table (a new one is part
        // of the job without a line here); the rest are the scene's, the camera's, the
        // method's and the outputs'.
        let settings = format!(
            "scene {scene} ({}); environment {env}; camera {camera}; {}{}; {}; adaptive min \
             spp {adaptive_min_spp}; {} fps; AOVs {}; view {}; EXR {}; {} bits, JPEG quality {}",
            request.load.describe(),
            platoon::request::options::image_settings(request).join(", "),
            if args.animated_seed {
                ", seed + frame"
            } else {
                ""
            },
            method(&request.method),
            args.fps,
            if aovs.is_empty() {
                "none".into()
            } else {
                aovs.join(",")
            },
            setup.image.view.describe(),
            setup.image.exr.describe(),
            setup.image.display.bits,
            setup.image.display.jpeg_quality,
        );
        Job {
            settings,
            fps: args.fps,
            animated_seed: args.animated_seed,
            denoised: request.denoiser.describe().is_some(),
        }
    }

    pub(super) fn of_frame(&self, frame: i64) -> String {
        format!("{}; frame {frame}", self.settings)
    }

    pub(super) fn time(&self, frame: i64) -> f32 {
        (frame as f64 / self.fps) as f32
    }

    /// Seconds from one frame to the next (what motion vectors measure over).
    pub(super) fn frame_interval(&self) -> f32 {
        (1.0 / self.fps) as f32
    }

    /// Whether `path` holds frame `frame` of this job, whole, and so does its raw image when
    /// the frame is denoised.
    pub(super) fn done(&self, path: &Path, frame: i64) -> bool {
        let want = self.of_frame(frame);
        let holds = |file: &Path| {
            platoon::core::output::read_metadata(file)
                .is_ok_and(|meta| meta.iter().any(|(k, v)| k == "platoon:job" && *v == want))
        };
        holds(path) && (!self.denoised || holds(&noisy_path(path)))
    }

    /// The frame's parameters: the request's, seen by `camera`, with its seed (plus the frame
    /// with an animated seed).
    pub(super) fn params(
        &self,
        request: &Request,
        frame: i64,
        camera: platoon::core::scene::camera::Camera,
    ) -> FrameParams {
        let mut params = request.frame_params(camera);
        if self.animated_seed {
            params.options.seed = params.options.seed.wrapping_add(frame as u32);
        }
        params
    }
}

/// The method as a person reads it, with every one of its settings (its kind's, by key):
/// frames of other settings are other images.
fn method(method: &platoon::core::Method) -> String {
    let settings: Vec<String> = method
        .settings()
        .0
        .iter()
        .map(|(key, value)| format!("{key} {value}"))
        .collect();
    format!("{} ({})", method.unit().describe(), settings.join(", "))
}

/// A file as a job names it: its whole path, and its size and modification time, which change
/// with its content (an environment map rewritten under the same name makes other frames).
fn file_stamp(p: &Path) -> String {
    let path = p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    let Ok(m) = std::fs::metadata(p) else {
        return path.display().to_string();
    };
    let modified = m
        .modified()
        .ok()
        .and_then(|t| t.duration_since(UNIX_EPOCH).ok())
        .map_or("at an unknown time".into(), |d| {
            format!("at {}.{:09} s", d.as_secs(), d.subsec_nanos())
        });
    format!(
        "{} ({} bytes, modified {modified})",
        path.display(),
        m.len()
    )
}

/// An optional setting: its value, or what stands in its place.
fn or<T: Display>(v: Option<T>, none: &str) -> String {
    v.map_or(none.to_string(), |v| v.to_string())
}

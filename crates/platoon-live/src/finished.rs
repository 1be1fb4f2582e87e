//! What the frame driver gives back for each frame: the film after it, the denoised image, the
//! camera and scene that render it again, and what it was and cost.

use std::sync::Arc;
use std::time::Duration;

use super::denoising::DenoiseStats;
use super::gi::GiStats;
use super::plan::FramePlan;
use super::UpdateTimes;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::{MethodReport, ReportValue};
use platoon_core::output::Film;
use platoon_core::scene::camera::Camera;
use platoon_schedule::renderer::{TracerFailure, TracerStats};

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
    /// What the frame taught the method, for a method that learns over frames (the path
    /// tracer's world cache and light reuse: `RenderMethod::learning`); its type is the
    /// method's (`learned`), its lines for a user `RenderMethod::report`'s.
    pub learned: Option<MethodReport>,
}

impl FrameStats {
    /// What the frame taught, as the method's type `T` (None: it learns nothing, or other
    /// things).
    pub fn learned<T: ReportValue>(&self) -> Option<T> {
        self.learned.as_ref()?.value::<T>()
    }

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
    /// The frame's camera, in render space (its scene's).
    pub camera: Camera,
    /// The generation the frame rendered, flattened, when [`DriverOptions::keep_frame_scenes`]
    /// asks.
    pub scene: Option<Arc<GpuScene>>,
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

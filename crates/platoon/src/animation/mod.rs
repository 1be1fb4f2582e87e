//! Animations rendered frame by frame: one scene carried from frame to frame by the
//! living-scene updater (skins re-posed, BVHs refitted rather than rebuilt, the tracers sent
//! only what changed), each frame posed and framed as a still render at its time would be.
//!
//! ```no_run
//! # fn main() -> anyhow::Result<()> {
//! use platoon::animation::{frame_path, Animation, FrameRange};
//! use platoon::core::frame::FrameParams;
//! use platoon::render::Tracers;
//!
//! let scene = platoon::load_scene(Some("CesiumMan.glb".as_ref()))?;
//! let mut animation = Animation::new(scene, &platoon::PrepareOptions::default())?;
//! let options = platoon::devices::tracer_options(
//!     &platoon::devices::DeviceSpec::Indices(vec![0]),
//!     false,
//!     platoon::tracer::Sampling::Mis,
//! )?;
//! let mut tracers = Tracers::new(&options, "cost-aware", animation.scene())?;
//! for frame in "1..48".parse::<FrameRange>().map_err(anyhow::Error::msg)?.frames() {
//!     let generation = animation.advance(frame as f32 / 24.0)?;
//!     tracers.apply_commit(&generation.commit, frame as u32)?;
//!     let params = FrameParams::new(256, 256, 64, animation.camera());
//!     let rendered = tracers.render(animation.scene(), &params, &mut |_| {})?;
//!     let out = frame_path("man_####.exr".as_ref(), frame);
//!     let meta = platoon::metadata_of(&animation.facts(), &params, &rendered, "mis");
//!     platoon::core::output::write_image(&out, &rendered.film, &meta)?;
//! }
//! # Ok(())
//! # }
//! ```

pub mod frames;

use anyhow::{bail, Result};
use platoon_core::flatten::GpuScene;
use platoon_core::scene::camera::Camera;
use platoon_core::scene::floating_origin::FloatingOrigin;
use platoon_core::Scene;
use platoon_live::{Edit, Generation, Refinement, StaticBuild, Updater, UpdaterOptions};

use crate::prepare::{camera_at, light};
use crate::{PrepareOptions, SceneFacts};

pub use frames::{frame_path, task_index, FrameRange};

/// A scene moving through its animation, with the camera of the current time.
pub struct Animation {
    updater: Updater,
    /// The camera and lens the frames use (`time` is the first frame's).
    options: PrepareOptions,
    camera: Camera,
    env_label: String,
    /// Set when platoon chose the lighting (the scene had none).
    pub note: Option<String>,
}

impl Animation {
    /// The scene lit and posed at `options.time`, as [`crate::prepare()`] would pose it, and
    /// flattened for the tracers ([`Animation::scene`]).
    pub fn new(mut scene: Scene, options: &PrepareOptions) -> Result<Animation> {
        let (env_label, note) = light(&mut scene, &options.env, &options.env_light)?;
        let time = finite(options.time)?;
        // Render space centred as prepare centres it: near the camera of the first frame.
        let mut origin = FloatingOrigin::default();
        origin.follow(
            camera_at(&scene, &scene.pose(time), options)?
                .position()
                .as_dvec3(),
        );
        // Big static geometry refined before the first frame: every frame the same whatever
        // the machine's speed (a game's pipeline refines it in the background instead).
        let updater_options = UpdaterOptions {
            merge_static: options.merge_static,
            static_build: StaticBuild {
                refinement: Refinement::Wait,
                ..Default::default()
            },
        };
        let updater = Updater::with_options(scene, time, origin.origin, updater_options)?;
        let posed = updater.scene().pose_around(time, updater.origin());
        let camera = camera_at(updater.scene(), &posed, options)?;
        Ok(Animation {
            updater,
            options: PrepareOptions {
                env: options.env.clone(),
                ..*options
            },
            camera,
            env_label,
            note,
        })
    }

    /// Moves the scene to animation time `time` (seconds): the generation whose commit brings
    /// tracers holding the previous one up to date.
    pub fn advance(&mut self, time: f32) -> Result<Generation> {
        let time = finite(time)?;
        self.updater.apply(Edit::Time(time))?;
        let posed = self
            .updater
            .scene()
            .pose_around(time, self.updater.origin());
        let camera = camera_at(self.updater.scene(), &posed, &self.options)?;
        let origin = self.updater.origin();
        self.updater
            .apply(Edit::FollowCamera(origin + camera.position().as_dvec3()))?;
        let generation = self.updater.update()?;
        self.camera = if generation.origin == origin {
            camera
        } else {
            let posed = self.updater.scene().pose_around(time, generation.origin);
            camera_at(self.updater.scene(), &posed, &self.options)?
        };
        self.options.time = time;
        Ok(generation)
    }

    /// The scene as flattened at the current time (what a new tracer uploads).
    pub fn scene(&self) -> &GpuScene {
        self.updater.flattened()
    }

    pub fn camera(&self) -> Camera {
        self.camera
    }

    /// The scene graph the animation moves (lit as prepared; posed at each frame's time).
    pub fn graph(&self) -> &Scene {
        self.updater.scene()
    }

    pub fn time(&self) -> f32 {
        self.options.time
    }

    /// What the metadata of a frame says of the scene.
    pub fn facts(&self) -> SceneFacts<'_> {
        SceneFacts {
            source: self.updater.scene().source.as_deref(),
            variant: self.updater.scene().variant.as_deref(),
            approximations: &self.updater.scene().approximations,
            features: self.updater.flattened().features,
            env_label: &self.env_label,
            origin: self.updater.origin(),
        }
    }
}

fn finite(time: f32) -> Result<f32> {
    if !time.is_finite() {
        bail!("an animation time must be a finite number of seconds, not {time}");
    }
    Ok(time)
}

//! The request's form: what it asks for, its defaults, and what it turns into for the layers
//! below (the preparation's options, the frame's parameters, the tracers' options).

use std::path::PathBuf;

use anyhow::Result;
use platoon_core::denoise::Denoiser;
use platoon_core::frame::adaptive::{Adaptive, Batching};
use platoon_core::frame::aov::Aov;
use platoon_core::frame::{FrameOptions, FrameParams, PathLoop, Region};
use platoon_core::scene::camera::Camera;
use platoon_core::scene::gltf_load::LoadOptions;
use platoon_core::scene::Scene;
use platoon_core::Method;
use platoon_tracer::{MemoryPath, Sampling, TracerOptions, Traversal};

use super::error::RequestError;
use crate::devices::DeviceSpec;
use crate::{EnvChoice, PrepareOptions};

/// Seconds from the frame before to a still (24 frames a second): what its motion vectors
/// measure over.
pub const DEFAULT_FRAME_INTERVAL: f32 = 1.0 / 24.0;

/// Where the scene comes from.
#[derive(Clone, Debug, Default)]
pub enum SceneSource {
    /// The built-in Cornell box.
    #[default]
    BuiltIn,
    /// A glTF file (.gltf or .glb), loaded with the request's `load` options.
    File(PathBuf),
    /// A scene the caller made (a generator, an edit of a loaded one).
    Scene(Box<Scene>),
}

/// Which camera renders.
#[derive(Clone, Debug)]
pub enum CameraChoice {
    /// The scene's camera of this index (None: its first; the scene framed from its bounds
    /// when it has none).
    Scene(Option<usize>),
    /// The scene's camera of this name (a glTF camera's name).
    Named(String),
    /// This camera, in world space.
    Given(Camera),
}

impl CameraChoice {
    /// The camera that renders, in render space: the scene's as posed (`posed`), or a given
    /// one moved by the prepared scene's floating `origin` (render space is centred on it).
    pub fn in_render_space(&self, posed: Camera, origin: glam::DVec3) -> Camera {
        match self {
            CameraChoice::Scene(_) | CameraChoice::Named(_) => posed,
            CameraChoice::Given(world) => {
                let mut c = *world;
                c.camera_to_world.w_axis -= origin.as_vec3().extend(0.0);
                c
            }
        }
    }
}

impl Default for CameraChoice {
    fn default() -> Self {
        CameraChoice::Scene(None)
    }
}

/// A render as a caller asks for it. `Default` is the built-in box, 512 x 512 at 64 samples on
/// Vulkan device 0, path traced.
#[derive(Clone, Debug)]
pub struct Request {
    pub scene: SceneSource,
    pub load: LoadOptions,
    /// The distant light (the scene's own by default).
    pub env: EnvChoice,
    /// The distant light's strength and rotation.
    pub env_light: crate::EnvLight,
    /// Animation time in seconds.
    pub time: f32,
    /// Seconds from the frame before to this one: what motion vectors measure over (an
    /// animation's 1 / fps; 1/24 by default).
    pub frame_interval: f32,
    pub camera: CameraChoice,
    /// Thin-lens aperture radius in scene units (0: a pinhole).
    pub aperture: f32,
    /// Distance to the plane in focus (None: the scene centre).
    pub focus_distance: Option<f32>,
    /// The image's size (the camera frames it; a crop renders a window of it).
    pub width: u32,
    pub height: u32,
    /// A border render: only this window of the image, whose pixels are the whole render's
    /// there (the output is the window's size).
    pub crop: Option<Region>,
    /// Samples per pixel (with a time limit, the most).
    pub spp: u32,
    /// The path loop every method's kernels run: its longest path in segments (`max_depth`,
    /// by default effectively unbounded), Russian roulette, clamp and light picking
    /// (`PathLoop`).
    pub path_loop: PathLoop,
    /// The options the frame takes as they are: the seed, the pixel filter, a transparent film (the
    /// environment the camera sees left out, an alpha channel: `Still::alpha`), the AO
    /// pass's distance, a time limit (one device only) (`FrameOptions`).
    pub frame: FrameOptions,
    /// The method and its options (the path tracer's kernel and resampled light among them:
    /// `method::path::PathTracing`).
    pub method: Method,
    pub sampling: Sampling,
    pub devices: DeviceSpec,
    /// How lines are split between devices (`platoon_core::balance::NAMES`).
    pub balancer: String,
    pub memory: MemoryPath,
    /// How each device's kernels find what a ray hits: platoon's own traversal or the device's
    /// ray queries (`--traversal`; refused on a device that offers none, naming it).
    pub traversal: Traversal,
    /// Device memory the scene may take on each device, in bytes: a scene over it (or over
    /// what the device has) is refused before upload, naming the device and the sizes.
    pub device_memory_limit: Option<u64>,
    /// The Khronos validation layer.
    pub validation: bool,
    /// AOVs rendered beside the beauty.
    pub aovs: Vec<Aov>,
    /// A denoiser run after assembly (biased).
    pub denoiser: Denoiser,
    pub adaptive: Option<Adaptive>,
}

impl Default for Request {
    fn default() -> Self {
        Request {
            scene: SceneSource::BuiltIn,
            load: LoadOptions::default(),
            env: EnvChoice::Scene,
            env_light: Default::default(),
            time: 0.0,
            frame_interval: DEFAULT_FRAME_INTERVAL,
            camera: CameraChoice::default(),
            aperture: 0.0,
            focus_distance: None,
            width: 512,
            height: 512,
            crop: None,
            spp: 64,
            path_loop: PathLoop::default(),
            frame: FrameOptions::default(),
            method: Method::path_tracing(),
            sampling: Sampling::Mis,
            devices: DeviceSpec::Auto,
            balancer: "cost-aware".into(),
            memory: MemoryPath::Auto,
            traversal: Traversal::Auto,
            device_memory_limit: None,
            validation: false,
            aovs: Vec::new(),
            denoiser: Denoiser::None,
            adaptive: None,
        }
    }
}

impl Request {
    /// The scene, loaded (a file) or as given.
    pub fn load_scene(&self) -> Result<Scene> {
        match &self.scene {
            SceneSource::BuiltIn => crate::load_scene_with(None, &self.load),
            SceneSource::File(path) => crate::load_scene_with(Some(path), &self.load),
            SceneSource::Scene(scene) => {
                crate::prepare::with_textures((**scene).clone(), &self.load)
            }
        }
    }

    /// How `scene` is posed and flattened (the scene's camera, found by index or name; a
    /// given one is placed after).
    pub fn prepare_options(&self, scene: &Scene) -> Result<PrepareOptions> {
        let camera = match &self.camera {
            CameraChoice::Scene(index) => *index,
            CameraChoice::Named(name) => Some(camera_named(scene, self.time, name)?),
            CameraChoice::Given(_) => None,
        };
        Ok(PrepareOptions {
            env: self.env.clone(),
            env_light: self.env_light,
            time: self.time,
            camera,
            aperture_radius: self.aperture,
            focus_distance: self.focus_distance,
            ..Default::default()
        })
    }

    /// The frame's parameters, seen by `camera` (in render space).
    pub fn frame_params(&self, camera: Camera) -> FrameParams {
        let mut params = FrameParams::new(self.width, self.height, self.spp, camera);
        if let Some(r) = self.crop {
            (params.width, params.height) = (r.width, r.height);
            params.crop = Some(r.crop_of(self.width, self.height));
        }
        params.options = self.frame;
        params.method = self.method.clone();
        params.path_loop = self.path_loop.clone();
        params
    }

    /// The batches of samples the outputs need: adaptive sampling, the variance AOV's.
    pub fn batching(&self) -> Batching {
        Batching {
            adaptive: self.adaptive,
            variance: self.aovs.contains(&Aov::Variance),
        }
    }

    /// One tracer's options per device of `devices`, each with the request's estimator,
    /// memory path and validation; refused where the devices cannot serve the request.
    pub fn tracer_options(&self) -> Result<Vec<TracerOptions>> {
        let mut tracers =
            crate::devices::tracer_options(&self.devices, self.validation, self.sampling)?;
        for t in &mut tracers {
            t.memory = self.memory;
            t.traversal = self.traversal;
            t.memory_limit = self.device_memory_limit;
        }
        self.validate_devices(tracers.len())?;
        Ok(tracers)
    }

    /// The camera that renders a scene prepared by `prepared` from this request.
    pub fn camera_in(&self, prepared: &crate::Prepared) -> Camera {
        self.camera
            .in_render_space(prepared.camera, prepared.posed.origin)
    }
}

/// The index (among the posed cameras `--camera` counts) of `scene`'s camera named `name`.
fn camera_named(scene: &Scene, time: f32, name: &str) -> Result<usize, RequestError> {
    let posed = scene.pose(time);
    let names: Vec<&str> = posed
        .cameras
        .iter()
        .map(|c| scene.cameras[c.camera].name.as_str())
        .collect();
    names
        .iter()
        .position(|n| *n == name)
        .ok_or_else(|| RequestError {
            option: "camera",
            problem: match names.is_empty() {
                true => format!("the scene has no cameras, so none named {name:?}"),
                false => format!(
                    "the scene has no camera named {name:?}; its cameras: {}",
                    names.join(", ")
                ),
            },
        })
}

//! The library API the `platoon` command is a thin layer over: load a scene (glTF or the
//! built-in Cornell box), choose its environment and camera, flatten it for the devices, render
//! a frame with a tracer and describe the result.

pub mod balance_bench;
pub mod bench;
pub mod devices;
pub mod plot;

use std::f32::consts::PI;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context as _, Result};
use glam::Vec3;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::renderer::Renderer;
use platoon_core::frame::{assemble, Band, FrameParams};
use platoon_core::output::Film;
use platoon_core::scene::camera::Camera;
use platoon_core::scene::environment::{EnvMap, Environment};
use platoon_core::scene::floating_origin::FloatingOrigin;
use platoon_core::scene::gltf_load::LoadOptions;
use platoon_core::scene::{Posed, Scene};
use platoon_tracer::{Tracer, TracerOptions};

pub use platoon_core as core;
pub use platoon_tracer as tracer;

/// The distant light of a render.
#[derive(Clone, Debug, Default)]
pub enum EnvChoice {
    /// The scene's own (none for glTF); a scene without any light gets [`DEFAULT_SKY`].
    #[default]
    Scene,
    File(PathBuf),
    Color(Vec3),
}

/// Radiance of the uniform sky given to scenes that have no light at all.
pub const DEFAULT_SKY: f32 = 1.0;

/// Loads a glTF scene (URIs confined to its folder), or the built-in Cornell box.
pub fn load_scene(path: Option<&Path>) -> Result<Scene> {
    load_scene_with(path, &LoadOptions::default())
}

pub fn load_scene_with(path: Option<&Path>, options: &LoadOptions) -> Result<Scene> {
    match path {
        None => Ok(platoon_core::scene::cornell::scene()),
        Some(p) => Ok(platoon_core::scene::gltf_load::load_with(p, options)?),
    }
}

/// A scene posed and flattened for the devices, with its camera.
pub struct Prepared {
    pub scene: Scene,
    pub posed: Posed,
    pub gpu: GpuScene,
    pub camera: Camera,
    /// Set when platoon chose the lighting (the scene had none).
    pub note: Option<String>,
    pub env_label: String,
    pub prepare_time: Duration,
}

pub struct PrepareOptions {
    pub env: EnvChoice,
    /// Animation time in seconds.
    pub time: f32,
    pub camera: Option<usize>,
    pub aperture_radius: f32,
    pub focus_distance: Option<f32>,
}

impl Default for PrepareOptions {
    fn default() -> Self {
        PrepareOptions {
            env: EnvChoice::Scene,
            time: 0.0,
            camera: None,
            aperture_radius: 0.0,
            focus_distance: None,
        }
    }
}

pub fn prepare(mut scene: Scene, options: &PrepareOptions) -> Result<Prepared> {
    let start = Instant::now();
    let mut note = None;
    let env_label;
    match &options.env {
        EnvChoice::File(path) => {
            scene.environment = Some(Environment::Map(EnvMap::load(path)?));
            env_label = path.display().to_string();
        }
        EnvChoice::Color(c) => {
            if c.min_element() < 0.0 || !c.is_finite() {
                bail!("--env-color must be three finite non-negative numbers");
            }
            scene.environment = Some(Environment::Constant(*c));
            env_label = format!("constant {},{},{}", c.x, c.y, c.z);
        }
        EnvChoice::Scene => env_label = "none".into(),
    }
    let lit = platoon_core::FeatureSet::of_scene(&scene);
    let env_label = if scene.environment.is_none()
        && !lit.emissive_triangles
        && !lit.punctual_lights
    {
        scene.environment = Some(Environment::Constant(Vec3::splat(DEFAULT_SKY)));
        note = Some(format!(
            "the scene has no lights: lighting it with a uniform white sky of radiance {DEFAULT_SKY} (use --env or --env-color to choose)"
        ));
        format!("default uniform sky {DEFAULT_SKY}")
    } else {
        env_label
    };
    let in_scene = |e: platoon_core::Error| match &scene.source {
        Some(path) => anyhow::anyhow!("{}: {e}", path.display()),
        None => anyhow::anyhow!("{e}"),
    };
    // Render space is centred near the camera (a floating origin), so a scene far from the
    // world origin keeps its precision; the first pose only finds where the camera is.
    let mut origin = FloatingOrigin::default();
    let mut posed = scene.pose(options.time);
    let camera = Camera::from_scene(&scene, &posed, options.camera).map_err(anyhow::Error::msg)?;
    if origin.follow(camera.position().as_dvec3()) {
        posed = scene.pose_around(options.time, origin.origin);
    }
    let mut camera =
        Camera::from_scene(&scene, &posed, options.camera).map_err(anyhow::Error::msg)?;
    if !camera.camera_to_world.is_finite() || !(f32::EPSILON..PI).contains(&camera.yfov) {
        return Err(in_scene(platoon_core::Error::Invalid(
            "the camera has a non-finite transform or a field of view outside (0, 180) degrees"
                .into(),
        )));
    }
    let gpu = GpuScene::build(&scene, &posed, scene.environment.as_ref()).map_err(in_scene)?;
    camera.aperture_radius = options.aperture_radius.max(0.0);
    if let Some(f) = options.focus_distance {
        if f.is_nan() || f <= 0.0 {
            bail!("--focus-distance must be positive");
        }
        camera.focus_distance = f;
    }
    Ok(Prepared {
        scene,
        posed,
        gpu,
        camera,
        note,
        env_label,
        prepare_time: start.elapsed(),
    })
}

/// A rendered frame and what it cost.
pub struct Rendered {
    pub film: Film,
    /// Samples per pixel reached (below `FrameParams::spp` when a time limit ended it).
    pub spp: u32,
    /// Time until the last band was done (the slowest tracer's time).
    pub wall_time: Duration,
    /// GPU time of all dispatches, summed over tracers.
    pub gpu_time: Duration,
    pub rays: u64,
    pub rejected_samples: u64,
    /// The devices, comma-separated.
    pub device: String,
    pub kernel_defines: Vec<&'static str>,
    /// Per-tracer statistics of a multi-device frame (empty for one device).
    pub tracers: Vec<platoon_core::frame::renderer::TracerStats>,
    pub balancer: Option<&'static str>,
    /// What the Khronos validation layer reported (with validation on).
    pub validation_messages: Vec<String>,
}

impl Rendered {
    pub fn rays(&self) -> u64 {
        self.rays
    }
    pub fn rejected_samples(&self) -> u64 {
        self.rejected_samples
    }
    pub fn gpu_time(&self) -> Duration {
        self.gpu_time
    }
}

/// Renders the frame on one tracer as the given bands (one band covering the frame is usual).
pub fn render_bands(
    tracer: &mut Tracer,
    params: &FrameParams,
    bands: &[(u32, u32)],
    progress: &mut dyn FnMut(u32),
) -> Result<Rendered> {
    let mut out: Vec<Band> = Vec::new();
    for &(y0, y1) in bands {
        out.push(
            tracer
                .render(params, y0, y1, progress)
                .context("render failed")?,
        );
    }
    Ok(Rendered {
        film: assemble(params, &out),
        spp: out
            .iter()
            .map(|b| b.spp(params))
            .min()
            .unwrap_or(params.spp),
        wall_time: out.iter().map(|b| b.wall_time).sum(),
        gpu_time: out.iter().map(|b| b.gpu_time).sum(),
        rays: out.iter().map(|b| b.rays).sum(),
        rejected_samples: out.iter().map(|b| b.rejected_samples).sum(),
        device: tracer.device_info().name.clone(),
        kernel_defines: tracer.kernel_defines(params),
        tracers: Vec::new(),
        balancer: None,
        validation_messages: tracer.validation_messages(),
    })
}

/// Renders a prepared scene on one device.
pub fn render(
    prepared: &Prepared,
    options: &TracerOptions,
    params: &FrameParams,
    progress: &mut dyn FnMut(u32),
) -> Result<Rendered> {
    let mut tracer = Tracer::new(options, &prepared.gpu)?;
    render_bands(&mut tracer, params, &[(0, params.height)], progress)
}

/// Renders one frame on a multi-device renderer.
pub fn render_frame(renderer: &mut Renderer<Tracer>, params: &FrameParams) -> Result<Rendered> {
    let frame = renderer.render_frame(params)?;
    for f in &frame.failures {
        eprintln!("warning: tracer {} failed in frame {} and was dropped; its lines were rendered by the others: {}", f.tracer, f.frame, f.message);
    }
    let names: Vec<String> = renderer
        .tracers_mut()
        .map(|t| t.device_info().name.clone())
        .collect();
    let defines = renderer
        .tracers_mut()
        .next()
        .map(|t| t.kernel_defines(params))
        .unwrap_or_default();
    Ok(Rendered {
        wall_time: frame
            .tracers
            .iter()
            .map(|t| t.wall_time)
            .max()
            .unwrap_or_default(),
        gpu_time: frame.tracers.iter().map(|t| t.gpu_time).sum(),
        rays: frame.tracers.iter().map(|t| t.rays).sum(),
        rejected_samples: frame.rejected_samples,
        device: names.join(", "),
        kernel_defines: defines,
        spp: params.spp,
        tracers: frame.tracers,
        balancer: Some(renderer.balancer_name()),
        validation_messages: renderer
            .tracers_mut()
            .flat_map(|t| t.validation_messages())
            .collect(),
        film: frame.film,
    })
}

/// The metadata written into EXR outputs.
pub fn metadata(
    prepared: &Prepared,
    params: &FrameParams,
    rendered: &Rendered,
    sampling: &str,
) -> Vec<(String, String)> {
    let features = prepared.gpu.features.with_render_options(params);
    let source = prepared
        .scene
        .source
        .as_ref()
        .map(|p| p.display().to_string())
        .unwrap_or_else(|| "built-in Cornell box".into());
    vec![
        ("scene".into(), source),
        ("spp".into(), rendered.spp.to_string()),
        (
            "time_limit_s".into(),
            params
                .time_limit
                .map(|t| format!("{:.3}", t.as_secs_f64()))
                .unwrap_or_else(|| "none".into()),
        ),
        ("width".into(), params.width.to_string()),
        ("height".into(), params.height.to_string()),
        ("seed".into(), params.seed.to_string()),
        ("frame".into(), params.frame.to_string()),
        ("max_depth".into(), params.max_depth.to_string()),
        ("russian_roulette_depth".into(), params.rr_depth.to_string()),
        (
            "render_time_s".into(),
            format!("{:.3}", rendered.wall_time.as_secs_f64()),
        ),
        (
            "gpu_time_s".into(),
            format!("{:.3}", rendered.gpu_time().as_secs_f64()),
        ),
        ("device".into(), rendered.device.clone()),
        (
            "balancer".into(),
            rendered.balancer.unwrap_or("single device").into(),
        ),
        ("features".into(), features.to_string()),
        ("kernel_defines".into(), rendered.kernel_defines.join(",")),
        ("sampling".into(), sampling.into()),
        ("environment".into(), prepared.env_label.clone()),
        (
            "render_origin".into(),
            format!(
                "{},{},{}",
                prepared.posed.origin.x, prepared.posed.origin.y, prepared.posed.origin.z
            ),
        ),
        (
            "rejected_samples".into(),
            rendered.rejected_samples().to_string(),
        ),
        ("approximations".into(), approximations(params)),
    ]
}

/// Every approximation in effect, so a reader of the image knows what it is not.
pub fn approximations(params: &FrameParams) -> String {
    let mut a = vec!["roughness<0.01 rendered as perfectly specular".to_string()];
    if params.max_depth < platoon_core::frame::DEFAULT_MAX_DEPTH {
        a.push(format!("path depth capped at {}", params.max_depth));
    }
    a.join("; ")
}

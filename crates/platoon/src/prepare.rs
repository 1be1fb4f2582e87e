//! Loading a scene (glTF or the built-in Cornell box), choosing its distant light and camera,
//! and flattening it for the devices.

use std::f32::consts::PI;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Result};
use glam::Vec3;
use platoon_core::flatten::static_merge::StaticMerge;
use platoon_core::flatten::GpuScene;
use platoon_core::scene::camera::Camera;
use platoon_core::scene::environment::{EnvMap, Environment};
use platoon_core::scene::floating_origin::FloatingOrigin;
use platoon_core::scene::gltf_load::LoadOptions;
use platoon_core::scene::{Posed, Scene};

/// The distant light of a render.
#[derive(Clone, Debug, Default)]
pub enum EnvChoice {
    /// The scene's own (none for glTF); a scene without any light gets [`DEFAULT_SKY`].
    #[default]
    Scene,
    File(PathBuf),
    Color(Vec3),
}

/// How the distant light is set: its strength (a factor on its radiance) and the map's
/// rotation about +Y in degrees (`EnvMap::rotate`), as Cycles' world strength and mapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvLight {
    pub strength: f32,
    pub rotation: f32,
}

impl Default for EnvLight {
    fn default() -> Self {
        EnvLight {
            strength: 1.0,
            rotation: 0.0,
        }
    }
}

impl EnvLight {
    /// What is wrong with it, if anything: the option (`env_strength`, `env_rotation`) and
    /// the problem.
    pub fn check(&self) -> std::result::Result<(), (&'static str, String)> {
        if !(self.strength.is_finite() && self.strength >= 0.0) {
            let problem = format!("must be a finite number >= 0, not {}", self.strength);
            return Err(("env_strength", problem));
        }
        if !self.rotation.is_finite() {
            let problem = format!("must be a finite number of degrees, not {}", self.rotation);
            return Err(("env_rotation", problem));
        }
        Ok(())
    }

    /// What differs from a plain light (", strength 2, rotated 90 degrees"; empty when nothing).
    pub fn describe(&self) -> String {
        let mut s = String::new();
        if self.strength != 1.0 {
            s += &format!(", strength {}", self.strength);
        }
        if self.rotation != 0.0 {
            s += &format!(", rotated {} degrees", self.rotation);
        }
        s
    }
}

/// Radiance of the uniform sky given to scenes that have no light at all.
pub const DEFAULT_SKY: f32 = 1.0;

/// Loads a glTF scene (URIs confined to its folder), or the built-in Cornell box.
pub fn load_scene(path: Option<&Path>) -> Result<Scene> {
    load_scene_with(path, &LoadOptions::default())
}

pub fn load_scene_with(path: Option<&Path>, options: &LoadOptions) -> Result<Scene> {
    match path {
        None if options.variant.is_some() => {
            bail!("the built-in Cornell box has no material variants (a variant needs a glTF file)")
        }
        None => with_textures(platoon_core::scene::cornell::scene(), options),
        Some(p) => with_textures(
            platoon_core::scene::gltf_load::load_with(p, options)?,
            options,
        ),
    }
}

/// `scene` with the textures `options` ask for (mip maps, a budget).
pub fn with_textures(mut scene: Scene, options: &LoadOptions) -> Result<Scene> {
    options.textures.apply(&mut scene)?;
    Ok(scene)
}

/// A scene posed and flattened for the devices, with its camera.
pub struct Prepared {
    pub scene: Scene,
    /// The scene posed, an instance per node (`gpu` has the objects that never move merged).
    pub posed: Posed,
    pub gpu: GpuScene,
    pub camera: Camera,
    /// Set when platoon chose the lighting (the scene had none).
    pub note: Option<String>,
    pub env_label: String,
    pub prepare_time: Duration,
    /// The animation time it was posed at.
    pub time: f32,
}

#[derive(Clone, Debug)]
pub struct PrepareOptions {
    pub env: EnvChoice,
    /// The distant light's strength and rotation.
    pub env_light: EnvLight,
    /// Animation time in seconds.
    pub time: f32,
    pub camera: Option<usize>,
    pub aperture_radius: f32,
    pub focus_distance: Option<f32>,
    /// Merge the objects that never move into one bottom level
    /// (`platoon_core::flatten::static_merge`); off keeps an instance per node.
    pub merge_static: bool,
}

impl Default for PrepareOptions {
    fn default() -> Self {
        PrepareOptions {
            env: EnvChoice::Scene,
            env_light: EnvLight::default(),
            time: 0.0,
            camera: None,
            aperture_radius: 0.0,
            focus_distance: None,
            merge_static: true,
        }
    }
}

pub fn prepare(mut scene: Scene, options: &PrepareOptions) -> Result<Prepared> {
    let start = Instant::now();
    let (env_label, note) = light(&mut scene, &options.env, &options.env_light)?;
    // Render space is centred near the camera (a floating origin), so a scene far from the
    // world origin keeps its precision; the first pose only finds where the camera is.
    if !options.time.is_finite() {
        bail!(
            "--time must be a finite number of seconds, not {}",
            options.time
        );
    }
    let mut origin = FloatingOrigin::default();
    let mut posed = scene.pose(options.time);
    let camera = Camera::from_scene(&scene, &posed, options.camera).map_err(anyhow::Error::msg)?;
    if origin.follow(camera.position().as_dvec3()) {
        posed = scene.pose_around(options.time, origin.origin);
    }
    let camera = camera_at(&scene, &posed, options)?;
    let mut merge = if options.merge_static {
        StaticMerge::of_scene(&scene)
    } else {
        StaticMerge::none()
    };
    let levels = merge.apply(&scene, posed.clone());
    let gpu = GpuScene::build(&scene, &levels, scene.environment.as_ref())
        .map_err(|e| in_scene(&scene, e))?;
    Ok(Prepared {
        scene,
        posed,
        gpu,
        camera,
        note,
        env_label,
        prepare_time: start.elapsed(),
        time: options.time,
    })
}

/// Gives `scene` the distant light `env` chooses (a uniform sky when it has no light at all):
/// the label the metadata gives it, and a note when platoon chose it.
pub fn light(
    scene: &mut Scene,
    env: &EnvChoice,
    env_light: &EnvLight,
) -> Result<(String, Option<String>)> {
    if let Err((option, problem)) = env_light.check() {
        bail!("{option}: {problem}");
    }
    let env_label = match env {
        EnvChoice::File(path) => {
            let mut map = EnvMap::load(path)?;
            map.rotate(env_light.rotation);
            if env_light.strength != 1.0 {
                for t in &mut map.texels {
                    *t = t.map(|c| c * env_light.strength);
                }
            }
            scene.environment = Some(Environment::Map(map));
            format!("{}{}", path.display(), env_light.describe())
        }
        EnvChoice::Color(c) => {
            if c.min_element() < 0.0 || !c.is_finite() {
                bail!("--env-color must be three finite non-negative numbers");
            }
            scene.environment = Some(Environment::Constant(*c * env_light.strength));
            format!("constant {},{},{}{}", c.x, c.y, c.z, env_light.describe())
        }
        EnvChoice::Scene => "none".into(),
    };
    let lit = platoon_core::SceneFeatures::of_scene(scene);
    if scene.environment.is_none() && !lit.emissive_triangles && !lit.punctual_lights {
        scene.environment = Some(Environment::Constant(Vec3::splat(DEFAULT_SKY)));
        let note = format!(
            "the scene has no lights: lighting it with a uniform white sky of radiance {DEFAULT_SKY} (use --env or --env-color to choose)"
        );
        return Ok((format!("default uniform sky {DEFAULT_SKY}"), Some(note)));
    }
    Ok((env_label, None))
}

/// The camera `options` choose in the scene posed as `posed`, with their lens, checked.
pub fn camera_at(scene: &Scene, posed: &Posed, options: &PrepareOptions) -> Result<Camera> {
    let mut camera =
        Camera::from_scene(scene, posed, options.camera).map_err(anyhow::Error::msg)?;
    let view_ok = camera.orthographic.is_some() || (f32::EPSILON..PI).contains(&camera.yfov);
    if !camera.camera_to_world.is_finite() || !view_ok {
        return Err(in_scene(
            scene,
            platoon_core::Error::Invalid(
                "the camera has a non-finite transform or a field of view outside (0, 180) degrees"
                    .into(),
            ),
        ));
    }
    camera.aperture_radius = options.aperture_radius.max(0.0);
    if let Some(f) = options.focus_distance {
        if f.is_nan() || f <= 0.0 {
            bail!("--focus-distance must be positive");
        }
        camera.focus_distance = f;
    }
    Ok(camera)
}

/// An error of the scene, naming its file.
fn in_scene(scene: &Scene, e: platoon_core::Error) -> anyhow::Error {
    match &scene.source {
        Some(path) => anyhow::anyhow!("{}: {e}", path.display()),
        None => anyhow::anyhow!("{e}"),
    }
}

//! platoon in a Bevy app: [`PlatoonPlugin`] mirrors the world (meshes with a
//! `StandardMaterial`, their transforms, skins, point, spot and directional lights, the 3D
//! camera) into a platoon living scene, path traces it on every Vulkan device on a thread of
//! its own, and shows the newest frame in an `Image` ([`PlatoonOutput`]).
//!
//! ```no_run
//! use bevy::prelude::*;
//! use platoon_bevy::{PlatoonOutput, PlatoonPlugin, PlatoonSettings};
//!
//! fn main() {
//!     App::new()
//!         .add_plugins(DefaultPlugins)
//!         .insert_resource(PlatoonSettings::new(640, 360))
//!         .add_plugins(PlatoonPlugin)
//!         .add_systems(Startup, |mut commands: Commands, output: Res<PlatoonOutput>| {
//!             // The path-traced frame on screen: a sprite of the plugin's image.
//!             commands.spawn(Sprite::from_image(output.image.clone()));
//!         })
//!         .run();
//! }
//! ```
//!
//! What is mirrored and what is not: docs/BEVY.md.

mod convert;
mod environment;
mod mirror;
mod render_thread;
mod warnings;

use std::path::Path;
use std::sync::Arc;

use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::VisibilitySystems;
use bevy::image::Image;
use bevy::light::EnvironmentMapLight;
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, TextureDimension, TextureFormat};
use bevy::transform::TransformSystems;
use platoon::core::output::Film;
use platoon::drive::DriverOptions;
use platoon::game::GameOptions;
use platoon::prepare::EnvChoice;

use mirror::{AssetChanges, Change, Mirror, WorldView};
use render_thread::{RenderThread, ThreadOptions, Update};

pub use platoon;

/// How the plugin renders (a resource; changing it restarts the render thread).
#[derive(Resource, Clone, Debug)]
pub struct PlatoonSettings {
    /// The frame driver's options: image size, samples per frame or a frame-time budget
    /// (`driver.target`), depth, method, denoiser; and the devices, balancer and updater.
    pub game: GameOptions,
    /// The distant light: the default (`EnvChoice::Scene`) lights a world without lights by a
    /// uniform sky, as platoon does a file without lights.
    pub environment: EnvChoice,
    /// Stop adding samples to a still view once it has this many a pixel (None: keep
    /// converging while the app runs). With it, any change restarts the film, as an editor's
    /// viewport does (`driver.restart_on_change`); without it, moving objects blend into the
    /// history, as a game's frames do.
    pub converge_at: Option<u32>,
}

impl PlatoonSettings {
    /// A `width` x `height` image on every Vulkan device, one sample a pixel a frame.
    pub fn new(width: u32, height: u32) -> PlatoonSettings {
        PlatoonSettings {
            game: GameOptions::new(DriverOptions::new(width, height)),
            environment: EnvChoice::Scene,
            converge_at: None,
        }
    }
}

impl Default for PlatoonSettings {
    fn default() -> Self {
        PlatoonSettings::new(640, 360)
    }
}

/// What the path tracer did since its render thread (re)started (a resource, updated as
/// frames arrive).
#[derive(Resource, Clone, Debug, Default)]
pub struct PlatoonStats {
    /// Frames finished since the render thread started.
    pub frames: u64,
    /// Samples a pixel of the frame last rendered, and behind the film shown (None while
    /// objects move and frames blend).
    pub spp: u32,
    pub film_samples: Option<u32>,
    /// The last frame's render-thread time, in milliseconds.
    pub frame_ms: f64,
    /// Whether the film shown is the still view's final one: `converge_at` samples a pixel of
    /// the world as the game last changed it (the render thread then rests).
    pub converged: bool,
    /// The devices' idle share of the last frame.
    pub idle: f64,
    /// Times the scene was built anew (the first time, then whenever its structure changed in
    /// a way an edit cannot carry), and the build the frame shown rendered: equal once the
    /// render thread has caught up with the newest.
    pub rebuilds: u64,
    pub build: u64,
    /// What the mirror could not carry over, each said once.
    pub warnings: Vec<String>,
    /// The render thread's errors (it stops at the first that is not an edit refused).
    pub errors: Vec<String>,
}

/// The newest frame: an sRGB image to show, and the linear film behind it.
#[derive(Resource, Clone)]
pub struct PlatoonOutput {
    pub image: Handle<Image>,
    /// The film shown (the denoised one when the driver denoises), linear radiance.
    pub film: Option<Arc<Film>>,
}

impl PlatoonOutput {
    /// Writes the film shown (EXR, PNG, ... by the extension; nothing yet: an error).
    pub fn write(&self, path: &Path) -> anyhow::Result<()> {
        let film = self
            .film
            .as_ref()
            .ok_or_else(|| anyhow::anyhow!("no frame has finished yet"))?;
        platoon::core::output::write_image(path, film, &[])?;
        Ok(())
    }
}

/// Marks the camera platoon renders from, active or not (an app that shows only platoon's
/// image keeps its 3D camera inactive, so that Bevy's rasteriser does not draw it too).
/// Without one: the active 3D camera drawn last.
#[derive(Component, Clone, Copy, Debug, Default)]
pub struct PlatoonCamera;

/// The platoon scene last built from the world (before the edits since): what the render
/// thread started from, for a game's own use (CPU ray queries, saving it, comparing renders).
#[derive(Resource, Clone, Default)]
pub struct PlatoonScene(pub Option<Arc<platoon::core::scene::Scene>>);

/// Mirrors the world into platoon and shows its frames (see the crate's documentation).
pub struct PlatoonPlugin;

impl Plugin for PlatoonPlugin {
    fn build(&self, app: &mut App) {
        app.init_resource::<PlatoonSettings>()
            .init_resource::<PlatoonStats>()
            .init_resource::<PlatoonScene>()
            .init_resource::<PluginState>()
            .add_systems(PreStartup, create_output)
            .add_systems(
                PostUpdate,
                (follow_world, show_frame)
                    .chain()
                    .after(TransformSystems::Propagate)
                    .after(VisibilitySystems::VisibilityPropagate),
            );
    }
}

/// The plugin's own state: the mirror and the render thread (both new when settings change).
#[derive(Resource, Default)]
struct PluginState {
    mirror: Mirror,
    thread: Option<RenderThread>,
    /// Updates sent (each a change: the render thread hears nothing from a still world), and
    /// the camera of the last.
    sent: u64,
    camera: Option<platoon::core::scene::camera::Camera>,
}

fn create_output(
    mut commands: Commands,
    mut images: ResMut<Assets<Image>>,
    settings: Res<PlatoonSettings>,
) {
    let o = &settings.game.driver;
    let image = images.add(blank(o.width, o.height));
    commands.insert_resource(PlatoonOutput { image, film: None });
}

fn blank(width: u32, height: u32) -> Image {
    Image::new_fill(
        Extent3d {
            width: width.max(1),
            height: height.max(1),
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        &[0, 0, 0, 255],
        TextureFormat::Rgba8UnormSrgb,
        RenderAssetUsages::default(),
    )
}

/// A 3D camera's components the plugin reads.
type CameraItem = (
    &'static Camera,
    &'static GlobalTransform,
    &'static Projection,
    Has<PlatoonCamera>,
    Option<&'static EnvironmentMapLight>,
);

/// Sends the render thread what changed in the world this frame and the camera.
fn follow_world(
    mut state: ResMut<PluginState>,
    settings: Res<PlatoonSettings>,
    view: WorldView,
    cameras: Query<CameraItem, With<Camera3d>>,
    mut changes: AssetChanges,
    mut stats: ResMut<PlatoonStats>,
    mut built: ResMut<PlatoonScene>,
) {
    let state = &mut *state;
    if settings.is_changed() || state.thread.is_none() {
        // A new thread on a scene built whole.
        let mut game = settings.game.clone();
        // A still view converges to exact sums only if a change restarts the film.
        game.driver.restart_on_change |= settings.converge_at.is_some();
        state.thread = Some(RenderThread::start(ThreadOptions {
            game,
            environment: settings.environment.clone(),
            converge_at: settings.converge_at,
        }));
        state.mirror = Mirror::default();
        state.sent = 0;
        state.camera = None;
        *stats = PlatoonStats::default();
    }
    let (modified, meshes_modified) = changes.take();
    // The marked camera, else the active 3D camera drawn last (the one the player sees).
    let marked = cameras.iter().find(|(.., marked, _)| *marked);
    let Some((_, transform, projection, _, env_light)) = marked.or_else(|| {
        cameras
            .iter()
            .filter(|(c, ..)| c.is_active)
            .max_by_key(|(c, ..)| c.order)
    }) else {
        return;
    };
    let o = &settings.game.driver;
    let camera = convert::camera(transform, projection, o.width, o.height);
    // The camera's environment map light is the distant light unless the settings choose one.
    let environment = env_light
        .filter(|_| matches!(settings.environment, EnvChoice::Scene))
        .map(|e| (e.specular_map.id(), e.intensity, e.rotation));
    let (scene, edits) = match state
        .mirror
        .follow(&view, &modified, &meshes_modified, environment)
    {
        Change::Rebuilt(scene) => {
            stats.rebuilds += 1;
            built.0 = Some(Arc::new((*scene).clone()));
            (Some(scene), Vec::new())
        }
        Change::Edits(edits) => (None, edits),
    };
    stats.warnings.extend(state.mirror.warnings.take_fresh());
    if scene.is_none() && edits.is_empty() && state.camera == Some(camera) {
        return;
    }
    state.sent += 1;
    state.camera = Some(camera);
    if let Some(thread) = &state.thread {
        thread.send(Update {
            seq: state.sent,
            scene,
            edits,
            camera,
        });
    }
}

/// Shows the render thread's newest frame, if a new one finished.
fn show_frame(
    state: Res<PluginState>,
    mut output: ResMut<PlatoonOutput>,
    mut images: ResMut<Assets<Image>>,
    mut stats: ResMut<PlatoonStats>,
) {
    let Some(thread) = &state.thread else { return };
    let (done, frames, build, errors) = {
        let mut o = thread.outbox.lock().expect("never poisoned");
        stats.converged = o.settled && o.seq == state.sent;
        (
            o.newest.take(),
            o.frames,
            o.build,
            std::mem::take(&mut o.errors),
        )
    };
    for e in &errors {
        error!("platoon: {e}");
    }
    stats.errors.extend(errors);
    let Some(done) = done else { return };
    let s = &done.stats;
    stats.frames = frames;
    stats.build = build;
    stats.spp = s.plan.spp;
    stats.film_samples = s.film_samples;
    stats.frame_ms = s.busy.as_secs_f64() * 1e3;
    stats.idle = s.idle_fraction;
    let done = *done;
    let film = done.denoised.unwrap_or(done.film);
    if let Some(mut image) = images.get_mut(&output.image) {
        *image = shown(&film);
    }
    output.film = Some(Arc::new(film));
}

/// A film as an 8-bit sRGB image (platoon's default view, as its PNGs).
fn shown(film: &Film) -> Image {
    let mut image = blank(film.width, film.height);
    let rgb = film.srgb8();
    let rgba: Vec<u8> = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    image.data = Some(rgba);
    image
}

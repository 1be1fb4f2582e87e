//! `platoon bench realtime` (issue 43): a game's image at its frame budget, technique by
//! technique, against converged renders of the same frames. The game loop (platoon's frame
//! driver, its frame time held by the workload scaler) plays a scripted scene: the many-light
//! hall by default with CesiumMan walking in it, the camera gliding sideways, each frame at its
//! own animation time (a fixed step, not the wall clock, so that every technique plays the same
//! frames). The last frames are measured: what the game shows (the denoised frame where a
//! denoiser runs, else the film) against a still render of that frame's scene and camera at many
//! samples, by relative MSE and LDR-FLIP (`tradeoff::metrics`).

use std::collections::HashMap;
use std::path::PathBuf;

use anyhow::{bail, Context as _, Result};
use glam::{DVec3, Mat4};
use platoon::devices::{create_tracers, DeviceSpec};
use platoon_core::denoise::Denoiser;
use platoon_core::frame::FrameParams;
use platoon_core::measure::median;
use platoon_core::method::path::ResampledLight;
use platoon_core::output::Film;
use platoon_core::scene::camera::Camera;
use platoon_core::scene::{Placement, Scene};
use platoon_live::{DriverOptions, Edit, FinishedFrame, Updater, REALTIME_CANDIDATES};
use platoon_schedule::renderer::Renderer;
use platoon_tracer::Sampling;

use crate::tradeoff::metrics;

/// What the game renders with: path tracing with NEE by power and MIS, and platoon's real-time
/// techniques on top, alone and together (named by their parts joined with `+`: `plain`,
/// `atrous`, `resampled+world-cache+atrous`...).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Technique {
    /// Resampled direct light over a game's [`REALTIME_CANDIDATES`] lights.
    pub resampled: bool,
    /// ... reusing the previous frame's reservoirs around each pixel (ReSTIR DI's temporal and
    /// spatial reuse, unbiased; implies `resampled`).
    pub reuse: bool,
    /// The world cache for the bounces after the first (default settings).
    pub world_cache: bool,
    /// The à-trous denoiser over the reprojected history.
    pub atrous: bool,
}

/// The parts' names, in the order a name lists them.
const PARTS: [&str; 4] = ["resampled", "reuse", "world-cache", "atrous"];

impl Technique {
    pub const PLAIN: Technique = Technique {
        resampled: false,
        reuse: false,
        world_cache: false,
        atrous: false,
    };
    pub const ATROUS: Technique = Technique {
        atrous: true,
        ..Technique::PLAIN
    };
    pub const RESAMPLED: Technique = Technique {
        resampled: true,
        ..Technique::PLAIN
    };
    pub const WORLD_CACHE: Technique = Technique {
        world_cache: true,
        ..Technique::PLAIN
    };
    pub const RESAMPLED_ATROUS: Technique = Technique {
        resampled: true,
        atrous: true,
        ..Technique::PLAIN
    };
    pub const ALL_ON: Technique = Technique {
        resampled: true,
        reuse: false,
        world_cache: true,
        atrous: true,
    };
    pub const REUSE: Technique = Technique {
        resampled: true,
        reuse: true,
        ..Technique::PLAIN
    };
    pub const REUSE_ATROUS: Technique = Technique {
        atrous: true,
        ..Technique::REUSE
    };
    pub const REUSE_ALL_ON: Technique = Technique {
        reuse: true,
        ..Technique::ALL_ON
    };
    /// The bench's default list: plain first (what the others are compared with).
    pub const DEFAULT: [Technique; 9] = [
        Technique::PLAIN,
        Technique::ATROUS,
        Technique::RESAMPLED,
        Technique::REUSE,
        Technique::WORLD_CACHE,
        Technique::RESAMPLED_ATROUS,
        Technique::REUSE_ATROUS,
        Technique::ALL_ON,
        Technique::REUSE_ALL_ON,
    ];

    /// The parts a name lists (reuse stands for resampling too).
    fn parts(self) -> [bool; 4] {
        [
            self.resampled && !self.reuse,
            self.reuse,
            self.world_cache,
            self.atrous,
        ]
    }

    pub fn name(self) -> String {
        let on: Vec<&str> = PARTS
            .iter()
            .zip(self.parts())
            .filter(|p| p.1)
            .map(|p| *p.0)
            .collect();
        if on.is_empty() {
            "plain".into()
        } else {
            on.join("+")
        }
    }

    pub fn parse(s: &str) -> Result<Technique> {
        if s == "plain" {
            return Ok(Technique::PLAIN);
        }
        let mut t = Technique::PLAIN;
        for part in s.split('+') {
            match part {
                "resampled" => t.resampled = true,
                "reuse" => (t.resampled, t.reuse) = (true, true),
                "world-cache" => t.world_cache = true,
                "atrous" => t.atrous = true,
                _ => bail!(
                    "unknown technique {s:?}: plain, or parts of {} joined by +",
                    PARTS.join(", ")
                ),
            }
        }
        Ok(t)
    }

    fn apply(self, driver: &mut DriverOptions) {
        if self.atrous {
            driver.denoise = Denoiser::Atrous;
        }
        let path = driver
            .method
            .path_mut()
            .expect("the bench renders by path tracing");
        if self.resampled {
            path.resampled_light = Some(ResampledLight::new(REALTIME_CANDIDATES));
        }
        if self.reuse {
            path.learning.light_reuse = Some(Default::default());
        }
        if self.world_cache {
            path.learning.world_cache = Some(Default::default());
        }
    }
}

/// The bench's settings.
#[derive(Clone, Debug)]
pub struct Options {
    pub scene: BenchScene,
    /// A skinned, animated glTF walking in the scene; None: none.
    pub character: Option<PathBuf>,
    pub width: u32,
    pub height: u32,
    /// The frame time the game holds.
    pub target_ms: f64,
    /// Frames played; the last `measured` are measured.
    pub frames: u32,
    pub measured: u32,
    /// Samples per pixel of each measured frame's reference.
    pub reference_spp: u32,
    pub devices: String,
    pub techniques: Vec<Technique>,
    /// How far the camera glides sideways a frame, in scene units.
    pub camera_step: f32,
    /// Each technique plays this many times, with other random numbers (seeds 0, 1...): two
    /// or more measure its bias.
    pub repeat: u32,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            scene: BenchScene::Hall,
            character: Some(crate::shared::path("scenes/CesiumMan.glb")),
            width: 160,
            height: 90,
            target_ms: 100.0,
            frames: 24,
            measured: 4,
            reference_spp: 256,
            devices: "auto".into(),
            techniques: Technique::DEFAULT.to_vec(),
            camera_step: 0.03,
            repeat: 2,
        }
    }
}

/// One technique's measure.
#[derive(Clone, Debug)]
pub struct Row {
    pub technique: Technique,
    pub frame_ms_median: f64,
    pub spp_median: f64,
    /// Over the measured frames' pixels and channels (and the plays).
    pub relmse: f64,
    pub flip: f64,
    /// The relative squared bias (`metrics::relative_squared_bias` over the plays, averaged
    /// over the measured frames): what is left of `relmse` once the noise is averaged away,
    /// the reference's own noise included; None with one play.
    pub bias: Option<f64>,
}

/// Animation time of frame `f`: a fixed step of the target frame time.
fn time_of(o: &Options, f: u32) -> f32 {
    f as f32 * (o.target_ms * 1e-3) as f32
}

/// The scene a bench plays.
#[derive(Clone, Debug, PartialEq)]
pub enum BenchScene {
    /// The many-light hall (`platoon-scenegen --many-lights`).
    Hall,
    /// The built-in Cornell box.
    Cornell,
    /// CesiumMan's walk (the character, not appended again): the character walking its
    /// animation on a ground under a sky and a low sun, as the game's world has.
    Walk,
    /// A glTF file.
    File(PathBuf),
}

impl BenchScene {
    /// `hall`, `cornell`, or a glTF file's path.
    pub fn parse(s: &str) -> BenchScene {
        match s {
            "hall" => BenchScene::Hall,
            "cornell" => BenchScene::Cornell,
            "walk" => BenchScene::Walk,
            path => BenchScene::File(path.into()),
        }
    }
}

/// The scene the bench plays and the camera path's start.
pub fn scene(o: &Options) -> Result<(Scene, Camera)> {
    if o.scene == BenchScene::Walk {
        return walk(o);
    }
    let mut scene = match &o.scene {
        BenchScene::Walk => unreachable!("played above"),
        BenchScene::File(path) => platoon::load_scene(Some(path))?,
        BenchScene::Cornell => platoon::load_scene(None)?,
        BenchScene::Hall => {
            crate::generated::load(&platoon_scenegen::many_lights::many_lights(), "many-lights")?
        }
    };
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None)
        .map_err(|e| anyhow::anyhow!("the camera path's start: {e}"))?;
    if let Some(path) = &o.character {
        let character = platoon::load_scene(Some(path))
            .with_context(|| format!("{}: the walking character", path.display()))?;
        // On the floor (the scene's lowest point), ahead of the camera: three units, or half
        // the way to the scene's centre in a smaller one; at most 0.6 of the scene's height.
        let (lo, hi) = scene.pose(0.0).bounds();
        let (clo, chi) = character.pose(0.0).bounds();
        let centre = (lo + hi) * 0.5;
        let reach = (0.5 * (centre - camera.position()).length()).min(3.0);
        let ahead = camera.position() + camera.basis(1, 1).forward * reach;
        let scale = (0.6 * (hi.y - lo.y) / (chi.y - clo.y).max(1e-6)).min(1.0);
        let placement = Placement {
            translation: DVec3::new(ahead.x as f64, lo.y as f64, ahead.z as f64),
            rotation: glam::Quat::IDENTITY,
            scale: glam::Vec3::splat(scale),
        };
        scene.append(&character, placement)?;
    }
    Ok((scene, camera))
}

/// CesiumMan's walk: the character (`o.character`) on the ground of
/// `platoon_scenegen::bench::walk_ground`, under a blue sky, seen from the front and a little
/// above, two heights away.
fn walk(o: &Options) -> Result<(Scene, Camera)> {
    let path = o
        .character
        .as_ref()
        .context("the walk needs its character (--character)")?;
    let character = platoon::load_scene(Some(path))
        .with_context(|| format!("{}: the walking character", path.display()))?;
    let (lo, hi) = character.pose(0.0).bounds();
    let height = (hi.y - lo.y).max(1e-3);
    let ground = platoon_scenegen::bench::walk_ground(3.0 * height);
    let mut scene = crate::generated::load(&ground, "walk-ground")?;
    scene.environment = Some(platoon_core::scene::environment::Environment::Constant(
        glam::Vec3::new(0.35, 0.45, 0.6),
    ));
    scene.append(
        &character,
        Placement {
            translation: DVec3::new(0.0, -lo.y as f64, 0.0),
            rotation: glam::Quat::IDENTITY,
            scale: glam::Vec3::ONE,
        },
    )?;
    let centre = glam::Vec3::new((lo.x + hi.x) * 0.5, 0.5 * height, (lo.z + hi.z) * 0.5);
    let eye = centre + glam::Vec3::new(0.6 * height, 0.4 * height, 2.0 * height);
    Ok((scene, Camera::look_at(eye, centre, 0.8)))
}

/// Frame `f`'s camera: `start` moved sideways by `step` a frame.
fn camera_of(start: Camera, step: f32, f: u32) -> Camera {
    let right = start.basis(1, 1).right.normalize_or_zero();
    let mut c = start;
    c.camera_to_world = Mat4::from_translation(right * step * f as f32) * start.camera_to_world;
    c
}

/// The still render of frame `f` at the reference's samples: its scene at its time, its camera.
fn reference(o: &Options, scene: &Scene, start: Camera, f: u32) -> Result<Film> {
    let updater = Updater::new(scene.clone(), time_of(o, f), DVec3::ZERO)?;
    let spec: DeviceSpec = o.devices.parse().map_err(anyhow::Error::msg)?;
    let tracers = create_tracers(&spec, updater.flattened(), false, Sampling::Mis)?;
    let mut renderer = Renderer::new(
        tracers,
        platoon_core::balance::by_name("cost-aware").unwrap(),
    );
    let mut params = FrameParams::new(
        o.width,
        o.height,
        o.reference_spp,
        camera_of(start, o.camera_step, f),
    );
    // Other random numbers than any game frame's.
    params.options.seed = 0x5eed_0000 + f;
    Ok(renderer.render_frame(&params)?.film)
}

/// Plays the game with `technique` and `seed`; the finished frames by index.
fn play(
    o: &Options,
    scene: &Scene,
    start: Camera,
    technique: Technique,
    seed: u32,
) -> Result<Vec<FinishedFrame>> {
    let mut driver = DriverOptions::new(o.width, o.height);
    driver.options.seed = seed;
    driver.target = Some(std::time::Duration::from_secs_f64(o.target_ms * 1e-3));
    technique.apply(&mut driver);
    let mut options = platoon::game::GameOptions::new(driver);
    options.devices = o.devices.parse().map_err(anyhow::Error::msg)?;
    let mut d = platoon::game::start(scene.clone(), &options)?;
    let mut done = Vec::new();
    for f in 0..o.frames {
        // An edit made before frame f's call is rendered by frame f + 1.
        d.scene().push(Edit::Time(time_of(o, f + 1)))?;
        done.extend(d.frame(camera_of(start, o.camera_step, f))?.finished);
    }
    done.extend(d.finish()?);
    Ok(done)
}

/// Runs the bench: one row per technique, in `o.techniques`' order.
pub fn run(o: &Options, progress: &mut dyn FnMut(&str)) -> Result<Vec<Row>> {
    if o.repeat == 0 {
        bail!("play each technique once at least");
    }
    if o.measured == 0 || o.measured > o.frames {
        bail!(
            "measure between 1 and the {} frames played, not {}",
            o.frames,
            o.measured
        );
    }
    o.devices
        .parse::<DeviceSpec>()
        .map_err(|e| anyhow::anyhow!("devices: {e}"))?;
    let (scene, start) = scene(o)?;
    let first = o.frames - o.measured;
    let mut references: HashMap<u32, Film> = HashMap::new();
    for f in first..o.frames {
        progress(&format!(
            "reference of frame {f} at {} spp",
            o.reference_spp
        ));
        references.insert(f, reference(o, &scene, start, f)?);
    }
    let mut rows = Vec::new();
    for &technique in &o.techniques {
        let mut shown: Vec<Vec<Film>> = vec![Vec::new(); o.measured as usize];
        let (mut busy, mut spp) = (Vec::new(), Vec::new());
        for seed in 0..o.repeat {
            progress(&format!(
                "playing {} frames with {} (seed {seed})",
                o.frames,
                technique.name()
            ));
            let frames = play(o, &scene, start, technique, seed)?;
            let settled = &frames[frames.len() / 2..];
            busy.extend(settled.iter().map(|f| f.stats.busy.as_secs_f64() * 1e3));
            spp.extend(settled.iter().map(|f| f.stats.plan.spp as f64));
            let measured: Vec<FinishedFrame> = frames
                .into_iter()
                .filter(|f| f.stats.frame >= first)
                .collect();
            if measured.len() != o.measured as usize {
                bail!(
                    "{}: {} of the {} measured frames finished",
                    technique.name(),
                    measured.len(),
                    o.measured
                );
            }
            for f in measured {
                let k = (f.stats.frame - first) as usize;
                shown[k].push(f.denoised.unwrap_or(f.film));
            }
        }
        let (mut relmse, mut flip, mut bias) = (0.0, 0.0, 0.0);
        let plays = (o.measured * o.repeat) as f64;
        for (k, films) in shown.iter().enumerate() {
            let reference = &references[&(first + k as u32)];
            for film in films {
                let e = metrics::errors(film, reference);
                relmse += e.relmse / plays;
                flip += e.flip / plays;
            }
            if o.repeat >= 2 {
                let films: Vec<&Film> = films.iter().collect();
                bias += metrics::relative_squared_bias(&films, reference) / o.measured as f64;
            }
        }
        rows.push(Row {
            technique,
            frame_ms_median: median(busy),
            spp_median: median(spp),
            relmse,
            flip,
            bias: (o.repeat >= 2).then_some(bias),
        });
    }
    Ok(rows)
}

/// The rows as a table, with each technique's relative MSE over the first row's.
pub fn text(o: &Options, rows: &[Row]) -> String {
    let mut s = format!(
        "{}x{} at {} ms a frame, {} frames played {} time(s), the last {} against {} spp \
         references\n\
         technique          frame ms   spp   relative MSE   x first   LDR-FLIP   squared bias\n",
        o.width, o.height, o.target_ms, o.frames, o.repeat, o.measured, o.reference_spp
    );
    let base = rows.first().map_or(1.0, |r| r.relmse);
    for r in rows {
        s += &format!(
            "{:<18} {:>8.1} {:>5.1} {:>14.4} {:>9.2} {:>10.4} {:>14}\n",
            r.technique.name(),
            r.frame_ms_median,
            r.spp_median,
            r.relmse,
            base / r.relmse.max(f64::MIN_POSITIVE),
            r.flip,
            r.bias.map_or("-".into(), |b| format!("{b:.4}"))
        );
    }
    s
}

/// The rows as one JSON object.
pub fn json(rows: &[Row]) -> String {
    let rows: Vec<_> = rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "technique": r.technique.name(),
                "frame_ms_median": r.frame_ms_median,
                "spp_median": r.spp_median,
                "relmse": r.relmse,
                "flip": r.flip,
                "relative_squared_bias": r.bias,
            })
        })
        .collect();
    serde_json::json!({ "rows": rows }).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn technique_names_parse_back_and_an_unknown_one_lists_them() {
        for t in Technique::DEFAULT {
            assert_eq!(Technique::parse(&t.name()).unwrap(), t);
        }
        assert_eq!(Technique::ALL_ON.name(), "resampled+world-cache+atrous");
        assert_eq!(
            Technique::parse("atrous+resampled").unwrap(),
            Technique::RESAMPLED_ATROUS
        );
        let e = Technique::parse("restir").unwrap_err().to_string();
        assert!(e.contains("world-cache"), "{e}");
    }

    #[test]
    fn the_camera_glides_sideways_by_its_step_a_frame() {
        let start = Camera::look_at(Vec3::ZERO, -Vec3::Z, 1.0);
        let c = camera_of(start, 0.5, 4);
        assert!(
            (c.position() - Vec3::X * 2.0).length() < 1e-5,
            "{}",
            c.position()
        );
    }
}

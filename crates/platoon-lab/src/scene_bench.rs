//! The bench scenes against Mitsuba 3 (issue 21): each scene rendered by `platoon render` and,
//! exported through [`crate::mitsuba`], by Mitsuba's `llvm_ad_rgb` path tracer
//! (tools/reference_bench.py), as whole processes on the same cores, alternated, medians.
//! Scenes as exporters write them, not only the one-mesh box: a node and a mesh per object,
//! textures, glTF materials, several kinds of light; and at real scale (issue 39): the box with
//! every face cut into 16 x 16 and 48 x 48 quads, the 152k-triangle conference room and the
//! 264k-triangle atrium (long thin triangles, alpha-tested leaves, 13 lights and a sky).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use anyhow::{bail, Context as _, Result};
use glam::Vec3;
use platoon::core::measure::median;
use platoon::{load_scene, prepare, EnvChoice, PrepareOptions};

use crate::mitsuba::{self, Settings};

/// tools/reference_bench.py, carried in the binary so that the bench runs from anywhere.
const REFERENCE_BENCH: &str = include_str!("../../../tools/reference_bench.py");

/// The sky of the spheres scene (`--env-color`).
pub const SPHERES_SKY: [f32; 3] = [0.25, 0.3, 0.4];

/// One bench scene: a file (`None`: the built-in box) and its distant light.
pub struct BenchScene {
    pub name: &'static str,
    pub what: &'static str,
    pub file: Option<PathBuf>,
    pub env: EnvChoice,
}

impl BenchScene {
    /// `platoon render`'s scene and light arguments.
    pub fn render_args(&self) -> Vec<String> {
        let mut args: Vec<String> = self.file.iter().map(|f| f.display().to_string()).collect();
        match &self.env {
            EnvChoice::File(p) => args.extend(["--env".into(), p.display().to_string()]),
            EnvChoice::Color(c) => {
                args.extend(["--env-color".into(), format!("{},{},{}", c.x, c.y, c.z)])
            }
            EnvChoice::Scene => {}
        }
        args
    }
}

/// The sky of the atrium (`--env-color`): daylight through its open roof.
pub const ATRIUM_SKY: [f32; 3] = [0.5, 0.6, 0.8];

/// The names [`scenes`] knows, in its order.
pub const NAMES: [&str; 10] = [
    "cornell",
    "cornell-nodes",
    "cornell-16",
    "cornell-48",
    "spheres",
    "field",
    "cesium",
    "room",
    "atrium",
    "all",
];

/// The scenes `all` names: every scene but the built-in box's duplicates.
pub const ALL: [&str; 8] = [
    "cornell",
    "cornell-nodes",
    "cornell-16",
    "cornell-48",
    "spheres",
    "field",
    "room",
    "atrium",
];

/// Writes the generated bench scenes into `dir` and returns those of `names` (CesiumMan from
/// `shared`/scenes under `shared`/envmaps/courtyard.exr; an error when it is missing).
pub fn scenes(dir: &Path, shared: &Path, names: &[String]) -> Result<Vec<BenchScene>> {
    let write = |name: &str, scene: platoon_scenegen::SceneData| -> Result<PathBuf> {
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, platoon_scenegen::to_glb(&scene))?;
        Ok(path)
    };
    let mut out = Vec::new();
    let names: Vec<String> = names
        .iter()
        .flat_map(|n| match n.as_str() {
            "all" => ALL.iter().map(|a| a.to_string()).collect(),
            _ => vec![n.clone()],
        })
        .collect();
    for name in &names {
        out.push(match name.as_str() {
            "cornell" => BenchScene {
                name: "cornell",
                what: "built-in Cornell box, one mesh",
                file: None,
                env: EnvChoice::Scene,
            },
            "cornell-nodes" => BenchScene {
                name: "cornell-nodes",
                what: "Cornell box, a node per object (8 instances)",
                file: Some(write(name, platoon_scenegen::bench::cornell_nodes())?),
                env: EnvChoice::Scene,
            },
            "cornell-16" | "cornell-48" => {
                let (what, cells) = match name.as_str() {
                    "cornell-16" => ("Cornell box, every face 16 x 16 quads (9,216 triangles)", 16),
                    _ => ("Cornell box, every face 48 x 48 quads (82,944 triangles)", 48),
                };
                BenchScene {
                    name: if cells == 16 { "cornell-16" } else { "cornell-48" },
                    what,
                    file: Some(write(name, platoon_scenegen::bench::cornell_cut(cells))?),
                    env: EnvChoice::Scene,
                }
            }
            "room" => BenchScene {
                name: "room",
                what: "conference room, 152k triangles, tessellated walls, 4 point lights",
                file: Some(write(name, platoon_scenegen::conference_room())?),
                env: EnvChoice::Scene,
            },
            "atrium" => BenchScene {
                name: "atrium",
                what: "Sponza-sized atrium, 264k triangles, thin triangles, alpha-tested leaves, 13 lights + sky",
                file: Some(write(name, platoon_scenegen::atrium::atrium())?),
                env: EnvChoice::Color(Vec3::from(ATRIUM_SKY)),
            },
            "spheres" => BenchScene {
                name: "spheres",
                what: "five glTF-material spheres, textured ground, 3 lights + sky",
                file: Some(write(name, platoon_scenegen::bench::spheres())?),
                env: EnvChoice::Color(Vec3::from(SPHERES_SKY)),
            },
            "field" => BenchScene {
                name: "field",
                what: "sphere field, 103k triangles, 16 instances",
                file: Some(write(name, platoon_scenegen::sphere_field(4, false))?),
                env: EnvChoice::Scene,
            },
            "cesium" => {
                let file = shared.join("scenes/CesiumMan.glb");
                let env = shared.join("envmaps/courtyard.exr");
                if !file.is_file() || !env.is_file() {
                    bail!(
                        "the cesium scene needs {} and {} (--shared DIR names the folder)",
                        file.display(),
                        env.display()
                    );
                }
                BenchScene {
                    name: "cesium",
                    what: "CesiumMan (skinned, textured) under courtyard.exr",
                    file: Some(file),
                    env: EnvChoice::File(env),
                }
            }
            other => bail!("unknown bench scene {other}: one of {}", NAMES.join(", ")),
        });
    }
    Ok(out)
}

/// A Python that runs Mitsuba 3's `llvm_ad_rgb` variant: `explicit`, else
/// `$PLATOON_MITSUBA_PYTHON`, else `python3`; with the reference script written into `dir`.
pub struct Mitsuba {
    python: PathBuf,
    script: PathBuf,
}

impl Mitsuba {
    /// `Err` says why none was found.
    pub fn find(explicit: Option<&Path>, dir: &Path) -> std::result::Result<Mitsuba, String> {
        let script = dir.join("reference_bench.py");
        std::fs::write(&script, REFERENCE_BENCH).map_err(|e| e.to_string())?;
        let candidates: Vec<PathBuf> = match explicit {
            Some(p) => vec![p.to_path_buf()],
            None => std::env::var_os("PLATOON_MITSUBA_PYTHON")
                .map(PathBuf::from)
                .into_iter()
                .chain([PathBuf::from("python3")])
                .collect(),
        };
        for python in &candidates {
            let ok = Command::new(python)
                .arg(&script)
                .arg("--check")
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .is_ok_and(|s| s.success());
            if ok {
                return Ok(Mitsuba {
                    python: python.clone(),
                    script,
                });
            }
        }
        Err(format!(
            "no Python with Mitsuba 3's llvm_ad_rgb variant among {} (install steps: \
             tools/reference_bench.py; --mitsuba PYTHON or PLATOON_MITSUBA_PYTHON names one)",
            candidates
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ))
    }

    /// [`Mitsuba::find`], saying on standard output why the bench goes on without it.
    pub fn find_or_say(explicit: Option<&Path>, dir: &Path) -> Option<Mitsuba> {
        match Mitsuba::find(explicit, dir) {
            Ok(m) => Some(m),
            Err(why) => {
                println!("Mitsuba 3 not found, platoon alone: {why}");
                None
            }
        }
    }

    /// The command that renders `xml` (an exported scene) with Mitsuba.
    pub fn command(&self, xml: &Path) -> Command {
        let mut c = Command::new(&self.python);
        c.arg(&self.script).arg("--scene").arg(xml);
        c
    }
}

/// The bench's settings.
pub struct Options {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Path lengths to measure (`None`: unbounded).
    pub depths: Vec<Option<u32>>,
    pub repeat: u32,
    /// The platoon binary to time (`platoon render ...`).
    pub platoon: PathBuf,
    /// Further `platoon render` arguments (a kernel, devices).
    pub platoon_args: Vec<String>,
}

/// One measured (scene, depth): whole-process seconds of each run.
pub struct Row {
    pub scene: &'static str,
    pub depth: Option<u32>,
    pub platoon: Vec<f64>,
    pub mitsuba: Vec<f64>,
    pub samples: f64,
}

impl Row {
    pub fn ratio(&self) -> Option<f64> {
        (!self.mitsuba.is_empty())
            .then(|| median(self.platoon.clone()) / median(self.mitsuba.clone()))
    }
}

fn timed(mut c: Command, what: &str) -> Result<f64> {
    let start = Instant::now();
    let out = c
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .with_context(|| format!("could not start {what}"))?;
    let t = start.elapsed().as_secs_f64();
    if !out.status.success() {
        bail!(
            "{what} failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    Ok(t)
}

/// Measures `scene` at every depth of `o`: a warm-up run of each renderer (kernel caches
/// filled), then `repeat` runs alternated. `dir` holds the exports and images.
pub fn measure(
    scene: &BenchScene,
    o: &Options,
    mitsuba: Option<&Mitsuba>,
    dir: &Path,
    report: &mut dyn FnMut(&Row),
) -> Result<Vec<Row>> {
    let prepared = match mitsuba {
        Some(_) => Some(prepare(
            load_scene(scene.file.as_deref())?,
            &PrepareOptions {
                env: scene.env.clone(),
                ..Default::default()
            },
        )?),
        None => None,
    };
    let mut rows = Vec::new();
    for &depth in &o.depths {
        let label = depth.map_or("unbounded".to_string(), |d| format!("depth{d}"));
        let render = || {
            let mut c = Command::new(&o.platoon);
            c.arg("render")
                .args(scene.render_args())
                .args(["--width", &o.width.to_string()])
                .args(["--height", &o.height.to_string()])
                .args(["--spp", &o.spp.to_string()])
                .args(&o.platoon_args)
                .arg("--out")
                .arg(dir.join(format!("{}-{label}.exr", scene.name)));
            if let Some(d) = depth {
                c.args(["--max-depth", &d.to_string()]);
            }
            timed(c, "platoon render")
        };
        let xml = match (&prepared, mitsuba) {
            (Some(p), Some(_)) => {
                let settings = Settings {
                    width: o.width,
                    height: o.height,
                    spp: o.spp,
                    max_depth: depth,
                    rr_depth: platoon::core::frame::DEFAULT_RR_DEPTH,
                };
                Some(mitsuba::export(
                    p,
                    &settings,
                    &dir.join(format!("{}-{label}", scene.name)),
                )?)
            }
            _ => None,
        };
        let mut row = Row {
            scene: scene.name,
            depth,
            platoon: Vec::new(),
            mitsuba: Vec::new(),
            samples: o.width as f64 * o.height as f64 * o.spp as f64,
        };
        render()?;
        if let (Some(m), Some(xml)) = (mitsuba, &xml) {
            timed(m.command(xml), "Mitsuba")?;
        }
        for _ in 0..o.repeat.max(1) {
            row.platoon.push(render()?);
            if let (Some(m), Some(xml)) = (mitsuba, &xml) {
                row.mitsuba.push(timed(m.command(xml), "Mitsuba")?);
            }
        }
        report(&row);
        rows.push(row);
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_names_every_generated_scene_once_and_unknown_names_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let scenes = scenes(dir.path(), Path::new("/nonexistent"), &["all".to_string()]).unwrap();
        let names: Vec<&str> = scenes.iter().map(|s| s.name).collect();
        assert_eq!(names, ALL);
        for s in &scenes {
            if let Some(f) = &s.file {
                assert!(f.is_file(), "{} not written", s.name);
            }
        }
        let e = scenes_err(dir.path(), "cornell-47");
        assert!(e.contains("unknown bench scene cornell-47"), "{e}");
    }

    fn scenes_err(dir: &Path, name: &str) -> String {
        match scenes(dir, Path::new("/nonexistent"), &[name.to_string()]) {
            Ok(_) => String::new(),
            Err(e) => e.to_string(),
        }
    }
}

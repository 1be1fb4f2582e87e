//! Scenes of production size (issue 59): what a user with a big file waits for and how much
//! memory it takes. Each scene is generated (platoon-scenegen's `scale`), then rendered by
//! `platoon render --log-json` as a whole process, whose `cost` field says its stages (load,
//! BVH build, upload, first pixel, render) and memory (host peak, each device's); the process's
//! own peak resident memory (polled) and wall time come from the system. Against Mitsuba 3 on
//! the same triangles where it is installed (the cut boxes: the instanced and textured scenes
//! are not exported).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use anyhow::{bail, Context as _, Result};
use glam::Vec3;
use platoon::{load_scene, prepare, EnvChoice, PrepareOptions};

use crate::mitsuba::{self, Settings};
use crate::scene_bench::Mitsuba;

/// The names [`scene`] knows, in the order `all` runs them.
pub const NAMES: [&str; 6] = [
    "box-1m",
    "box-4m",
    "box-16m",
    "instances-1m",
    "textures-200",
    "all",
];

/// The scenes `all` names.
pub const ALL: [&str; 5] = [
    "box-1m",
    "box-4m",
    "box-16m",
    "instances-1m",
    "textures-200",
];

/// A generated scale scene written to a file.
pub struct ScaleScene {
    pub name: String,
    pub what: String,
    pub file: PathBuf,
    /// The distant light `platoon render` is given.
    pub env: EnvChoice,
    /// Mitsuba renders the same triangles (the exporter writes posed triangles and materials,
    /// not a million instances or hundreds of textures).
    pub mitsuba: bool,
    /// `platoon render` arguments of this scene's own.
    pub args: Vec<String>,
}

/// The device budget textures-200 renders in: its 3.1 GiB of texels (4.2 GiB with mip levels)
/// do not fit one buffer of lavapipe (2 GiB), so the largest are halved until they fit.
pub const TEXTURE_BUDGET: &str = "1G";

/// Writes scene `name` into `dir` (kept when it is there already: generating 16 million
/// triangles takes a while).
pub fn scene(dir: &Path, name: &str) -> Result<ScaleScene> {
    let file = dir.join(format!("{name}.glb"));
    let sky = EnvChoice::Color(Vec3::new(0.4, 0.5, 0.7));
    let mut args = Vec::new();
    let (what, env, mitsuba, make): (String, EnvChoice, bool, Box<dyn Fn() -> Vec<u8>>) = match name
    {
        "box-1m" | "box-4m" | "box-16m" => {
            let millions: usize = name[4..name.len() - 1].parse()?;
            let triangles = millions * 1_000_000;
            (
                format!("Cornell box, every face cut into quads: {millions}M unique triangles"),
                EnvChoice::Scene,
                true,
                Box::new(move || {
                    platoon_scenegen::to_glb(&platoon_scenegen::scale::cut_box(triangles))
                }),
            )
        }
        "instances-1m" => (
            "1M instances of 3 meshes (EXT_mesh_gpu_instancing), sun, 3 point lights, panel".into(),
            sky,
            false,
            Box::new(|| platoon_scenegen::scale::instanced_field(1_000_000)),
        ),
        "textures-200" => (
            {
                args = [
                    "--texture-lod",
                    "ray-cone",
                    "--texture-budget",
                    TEXTURE_BUDGET,
                ]
                .map(String::from)
                .to_vec();
                format!(
                    "200 quads, each its own 2048 x 2048 texture (800M texels), sun, strip \
                     light; mip-mapped, in a texture budget of {TEXTURE_BUDGET}"
                )
            },
            sky,
            false,
            Box::new(|| {
                platoon_scenegen::to_glb(&platoon_scenegen::scale::textured_wall(200, 2048))
            }),
        ),
        other => bail!("unknown scale scene {other}: one of {}", NAMES.join(", ")),
    };
    if !file.is_file() {
        let part = file.with_extension("glb.part");
        std::fs::write(&part, make()).with_context(|| format!("writing {}", part.display()))?;
        std::fs::rename(&part, &file)?;
    }
    Ok(ScaleScene {
        name: name.into(),
        what,
        file,
        env,
        mitsuba,
        args,
    })
}

/// The names of `list`, `all` expanded.
pub fn expand(list: &[String]) -> Vec<String> {
    list.iter()
        .flat_map(|n| match n.as_str() {
            "all" => ALL.iter().map(|a| a.to_string()).collect(),
            _ => vec![n.clone()],
        })
        .collect()
}

/// The bench's settings.
pub struct Options {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    pub max_depth: u32,
    /// The platoon binary to run (`platoon render ...`).
    pub platoon: PathBuf,
    /// Further `platoon render` arguments.
    pub platoon_args: Vec<String>,
}

/// A whole process: its wall time and peak resident memory, and what it printed.
pub struct Process {
    pub seconds: f64,
    pub peak_bytes: u64,
    pub stdout: String,
}

/// Runs `c` to its end, measuring it; an error with its standard error when it fails.
///
/// The peak is the child's own `VmHWM`, read every few milliseconds while it runs (the last
/// milliseconds before it exits can escape). `wait4`'s `ru_maxrss` would not do: Linux starts
/// an exec'd child's count at its parent's high-water mark, and this bench holds a 16-million-
/// triangle scene in memory while it exports it for Mitsuba.
pub fn run_measured(mut c: Command, what: &str) -> Result<Process> {
    use std::io::Read;
    let start = Instant::now();
    let mut child = c
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .with_context(|| format!("could not start {what}"))?;
    // The pipes are drained on their own threads: a child filling one would never end.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_string(&mut s);
            }
            s
        })
    };
    let out = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let err = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let status_file = format!("/proc/{}/status", child.id());
    let mut peak = 0;
    let status = loop {
        if let Some(bytes) = std::fs::read_to_string(&status_file)
            .ok()
            .and_then(|t| platoon::cost::peak_bytes_in(&t))
        {
            peak = peak.max(bytes);
        }
        if let Some(status) = child.try_wait()? {
            break status;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    };
    let seconds = start.elapsed().as_secs_f64();
    let (stdout, stderr) = (
        out.join().unwrap_or_default(),
        err.join().unwrap_or_default(),
    );
    if !status.success() {
        bail!("{what} failed: {}", stderr.trim());
    }
    Ok(Process {
        seconds,
        peak_bytes: peak,
        stdout,
    })
}

/// What one platoon render cost (its `--log-json` line's `cost`) and the whole process.
pub struct Measured {
    pub process: Process,
    pub load: f64,
    pub bvh: f64,
    pub prepare: f64,
    pub upload: f64,
    pub first_pixel: f64,
    pub render: f64,
    pub device_bytes: Vec<u64>,
    pub triangles: u64,
    pub instances: u64,
}

impl Measured {
    pub fn bytes_per_triangle(&self) -> Option<f64> {
        let d = *self.device_bytes.first()?;
        (self.triangles > 0).then(|| d as f64 / self.triangles as f64)
    }
}

/// Renders `scene` once with platoon: what it cost.
pub fn render_platoon(scene: &ScaleScene, o: &Options, dir: &Path) -> Result<Measured> {
    let mut c = Command::new(&o.platoon);
    c.arg("render")
        .arg(&scene.file)
        .args(["--width", &o.width.to_string()])
        .args(["--height", &o.height.to_string()])
        .args(["--spp", &o.spp.to_string()])
        .args(["--max-depth", &o.max_depth.to_string()])
        .arg("--log-json")
        .args(&scene.args)
        .args(&o.platoon_args)
        .arg("--out")
        .arg(dir.join(format!("{}.exr", scene.name)));
    if let EnvChoice::Color(c3) = &scene.env {
        c.args(["--env-color", &format!("{},{},{}", c3.x, c3.y, c3.z)]);
    }
    let process = run_measured(c, &format!("platoon render {}", scene.file.display()))?;
    let line = process
        .stdout
        .lines()
        .rev()
        .find(|l| l.contains("\"cost\""))
        .context("platoon render printed no cost (--log-json)")?;
    let v: serde_json::Value = serde_json::from_str(line)?;
    let c = &v["cost"];
    let secs = |k: &str| c[k].as_f64().unwrap_or(f64::NAN);
    Ok(Measured {
        load: secs("load_seconds"),
        bvh: secs("bvh_seconds"),
        prepare: secs("prepare_seconds"),
        upload: secs("upload_seconds"),
        first_pixel: secs("first_pixel_seconds"),
        render: secs("render_seconds"),
        device_bytes: c["device_bytes"]
            .as_array()
            .map(|a| a.iter().filter_map(|b| b.as_u64()).collect())
            .unwrap_or_default(),
        triangles: c["triangles"].as_u64().unwrap_or(0),
        instances: c["instances"].as_u64().unwrap_or(0),
        process,
    })
}

/// The Mitsuba 3 scene of `scene` (exported once into `dir`), when it has one.
pub fn export_mitsuba(scene: &ScaleScene, o: &Options, dir: &Path) -> Result<PathBuf> {
    let prepared = prepare(
        load_scene(Some(&scene.file))?,
        &PrepareOptions {
            env: scene.env.clone(),
            ..Default::default()
        },
    )?;
    let settings = Settings {
        width: o.width,
        height: o.height,
        spp: o.spp,
        max_depth: Some(o.max_depth),
        rr_depth: platoon::core::frame::DEFAULT_RR_DEPTH,
    };
    mitsuba::export(
        &prepared,
        &settings,
        &dir.join(format!("{}-mitsuba", scene.name)),
    )
}

/// Renders the exported `xml` with Mitsuba once: the whole process.
pub fn render_mitsuba(m: &Mitsuba, xml: &Path) -> Result<Process> {
    run_measured(m.command(xml), "Mitsuba")
}

/// A living scene's refinement of its big static geometry ([`platoon_live::refinement`]):
/// what it costs and what it brings.
pub struct Refined {
    /// The updater's first generation (the quick build and the flattening).
    pub first_generation: f64,
    /// The refinement alone, waited for right after.
    pub refine: f64,
    /// SAH cost of the largest bottom level, quick and refined.
    pub sah: (f64, f64),
    /// Median frame times (`frames` alternated renders each), quick and refined.
    pub render: (f64, f64),
}

/// [`Refined`] of `scene` on the first device: an updater refining in the background, a
/// tracer holding its first generation and one holding the generation after the swap, frames
/// of `o`'s size rendered alternately.
pub fn refinement(scene: &ScaleScene, o: &Options, frames: usize) -> Result<Refined> {
    use platoon::core::frame::FrameParams;
    use platoon::core::scene::camera::Camera;
    use platoon::drive::{Refinement, StaticBuild, Updater, UpdaterOptions};
    use platoon::render::Tracers;
    let loaded = load_scene(Some(&scene.file))?;
    let camera =
        Camera::from_scene(&loaded, &loaded.pose(0.0), None).map_err(anyhow::Error::msg)?;
    let options = UpdaterOptions {
        static_build: StaticBuild {
            refinement: Refinement::Background,
            ..Default::default()
        },
        ..Default::default()
    };
    let start = Instant::now();
    let mut updater = Updater::with_options(loaded, 0.0, glam::DVec3::ZERO, options)?;
    let first_generation = start.elapsed().as_secs_f64();
    if updater.refinements_pending() == 0 {
        bail!("{}: no static mesh past the quick build's size", scene.name);
    }
    let quick_scene = updater.flattened().clone();
    let start = Instant::now();
    updater.finish_refinements();
    let refine = start.elapsed().as_secs_f64();
    let g = updater.update()?;
    if g.refined == 0 {
        bail!("{}: the refinement was not swapped in", scene.name);
    }
    let sah = (
        quick_scene.bvh_report().largest,
        updater.flattened().bvh_report().largest,
    );
    let spec = platoon::devices::DeviceSpec::Indices(vec![0]);
    let options = platoon::devices::tracer_options(&spec, false, platoon::tracer::Sampling::Mis)?;
    let mut quick = Tracers::new(&options, "cost-aware", &quick_scene)?;
    let mut refined = Tracers::new(&options, "cost-aware", updater.flattened())?;
    let mut params = FrameParams::new(o.width, o.height, o.spp, camera);
    params.path_loop.max_depth = o.max_depth;
    let time = |t: &mut Tracers, s| -> Result<f64> {
        let start = Instant::now();
        t.render(s, &params, &mut |_| {})?;
        Ok(start.elapsed().as_secs_f64())
    };
    // One frame each first (the kernels' compiles), then alternated.
    time(&mut quick, &quick_scene)?;
    time(&mut refined, updater.flattened())?;
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..frames.max(1) {
        a.push(time(&mut quick, &quick_scene)?);
        b.push(time(&mut refined, updater.flattened())?);
    }
    let median = platoon::core::measure::median;
    Ok(Refined {
        first_generation,
        refine,
        sah,
        render: (median(a), median(b)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_measured_process_reports_its_peak_memory_and_failures_their_stderr() {
        // A Python writing 200 MB and holding them a moment: the child's peak is read.
        let mut c = Command::new("python3");
        c.args([
            "-c",
            "import time; b = b'x' * 200000000; print('out'); time.sleep(0.3)",
        ]);
        let p = run_measured(c, "python3").unwrap();
        assert_eq!(p.stdout.trim(), "out");
        assert!(
            (200_000_000..400_000_000).contains(&p.peak_bytes),
            "{}",
            p.peak_bytes
        );
        let mut bad = Command::new("sh");
        bad.args(["-c", "echo broken >&2; exit 3"]);
        let e = run_measured(bad, "sh").err().unwrap().to_string();
        assert!(e.contains("sh failed: broken"), "{e}");
        assert!(scene(Path::new("/nonexistent"), "box-2m").is_err());
        assert_eq!(expand(&["all".into()]), ALL.map(String::from).to_vec());
    }
}

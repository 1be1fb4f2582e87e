//! Scenes of production size (issue 59): what a user with a big file waits for and how much
//! memory it takes. Each scene is generated (platoon-scenegen's `scale`), then rendered by
//! `platoon render --log-json` as a whole process, whose `cost` field says its stages (load,
//! BVH build, upload, first pixel, render) and memory (host peak, each device's); the process's
//! own peak resident memory and wall time come from the system (`wait4`). Against Mitsuba 3 on
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
}

/// Writes scene `name` into `dir` (kept when it is there already: generating 16 million
/// triangles takes a while).
pub fn scene(dir: &Path, name: &str) -> Result<ScaleScene> {
    let file = dir.join(format!("{name}.glb"));
    let sky = EnvChoice::Color(Vec3::new(0.4, 0.5, 0.7));
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
            "200 quads, each its own 2048 x 2048 texture (800M texels), sun, strip light".into(),
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
pub fn run_measured(mut c: Command, what: &str) -> Result<Process> {
    let start = Instant::now();
    let child = c
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .with_context(|| format!("could not start {what}"))?;
    let pid = child.id() as libc::pid_t;
    // The pipes are read before the wait: a child filling one would otherwise never end.
    let (stdout, stderr) = read_pipes(child);
    let mut status = 0;
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waits for our own child, writing into the locals above.
    let r = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    let seconds = start.elapsed().as_secs_f64();
    if r != pid {
        bail!(
            "{what}: waiting for it failed: {}",
            std::io::Error::last_os_error()
        );
    }
    if !(libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0) {
        bail!("{what} failed: {}", stderr.trim());
    }
    Ok(Process {
        seconds,
        // ru_maxrss is in KiB on Linux.
        peak_bytes: usage.ru_maxrss as u64 * 1024,
        stdout,
    })
}

fn read_pipes(mut child: std::process::Child) -> (String, String) {
    use std::io::Read;
    let mut err_pipe = child.stderr.take();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        if let Some(e) = err_pipe.as_mut() {
            let _ = e.read_to_string(&mut s);
        }
        s
    });
    let mut out = String::new();
    if let Some(o) = child.stdout.as_mut() {
        let _ = o.read_to_string(&mut out);
    }
    let err = reader.join().unwrap_or_default();
    // The Child is dropped without a wait: wait4 reaps it.
    std::mem::forget(child);
    (out, err)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_measured_process_reports_its_peak_memory_and_failures_their_stderr() {
        let mut c = Command::new("sh");
        c.args([
            "-c",
            "echo out; head -c 50000000 /dev/zero | tail -c 1 >/dev/null",
        ]);
        let p = run_measured(c, "sh").unwrap();
        assert_eq!(p.stdout.trim(), "out");
        assert!(p.peak_bytes > 0);
        let mut bad = Command::new("sh");
        bad.args(["-c", "echo broken >&2; exit 3"]);
        let e = run_measured(bad, "sh").err().unwrap().to_string();
        assert!(e.contains("sh failed: broken"), "{e}");
        assert!(scene(Path::new("/nonexistent"), "box-2m").is_err());
        assert_eq!(expand(&["all".into()]), ALL.map(String::from).to_vec());
    }
}

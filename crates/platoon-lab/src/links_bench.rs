//! The vertex-links bench (`platoon bench links`): Schmitz et al.'s table for platoon. Per scene
//! the update's stages timed apart from the frame (shoot, reduce, direct light, gather, smooth),
//! the links raw and compressed, their bytes, the first frame (update and one frame) and a
//! frame alone. Each update runs once to compile its kernels, then timed.

use std::time::{Duration, Instant};

use anyhow::{bail, Context as _, Result};
use glam::Vec3;
use platoon::core::frame::FrameParams;
use platoon::core::method::links::job::UpdateStats;
use platoon::core::method::links::{Job, Links, LinksOptions};
use platoon::core::Method;
use platoon::tracer::{Tracer, TracerOptions};
use platoon::{EnvChoice, PrepareOptions};

/// A scene of the bench: its name, what it is, and how it is made.
pub struct LinksScene {
    pub name: String,
    pub what: String,
    pub scene: platoon::core::Scene,
    pub env: EnvChoice,
}

/// The named scenes: `boxN` (the Cornell box, every face N x N quads), `conference` (the
/// generated conference room), `cesium` (CesiumMan from the shared data, under a grey sky),
/// `tearoomN` (a furnished room, walls N x N quads, teapots from the shared data).
pub fn scenes(names: &[String], shared: &std::path::Path) -> Result<Vec<LinksScene>> {
    names
        .iter()
        .map(|name| {
            if let Some(cells) = name.strip_prefix("box").and_then(|n| n.parse().ok()) {
                return Ok(LinksScene {
                    name: name.clone(),
                    what: format!("Cornell box, every face {cells}x{cells} quads"),
                    scene: platoon::core::scene::cornell::tessellated(cells),
                    env: EnvChoice::Scene,
                });
            }
            if let Some(cells) = name.strip_prefix("tearoom").and_then(|n| n.parse().ok()) {
                let path = shared.join("scenes/teapot.gltf");
                if !path.is_file() {
                    bail!("{}: not found (--shared names the folder)", path.display());
                }
                let teapot = platoon::load_scene(Some(&path))?;
                return Ok(LinksScene {
                    name: name.clone(),
                    what: format!(
                        "a tea room: walls {cells}x{cells} quads, six tables, chairs, teapots"
                    ),
                    scene: crate::tearoom::tearoom(&teapot, cells)?,
                    env: EnvChoice::Scene,
                });
            }
            let (what, path, env) = match name.as_str() {
                "conference" => {
                    let dir = tempfile::tempdir()?;
                    let path = dir.path().join("conference.glb");
                    std::fs::write(
                        &path,
                        platoon_scenegen::to_glb(&platoon_scenegen::conference_room()),
                    )?;
                    let scene = platoon::load_scene(Some(&path))?;
                    return Ok(LinksScene {
                        name: name.clone(),
                        what: "the generated conference room".into(),
                        scene,
                        env: EnvChoice::Scene,
                    });
                }
                "cesium" => (
                    "CesiumMan under a grey sky",
                    shared.join("scenes/CesiumMan.glb"),
                    EnvChoice::Color(Vec3::splat(0.8)),
                ),
                _ => {
                    bail!("unknown links bench scene {name:?}: boxN, conference, cesium, tearoomN")
                }
            };
            if !path.is_file() {
                bail!("{}: not found (--shared names the folder)", path.display());
            }
            Ok(LinksScene {
                name: name.clone(),
                what: what.into(),
                scene: platoon::load_scene(Some(&path))?,
                env,
            })
        })
        .collect()
}

/// One scene's row.
pub struct LinksRow {
    pub scene: String,
    pub stats: UpdateStats,
    /// The update and one frame, then a frame alone (wall time, kernels compiled).
    pub first_frame: Duration,
    pub frame: Duration,
}

impl LinksScene {
    /// The scene prepared for rendering (flattened, its BVHs built).
    pub fn prepare(&self) -> Result<platoon::Prepared> {
        platoon::prepare(
            self.scene.clone(),
            &PrepareOptions {
                env: self.env.clone(),
                ..Default::default()
            },
        )
        .with_context(|| format!("preparing {}", self.name))
    }
}

/// Measures `scene` with `options` on device 0, frames of `size` x `size` at `spp`.
pub fn measure(s: &LinksScene, options: LinksOptions, size: u32, spp: u32) -> Result<LinksRow> {
    let prepared = s.prepare()?;
    let mut tracer = Tracer::new(&TracerOptions::default(), &prepared.gpu)?;
    let mut params = FrameParams::new(size, size, spp, prepared.camera);
    params.method = Method::Links(Links::new(options));
    // Warm-up: every kernel compiled.
    let solved = platoon::method_update::on_tracer(&mut tracer, &prepared.gpu, &params)?;
    tracer.render(&solved, 0, size, &mut |_| {})?;
    let clock = Instant::now();
    let solved = platoon::method_update::on_tracer(&mut tracer, &prepared.gpu, &params)?;
    tracer.render(&solved, 0, size, &mut |_| {})?;
    let first_frame = clock.elapsed();
    let clock = Instant::now();
    tracer.render(&solved, 0, size, &mut |_| {})?;
    let frame = clock.elapsed();
    let stats = match solved.method.links().and_then(|l| l.job.as_ref()) {
        Some(Job::Render(solution)) => solution.stats.clone(),
        _ => bail!("the update left no solution"),
    };
    Ok(LinksRow {
        scene: s.name.clone(),
        stats,
        first_frame,
        frame,
    })
}

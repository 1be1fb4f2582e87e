//! The walk of `platoon bench links --walk`: CesiumMan walking across a tessellated Cornell
//! box (`platoon::drive::walk`). Per step: the paper's regeneration of every link against
//! platoon's revalidation (wall time, rays shot, elements regrouped), the two compared bit for
//! bit, and the error of lighting the step with the previous step's links (what a
//! frame shows while an asynchronous update is a generation behind).

use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Result};
use glam::DVec3;
use platoon::core::flatten::GpuScene;
use platoon::core::frame::FrameParams;
use platoon::core::method::links::job::UpdateStats;
use platoon::core::method::links::{Job, Links, LinksOptions, Solution};
use platoon::core::scene::camera::Camera;
use platoon::core::{Method, Scene};
use platoon::drive::walk::{walk_edits, walk_in_a_room, walk_step};
use platoon::drive::{DriverOptions, Edit, GiUpdate, Updater};
use platoon::game::{start, GameOptions};
use platoon::tracer::{Tracer, TracerOptions};

/// One step of the walk.
pub struct WalkStep {
    pub regenerated: UpdateStats,
    pub regenerate_s: f64,
    pub revalidated: UpdateStats,
    pub revalidate_s: f64,
    /// Revalidation gave the links and the light of regeneration, bit for bit.
    pub same_bits: bool,
    /// The previous step's indirect irradiance against this step's: RMS over elements and
    /// channels, relative to this step's RMS.
    pub stale_error: f64,
    /// Rays a regeneration shoots.
    pub all_rays: u64,
}

/// Walks `character` `steps` steps across the box with faces of `cells` x `cells` quads,
/// solving each step both ways on device 0.
pub fn walk(
    character: &Scene,
    cells: u32,
    options: LinksOptions,
    steps: usize,
) -> Result<Vec<WalkStep>> {
    let (scene, node) = walk_in_a_room(character, cells)?;
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).map_err(anyhow::Error::msg)?;
    let mut updater = Updater::new(scene, 0.0, DVec3::ZERO)?;
    let mut tracer = Tracer::new(&TracerOptions::default(), updater.flattened())?;
    let params = FrameParams::new(16, 16, 1, camera);
    let solve = |tracer: &mut Tracer, g: &GpuScene, previous: Option<Arc<Solution>>| {
        let mut p = params.clone();
        p.method = Method::new(Links {
            previous,
            ..Links::new(options)
        });
        let clock = Instant::now();
        let p = platoon::method_update::on_tracer(tracer, g, &p)?;
        let seconds = clock.elapsed().as_secs_f64();
        match p.method.state::<Links>().and_then(|l| l.job.as_ref()) {
            Some(Job::Render(s)) => Ok((s.clone(), seconds)),
            _ => bail!("the update left no solution"),
        }
    };
    // Once to compile the kernels, then the walk's first solution.
    solve(&mut tracer, updater.flattened(), None)?;
    let (mut last, _) = solve(&mut tracer, updater.flattened(), None)?;
    let mut rows = Vec::new();
    for step in 1..=steps {
        for e in walk_edits(node, step) {
            updater.apply(e)?;
        }
        let generation = updater.update()?;
        tracer.apply_commit(&generation.commit)?;
        let g = updater.flattened();
        let (regenerated, regenerate_s) = solve(&mut tracer, g, None)?;
        let (revalidated, revalidate_s) = solve(&mut tracer, g, Some(last.clone()))?;
        rows.push(WalkStep {
            all_rays: regenerated.stats.rays,
            same_bits: regenerated.links == revalidated.links
                && regenerated.irradiance == revalidated.irradiance,
            stale_error: relative_rms(&last.irradiance, &regenerated.irradiance),
            regenerated: regenerated.stats.clone(),
            regenerate_s,
            revalidated: revalidated.stats.clone(),
            revalidate_s,
        });
        last = revalidated;
    }
    Ok(rows)
}

/// The walk played in the game loop.
pub struct Played {
    /// Frames a second the game got (wall time between its calls, first frame left out).
    pub fps: f64,
    /// The render thread's mean time a frame, and the ages of the frames' lighting.
    pub busy_ms: f64,
    pub ages: Vec<u64>,
    /// Updates the frames used, and their mean wall time.
    pub updates: usize,
    pub update_ms: f64,
}

/// Plays the walk for `frames` frames of `size` x `size` at one sample through the frame
/// driver (`platoon::game::start`, every device), the man moving a tenth of a step and his
/// clock 1/30 s each frame, the links updated as `gi_update` says.
pub fn play(
    character: &Scene,
    cells: u32,
    options: LinksOptions,
    gi_update: GiUpdate,
    frames: usize,
    size: u32,
) -> Result<Played> {
    let (scene, node) = walk_in_a_room(character, cells)?;
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).map_err(anyhow::Error::msg)?;
    let mut game = GameOptions::new(DriverOptions::new(size, size));
    game.driver.method = Method::new(Links::new(options));
    game.driver.gi_update = gi_update;
    let mut driver = start(scene, &game)?;
    let mut stats = Vec::new();
    let mut clock = Instant::now();
    for frame in 0..=frames {
        let step = frame as f64 / 10.0;
        driver.scene().push(Edit::Time(frame as f32 / 30.0))?;
        driver.scene().push(Edit::Placement {
            node,
            placement: walk_step(step),
        })?;
        let out = driver.frame(camera)?;
        if frame == 1 {
            // The first frame waited for the first solution and compiled the kernels.
            clock = Instant::now();
        }
        stats.extend(out.finished.map(|f| f.stats));
    }
    let fps = (frames - 1) as f64 / clock.elapsed().as_secs_f64();
    stats.extend(driver.finish()?.map(|f| f.stats));
    let stats = &stats[1..];
    let gi: Vec<_> = stats.iter().filter_map(|s| s.gi.as_ref()).collect();
    let fresh: Vec<f64> = gi
        .iter()
        .filter(|g| !g.update.is_zero())
        .map(|g| g.update.as_secs_f64() * 1e3)
        .collect();
    Ok(Played {
        fps,
        busy_ms: stats.iter().map(|s| s.busy.as_secs_f64()).sum::<f64>() * 1e3
            / stats.len().max(1) as f64,
        ages: gi.iter().map(|g| g.age).collect(),
        updates: fresh.len(),
        update_ms: if fresh.is_empty() {
            0.0
        } else {
            fresh.iter().sum::<f64>() / fresh.len() as f64
        },
    })
}

/// RMS of `a - b` relative to the RMS of `b` (rgb of each element).
fn relative_rms(a: &[[f32; 4]], b: &[[f32; 4]]) -> f64 {
    let (mut diff, mut norm) = (0.0f64, 0.0f64);
    for (x, y) in a.iter().zip(b) {
        for c in 0..3 {
            diff += (x[c] as f64 - y[c] as f64).powi(2);
            norm += (y[c] as f64).powi(2);
        }
    }
    (diff / norm.max(1e-30)).sqrt()
}

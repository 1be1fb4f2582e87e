//! Embedding platoon in a game loop: the frame driver renders each frame while the game goes on
//! with the next, converges while the camera rests, restarts when it moves, and holds a frame
//! time by scaling the samples per frame. Prints what each frame cost.
//!
//! ```sh
//! cargo run --release --example game_loop -- [SCENE.glb] [--devices lavapipe:1,1] [--frames 60] [--target-ms 40]
//! ```

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result};
use glam::Vec3;
use platoon::core::scene::camera::Camera;
use platoon::devices::DeviceSpec;
use platoon::drive::DriverOptions;
use platoon::game::{start, GameOptions};

fn main() -> Result<()> {
    let mut scene_path: Option<PathBuf> = None;
    let mut spec: DeviceSpec = "lavapipe:1,1".parse().map_err(anyhow::Error::msg)?;
    let mut frames = 60u32;
    let mut target_ms = 40.0f64;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().with_context(|| format!("{a} needs a value"));
        match a.as_str() {
            "--devices" => spec = value()?.parse().map_err(anyhow::Error::msg)?,
            "--frames" => frames = value()?.parse()?,
            "--target-ms" => target_ms = value()?.parse()?,
            other => scene_path = Some(other.into()),
        }
    }

    let scene = platoon::load_scene(scene_path.as_deref())?;
    let (lo, hi) = scene.pose(0.0).bounds();
    let (center, radius) = ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3));
    let mut options = GameOptions::new(DriverOptions::new(160, 120));
    options.devices = spec;
    options.driver.target = Some(Duration::from_secs_f64(target_ms * 1e-3));
    let mut driver = start(scene, &options)?;

    let mut last = None;
    for f in 0..frames {
        // The camera orbits for a second of frames, then rests: the image converges.
        let a = f.min(frames / 2) as f32 * 0.05;
        let eye = center + radius * Vec3::new(2.2 * a.sin(), 0.8, 2.2 * a.cos());
        let out = driver.frame(Camera::look_at(eye, center, 0.9))?;
        if let Some(done) = out.finished {
            let s = &done.stats;
            println!(
                "frame {:3}: {:5.1} ms busy, {:3} spp, f = {:.3} ({:?}), idle {:4.1}%",
                s.frame,
                s.busy.as_secs_f64() * 1e3,
                s.plan.spp,
                s.weight,
                s.plan.join,
                100.0 * s.idle_fraction,
            );
            for failure in &s.failures {
                eprintln!("tracer {} was dropped: {}", failure.tracer, failure.message);
            }
            last = Some(done.film);
        }
    }
    if let Some(done) = driver.finish()? {
        last = Some(done.film);
    }
    if let Some(film) = last {
        platoon::core::output::write_image(std::path::Path::new("game_loop.png"), &film, &[])?;
        println!("last frame written to game_loop.png");
    }
    Ok(())
}

//! Embedding platoon in a loop: render frames of an orbiting camera on several tracers, with the
//! balancer re-cutting the lines every frame, and print what each frame cost.
//!
//! ```sh
//! cargo run --example game_loop -- [SCENE.glb] [--devices lavapipe:1,1] [--frames 16]
//! ```

use std::path::PathBuf;

use anyhow::{Context, Result};
use glam::Vec3;
use platoon::core::balance;
use platoon::core::frame::FrameParams;
use platoon::core::scene::camera::Camera;
use platoon::devices::{self, DeviceSpec};
use platoon::tracer::Sampling;

fn main() -> Result<()> {
    let mut scene_path: Option<PathBuf> = None;
    let mut spec: DeviceSpec = "lavapipe:1,1".parse().map_err(anyhow::Error::msg)?;
    let mut frames = 16u32;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--devices" => {
                spec = args
                    .next()
                    .context("--devices needs a value")?
                    .parse()
                    .map_err(anyhow::Error::msg)?
            }
            "--frames" => frames = args.next().context("--frames needs a value")?.parse()?,
            other => scene_path = Some(other.into()),
        }
    }

    // Load once; the scene is uploaded once to every tracer.
    let scene = platoon::load_scene(scene_path.as_deref())?;
    let prepared = platoon::prepare(scene, &platoon::PrepareOptions::default())?;
    let policy = balance::by_name("cost-aware").expect("a known balancer");
    let mut renderer = devices::renderer(&spec, &prepared.gpu, policy, false, Sampling::Mis)?;

    let (lo, hi) = prepared.posed.bounds();
    let (center, radius) = ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3));
    let mut last = None;
    for f in 0..frames {
        // The game moves the camera; platoon renders the frame with it.
        let a = f as f32 * 0.1;
        let eye = center + radius * Vec3::new(2.2 * a.sin(), 0.8, 2.2 * a.cos());
        let mut params = FrameParams::new(128, 96, 4, Camera::look_at(eye, center, 0.9));
        params.frame = f;
        let frame = renderer.render_frame(&params)?;
        let bands: Vec<String> = frame
            .tracers
            .iter()
            .map(|t| format!("{}..{}", t.y0, t.y1))
            .collect();
        println!(
            "frame {f:3}: {:6.1} ms, idle {:4.1}%, bands [{}]",
            frame.wall_time.as_secs_f64() * 1e3,
            100.0 * frame.idle_fraction,
            bands.join(" ")
        );
        for failure in &frame.failures {
            eprintln!(
                "tracer {} failed and was dropped: {}",
                failure.tracer, failure.message
            );
        }
        last = Some(frame.film);
    }
    if let Some(film) = last {
        platoon::core::output::write_image(std::path::Path::new("game_loop.png"), &film, &[])?;
        println!("last frame written to game_loop.png");
    }
    Ok(())
}

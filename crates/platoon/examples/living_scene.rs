//! A game embedding platoon with a living scene: a character walks (its skin refitted every
//! frame), an object circles it, and the game asks the CPU what the centre of the screen sees,
//! while the updater builds the next frame on its own thread and the tracers render this one.
//!
//! ```sh
//! cargo run --example living_scene -- [CHARACTER.glb] [--devices lavapipe:1,1] [--frames 24]
//! ```
//! (CHARACTER defaults to ../shared/scenes/CesiumMan.glb.)

use std::path::PathBuf;

use anyhow::{Context, Result};
use glam::{DVec3, Quat, Vec3};
use platoon::core::balance;
use platoon::core::frame::FrameParams;
use platoon::core::scene::camera::Camera;
use platoon::core::scene::environment::Environment;
use platoon::core::scene::Placement;
use platoon::devices::{self, DeviceSpec};
use platoon::drive::Edit;
use platoon::drive::{Pipeline, QueryScene};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::Sampling;

fn main() -> Result<()> {
    let mut character = PathBuf::from("../shared/scenes/CesiumMan.glb");
    let mut spec: DeviceSpec = "lavapipe:1,1".parse().map_err(anyhow::Error::msg)?;
    let mut frames = 24u32;
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
            other => character = other.into(),
        }
    }

    // The world: the character, and a second copy of its first mesh as a moving prop.
    let mut scene = platoon::load_scene(Some(&character))?;
    scene.environment = Some(Environment::Constant(Vec3::splat(0.8)));
    let walk = scene
        .animations
        .first()
        .map_or(1.0, |a| a.duration().max(1e-3));
    let (lo, hi) = scene.pose(0.0).bounds();
    let (center, size) = ((lo + hi) * 0.5, (hi - lo).max_element().max(1e-3));
    let camera = Camera::look_at(center + Vec3::new(0.0, 0.3, 2.2) * size, center, 0.8);

    let (mut pipeline, first) = Pipeline::new(scene, 0.0, DVec3::ZERO)?;
    let prop = pipeline
        .push(Edit::AddInstance {
            mesh: 0,
            placement: Placement::at(center.as_dvec3()),
        })?
        .expect("an added instance has a node");
    let policy = balance::by_name("cost-aware").expect("a known balancer");
    let tracers = devices::create_tracers(&spec, &first, false, Sampling::Mis)?;
    let mut renderer = Renderer::new(tracers, policy);
    let mut queries = QueryScene::new(&first);

    pipeline.submit()?;
    let mut last = None;
    for f in 0..frames {
        // This frame's generation, built while the previous frame rendered.
        let generation = pipeline.take()?;
        // The game's changes for the next frame: time runs, the prop circles.
        let a = 0.3 * f as f64;
        pipeline.push(Edit::Time(((f + 1) as f32 / 30.0) % walk))?;
        pipeline.push(Edit::Placement {
            node: prop,
            placement: Placement {
                translation: center.as_dvec3()
                    + DVec3::new(a.cos(), 0.2, a.sin()) * 0.6 * size as f64,
                rotation: Quat::from_rotation_y(a as f32),
                scale: Vec3::splat(0.3),
            },
        })?;
        pipeline.submit()?;

        // The tracers and the game's own copy take this frame's changes, then the frame renders.
        let uploaded = renderer.apply_commit(&generation.commit, f)?;
        queries.apply_commit(&generation.commit);
        let mut params = FrameParams::new(128, 96, 4, camera);
        params.frame = f;
        let frame = renderer.render_frame(&params)?;

        // What is under the crosshair, asked on the CPU of the frame just rendered.
        let basis = camera.basis(params.width, params.height);
        let dir = basis.pixel_centre_direction(64, 48, 128, 96);
        let seen = match queries.closest_hit(basis.origin, dir, f32::INFINITY) {
            Some(hit) => format!("instance {} at {:.2}", hit.instance, hit.t),
            None => "sky".into(),
        };
        println!(
            "frame {f:3}: {:6.1} ms, update {:4.1} ms, {:7} bytes to each tracer, crosshair: {seen}",
            frame.wall_time.as_secs_f64() * 1e3,
            (generation.times.pose + generation.times.bottom_level + generation.times.flatten)
                .as_secs_f64()
                * 1e3,
            uploaded.first().map_or(0, |u| u.1),
        );
        last = Some(frame.film);
    }
    if let Some(film) = last {
        platoon::core::output::write_image(std::path::Path::new("living_scene.png"), &film, &[])?;
        println!("last frame written to living_scene.png");
    }
    Ok(())
}

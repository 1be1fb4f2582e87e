//! A scripted game loop over a living scene through the facade (`Request::start_game`): the
//! built-in box at 24 x 16, 2 samples a frame on two lavapipe tracers; a copy of its first mesh
//! added, two frames, the copy moved, two frames. Writes the last frame's film as raw
//! little-endian f32 (height x width x RGB) to the path given. The Python module's test runs
//! the same script through `platoon.Game` and holds its last frame to this one bit for bit
//! (crates/platoon-py/tests/test_platoon.py).
//!
//! ```sh
//! cargo run --example scripted_game -- last.f32
//! ```

use anyhow::{Context, Result};
use glam::{DVec3, Quat, Vec3};
use platoon::core::scene::camera::Camera;
use platoon::core::scene::Placement;
use platoon::drive::Edit;

/// The prop's placement: `x` across the box, a third of the mesh's size.
fn prop_at(x: f64) -> Placement {
    Placement {
        translation: DVec3::new(x, 0.6, 0.0),
        rotation: Quat::IDENTITY,
        scale: Vec3::splat(0.3),
    }
}

fn main() -> Result<()> {
    let out = std::env::args()
        .nth(1)
        .context("usage: scripted_game OUT.f32")?;
    let request = platoon::Request {
        width: 24,
        height: 16,
        spp: 2,
        devices: "lavapipe:1,1".parse().map_err(anyhow::Error::msg)?,
        ..Default::default()
    };
    let camera = Camera::look_at(
        Vec3::new(0.0, 1.0, 3.4),
        Vec3::new(0.0, 1.0, 0.0),
        40f32.to_radians(),
    );
    let mut game = request.start_game(None)?;
    let prop = game
        .scene()
        .push(Edit::AddInstance {
            mesh: 0,
            placement: prop_at(-0.3),
        })?
        .context("an added instance has a node")?;
    game.frame(camera)?;
    game.frame(camera)?;
    game.scene().push(Edit::Placement {
        node: prop,
        placement: prop_at(0.3),
    })?;
    game.frame(camera)?;
    game.frame(camera)?;
    let last = game.finish()?.context("the game ended without a frame")?;
    let bytes: Vec<u8> = last
        .film
        .pixels
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(&out, bytes).with_context(|| format!("{out}: cannot write"))?;
    eprintln!(
        "{out}: frame {} of {} samples a pixel",
        last.stats.frame,
        last.stats.film_samples.unwrap_or(0)
    );
    Ok(())
}

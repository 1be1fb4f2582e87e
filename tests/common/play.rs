//! The frame driver on lavapipe tracers for the tests of what frames learn from the frames
//! before them (the world cache, light reuse): a run of frames and each frame's own estimate.
#![allow(dead_code)]

use glam::DVec3;
use platoon::core::balance::by_name;
use platoon::core::output::Film;
use platoon::core::scene::camera::Camera;
use platoon::devices::create_tracers;
use platoon::drive::{DriverOptions, FinishedFrame, FrameDriver, Pipeline};
use platoon::tracer::Sampling;

/// Plays `frames` still frames of `scene` from `camera` on the tracers of `spec`.
pub fn play(
    scene: platoon::core::Scene,
    camera: Camera,
    spec: &str,
    options: DriverOptions,
    frames: u32,
) -> Vec<FinishedFrame> {
    play_with(scene, spec, "cost-aware", options, frames, |_| camera)
}

/// ... under `balancer`, frame f seen from `camera_of(f)`.
pub fn play_with(
    scene: platoon::core::Scene,
    spec: &str,
    balancer: &str,
    options: DriverOptions,
    frames: u32,
    camera_of: impl Fn(u32) -> Camera,
) -> Vec<FinishedFrame> {
    super::common::init();
    let (pipeline, first) = Pipeline::new(scene, 0.0, DVec3::ZERO).unwrap();
    let tracers = create_tracers(&spec.parse().unwrap(), &first, true, Sampling::Mis).unwrap();
    let mut d = FrameDriver::new(
        pipeline,
        &first,
        tracers,
        by_name(balancer).unwrap(),
        options,
    )
    .unwrap();
    let mut done = Vec::new();
    for f in 0..frames {
        done.extend(d.frame(camera_of(f)).unwrap().finished);
    }
    done.extend(d.finish().unwrap());
    for f in &done {
        assert!(f.stats.failures.is_empty(), "{:?}", f.stats.failures);
        assert!(
            f.stats.device_messages.is_empty(),
            "{:?}",
            f.stats.device_messages
        );
    }
    done
}

/// Each frame's own estimate, from the still view's film before and after it (exact sums).
pub fn own_frames(run: &[FinishedFrame]) -> Vec<Film> {
    let mut out = Vec::new();
    let (mut before, mut n0) = (None::<&Film>, 0u32);
    for f in run {
        let n = f.stats.film_samples.expect("a still view sums");
        let pixels = f
            .film
            .pixels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                std::array::from_fn(|k| {
                    let earlier = before.map_or(0.0, |b| b.pixels[i][k] * n0 as f32);
                    (p[k] * n as f32 - earlier) / (n - n0) as f32
                })
            })
            .collect();
        out.push(Film {
            width: f.film.width,
            height: f.film.height,
            pixels,
        });
        (before, n0) = (Some(&f.film), n);
    }
    out
}

/// The mean of `films`, pixel by pixel.
pub fn average(films: &[Film]) -> Film {
    let n = films.len() as f32;
    Film {
        width: films[0].width,
        height: films[0].height,
        pixels: (0..films[0].pixels.len())
            .map(|i| std::array::from_fn(|k| films.iter().map(|f| f.pixels[i][k]).sum::<f32>() / n))
            .collect(),
    }
}

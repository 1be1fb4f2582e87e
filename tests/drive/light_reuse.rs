//! Light reuse (issue 43, `method::path::light_reuse`: ReSTIR DI's temporal and spatial reuse of
//! resampled direct light from the previous frame's reservoirs): the unbiased setting converges
//! to the path tracer's mean with less noise a frame than resampling alone; one tracer and
//! three show the same bits.

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/play.rs"]
mod play;

use common::*;
use glam::DVec3;
use platoon::core::balance::by_name;
use platoon::core::frame::FrameParams;
use platoon::core::method::path::light_reuse::{LightReuse, ReuseStats};
use platoon::core::method::path::Learned;
use platoon::core::output::Film;
use platoon::core::scene::camera::Camera;
use platoon::devices::create_tracers;
use platoon::drive::{DriverOptions, FinishedFrame, Pipeline};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::Sampling;
use play::{own_frames, play, play_with};

fn reference(scene: platoon::core::Scene, camera: Camera, w: u32, h: u32, spp: u32) -> Film {
    let (_, first) = Pipeline::new(scene, 0.0, DVec3::ZERO).unwrap();
    let tracers =
        create_tracers(&"lavapipe:1".parse().unwrap(), &first, true, Sampling::Mis).unwrap();
    let mut renderer = Renderer::new(tracers, by_name("none").unwrap());
    let mut p = FrameParams::new(w, h, spp, camera);
    p.path_loop.max_depth = 2;
    renderer.render_frame(&p).unwrap().film
}

fn hall() -> (platoon::core::Scene, Camera) {
    let scene = load_generated(&platoon_scenegen::many_lights::many_lights());
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    (scene, camera)
}

/// RMS error over the pixels that do not see a light (whose edges' jitter is no light's noise).
fn lit_rmse(f: &Film, r: &Film) -> f64 {
    let (mut s, mut n) = (0.0, 0.0);
    for (a, b) in f.pixels.iter().zip(&r.pixels) {
        if luminance(*b) < 1.0 {
            s += (luminance(*a) - luminance(*b)).powi(2);
            n += 1.0;
        }
    }
    (s / n).sqrt()
}

/// The last frame's own estimate of `frames` played with `seed`.
fn last_frame(
    scene: &platoon::core::Scene,
    camera: Camera,
    mut o: DriverOptions,
    seed: u32,
    frames: u32,
) -> Film {
    o.options.seed = seed;
    let run = play(scene.clone(), camera, "lavapipe:1", o, frames);
    own_frames(&run).pop().unwrap()
}

/// The mean over the pixels `lit` (those that do not see the light: its edges' jitter is
/// every estimator's noise alike).
fn mean_over(f: &Film, lit: &[usize]) -> f64 {
    lit.iter().map(|&i| luminance(f.pixels[i])).sum::<f64>() / lit.len() as f64
}

/// Resampled light over 4 candidates, direct light only (max depth 2: where the reuse acts).
fn options(w: u32, h: u32, reuse: Option<LightReuse>) -> DriverOptions {
    let mut o = DriverOptions::new(w, h);
    o.method = resampled(4);
    o.method.path_mut().unwrap().learning.light_reuse = reuse;
    o.path_loop.max_depth = 2;
    o
}

/// The unbiased setting's last frame (after three frames of history) over independent plays
/// agrees with resampling without reuse played with the same seeds (the same camera rays:
/// their difference leaves out the noise both share) and with the path tracer's converged
/// mean in the many-light hall; its error a frame is lower than resampling's.
#[test]
fn unbiased_reuse_converges_to_the_path_tracers_mean_with_less_noise() {
    let (w, h, frames, seeds) = (32u32, 24u32, 4u32, 48u32);
    let (scene, camera) = hall();
    let reference = reference(scene.clone(), camera, w, h, 4096);
    let lit: Vec<usize> = (0..reference.pixels.len())
        .filter(|&i| luminance(reference.pixels[i]) < 1.0)
        .collect();
    let r = mean_over(&reference, &lit);
    let play_all = |reuse: Option<LightReuse>| -> Vec<Film> {
        (0..seeds)
            .map(|s| last_frame(&scene, camera, options(w, h, reuse), s, frames))
            .collect()
    };
    let plain = play_all(None);
    let reused = play_all(Some(LightReuse::default()));
    let means = |films: &[Film]| -> Vec<f64> { films.iter().map(|f| mean_over(f, &lit)).collect() };
    let (pm, reused_means) = (means(&plain), means(&reused));
    let (m, e) = mean_and_stderr(reused_means.iter().copied());
    let (d, de) = mean_and_stderr(reused_means.iter().zip(&pm).map(|(a, b)| a - b));
    let z = (m - r) / e;
    let error =
        |films: &[Film]| films.iter().map(|f| lit_rmse(f, &reference)).sum::<f64>() / seeds as f64;
    let (plain_error, reused_error) = (error(&plain), error(&reused));
    eprintln!(
        "reused {m:.5} ± {e:.5} vs reference {r:.5} ({z:.1} sigma); minus resampled's {d:.5} ± \
         {de:.5} ({:.1} sigma); error a frame {reused_error:.4} vs resampled's {plain_error:.4}",
        d / de
    );
    // Resampling alone falls 3% (3 sigma) below the reference here: its rare bright samples
    // (sconces by the walls), which 4096 samples a pixel catch and these plays under-count. It
    // agrees with MIS elsewhere (tests/kernel/estimators.rs); the difference paired by seed is
    // the sharp test of the reuse (measured -0.3 and -0.8 sigma over 64 seeds).
    assert!(
        (m - r).abs() < 0.05 * r,
        "{:.1}% from the reference",
        100.0 * (m - r) / r
    );
    assert!((d / de).abs() < 3.5, "{:.1} sigma from resampling", d / de);
    // Measured 0.90 (direct light, 4 candidates, three frames of history).
    assert!(
        reused_error < 0.95 * plain_error,
        "error a frame {reused_error:.4} vs resampled's {plain_error:.4}"
    );
}

/// The reuse reads the previous frame's reservoirs of the whole image: one tracer and three
/// show the same bits and leave the same reservoirs, the camera moving, under two balancers.
#[test]
fn one_and_three_tracers_reuse_the_same_reservoirs() {
    let (scene, camera) = hall();
    let mut o = options(32, 24, Some(LightReuse::default()));
    o.path_loop.max_depth = 4;
    for balancer in ["cost-aware", "perfect-smooth"] {
        let runs: Vec<Vec<FinishedFrame>> = ["lavapipe:1", "lavapipe:1,1,1"]
            .iter()
            .map(|spec| {
                play_with(scene.clone(), spec, balancer, o.clone(), 5, |f| {
                    let mut c = camera;
                    c.camera_to_world.w_axis.x += 0.05 * f as f32;
                    c
                })
            })
            .collect();
        for (a, b) in runs[0].iter().zip(&runs[1]) {
            let f = a.stats.frame;
            assert!(a.film == b.film, "{balancer}, frame {f}: the films differ");
            assert_eq!(reused(a), reused(b), "frame {f}");
        }
        let last = reused(runs[0].last().unwrap());
        assert!(last.samples > 500 && last.mean_candidates > 8.0, "{last:?}");
    }
}

/// What a frame's reservoirs hold.
fn reused(f: &FinishedFrame) -> ReuseStats {
    let learned = f
        .stats
        .learned::<Learned>()
        .expect("the path tracer's report");
    learned.light_reuse.expect("light reuse's")
}

//! The world cache (issue 43, `method::path::world_cache`): its light agrees with the closed form
//! where the radiance a surface reflects is the same everywhere (inside a glowing sphere), with
//! less noise than the paths it stands for; its bias in the Cornell box is measured and bounded
//! against the path tracer; one tracer and three train the same cache and show the same bits.

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/play.rs"]
mod play;

use common::*;
use glam::{DVec3, Vec3};
use platoon::core::balance::by_name;
use platoon::core::frame::FrameParams;
use platoon::core::method::path::world_cache::{CacheUpdate, WorldCacheOptions};
use platoon::core::method::path::Learned;
use platoon::core::output::Film;
use platoon::core::scene::camera::Camera;
use platoon::devices::create_tracers;
use platoon::drive::{DriverOptions, FinishedFrame, Pipeline};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::Sampling;
use play::{own_frames, play, play_with};

fn cache_options(resolution: u32, train_stride: u32) -> WorldCacheOptions {
    WorldCacheOptions {
        resolution,
        train_stride,
        ..Default::default()
    }
}

/// The camera at the centre of a closed sphere whose inside glows with 0.5 and reflects half
/// of what it receives: every point sees 0.5 / (1 - 0.5) = 1.
fn glowing_sphere() -> (platoon::core::Scene, Camera) {
    let mut wall = platoon::core::scene::cornell::lambertian("wall", Vec3::splat(0.5));
    wall.emissive = Vec3::splat(0.5);
    wall.double_sided = true;
    let sphere = mesh_from(&platoon_scenegen::uv_sphere(24, 32), 0);
    let scene = scene_of(
        vec![(sphere, Vec3::ZERO, 1.0)],
        vec![wall],
        Vec3::new(0.0, 0.0, 0.1),
        Vec3::Z,
        1.2,
    );
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    (scene, camera)
}

fn rms_about(film: &Film, value: f64) -> (f64, f64) {
    let n = film.pixels.len() as f64;
    let mean = film.pixels.iter().map(|p| luminance(*p)).sum::<f64>() / n;
    let rms = (film
        .pixels
        .iter()
        .map(|p| (luminance(*p) - value).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    (mean, rms)
}

#[test]
fn inside_a_glowing_sphere_the_cache_gives_the_closed_form_with_less_noise() {
    let frames = 12;
    let mut options = DriverOptions::new(24, 24);
    let (scene, camera) = glowing_sphere();
    let plain = play(scene.clone(), camera, "lavapipe:1", options.clone(), frames);
    options.method.path_mut().unwrap().learning.world_cache = Some(cache_options(8, 1));
    let cached = play(scene, camera, "lavapipe:1", options, frames);
    let stats = cache(cached.last().unwrap());
    eprintln!("cache after {frames} frames: {stats:?}");
    assert!(stats.cells > 50 && stats.records > 400, "{stats:?}");
    // Each frame's own estimate, the cache read from the second frame on.
    let (mut plain_rms, mut cached_rms) = (0.0, 0.0);
    for (f, (p, c)) in own_frames(&plain)
        .iter()
        .zip(&own_frames(&cached))
        .enumerate()
        .skip(4)
    {
        let (pm, pr) = rms_about(p, 1.0);
        let (cm, cr) = rms_about(c, 1.0);
        eprintln!("frame {f}: plain {pm:.4} (rms {pr:.4}), cached {cm:.4} (rms {cr:.4})");
        (plain_rms, cached_rms) = (plain_rms + pr, cached_rms + cr);
    }
    // The film sums the frames: the cache's mean is the closed form's.
    let (mean, _) = rms_about(&cached.last().unwrap().film, 1.0);
    assert!((mean - 1.0).abs() < 0.01, "cached film mean {mean}");
    let (mean, _) = rms_about(&plain.last().unwrap().film, 1.0);
    assert!((mean - 1.0).abs() < 0.01, "plain film mean {mean}");
    assert!(
        cached_rms < 0.5 * plain_rms,
        "cached {cached_rms} vs plain {plain_rms}"
    );
}

fn cornell() -> (platoon::core::Scene, Camera) {
    let scene = platoon::load_scene(None).unwrap();
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    (scene, camera)
}

#[test]
fn one_tracer_and_three_train_the_same_cache_and_show_the_same_bits() {
    let mut options = DriverOptions::new(32, 32);
    options.method.path_mut().unwrap().learning.world_cache = Some(cache_options(16, 2));
    let runs: Vec<Vec<FinishedFrame>> = ["lavapipe:1", "lavapipe:1,1,1"]
        .iter()
        .map(|spec| {
            let (scene, camera) = cornell();
            play(scene, camera, spec, options.clone(), 6)
        })
        .collect();
    for (a, b) in runs[0].iter().zip(&runs[1]) {
        let f = a.stats.frame;
        assert!(a.film == b.film, "frame {f}: the films differ");
        assert_eq!(cache(a), cache(b), "frame {f}");
    }
    let last = cache(runs[0].last().unwrap());
    assert!(last.cells > 100, "{last:?}");
}

#[test]
fn the_cache_bias_in_the_cornell_box_is_bounded_and_its_noise_lower() {
    let (w, h, frames) = (32u32, 32u32, 24u32);
    let (scene, camera) = cornell();
    let mut options = DriverOptions::new(w, h);
    options.spp = 8;
    let plain = play(scene.clone(), camera, "lavapipe:1", options.clone(), frames);
    options.method.path_mut().unwrap().learning.world_cache = Some(cache_options(32, 1));
    let cached = play(scene.clone(), camera, "lavapipe:1", options, frames);
    // The reference: the path tracer at 1024 samples.
    let (_, first) = Pipeline::new(scene, 0.0, DVec3::ZERO).unwrap();
    let tracers =
        create_tracers(&"lavapipe:1".parse().unwrap(), &first, true, Sampling::Mis).unwrap();
    let mut renderer = Renderer::new(tracers, by_name("none").unwrap());
    let reference = renderer
        .render_frame(&FrameParams::new(w, h, 4096, camera))
        .unwrap()
        .film;
    let mean =
        |f: &Film| f.pixels.iter().map(|p| luminance(*p)).sum::<f64>() / f.pixels.len() as f64;
    // The last 16 frames (the cache warm), averaged: their mean and error against the reference.
    let last = |run: &[FinishedFrame]| -> Film {
        let own = own_frames(run);
        let tail = &own[own.len() - 16..];
        Film {
            width: w,
            height: h,
            pixels: (0..(w * h) as usize)
                .map(|i| {
                    std::array::from_fn(|k| tail.iter().map(|f| f.pixels[i][k]).sum::<f32>() / 16.0)
                })
                .collect(),
        }
    };
    let (pf, cf) = (&last(&plain), &last(&cached));
    let r = mean(&reference);
    eprintln!(
        "image mean: reference {r:.4}, plain film {:.4}, cached film {:.4}; rmse plain {:.4}, cached {:.4}",
        mean(pf),
        mean(cf),
        rmse(pf, &reference),
        rmse(cf, &reference)
    );
    // Blocks of 8 x 8 pixels: the cache's relative bias where it is largest.
    let block = |f: &Film, bx: u32, by: u32| {
        let mut s = 0.0;
        for y in by * 8..by * 8 + 8 {
            for x in bx * 8..bx * 8 + 8 {
                s += luminance(f.pixels[(y * w + x) as usize]);
            }
        }
        s / 64.0
    };
    let mut worst = 0.0f64;
    for by in 0..h / 8 {
        for bx in 0..w / 8 {
            let (c, r) = (block(cf, bx, by), block(&reference, bx, by));
            if r > 0.05 {
                worst = worst.max((c - r).abs() / r);
            }
        }
    }
    eprintln!("largest block bias {worst:.4}");
    // Measured: 0.9% and 3.0% (the plain path tracer's own: 1.4% and 3.2%, its noise and the
    // reference's). The box is lit directly, mostly: the cache leaves its noise as it is.
    assert!((mean(cf) - r).abs() / r < 0.03, "image mean bias");
    assert!(worst < 0.08, "block bias {worst}");
    assert!(
        rmse(cf, &reference) < 1.1 * rmse(pf, &reference),
        "the cache added noise"
    );
}

#[test]
fn every_technique_at_once_gives_the_same_bits_on_one_and_three_tracers_under_every_balancer() {
    // Resampled light reusing reservoirs, the world cache and the device denoiser, the camera
    // moving: what a game runs with `--realtime --light-reuse --world-cache --denoise
    // atrous-device`.
    let mut options = DriverOptions::new(24, 24);
    options.method = resampled(8);
    options.method.path_mut().unwrap().learning.light_reuse = Some(Default::default());
    options.method.path_mut().unwrap().learning.world_cache = Some(cache_options(16, 2));
    options.denoise = platoon::core::denoise::Denoiser::AtrousDevice;
    let (scene, camera) = cornell();
    let moving = |f: u32| {
        let mut c = camera;
        c.camera_to_world =
            glam::Mat4::from_translation(Vec3::X * 0.01 * f as f32) * camera.camera_to_world;
        c
    };
    let one = play_with(
        scene.clone(),
        "lavapipe:1",
        "none",
        options.clone(),
        4,
        moving,
    );
    for balancer in platoon::core::balance::NAMES {
        let three = play_with(
            scene.clone(),
            "lavapipe:1,1,1",
            balancer,
            options.clone(),
            4,
            moving,
        );
        for (a, b) in one.iter().zip(&three) {
            let f = a.stats.frame;
            assert!(a.film == b.film, "{balancer}, frame {f}: the films differ");
            assert!(
                a.denoised == b.denoised,
                "{balancer}, frame {f}: denoised differently"
            );
            // The cache's update and the reservoirs' stats.
            assert_eq!(a.stats.learned, b.stats.learned, "{balancer}, frame {f}");
        }
    }
    assert!(cache(one.last().unwrap()).cells > 0);
}

/// What a frame's training paths did to the cache.
fn cache(f: &FinishedFrame) -> CacheUpdate {
    let learned = f
        .stats
        .learned::<Learned>()
        .expect("the path tracer's report");
    learned.world_cache.expect("the world cache's")
}

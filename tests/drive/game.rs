//! The game loop (issue 9): the frame driver's film converges exactly while the view is still,
//! restarts when the camera moves, keeps a floor on the blend weight while objects move, and
//! the samples per frame follow a target frame time.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use glam::{DVec3, Vec3};
use platoon::core::balance::by_name;
use platoon::core::drive::plan::Join;
use platoon::core::drive::scaling::BelowOneSample;
use platoon::core::drive::Edit;
use platoon::core::drive::{DriverOptions, FrameDriver, FrameStats, Pipeline};
use platoon::core::frame::renderer::Renderer;
use platoon::core::frame::FrameParams;
use platoon::core::scene::camera::Camera;
use platoon::core::scene::Placement;
use platoon::devices::{create_tracers, DeviceSpec};
use platoon::tracer::Sampling;

const W: u32 = 32;
const H: u32 = 32;

fn cornell() -> (platoon::core::Scene, Camera) {
    let scene = platoon::load_scene(None).unwrap();
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    (scene, camera)
}

fn driver(
    spec: &str,
    options: DriverOptions,
) -> (FrameDriver, Camera, Vec<platoon::tracer::Tracer>) {
    init();
    let (scene, camera) = cornell();
    let (pipeline, first) = Pipeline::new(scene, 0.0, DVec3::ZERO).unwrap();
    let spec: DeviceSpec = spec.parse().unwrap();
    let tracers = create_tracers(&spec, &first, true, Sampling::Mis).unwrap();
    // A tracer of the same first generation, for the offline render to compare with.
    let offline =
        create_tracers(&"lavapipe:1".parse().unwrap(), &first, true, Sampling::Mis).unwrap();
    let d = FrameDriver::new(
        pipeline,
        &first,
        tracers,
        by_name("cost-aware").unwrap(),
        options,
    )
    .unwrap();
    (d, camera, offline)
}

/// Runs `frames` frames from `camera_of(frame)`, with `edit` before each, and returns every
/// finished frame's statistics and the last film.
fn run(
    d: &mut FrameDriver,
    frames: u32,
    mut camera_of: impl FnMut(u32) -> Camera,
    mut edit: impl FnMut(&mut FrameDriver, u32),
) -> (Vec<FrameStats>, platoon::core::output::Film) {
    let mut stats = Vec::new();
    for f in 0..frames {
        edit(d, f);
        if let Some(done) = d.frame(camera_of(f)).unwrap().finished {
            stats.push(done.stats);
        }
    }
    let done = d.finish().unwrap().expect("the last frame");
    stats.push(done.stats);
    for s in &stats {
        assert!(s.failures.is_empty(), "{:?}", s.failures);
        assert!(s.device_messages.is_empty(), "{:?}", s.device_messages);
    }
    (stats, done.film)
}

#[test]
fn still_frames_of_the_driver_are_bit_for_bit_one_offline_render() {
    // k frames of s samples on two tracers whose bands the balancer moves between frames, in
    // passes of 2 samples; the offline render takes k s samples in one band, in passes of 16.
    let (k, s) = (5u32, 3u32);
    let mut options = DriverOptions::new(W, H);
    options.spp = s;
    options.samples_per_pass = 2;
    let (mut d, camera, offline) = driver("lavapipe:1,1", options);
    let (stats, film) = run(&mut d, k, |_| camera, |_, _| {});
    let joins: Vec<Join> = stats.iter().map(|s| s.plan.join).collect();
    assert_eq!(joins[0], Join::Restart);
    assert!(joins[1..].iter().all(|j| *j == Join::Sum), "{joins:?}");
    assert_eq!(stats.last().unwrap().film_samples, Some(k * s));
    let weights: Vec<f32> = stats.iter().map(|s| s.weight).collect();
    assert_eq!(weights[k as usize - 1], 1.0 / k as f32);
    // The frame's cost map: every traced ray in some line; no per-line seconds from two
    // devices, whose times are not in one unit.
    for st in &stats {
        let rays: u64 = st.tracers.iter().map(|t| t.rays).sum();
        assert_eq!(st.line_rays.iter().sum::<u64>(), rays);
        assert_eq!(st.line_rays.len(), H as usize);
        assert!(st.line_seconds().is_none());
    }

    let mut renderer = Renderer::new(offline, by_name("none").unwrap());
    let reference = renderer
        .render_frame(&FrameParams::new(W, H, k * s, camera))
        .unwrap()
        .film;
    assert_eq!(film.count_non_finite(), 0);
    assert!(film.mean()[0] > 0.0);
    assert!(
        film == reference,
        "the driver's film differs from one render of {} spp",
        k * s
    );
}

#[test]
fn a_moving_camera_restarts_and_moving_objects_keep_the_floor() {
    let mut options = DriverOptions::new(W, H);
    options.spp = 1;
    options.blend_floor = 0.25;
    let (mut d, camera, _) = driver("lavapipe:1", options);
    let prop = d
        .scene()
        .push(Edit::AddInstance {
            mesh: 0,
            placement: Placement::at(DVec3::new(0.0, 0.5, 0.0)),
        })
        .unwrap()
        .unwrap();
    let mut moved = camera;
    moved.camera_to_world = glam::Mat4::from_translation(Vec3::X * 0.01) * camera.camera_to_world;
    // Frames 0-5 still (the prop's arrival is built during frame 0, rendered by frame 1), the
    // camera moves at 6, the prop moves from 9 on (edits rendered one frame later).
    let (stats, film) = run(
        &mut d,
        16,
        |f| if f < 6 { camera } else { moved },
        |d, f| {
            if f >= 9 {
                let p = Placement::at(DVec3::new(0.05 * f as f64, 0.5, 0.0));
                d.scene()
                    .push(Edit::Placement {
                        node: prop,
                        placement: p,
                    })
                    .unwrap();
            }
        },
    );
    // One tracer: its band's time spread over the lines by their rays (what
    // `bench game --record-costs` writes for bench balance).
    let seconds = stats[3]
        .line_seconds()
        .expect("one tracer rendered the frame");
    assert_eq!(seconds.len(), H as usize);
    let band = stats[3].tracers[0].wall_time.as_secs_f64();
    assert!((seconds.iter().sum::<f64>() - band).abs() < 1e-9 * band.max(1.0));
    let joins: Vec<Join> = stats.iter().map(|s| s.plan.join).collect();
    assert_eq!(joins[0], Join::Restart);
    assert!(
        matches!(joins[1], Join::Blend { .. }),
        "the prop arrived: {joins:?}"
    );
    assert_eq!(joins[6], Join::Restart, "{joins:?}");
    assert_eq!(stats[6].weight, 1.0);
    // Whatever moved changed the lines' costs: the balancer cuts those frames anew.
    assert!(stats[0].plan.rebalance && stats[1].plan.rebalance && stats[6].plan.rebalance);
    assert_eq!(stats[6].plan.first_sample, 0);
    assert_eq!(joins[7..10], [Join::Sum, Join::Sum, Join::Sum], "{joins:?}");
    for s in &stats[10..] {
        assert!(matches!(s.plan.join, Join::Blend { .. }), "{joins:?}");
        assert!(s.weight >= 0.25, "frame {}: f = {}", s.frame, s.weight);
        assert!(s.commit_bytes > 0);
        assert!(s.plan.rebalance, "frame {}: objects moved", s.frame);
    }
    assert_eq!(film.count_non_finite(), 0);
}

#[test]
fn below_one_sample_the_driver_scales_roulette_and_resolution_into_one_film() {
    // A target no lavapipe frame of 64x64 can meet: the scaler goes below one sample a frame
    // through both options.
    let mut options = DriverOptions::new(64, 64);
    options.spp = 1;
    options.target = Some(std::time::Duration::from_micros(200));
    options.below_one = BelowOneSample {
        roulette: true,
        resolution: true,
    };
    let (mut d, camera, _) = driver("lavapipe:1", options);
    let (stats, film) = run(&mut d, 12, |_| camera, |_, _| {});
    let last = stats.last().unwrap().plan;
    assert_eq!(last.spp, 1);
    assert!(last.rr_survival < 1.0, "{last:?}");
    assert!(last.resolution <= 0.5, "{last:?}");
    // The film keeps its size (the frames are upscaled into it) and holds no NaN.
    assert_eq!((film.width, film.height), (64, 64));
    assert_eq!(film.count_non_finite(), 0);
    assert!(film.mean()[0] > 0.0);
    // Frames at a reduced size hold a mean: they blend (f = 1/k while the size holds, at least
    // the floor when it changed), never sum; and a change of size does not restart the film.
    for pair in stats.windows(2) {
        let (before, now) = (pair[0].plan, pair[1].plan);
        if now.resolution < 1.0 || before.resolution < 1.0 {
            assert!(matches!(now.join, Join::Blend { .. }), "{now:?}");
        }
        if now.resolution != before.resolution {
            assert!(now.join.weight(now.frames_joined) >= 0.2, "{now:?}");
        }
    }
    // Rendered at the plan's size: the lines the balancer saw.
    let (_, h) = platoon::core::drive::driver::render_size(64, 64, last.resolution);
    assert_eq!(stats.last().unwrap().line_rays.len(), h as usize);
}

#[test]
fn without_the_options_one_sample_a_frame_is_the_floor() {
    let mut options = DriverOptions::new(W, H);
    options.spp = 4;
    options.target = Some(std::time::Duration::from_micros(200));
    let (mut d, camera, _) = driver("lavapipe:1", options);
    let (stats, _) = run(&mut d, 8, |_| camera, |_, _| {});
    let last = stats.last().unwrap().plan;
    assert_eq!((last.spp, last.rr_survival, last.resolution), (1, 1.0, 1.0));
    // Still frames of one sample sum exactly, as at any spp.
    assert_eq!(last.join, Join::Sum);
}

/// A method updated asynchronously (vertex links) without tracers of its own is refused by
/// name at construction, rather than failing at its first frame.
#[test]
fn an_asynchronous_update_without_its_own_tracers_is_refused() {
    init();
    let (scene, _) = cornell();
    let (pipeline, first) = Pipeline::new(scene, 0.0, DVec3::ZERO).unwrap();
    let tracers =
        create_tracers(&"lavapipe:1".parse().unwrap(), &first, true, Sampling::Mis).unwrap();
    let mut options = DriverOptions::new(16, 16);
    options.method =
        platoon::core::Method::Links(platoon::core::method::links::Links::new(Default::default()));
    options.gi_update = platoon::core::drive::GiUpdate::Asynchronous;
    let e = FrameDriver::new(pipeline, &first, tracers, by_name("none").unwrap(), options)
        .err()
        .expect("refused");
    assert!(
        e.to_string()
            .contains("asynchronous update of links needs tracers"),
        "{e}"
    );
}

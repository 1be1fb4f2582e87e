//! The game loop (issue 9): the frame driver's film converges exactly while the view is still,
//! restarts when the camera moves, keeps a floor on the blend weight while objects move, and
//! the samples per frame follow a target frame time.

#[path = "../common/mod.rs"]
mod common;
#[path = "../method/toy/grey.rs"]
mod toy;

use common::*;
use glam::{DVec3, Vec3};
use platoon::core::balance::by_name;
use platoon::core::denoise::temporal::{GBuffer, Temporal};
use platoon::core::denoise::Denoiser;
use platoon::core::frame::{FrameParams, Output};
use platoon::core::output::Film;
use platoon::core::scene::camera::Camera;
use platoon::core::scene::Placement;
use platoon::devices::{create_tracers, DeviceSpec};
use platoon::distribute::Collective as _;
use platoon::drive::plan::Join;
use platoon::drive::scaling::BelowOneSample;
use platoon::drive::Edit;
use platoon::drive::{DriverOptions, FinishedFrame, FrameDriver, FrameStats, Pipeline};
use platoon::schedule::renderer::Renderer;
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
    let (scene, camera) = cornell();
    driver_of(scene, spec, options, camera)
}

fn driver_of(
    scene: platoon::core::Scene,
    spec: &str,
    options: DriverOptions,
    camera: Camera,
) -> (FrameDriver, Camera, Vec<platoon::tracer::Tracer>) {
    init();
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

/// A finished frame carries what renders it again (`DriverOptions::keep_frame_scenes`, what
/// `bench game` measures its error with): a frame that restarted (the camera moved) while a
/// prop walked is one render of its generation's scene from its camera, bit for bit.
#[test]
fn a_finished_frame_keeps_the_scene_and_camera_that_render_it_again() {
    let mut options = DriverOptions::new(W, H);
    options.spp = 2;
    options.keep_frame_scenes = true;
    let (mut d, camera, _) = driver("lavapipe:1", options);
    let prop = add_prop(&mut d);
    let mut done = Vec::new();
    for f in 0..5 {
        move_prop(&mut d, prop, f);
        let mut c = camera;
        c.camera_to_world =
            glam::Mat4::from_translation(Vec3::X * 0.01 * f as f32) * camera.camera_to_world;
        done.extend(d.frame(c).unwrap().finished);
    }
    done.extend(d.finish().unwrap());
    let last = done.last().unwrap();
    assert_eq!(last.stats.plan.join, Join::Restart);
    let scene = last.scene.as_ref().expect("the frame's scene");
    let first = done.first().unwrap().scene.as_ref().unwrap();
    assert!(
        scene.instances.len() > first.instances.len() || !std::sync::Arc::ptr_eq(scene, first),
        "the last frame kept the first generation"
    );
    let tracers =
        create_tracers(&"lavapipe:1".parse().unwrap(), scene, true, Sampling::Mis).unwrap();
    let mut renderer = Renderer::new(tracers, by_name("none").unwrap());
    let mut params = FrameParams::new(W, H, 2, last.camera);
    params.frame = last.stats.frame;
    let again = renderer.render_frame(&params).unwrap().film;
    assert!(
        again == last.film,
        "frame {} rendered again from its scene and camera differs",
        last.stats.frame
    );
}

/// The prop both living-scene tests add: a copy of mesh 0 above the floor.
fn add_prop(d: &mut FrameDriver) -> usize {
    d.scene()
        .push(Edit::AddInstance {
            mesh: 0,
            placement: Placement::at(DVec3::new(0.0, 0.5, 0.0)),
        })
        .unwrap()
        .unwrap()
}

/// The prop at frame `f` of its walk along x.
fn move_prop(d: &mut FrameDriver, prop: usize, f: u32) {
    let p = Placement::at(DVec3::new(0.05 * f as f64, 0.5, 0.0));
    d.scene()
        .push(Edit::Placement {
            node: prop,
            placement: p,
        })
        .unwrap();
}

/// `camera` moved sideways by a hundredth of a unit.
fn nudged(camera: Camera) -> Camera {
    let mut moved = camera;
    moved.camera_to_world = glam::Mat4::from_translation(Vec3::X * 0.01) * camera.camera_to_world;
    moved
}

#[test]
fn a_moving_camera_restarts_and_moving_objects_keep_the_floor() {
    let mut options = DriverOptions::new(W, H);
    options.spp = 1;
    options.blend_floor = 0.25;
    let (mut d, camera, _) = driver("lavapipe:1", options);
    let prop = add_prop(&mut d);
    let moved = nudged(camera);
    // Frames 0-5 still (the prop's arrival is built during frame 0, rendered by frame 1), the
    // camera moves at 6, the prop moves from 9 on (edits rendered one frame later).
    let (stats, film) = run(
        &mut d,
        16,
        |f| if f < 6 { camera } else { moved },
        |d, f| {
            if f >= 9 {
                move_prop(d, prop, f);
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
fn with_restart_on_change_a_moved_object_restarts_the_film_and_the_still_view_sums_again() {
    let mut options = DriverOptions::new(W, H);
    options.spp = 2;
    options.restart_on_change = true;
    let (mut d, camera, _) = driver("lavapipe:1", options);
    let prop = add_prop(&mut d);
    // The prop arrives with frame 0's edits (rendered by frame 1) and moves once at frame 4
    // (rendered by frame 5); the camera never moves.
    let (stats, _) = run(
        &mut d,
        9,
        |_| camera,
        |d, f| {
            if f == 4 {
                move_prop(d, prop, 1);
            }
        },
    );
    let joins: Vec<Join> = stats.iter().map(|s| s.plan.join).collect();
    let restarts: Vec<usize> = (0..joins.len())
        .filter(|&f| joins[f] == Join::Restart)
        .collect();
    assert_eq!(restarts, [0, 1, 5], "{joins:?}");
    assert!(
        joins.iter().all(|j| !matches!(j, Join::Blend { .. })),
        "{joins:?}"
    );
    // Exact sums again after the change: four still frames of 2 samples.
    assert_eq!(stats[8].film_samples, Some(8), "{joins:?}");
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
    let (_, h) = platoon::drive::driver::render_size(64, 64, last.resolution);
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
        platoon::core::Method::new(platoon::core::method::links::Links::new(Default::default()));
    options.gi_update = platoon::drive::GiUpdate::Asynchronous;
    let e = FrameDriver::new(pipeline, &first, tracers, by_name("none").unwrap(), options)
        .err()
        .expect("refused");
    assert!(
        e.to_string()
            .contains("asynchronous update of links needs tracers"),
        "{e}"
    );
}

/// Mean squared error of `a` against `b` as the screen shows them (tone-mapped, x / (1 + x),
/// so that the light's own pixels do not outweigh the room), over pixels and channels.
fn mse(a: &Film, b: &Film) -> f64 {
    let tone = |x: f32| x as f64 / (1.0 + x as f64);
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |k| (tone(p[k]) - tone(q[k])).powi(2)))
        .sum();
    sum / (3 * a.pixels.len()) as f64
}

/// Denoising in the game loop (issue 24): while the camera pans, each denoised frame takes the
/// previous frames' samples through reprojection, which brings it nearer the converged image
/// than the same filter on its own samples, and far nearer than the raw film; once the camera
/// stops every new sample joins the history. Every split between devices gives the same bits,
/// and the film stays the raw one.
#[test]
fn denoised_frames_of_a_panning_view_reuse_their_history_with_the_same_bits_for_any_split() {
    let spp = 2;
    // Frames 0-7 pan, 8-11 hold still.
    let (pan, frames) = (8u32, 12u32);
    let mut runs = Vec::new();
    for spec in ["lavapipe:1", "lavapipe:1,1,1"] {
        let mut options = DriverOptions::new(W, H);
        options.spp = spp;
        options.denoise = Denoiser::Atrous;
        let (mut d, camera, offline) = driver(spec, options);
        // About a pixel a frame (the box is about 2 units across 32 pixels).
        let at = move |f: u32| {
            let mut c = camera;
            let x = 0.06 * f.min(pan - 1) as f32;
            c.camera_to_world = glam::Mat4::from_translation(Vec3::X * x) * camera.camera_to_world;
            c
        };
        let mut done = Vec::new();
        for f in 0..frames {
            done.extend(d.frame(at(f)).unwrap().finished);
        }
        done.extend(d.finish().unwrap());
        runs.push((done, at(pan - 1), offline));
    }
    let (one, camera, offline) = runs.remove(0);
    let (three, _, _) = runs.remove(0);
    assert_same_frames(&one, &three);
    let (moving, still) = (&one[pan as usize - 1], one.last().unwrap());
    let (m, s) = (
        moving.stats.denoise.clone().expect("denoised"),
        still.stats.denoise.clone().expect("denoised"),
    );
    assert_eq!(moving.stats.plan.join, Join::Restart, "the camera moved");
    assert!(m.reused > 0.8, "{m:?}");
    // The history holds a moving view's cap of frames (4) and this one; once still, every
    // frame's samples join it.
    assert!(m.history_samples > 3.0 * spp as f32, "{m:?}");
    assert_eq!(still.stats.plan.join, Join::Sum);
    assert_eq!(s.reused, 1.0);
    let joined = (frames - pan) as f32 * spp as f32;
    assert!(
        (s.history_samples - m.history_samples - joined).abs() < 1e-3,
        "{m:?} {s:?}"
    );
    assert!(
        m.guides.is_some() && s.guides.is_none(),
        "still: the guides are kept"
    );

    let mut renderer = Renderer::new(offline, by_name("none").unwrap());
    let mut render = |p: &FrameParams| renderer.render_frame(p).unwrap().film;
    let reference = render(&FrameParams::new(W, H, 1024, camera));
    // The same filter on the last moving frame's samples alone (its raw film: the camera
    // moved), with its guides rendered as the driver renders them (one sample a pixel).
    let passes: Vec<_> = GBuffer::PASSES
        .iter()
        .map(|&pass| {
            let mut p = FrameParams::new(W, H, 1, camera);
            p.output = Output::Aov(pass);
            (pass, render(&p))
        })
        .collect();
    let film = |pass| passes.iter().find(|(p, _)| *p == pass).unwrap().1.clone();
    let geometry = GBuffer::from_passes(&film, &camera);
    let alone = Temporal::new(Denoiser::Atrous)
        .filter(
            &moving.film,
            spp,
            geometry,
            camera,
            true,
            &mut platoon::core::denoise::NoDevice,
        )
        .unwrap()
        .film;
    let denoised = moving.denoised.clone().unwrap();
    assert_eq!(denoised.count_non_finite(), 0);
    let (raw, alone, with_history, still) = (
        mse(&moving.film, &reference),
        mse(&alone, &reference),
        mse(&denoised, &reference),
        mse(still.denoised.as_ref().unwrap(), &reference),
    );
    eprintln!(
        "MSE against 1024 spp: raw {raw:.5}, filtered alone {alone:.5}, with history \
         {with_history:.5}, {} frames still {still:.5}",
        frames - pan
    );
    assert!(with_history < 0.7 * alone, "{with_history} vs {alone}");
    assert!(with_history < 0.5 * raw, "{with_history} vs {raw}");
    assert!(still < with_history, "{still} vs {with_history}");
}

/// The Cornell box with a red cube of its own mesh floating in the middle (its node).
fn cornell_with_cube() -> (platoon::core::Scene, Camera, usize) {
    let (mut scene, camera) = cornell();
    let mut mesh = platoon::core::scene::Mesh::default();
    platoon::core::scene::cornell::push_box(&mut mesh, (0.0, 0.0), Vec3::splat(1.6), 0.0, 1, 1);
    scene.meshes.push(std::sync::Arc::new(mesh));
    let mut node = platoon::core::scene::Node::new("cube".to_string());
    node.mesh = Some(scene.meshes.len() - 1);
    scene.nodes.push(node);
    let cube = scene.nodes.len() - 1;
    (scene, camera, cube)
}

/// The cube at frame `f`: turned 30 degrees a frame about its vertical axis.
fn spin_cube(d: &mut FrameDriver, cube: usize, f: u32) {
    let placement = Placement {
        translation: DVec3::new(2.78, 1.6, 2.78),
        rotation: glam::Quat::from_rotation_y((30.0 * f as f32).to_radians()),
        scale: Vec3::ONE,
    };
    d.scene()
        .push(Edit::Placement {
            node: cube,
            placement,
        })
        .unwrap();
}

/// Motion vectors in the game loop (issue 43): a cube spinning under a still camera keeps its
/// denoised history (each hit carried back through its triangle to where the cube had it a
/// frame before), and 1 and 3 tracers denoise it to the same bits.
/// Frames of one tracer and of three, without failures: the same raw films and denoised
/// frames, bit for bit.
fn assert_same_frames(one: &[FinishedFrame], three: &[FinishedFrame]) {
    for (a, b) in one.iter().zip(three) {
        assert!(a.stats.failures.is_empty(), "{:?}", a.stats.failures);
        assert!(
            a.film == b.film,
            "frame {}: the raw films differ",
            a.stats.frame
        );
        assert!(
            a.denoised == b.denoised,
            "frame {}: 1 and 3 tracers denoised differently",
            a.stats.frame
        );
    }
}

/// `frames` frames of the spinning cube denoised by `denoiser` on the tracers of `spec`.
fn spinning(spec: &str, denoiser: Denoiser, frames: u32) -> Vec<FinishedFrame> {
    let mut options = DriverOptions::new(W, H);
    options.spp = 1;
    options.denoise = denoiser;
    let (scene, camera, cube) = cornell_with_cube();
    let (mut d, camera, _) = driver_of(scene, spec, options, camera);
    let mut done = Vec::new();
    for f in 0..frames {
        spin_cube(&mut d, cube, f);
        done.extend(d.frame(camera).unwrap().finished);
    }
    done.extend(d.finish().unwrap());
    done
}

#[test]
fn a_spinning_object_keeps_its_denoised_history_with_the_same_bits_for_any_split() {
    let runs: Vec<_> = ["lavapipe:1", "lavapipe:1,1,1"]
        .map(|spec| spinning(spec, Denoiser::Atrous, 8))
        .into();
    assert_same_frames(&runs[0], &runs[1]);
    let reused: Vec<f32> = runs[0]
        .iter()
        .map(|f| f.stats.denoise.as_ref().expect("denoised").reused)
        .collect();
    eprintln!("history reused: {reused:?}");
    // Frame 1: the cube, split out of the merged static geometry as it starts to turn, starts
    // over; the rest keeps its history (objects are named by node, not by instance order).
    assert!(reused[1] > 0.8, "{reused:?}");
    for (f, r) in reused.iter().enumerate().skip(2) {
        assert!(*r > 0.9, "frame {f}: {reused:?}");
    }
}

#[test]
fn the_device_denoiser_in_the_game_loop_is_the_cpu_one_with_the_same_bits_for_any_split() {
    let cpu = spinning("lavapipe:1", Denoiser::Atrous, 4);
    let runs: Vec<_> = ["lavapipe:1", "lavapipe:1,1,1"]
        .map(|spec| spinning(spec, Denoiser::AtrousDevice, 4))
        .into();
    assert_same_frames(&runs[0], &runs[1]);
    for (a, c) in runs[0].iter().zip(&cpu) {
        let f = a.stats.frame;
        assert!(a.film == c.film, "frame {f}: the raw films differ");
        let (device, cpu) = (a.denoised.as_ref().unwrap(), c.denoised.as_ref().unwrap());
        assert_eq!(device.count_non_finite(), 0);
        let worst = device
            .pixels
            .iter()
            .zip(&cpu.pixels)
            .flat_map(|(d, c)| (0..3).map(move |k| (d[k] - c[k]).abs() / c[k].abs().max(1e-2)))
            .fold(0.0f32, f32::max);
        assert!(worst < 2e-3, "frame {f}: device vs CPU differ by {worst}");
        assert_eq!(
            a.stats.denoise.as_ref().unwrap().denoiser,
            Denoiser::AtrousDevice
        );
    }
}

/// Ranks as threads for the facade's game loop over ranks (`platoon::distributed::game`): the
/// collectives and links of `platoon_distribute::local`.
struct ThreadRanks {
    group: platoon::distribute::local::LocalGroup,
    link: std::sync::Arc<platoon::distribute::local::LocalLink>,
}

impl platoon::distribute::Collective for ThreadRanks {
    fn rank(&self) -> usize {
        self.group.rank()
    }
    fn size(&self) -> usize {
        self.group.size()
    }
    fn broadcast(&self, bytes: Vec<u8>) -> Vec<u8> {
        self.group.broadcast(bytes)
    }
    fn scatter(&self, parts: Vec<Vec<u8>>) -> Vec<u8> {
        self.group.scatter(parts)
    }
    fn gather(&self, mine: Vec<u8>) -> Vec<Vec<u8>> {
        self.group.gather(mine)
    }
    fn barrier(&self) {
        self.group.barrier()
    }
}

impl platoon::distributed::Session for ThreadRanks {
    fn abort(&self, code: i32) -> ! {
        panic!("rank {} aborted the job with {code}", self.group.rank())
    }
    fn deal(&self, frames: Vec<i64>) -> Box<dyn Iterator<Item = i64>> {
        Box::new(frames.into_iter())
    }
    fn link(&self) -> anyhow::Result<std::sync::Arc<dyn platoon::distribute::remote::Link>> {
        Ok(self.link.clone())
    }
}

/// A living scene's game loop, rank 0 with two other ranks as threads (each a tracer of its
/// frame driver, two lavapipe tracers inside one of them): every finished frame is the
/// one-process driver's bit for bit, through a prop arriving, a camera move and the prop
/// moving every frame (commits and the film's sums sent to the ranks).
#[test]
fn the_game_loop_over_ranks_is_the_one_process_loop_bit_for_bit() {
    game_over_ranks_and_alone(platoon::core::Method::path_tracing(), |_| {});
}

/// ... with resampled light reusing reservoirs and the world cache (its table and the previous
/// frame's reservoirs sent to the ranks with each frame, their records and reservoirs back with
/// their bands): the cache the one process trains, the same film.
#[test]
fn the_game_loop_over_ranks_trains_the_one_process_world_cache() {
    game_over_ranks_and_alone(platoon::core::Method::path_tracing(), |d| {
        d.method = resampled(4);
        let path = d.method.path_mut().unwrap();
        path.learning.light_reuse = Some(Default::default());
        path.learning.world_cache = Some(
            platoon::core::method::path::world_cache::WorldCacheOptions {
                resolution: 16,
                ..Default::default()
            },
        );
    });
}

/// A method from outside platoon's crates, registered at run time, goes over the ranks as the
/// built-in ones do: by its name and settings (distribute/ names no method).
#[test]
fn a_method_registered_at_run_time_renders_over_the_ranks_as_alone() {
    game_over_ranks_and_alone(toy::grey(0.5, true), |_| {});
}

/// The same game played by one process and by three thread ranks with `method`: the same film.
fn game_over_ranks_and_alone(method: platoon::core::Method, configure: fn(&mut DriverOptions)) {
    init();
    let play = |ranks: Option<platoon::distributed::Ranks>, devices: &str| {
        let (scene, camera) = cornell();
        let mut driver = DriverOptions::new(W, H);
        driver.method = method.clone();
        driver.spp = 2;
        driver.samples_per_pass = 2;
        driver.blend_floor = 0.25;
        configure(&mut driver);
        let mut options = platoon::game::GameOptions::new(driver);
        options.devices = devices.parse().unwrap();
        options.validation = true;
        let mut d = match &ranks {
            Some(r) => platoon::distributed::game::start(scene, &options, r).unwrap(),
            None => platoon::game::start(scene, &options).unwrap(),
        };
        let prop = add_prop(&mut d);
        let moved = nudged(camera);
        let (stats, film) = run(
            &mut d,
            10,
            |f| if f < 4 { camera } else { moved },
            |d, f| {
                if f >= 6 {
                    move_prop(d, prop, f);
                }
            },
        );
        (stats.len(), stats.last().unwrap().commit_bytes, film)
    };
    let alone = play(None, "lavapipe:1");
    let mut groups = platoon::distribute::local::LocalGroup::new(3);
    let links = platoon::distribute::local::LocalLink::new(3);
    let over_ranks = std::thread::scope(|s| {
        for (group, link) in groups.drain(1..).zip(links[1..].iter().cloned()) {
            s.spawn(move || {
                let devices = if group.rank() == 1 {
                    "lavapipe:1,1"
                } else {
                    "lavapipe:1"
                };
                let ranks =
                    platoon::distributed::Ranks(std::rc::Rc::new(ThreadRanks { group, link }));
                platoon::distributed::game::serve(
                    &ranks,
                    &devices.parse().unwrap(),
                    "perfect",
                    true,
                )
                .unwrap();
            });
        }
        let ranks = platoon::distributed::Ranks(std::rc::Rc::new(ThreadRanks {
            group: groups.remove(0),
            link: links[0].clone(),
        }));
        play(Some(ranks), "lavapipe:1")
    });
    assert_eq!(over_ranks.0, alone.0);
    assert!(over_ranks.1 > 0, "the prop's moves committed nothing");
    assert!(
        over_ranks.2 == alone.2,
        "the game over three ranks differs from one process"
    );
}

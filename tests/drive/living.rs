//! Living scenes (issue 8): generations made by the updater reach the tracers as commits, and a
//! tracer that followed the commits renders the same bits as one given the same scene fresh.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use glam::{DVec3, Vec3};
use platoon::core::balance::by_name;
use platoon::core::frame::{FrameParams, Output};
use platoon::core::scene::camera::Camera;
use platoon::core::scene::environment::Environment;
use platoon::core::scene::Placement;
use platoon::core::Scene;
use platoon::devices::{create_tracers, DeviceSpec};
use platoon::drive::Edit;
use platoon::drive::{Pipeline, QueryScene, Updater};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::{Sampling, Tracer};
use platoon_test_support::fault::FaultInjector;

fn new_tracer(scene: &platoon::core::flatten::GpuScene) -> Tracer {
    tracer_reading(scene, Default::default())
}

/// CesiumMan (skinned, animated) under a uniform sky, and a camera on it.
fn cesium_man() -> (Scene, Camera) {
    let mut scene = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    scene.environment = Some(Environment::Constant(Vec3::ONE));
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    (scene, camera)
}

#[test]
fn a_tracer_that_follows_commits_renders_the_bits_of_a_fresh_upload() {
    let (scene, camera) = cesium_man();
    let mut updater = Updater::new(scene, 0.0, DVec3::ZERO).unwrap();
    let mut followed = new_tracer(updater.flattened());
    let params = FrameParams::new(24, 24, 4, camera);
    let before = render_with(&mut followed, &params);
    for t in [0.3f32, 0.6, 0.9] {
        updater.apply(Edit::Time(t)).unwrap();
        let g = updater.update().unwrap();
        assert!(g.refitted + g.rebuilt > 0, "the skin deformed its mesh");
        assert!(g.commit.mesh_bytes() > 0);
        let stats = followed.apply_commit(&g.commit).unwrap();
        assert_eq!(stats.bytes, g.commit.bytes());
    }
    // The camera alone moving: nothing to send.
    let still = updater.update().unwrap();
    assert!(still.commit.is_empty());
    assert_eq!(still.commit.mesh_bytes(), 0);
    assert_eq!(followed.apply_commit(&still.commit).unwrap().bytes, 0);
    let after = render_with(&mut followed, &params);
    let mut fresh = new_tracer(updater.flattened());
    assert!(
        after == render_with(&mut fresh, &params),
        "commits drifted from the scene"
    );
    assert!(after != before, "the animation moved nothing");
    assert_no_validation_messages(&followed);
}

#[test]
fn added_and_removed_instances_on_three_tracers_with_one_killed() {
    init();
    let scene = platoon::core::scene::cornell::scene();
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let mut updater = Updater::new(scene, 0.0, DVec3::ZERO).unwrap();
    let spec: DeviceSpec = "lavapipe:1,1,1".parse().unwrap();
    // Tracer 1 is lost from frame 2 on; the others take its lines on the current generation.
    let tracers = FaultInjector::one_failing(
        create_tracers(&spec, updater.flattened(), true, Sampling::Mis).unwrap(),
        1,
        |t| FaultInjector::failing_from(t, 2),
    );
    let mut renderer = Renderer::new(tracers, by_name("cost-aware").unwrap());
    let mut added = None;
    for f in 0..4u32 {
        match f {
            1 => {
                let at = Placement {
                    scale: Vec3::splat(0.3),
                    ..Placement::at(DVec3::new(0.2, 0.1, 0.0))
                };
                added = updater
                    .apply(Edit::AddInstance {
                        mesh: 0,
                        placement: at,
                    })
                    .unwrap();
            }
            3 => {
                updater.apply(Edit::RemoveInstance(added.unwrap())).unwrap();
            }
            _ => {}
        }
        let g = updater.update().unwrap();
        renderer.apply_commit(&g.commit, f).unwrap();
        let mut params = FrameParams::new(16, 24, 2, camera);
        params.frame = f;
        let frame = renderer.render_frame(&params).expect("frame completes");
        let mut fresh = new_tracer(updater.flattened());
        assert!(frame.film == render_with(&mut fresh, &params), "frame {f}");
    }
    assert_eq!(renderer.alive(), vec![0, 2]);
    assert_eq!(renderer.failures().len(), 1);
    for t in renderer.into_tracers() {
        assert_no_validation_messages(&t.inner);
        // The arrays that grew got new buffers bound in place: the kernel was not rebuilt.
        assert_eq!(t.inner.pipelines_built(), 1);
    }
}

#[test]
fn cpu_ray_queries_agree_with_the_kernels_primary_hits() {
    let (scene, camera) = cesium_man();
    let mut updater = Updater::new(scene, 0.0, DVec3::ZERO).unwrap();
    let mut tracer = new_tracer(updater.flattened());
    let mut queries = QueryScene::new(updater.flattened());
    // Both follow the same commits to a walking pose.
    updater.apply(Edit::Time(0.7)).unwrap();
    let g = updater.update().unwrap();
    tracer.apply_commit(&g.commit).unwrap();
    queries.apply_commit(&g.commit);
    let (w, h) = (32u32, 32u32);
    let mut params = FrameParams::new(w, h, 1, camera);
    params.output = Output::PrimaryHit;
    let film = render_with(&mut tracer, &params);
    let basis = camera.basis(w, h);
    let (mut agree, mut hits) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let gpu = film.pixels[(y * w + x) as usize];
            let dir = basis.pixel_centre_direction(x, y, w, h);
            let cpu = queries.closest_hit(basis.origin, dir, f32::INFINITY);
            let same = match cpu {
                None => gpu == [-1.0; 3],
                Some(q) => {
                    hits += 1;
                    gpu[1] == q.instance as f32
                        && gpu[2] == q.triangle as f32
                        && (gpu[0] - q.t).abs() <= 1e-4 * q.t
                }
            };
            agree += same as u32;
        }
    }
    assert!(
        hits > 50,
        "the character fills part of the view: {hits} hits"
    );
    // Rays that graze a shared edge may pick either triangle; nearly all agree exactly.
    assert!(
        agree as f32 >= 0.99 * (w * h) as f32,
        "{agree} of {} pixels agree",
        w * h
    );
}

#[test]
fn the_threaded_pipeline_feeds_tracers_the_bits_of_a_fresh_upload() {
    let (scene, camera) = cesium_man();
    let node = scene.nodes.iter().position(|n| n.mesh.is_some()).unwrap();
    // The same edits, made on an updater on this thread: the reference the threaded one must
    // reproduce.
    let mut reference = Updater::new(scene.clone(), 0.0, DVec3::ZERO).unwrap();
    let (mut pipeline, first) = Pipeline::new(scene, 0.0, DVec3::ZERO).unwrap();
    let mut followed = new_tracer(&first);
    let mut queries = QueryScene::new(&first);
    // Three more tracers, behind the renderer that splits frames between them.
    let spec: DeviceSpec = "lavapipe:1,1,1".parse().unwrap();
    let three = create_tracers(&spec, &first, true, Sampling::Mis).unwrap();
    let mut renderer = Renderer::new(three, by_name("cost-aware").unwrap());
    let params = FrameParams::new(20, 20, 2, camera);
    pipeline.submit().unwrap();
    reference.update().unwrap();
    let mut last = None;
    for f in 1..4u32 {
        let g = pipeline.take().unwrap();
        // The game edits the next generation while this one renders.
        let at = Placement::at(DVec3::new(0.05 * f as f64, 0.0, 0.0));
        let mut edits = vec![
            Edit::Time(0.25 * f as f32),
            Edit::Placement {
                node,
                placement: at,
            },
        ];
        if f == 2 {
            let sky = Environment::Constant(Vec3::new(0.2, 0.4, 0.9));
            edits.push(Edit::Environment(Box::new(Some(sky))));
        }
        // The same edits, queued for the updater's thread and applied here.
        for e in edits {
            pipeline.push(e.clone()).unwrap();
            reference.apply(e).unwrap();
        }
        pipeline.submit().unwrap();
        reference.update().unwrap();
        followed.apply_commit(&g.commit).unwrap();
        queries.apply_commit(&g.commit);
        renderer.apply_commit(&g.commit, f).unwrap();
        last = Some(render_with(&mut followed, &params));
        assert!(renderer.render_frame(&params).unwrap().film == *last.as_ref().unwrap());
    }
    let g = pipeline.take().unwrap();
    followed.apply_commit(&g.commit).unwrap();
    queries.apply_commit(&g.commit);
    renderer.apply_commit(&g.commit, 4).unwrap();
    let after = render_with(&mut followed, &params);
    assert!(
        Some(&after) != last.as_ref(),
        "the last generation changed the image"
    );
    assert!(
        queries.scene().array_bytes() == reference.flattened().array_bytes(),
        "the game thread's replica differs from the reference"
    );
    let mut fresh = new_tracer(reference.flattened());
    assert!(
        after == render_with(&mut fresh, &params),
        "threaded commits drifted"
    );
    assert_no_validation_messages(&followed);
}

#[test]
fn an_object_that_starts_moving_is_split_out_of_the_merged_geometry() {
    init();
    // The Cornell box a node per object: nothing moves, so all of it is one merged mesh.
    let scene = load_generated(&platoon_scenegen::bench::cornell_nodes());
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let block = scene
        .nodes
        .iter()
        .position(|n| (n.translation - DVec3::new(1.855, 0.825, 1.69)).length() < 1e-6)
        .expect("the short block");
    let mut updater = Updater::new(scene.clone(), 0.0, DVec3::ZERO).unwrap();
    assert_eq!(updater.flattened().instances.len(), 1, "everything merged");
    let mut followed = new_tracer(updater.flattened());
    let mut queries = QueryScene::new(updater.flattened());
    // A ray straight down onto the block's top (1.65 m above the floor).
    let top = |q: &QueryScene| {
        let hit = q.closest_hit(Vec3::new(1.855, 5.0, 1.69), Vec3::NEG_Y, 100.0);
        5.0 - hit.expect("the block or the floor").t
    };
    assert!((top(&queries) - 1.65).abs() < 1e-4);
    let params = FrameParams::new(24, 24, 4, camera);
    let before = render_with(&mut followed, &params);
    let rotation = scene.nodes[block].rotation;
    let scale = scene.nodes[block].scale;
    for (lift, rebuilt) in [(1.0, 1), (2.0, 0)] {
        let placement = Placement {
            translation: DVec3::new(1.855, 0.825 + lift, 1.69),
            rotation,
            scale,
        };
        updater
            .apply(Edit::Placement {
                node: block,
                placement,
            })
            .unwrap();
        let g = updater.update().unwrap();
        // The first move builds the merged mesh again without the block; after that the block
        // moves by its own instance.
        assert_eq!(g.rebuilt, rebuilt, "lifted by {lift}");
        assert_eq!(updater.flattened().instances.len(), 2);
        followed.apply_commit(&g.commit).unwrap();
        queries.apply_commit(&g.commit);
        assert!(
            (top(&queries) - (1.65 + lift as f32)).abs() < 1e-4,
            "lifted by {lift}"
        );
    }
    let after = render_with(&mut followed, &params);
    let mut fresh = new_tracer(updater.flattened());
    assert!(
        after == render_with(&mut fresh, &params),
        "commits drifted from the scene"
    );
    assert!(after != before, "the block did not move");
}

#[test]
fn merged_static_geometry_follows_a_far_camera_with_its_precision() {
    init();
    // The Cornell box a node per object, 1e7 m from the world origin.
    let mut scene = load_generated(&platoon_scenegen::bench::cornell_nodes());
    let far = DVec3::new(1e7, 0.0, 0.0);
    for n in scene.nodes.iter_mut().filter(|n| n.parent.is_none()) {
        n.translation += far;
    }
    let camera = Camera::from_scene(&scene, &scene.pose_around(0.0, far), None).unwrap();
    let mut updater = Updater::new(scene, 0.0, far).unwrap();
    let mut followed = new_tracer(updater.flattened());
    let mut queries = QueryScene::new(updater.flattened());
    // The camera went 2 km: render space follows it and the merged mesh is placed about the
    // new origin (one rebuild), its vertices as precise as before.
    let origin = far + DVec3::new(2000.0, 0.0, 0.0);
    updater.apply(Edit::FollowCamera(origin)).unwrap();
    let g = updater.update().unwrap();
    assert_eq!(g.origin, origin);
    assert_eq!(g.rebuilt, 1);
    followed.apply_commit(&g.commit).unwrap();
    queries.apply_commit(&g.commit);
    let shift = (far - origin).as_vec3();
    let hit = queries
        .closest_hit(shift + Vec3::new(1.855, 5.0, 1.69), Vec3::NEG_Y, 100.0)
        .expect("the short block");
    assert!((5.0 - hit.t - 1.65).abs() < 1e-3, "top at {}", 5.0 - hit.t);
    let mut camera = camera;
    camera.camera_to_world.w_axis += (far - origin).as_vec3().extend(0.0);
    let params = FrameParams::new(24, 24, 4, camera);
    let mut fresh = new_tracer(updater.flattened());
    assert!(
        render_with(&mut followed, &params) == render_with(&mut fresh, &params),
        "commits drifted from the scene"
    );
}

#[test]
fn a_refined_bvh_swapped_in_mid_run_keeps_the_image_and_the_split() {
    use platoon::drive::{Refinement, StaticBuild, UpdaterOptions};
    init();
    // The Cornell box cut into 24 x 24 quads a face (5,772 triangles), its merged geometry
    // built quick and refined in the background as a scene past 2^19 triangles is.
    let scene = platoon::core::scene::cornell::tessellated(24);
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let options = UpdaterOptions {
        static_build: StaticBuild {
            quick_above: 100,
            refinement: Refinement::Background,
        },
        ..Default::default()
    };
    let mut updater = Updater::with_options(scene, 0.0, DVec3::ZERO, options).unwrap();
    let mut followed = new_tracer(updater.flattened());
    let spec: DeviceSpec = "lavapipe:1,1,1".parse().unwrap();
    let three = create_tracers(&spec, updater.flattened(), true, Sampling::Mis).unwrap();
    let mut renderer = Renderer::new(three, by_name("cost-aware").unwrap());
    // The same samples before and after the swap: frame 0's.
    let mut same = FrameParams::new(24, 24, 4, camera);
    same.frame = 0;
    let before = render_with(&mut followed, &same);
    let blas = platoon::core::flatten::arrays::SceneArray::Blas;
    let quick_nodes = updater.flattened().bytes_of(blas).to_vec();
    let mut swaps = Vec::new();
    for f in 0..3u32 {
        if f == 1 {
            // The swap lands in this frame's generation at the latest (earlier if the
            // refinement was done by then).
            updater.finish_refinements();
        }
        let g = updater.update().unwrap();
        swaps.extend((g.refined > 0).then_some(f));
        followed.apply_commit(&g.commit).unwrap();
        renderer.apply_commit(&g.commit, f).unwrap();
        let mut params = FrameParams::new(24, 24, 4, camera);
        params.frame = f;
        assert!(
            renderer.render_frame(&params).unwrap().film == render_with(&mut followed, &params),
            "frame {f}: three tracers against one"
        );
    }
    assert!(
        swaps.len() == 1 && swaps[0] <= 1,
        "swapped in frames {swaps:?}"
    );
    assert!(updater.flattened().bytes_of(blas) != quick_nodes);
    let after = render_with(&mut followed, &same);
    let mut fresh = new_tracer(updater.flattened());
    assert!(
        render_with(&mut fresh, &same) == after,
        "the swap's commit drifted from the scene"
    );
    // The refined tree finds the same hits (the triangles and lights kept their order): the
    // same samples give the same image but where a tie between hits breaks another way.
    let (before, after) = (&before, &after);
    let mean = |f: &platoon::core::output::Film| {
        f.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / f.pixels.len() as f32
    };
    let moved = before
        .pixels
        .iter()
        .zip(&after.pixels)
        .filter(|(a, b)| a != b)
        .count();
    eprintln!(
        "{moved} of {} pixels moved; mean {} -> {}",
        before.pixels.len(),
        mean(before),
        mean(after)
    );
    assert!(moved * 20 <= before.pixels.len(), "{moved} pixels moved");
    assert!((mean(before) - mean(after)).abs() < 0.01 * mean(before));
    assert_no_validation_messages(&followed);
}

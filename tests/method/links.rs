//! Vertex links (issue 22): the update on the devices meets the brief's closed form, shoots what
//! the CPU oracle shoots, converges towards the path tracer's indirect light with directions and
//! with tessellation, and gives the same bits for one and three tracers under every balancer.

#[path = "../common/mod.rs"]
mod common;

use std::sync::Arc;
use std::time::Duration;

use common::*;
use glam::{DVec3, Vec3};
use platoon::core::balance::{by_name, NAMES};
use platoon::core::flatten::GpuScene;
use platoon::core::frame::FrameParams;
use platoon::core::method::links::reduce::LinkGroups;
use platoon::core::method::links::scene_elements::SceneElements;
use platoon::core::method::links::{shoot_cpu, Job, Links, LinksOptions, Solution};
use platoon::core::scene::camera::Camera;
use platoon::core::scene::{cornell, LightKind, Mesh, Scene};
use platoon::core::Method;
use platoon::devices::{create_tracers, DeviceSpec};
use platoon::drive::{
    DriverOptions, Edit, FrameDriver, FrameStats, GiStats, GiUpdate, Pipeline, Updater,
};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::{Sampling, Tracer};
use platoon_test_support::fault::FaultInjector;

fn links(options: LinksOptions) -> Method {
    Method::new(Links::new(options))
}

/// `params` solved on `tracer` (the facade's update), asserting the devices said nothing.
fn solved(tracer: &mut Tracer, prepared: &platoon::Prepared, params: &FrameParams) -> FrameParams {
    solved_in(tracer, &prepared.gpu, params)
}

/// `params` solved on `tracer` holding `g`, asserting the devices said nothing.
fn solved_in(tracer: &mut Tracer, g: &GpuScene, params: &FrameParams) -> FrameParams {
    let p = platoon::method_update::on_tracer(tracer, g, params).expect("links update");
    assert_no_validation_messages(tracer);
    p
}

/// Vertex links with `options` to be solved from `previous` (relit or revalidated).
fn links_after(options: LinksOptions, previous: Option<Arc<Solution>>) -> Method {
    Method::new(Links {
        previous,
        ..Links::new(options)
    })
}

fn solution(params: &FrameParams) -> &Arc<Solution> {
    match params.method.state::<Links>().and_then(|l| l.job.as_ref()) {
        Some(Job::Render(s)) => s,
        _ => panic!("not a solved links frame"),
    }
}

/// An icosphere of radius 2 about the origin seen from inside (normals and winding turned
/// in), albedo 0.5, a point light of 4 W/sr at its centre, the camera inside.
fn lit_inward_sphere() -> Scene {
    let m = platoon_scenegen::icosphere(2);
    let sphere = Mesh {
        normals: m.normals.iter().map(|&n| -Vec3::from(n)).collect(),
        positions: m.positions.iter().map(|&p| Vec3::from(p) * 2.0).collect(),
        triangle_materials: vec![0; m.indices.len() / 3],
        indices: m.indices.chunks(3).map(|t| [t[0], t[2], t[1]]).collect(),
        ..Default::default()
    };
    let mut scene = scene_of(
        vec![(sphere, Vec3::ZERO, 1.0)],
        vec![cornell::lambertian("grey", Vec3::splat(0.5))],
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 0.0, -1.0),
        1.0,
    );
    add_light(&mut scene, LightKind::Point, 4.0, Vec3::ZERO);
    scene
}

/// The brief's closed form, through the devices' shooting and lighting frames: a point light
/// at the centre of a closed inward sphere gives every vertex E_d = I / r^2 = 1; every
/// element's weights sum to one, so the gather gives E_ind = (rho + rho^2 + rho^3) E_d.
#[test]
fn inside_a_closed_sphere_the_update_gives_the_closed_form() {
    let prepared = prepare(lit_inward_sphere(), platoon::EnvChoice::Scene);
    let mut tracer = tracer(&prepared, Sampling::Mis);
    for directions in [16, 64, 256] {
        let mut params = FrameParams::new(16, 16, 4, prepared.camera);
        // At the vertex itself: the fan's points lie inside the sphere, nearer the light.
        params.method = links(LinksOptions {
            directions,
            light_samples: 4,
            fan_light: false,
            ..Default::default()
        });
        let params = solved(&mut tracer, &prepared, &params);
        let s = solution(&params);
        assert_eq!(s.stats.elements, 162);
        for x in 0..162 {
            let sum: f32 = s.links.group(x).map(|l| l.1).sum();
            assert!(
                (sum - 1.0).abs() < 1e-5,
                "element {x}, n_C {directions}: {sum}"
            );
        }
        let expected = 0.5 + 0.25 + 0.125;
        for (x, e) in s.irradiance.iter().enumerate() {
            for c in 0..3 {
                assert!(
                    (e[c] - expected).abs() < 1e-3 * expected,
                    "element {x}, n_C {directions}: {e:?}"
                );
            }
        }
        // And the image: the sphere lit directly and by the links, nowhere black.
        let film = render_with(&mut tracer, &params);
        assert!(film.pixels.iter().all(|p| p[0] > 0.0));
    }
}

/// The devices' shooting is the CPU's but for the traversal: on a tessellated Cornell box the
/// same total weight for every element within a ray or two (1/64 each), and all but a sliver of
/// the link weight on the same peers (rays that graze a box's edge may meet the face on either
/// side of it in the two traversals).
#[test]
fn the_devices_shoot_the_links_the_cpu_oracle_shoots() {
    let prepared = prepare(cornell::tessellated(3), platoon::EnvChoice::Scene);
    let mut tracer = tracer(&prepared, Sampling::Mis);
    let options = LinksOptions {
        directions: 64,
        light_samples: 1,
        ..Default::default()
    };
    let mut params = FrameParams::new(8, 8, 1, prepared.camera);
    params.method = links(options);
    let params = solved(&mut tracer, &prepared, &params);
    let device = &solution(&params).links;
    let g = &prepared.gpu;
    let elements = SceneElements::of(g, options.cos_feature()).unwrap();
    let dirs = platoon::core::method::links::directions::directions(64).unwrap();
    let cpu = LinkGroups::from_hits(64, &shoot_cpu::shoot(g, &elements, &dirs));
    assert_eq!(device.elements(), cpu.elements());
    let (mut total, mut moved) = (0.0f64, 0.0f64);
    for x in 0..cpu.elements() {
        let weights = |g: &LinkGroups| {
            let mut w = std::collections::BTreeMap::new();
            for (peer, weight) in g.group(x) {
                *w.entry(peer).or_insert(0.0f64) += weight as f64;
            }
            w
        };
        let (a, b) = (weights(device), weights(&cpu));
        let sum = |w: &std::collections::BTreeMap<u32, f64>| w.values().sum::<f64>();
        assert!((sum(&a) - sum(&b)).abs() < 2.0 / 64.0 + 1e-5, "element {x}");
        total += sum(&b);
        let peers: std::collections::BTreeSet<u32> = a.keys().chain(b.keys()).copied().collect();
        moved += peers
            .iter()
            .map(|p| (a.get(p).unwrap_or(&0.0) - b.get(p).unwrap_or(&0.0)).abs())
            .sum::<f64>();
    }
    println!("link weight that differs: {:.3}%", 100.0 * moved / total);
    assert!(moved < 0.005 * total, "{moved} of {total}");
}

/// The Cornell box is Lambertian: vertex links with B bounces estimate what the path tracer
/// does with paths of B + 2 segments. Links minus the path tracer capped at 2 segments (the
/// same random numbers: the camera paths are the path tracer's up to the first diffuse vertex)
/// is the links' indirect light alone. Its error falls with the directions (at a fine
/// tessellation) and with the tessellation; at the finest setting its mean is within 3% of the
/// path tracer's. What remains at a tessellation is its floor: light interpolated across
/// triangles that a shadow edge or a contact (the boxes on the floor) cuts.
#[test]
fn links_indirect_light_converges_with_directions_and_tessellation() {
    let bounces = LinksOptions::default().bounces;
    let reference = {
        let prepared = prepare(cornell::scene(), platoon::EnvChoice::Scene);
        let mut tracer = tracer(&prepared, Sampling::Mis);
        let mut params = FrameParams::new(32, 32, 4096, prepared.camera);
        params.path_loop.max_depth = bounces + 2;
        let full = render_with(&mut tracer, &params);
        params.path_loop.max_depth = 2;
        minus(&full, &render_with(&mut tracer, &params))
    };
    let m = mean(&reference);
    println!("path-traced indirect: mean {m:.4}");
    let error = |cells: u32, directions: u32| {
        let prepared = prepare(cornell::tessellated(cells), platoon::EnvChoice::Scene);
        let mut tracer = tracer(&prepared, Sampling::Mis);
        let mut params = FrameParams::new(32, 32, 8, prepared.camera);
        params.options.seed = 1;
        params.path_loop.max_depth = 2;
        let direct = render_with(&mut tracer, &params);
        params.path_loop.max_depth = platoon::core::frame::DEFAULT_MAX_DEPTH;
        params.method = links(LinksOptions {
            directions,
            ..Default::default()
        });
        let params = solved(&mut tracer, &prepared, &params);
        let indirect = minus(&render_with(&mut tracer, &params), &direct);
        let (e, mi) = (rmse(&indirect, &reference), mean(&indirect));
        let s = &solution(&params).stats;
        println!(
            "{cells}x{cells} cells, n_C {directions}: RMSE {e:.4}, mean {mi:.4} ({:+.1}%); \
             {} elements, shoot {:.2} s, reduce {:.2} s, light {:.2} s",
            100.0 * (mi / m - 1.0),
            s.elements,
            s.shoot_s,
            s.reduce_s,
            s.light_s
        );
        (e, mi)
    };
    let at_32 = error(32, 256);
    let by_directions = [error(32, 16).0, error(32, 64).0, at_32.0];
    let by_cells: Vec<(f64, f64)> = [2, 4, 8, 16]
        .iter()
        .map(|&c| error(c, 256))
        .chain([at_32, error(48, 256)])
        .collect();
    // The directions' error falls to the tessellation's floor: a step may stay at it (within
    // the direct light's noise), never rise past it.
    assert!(
        by_directions[1] < 0.6 * by_directions[0],
        "{by_directions:?}"
    );
    assert!(
        by_directions[2] < 1.03 * by_directions[1],
        "{by_directions:?}"
    );
    assert!(by_cells.windows(2).all(|w| w[1].0 < w[0].0), "{by_cells:?}");
    let finest = by_cells.last().unwrap().1;
    assert!((finest / m - 1.0).abs() < 0.03, "mean {finest} against {m}");
}

/// The update's frames are split between tracers like any frame: the solution and the image
/// are the same bits for one tracer and for three under every balancer (twice each, so the
/// balancer's second cut follows what it learnt), and when a tracer is lost midway through the
/// update (its first shooting frame, or the lighting frame after it) the others finish it.
#[test]
fn one_and_three_tracers_give_the_same_bits_under_every_balancer() {
    init();
    let prepared = prepare(cornell::tessellated(2), platoon::EnvChoice::Scene);
    let mut params = FrameParams::new(24, 20, 2, prepared.camera);
    params.method = links(LinksOptions {
        directions: 64,
        light_samples: 4,
        ..Default::default()
    });
    let mut one = tracer(&prepared, Sampling::Mis);
    let solved_once = solved(&mut one, &prepared, &params);
    let expected = solution(&solved_once);
    let image = render_with(&mut one, &solved_once);
    assert!(mean(&image) > 0.0);
    let same = |p: &FrameParams, what: &str| {
        let s = solution(p);
        assert!(
            s.irradiance == expected.irradiance,
            "{what}: irradiance differs"
        );
        assert!(s.links == expected.links, "{what}: links differ");
    };
    let spec: DeviceSpec = "lavapipe:1,1,1".parse().unwrap();
    let mut tracers = create_tracers(&spec, &prepared.gpu, true, Sampling::Mis).unwrap();
    for name in NAMES {
        let mut renderer = Renderer::new(tracers, by_name(name).unwrap());
        for round in 0..2 {
            let p =
                platoon::method_update::on_renderer(&mut renderer, &prepared.gpu, &params).unwrap();
            same(&p, &format!("{name}, round {round}"));
            let f = renderer.render_frame(&p).unwrap();
            assert!(f.film == image, "{name}, round {round}: image differs");
        }
        tracers = renderer.into_tracers();
    }
    for t in &tracers {
        assert_no_validation_messages(t);
    }
    for lost_after in [0, 1] {
        let tracers = FaultInjector::one_failing(
            create_tracers(&spec, &prepared.gpu, true, Sampling::Mis).unwrap(),
            1,
            |t| FaultInjector::failing_after_bands(t, lost_after),
        );
        let mut renderer = Renderer::new(tracers, by_name("cost-aware").unwrap());
        let p = platoon::method_update::on_renderer(&mut renderer, &prepared.gpu, &params).unwrap();
        same(&p, &format!("tracer lost after {lost_after} bands"));
        assert_eq!(renderer.alive(), [0, 2]);
        assert!(renderer.render_frame(&p).unwrap().film == image);
    }
}

/// The Cornell box with faces of 4 x 4 quads and a point light at `light` besides its area
/// light.
fn box_with_point_light(light: Vec3) -> platoon::Prepared {
    let mut scene = cornell::tessellated(4);
    add_light(&mut scene, LightKind::Point, 20.0, light);
    prepare(scene, platoon::EnvChoice::Scene)
}

/// Relighting a still scene: an update given an earlier solution of the same geometry shoots
/// nothing, takes its links, and gives the bits a full update of the relit scene gives; after
/// a change of geometry it shoots again.
#[test]
fn relighting_a_still_scene_reuses_the_links_and_equals_a_full_update() {
    let before = box_with_point_light(Vec3::new(1.0, 4.0, 1.0));
    let after = box_with_point_light(Vec3::new(4.5, 1.0, 4.0));
    let options = LinksOptions {
        directions: 64,
        light_samples: 8,
        ..Default::default()
    };
    let mut params = FrameParams::new(16, 16, 1, before.camera);
    params.method = links(options);
    let first = solved(&mut tracer(&before, Sampling::Mis), &before, &params);
    let first = solution(&first).clone();
    let mut t = tracer(&after, Sampling::Mis);
    let full = solved(&mut t, &after, &params);
    let full = solution(&full);
    assert!(!full.stats.relit && full.irradiance != first.irradiance);
    let mut relight = params.clone();
    relight.method = links_after(options, Some(first.clone()));
    let relit = solved(&mut t, &after, &relight);
    let relit = solution(&relit);
    assert!(relit.stats.relit && relit.stats.rays == 0 && relit.stats.shoot_s == 0.0);
    assert!(Arc::ptr_eq(&relit.links, &first.links));
    assert!(
        relit.irradiance == full.irradiance,
        "relit differs from a full update"
    );
    // Moved geometry: the earlier links are not taken.
    let mut moved = cornell::tessellated(4);
    moved.nodes[0].translation.y += 0.5;
    let moved = prepare(moved, platoon::EnvChoice::Scene);
    let m = solved(&mut tracer(&moved, Sampling::Mis), &moved, &relight);
    assert!(!solution(&m).stats.relit);
}

/// CesiumMan in the tessellated Cornell box, walking (his skin's animation) and carried across
/// the floor (his node's placement), as the updater makes its generations.
fn walk_in_a_room() -> (Updater, usize, Camera) {
    let man = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    let (scene, node) = platoon::drive::walk::walk_in_a_room(&man, 6).unwrap();
    let camera = Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    (Updater::new(scene, 0.0, DVec3::ZERO).unwrap(), node, camera)
}

/// Living scenes: after each step of a walk the update given the earlier solution shoots
/// again only the rays that can have changed (those of the man's elements, those that hit
/// him, those that pass his new bounds) and gives the bits of shooting every ray again: the
/// hits, the links and the light. A frame of the same geometry relights.
#[test]
fn revalidating_a_walk_gives_the_bits_of_regenerating_every_link() {
    let (mut updater, node, camera) = walk_in_a_room();
    let mut t = tracer_reading(updater.flattened(), Default::default());
    let options = LinksOptions {
        directions: 64,
        light_samples: 4,
        ..Default::default()
    };
    let mut params = FrameParams::new(16, 16, 1, camera);
    params.method = links(options);
    let solve = |t: &mut Tracer, g: &GpuScene, previous: Option<Arc<Solution>>| {
        let mut p = params.clone();
        p.method = links_after(options, previous);
        solution(&solved_in(t, g, &p)).clone()
    };
    let mut last = solve(&mut t, updater.flattened(), None);
    let all_rays = last.stats.rays;
    for step in 1..=2 {
        for e in platoon::drive::walk::walk_edits(node, step) {
            updater.apply(e).unwrap();
        }
        let generation = updater.update().unwrap();
        t.apply_commit(&generation.commit).unwrap();
        let g = updater.flattened();
        let revalidated = solve(&mut t, g, Some(last.clone()));
        let regenerated = solve(&mut t, g, None);
        let s = &revalidated.stats;
        println!(
            "step {step}: {} of {all_rays} rays shot again, {} of {} elements regrouped, {} \
             instances and {} elements moved",
            s.rays, s.regrouped, s.elements, s.moved_instances, s.moved_elements
        );
        assert!(s.revalidated && !regenerated.stats.revalidated);
        assert_eq!(s.moved_instances, 1);
        // Of the still room's rays, those that may see the man: a few.
        let moved_rays = s.moved_elements as u64 * 64;
        assert!(s.moved_elements > 0 && s.rays > moved_rays);
        assert!(s.rays - moved_rays < (all_rays - moved_rays) / 4);
        let (a, b) = (revalidated.shot.as_ref(), regenerated.shot.as_ref());
        let differing = a
            .unwrap()
            .hits
            .iter()
            .zip(&b.unwrap().hits)
            .filter(|(x, y)| x != y)
            .count();
        assert_eq!(differing, 0, "step {step}: hits differ from shooting all");
        assert!(revalidated.links == regenerated.links, "step {step}: links");
        assert!(
            revalidated.irradiance == regenerated.irradiance,
            "step {step}: light"
        );
        assert!(revalidated.links != last.links, "the walk changed no link");
        last = revalidated;
    }
    // The same geometry again: relit from the last links.
    let generation = updater.update().unwrap();
    t.apply_commit(&generation.commit).unwrap();
    let relit = solve(&mut t, updater.flattened(), Some(last.clone()));
    assert!(relit.stats.relit && Arc::ptr_eq(&relit.links, &last.links));
}

/// A revalidation's frames of single rays split like any frame: on three tracers under every
/// balancer, and with a tracer lost after a band, it gives the bits of one tracer's.
#[test]
fn revalidating_on_three_tracers_gives_one_tracers_bits_under_every_balancer() {
    let (mut updater, node, camera) = walk_in_a_room();
    let options = LinksOptions {
        directions: 16,
        light_samples: 2,
        ..Default::default()
    };
    let mut params = FrameParams::new(16, 16, 1, camera);
    params.method = links(options);
    let first = {
        let g = updater.flattened();
        solution(&solved_in(
            &mut tracer_reading(g, Default::default()),
            g,
            &params,
        ))
        .clone()
    };
    updater.apply(Edit::Time(0.4)).unwrap();
    updater
        .apply(Edit::Placement {
            node,
            placement: platoon::drive::walk::walk_step(1.0),
        })
        .unwrap();
    updater.update().unwrap();
    let g = updater.flattened();
    params.method = links_after(options, Some(first));
    let mut one = tracer_reading(g, Default::default());
    let expected = solution(&solved_in(&mut one, g, &params)).clone();
    assert!(expected.stats.revalidated && expected.stats.rays > 0);
    let same = |p: &FrameParams, what: &str| {
        let s = solution(p);
        assert!(s.stats.revalidated, "{what}: not revalidated");
        assert!(s.links == expected.links, "{what}: links differ");
        assert!(
            s.irradiance == expected.irradiance,
            "{what}: irradiance differs"
        );
    };
    let spec: DeviceSpec = "lavapipe:1,1,1".parse().unwrap();
    let mut tracers = create_tracers(&spec, g, true, Sampling::Mis).unwrap();
    for name in NAMES {
        let mut renderer = Renderer::new(tracers, by_name(name).unwrap());
        let p = platoon::method_update::on_renderer(&mut renderer, g, &params).unwrap();
        same(&p, name);
        tracers = renderer.into_tracers();
    }
    for t in &tracers {
        assert_no_validation_messages(t);
    }
    let tracers = FaultInjector::one_failing(
        create_tracers(&spec, g, true, Sampling::Mis).unwrap(),
        1,
        |t| FaultInjector::failing_after_bands(t, 1),
    );
    let mut renderer = Renderer::new(tracers, by_name("cost-aware").unwrap());
    let p = platoon::method_update::on_renderer(&mut renderer, g, &params).unwrap();
    same(&p, "a tracer lost after a band");
    assert_eq!(renderer.alive(), [0, 2]);
}

/// The walk as a game plays it: `frames` calls of the frame driver over `tracers` (and
/// `update_tracers` for an asynchronous update), the man stepping before the first `steps`;
/// every finished frame's statistics, and the scene the walk ends in.
fn play_the_walk(
    gi_update: GiUpdate,
    steps: usize,
    frames: usize,
    until_caught_up: bool,
) -> (Vec<FrameStats>, GpuScene) {
    let (mut updater, node, camera) = walk_in_a_room();
    let (pipeline, first) = Pipeline::new(updater.scene().clone(), 0.0, DVec3::ZERO).unwrap();
    let spec: DeviceSpec = "lavapipe:1,1".parse().unwrap();
    let tracers = create_tracers(&spec, &first, true, Sampling::Mis).unwrap();
    let update_tracers = match gi_update {
        GiUpdate::Asynchronous => create_tracers(&spec, &first, true, Sampling::Mis).unwrap(),
        GiUpdate::Synchronous => Vec::new(),
    };
    let mut options = DriverOptions::new(16, 16);
    options.method = links(walk_options());
    options.gi_update = gi_update;
    let mut d = FrameDriver::with_update_tracers(
        pipeline,
        &first,
        tracers,
        update_tracers,
        by_name("cost-aware").unwrap(),
        options,
    )
    .unwrap();
    let mut stats = Vec::new();
    let mut frame = 0;
    loop {
        if frame < steps {
            // The replica takes each step's edits as one generation, as the driver's updater.
            for e in platoon::drive::walk::walk_edits(node, frame + 1) {
                updater.apply(e.clone()).unwrap();
                d.scene().push(e).unwrap();
            }
            updater.update().unwrap();
        }
        let out = d.frame(camera).unwrap();
        stats.extend(out.finished.map(|f| f.stats));
        frame += 1;
        let caught_up = stats
            .last()
            .and_then(|s| s.gi.as_ref())
            .is_some_and(|g| g.age == 0 && g.generation == steps as u64);
        if frame >= frames && (!until_caught_up || caught_up) {
            break;
        }
        assert!(frame < 400, "the update never caught up with the walk");
    }
    stats.extend(d.finish().unwrap().map(|f| f.stats));
    for s in &stats {
        assert!(s.device_messages.is_empty(), "{:?}", s.device_messages);
        assert!(s.failures.is_empty());
    }
    (stats, updater.flattened().clone())
}

fn walk_options() -> LinksOptions {
    LinksOptions {
        directions: 16,
        light_samples: 2,
        ..Default::default()
    }
}

/// The solution a frame was lit by.
fn lit_by(s: &FrameStats) -> Arc<Solution> {
    let gi = s.gi.as_ref().expect("a links frame reports its lighting");
    match gi.method.state::<Links>().and_then(|l| l.job.as_ref()) {
        Some(Job::Render(s)) => s.clone(),
        _ => panic!("a frame lit by no solution"),
    }
}

/// The links of `g` solved afresh on a tracer of its own, as the driver's update params set
/// them.
fn solved_afresh(g: &GpuScene, camera: Camera) -> Arc<Solution> {
    let mut t = tracer_reading(g, Default::default());
    let mut p = FrameParams::new(16, 16, 1, camera);
    p.method = links(walk_options());
    solution(&solved_in(&mut t, g, &p)).clone()
}

/// In the game loop, synchronously: each frame of a new generation is lit by links of its own
/// scene (age 0), revalidated from the last and the bits of solving that scene afresh; a frame
/// of an unchanged scene reuses them.
#[test]
fn the_game_loop_updates_the_links_before_each_new_generation() {
    let (stats, last_scene) = play_the_walk(GiUpdate::Synchronous, 2, 5, false);
    let gis: Vec<&GiStats> = stats.iter().map(|s| s.gi.as_ref().unwrap()).collect();
    let generations: Vec<u64> = gis.iter().map(|g| g.generation).collect();
    assert_eq!(generations, [0, 1, 2, 2, 2]);
    assert!(gis.iter().all(|g| g.age == 0));
    let fresh: Vec<bool> = gis.iter().map(|g| g.update > Duration::ZERO).collect();
    assert_eq!(fresh, [true, true, true, false, false]);
    for g in &gis[1..3] {
        assert!(g.metadata[0].1.contains("revalidated"), "{:?}", g.metadata);
    }
    let (_, _, camera) = walk_in_a_room();
    let last = lit_by(stats.last().unwrap());
    let afresh = solved_afresh(&last_scene, camera);
    assert_eq!(last.geometry, afresh.geometry, "another scene");
    assert!(last.links == afresh.links, "links");
    assert!(last.irradiance == afresh.irradiance, "light");
}

/// Asynchronously: frames render while the update's own tracers solve the newest generation;
/// each frame says how many generations its lighting lags, and once the walk stops the
/// lighting catches up with the bits of solving the last scene afresh.
#[test]
fn asynchronous_links_follow_the_walk_and_catch_up() {
    let (stats, last_scene) = play_the_walk(GiUpdate::Asynchronous, 3, 4, true);
    let mut last_generation = 0;
    for s in &stats {
        let gi = s.gi.as_ref().unwrap();
        assert!(
            gi.generation >= last_generation,
            "lighting went back in time"
        );
        last_generation = gi.generation;
        assert!(gi.generation + gi.age <= 3);
    }
    println!(
        "ages: {:?}",
        stats
            .iter()
            .map(|s| s.gi.as_ref().unwrap().age)
            .collect::<Vec<_>>()
    );
    let (_, _, camera) = walk_in_a_room();
    let last = lit_by(stats.last().unwrap());
    let afresh = solved_afresh(&last_scene, camera);
    assert!(last.links == afresh.links && last.irradiance == afresh.irradiance);
}

/// Vertex links compile their kernels' options in only when a frame asks for them.
#[test]
fn links_options_change_the_kernels_only_when_enabled() {
    let prepared = prepare(cornell::scene(), platoon::EnvChoice::Scene);
    let tracer = tracer(&prepared, Sampling::Mis);
    let mut params = FrameParams::new(8, 8, 1, prepared.camera);
    let path = tracer.kernel_defines(&params);
    assert!(!path
        .iter()
        .any(|d| d.starts_with("LINKS") || *d == "METHOD_LINKS"));
    params.method = links(LinksOptions {
        fan_light: false,
        ..Default::default()
    });
    let plain = tracer.kernel_defines(&params);
    assert!(plain.contains(&"METHOD_LINKS") && !plain.contains(&"LINKS_FAN_LIGHT"));
    params.method = links(LinksOptions::default());
    assert!(tracer.kernel_defines(&params).contains(&"LINKS_FAN_LIGHT"));
}

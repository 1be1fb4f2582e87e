//! Instant global illumination (issue 11): IGI's indirect light converges to the path tracer's,
//! each acceleration changes the kernel only when enabled, and a frame is the same bits for one
//! and three tracers with every option.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::balance::by_name;
use platoon::core::frame::FrameParams;
use platoon::core::method::igi::IgiOptions;
use platoon::core::Method;
use platoon::devices::{create_tracers, DeviceSpec};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::Sampling;

fn cornell() -> platoon::Prepared {
    prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    )
}

/// The Cornell box is Lambertian: IGI with exact visibility, no bound on the geometry term and
/// B bounces of VPLs estimates what the path tracer does with paths of B + 2 segments. Its
/// direct light uses the random numbers of the path tracer capped at 2 segments, so IGI minus
/// that render is its indirect light alone, free of the direct light's noise.
#[test]
fn igi_indirect_light_converges_to_the_path_tracers_as_the_vpls_grow_in_number() {
    let prepared = cornell();
    let mut tracer = tracer(&prepared, Sampling::Mis);
    let mut params = FrameParams::new(32, 32, 4096, prepared.camera);
    let bounces = IgiOptions::default().bounces;
    params.path_loop.max_depth = bounces + 2;
    let full = render_with(&mut tracer, &params);
    params.path_loop.max_depth = 2;
    let reference = minus(&full, &render_with(&mut tracer, &params));
    params.spp = 8;
    params.options.seed = 1;
    let direct = render_with(&mut tracer, &params);
    params.path_loop.max_depth = platoon::core::frame::DEFAULT_MAX_DEPTH;
    let mut errors = Vec::new();
    for vpls in [12, 48, 192, 768] {
        params.method = Method::new(IgiOptions::with_vpls(vpls));
        let indirect = minus(&render_with(&mut tracer, &params), &direct);
        errors.push((vpls, rmse(&indirect, &reference), mean(&indirect)));
    }
    let m = mean(&reference);
    println!("path-traced indirect: mean {m:.4} (of {:.4})", mean(&full));
    for (vpls, e, mi) in &errors {
        println!("{vpls:4} VPLs: indirect RMSE {e:.4}, mean {mi:.4}");
    }
    assert!(m > 0.15 * mean(&full), "the box has indirect light to find");
    for w in errors.windows(2) {
        assert!(
            w[1].1 < w[0].1,
            "error does not fall with VPL count: {errors:?}"
        );
    }
    let (_, last_error, last_mean) = errors[errors.len() - 1];
    assert!((last_mean - m).abs() < 0.03 * m, "mean {last_mean} vs {m}");
    assert!(last_error < 0.35 * errors[0].1, "{errors:?}");
}

fn every_option() -> Vec<IgiOptions> {
    let base = IgiOptions::with_vpls(48);
    vec![
        base,
        IgiOptions {
            imperfect_visibility: true,
            ..base
        },
        IgiOptions {
            min_distance: 0.05,
            ..base
        },
        IgiOptions {
            downsample: 4,
            ..base
        },
        IgiOptions {
            interleave: [3, 3],
            ..base
        },
        IgiOptions {
            imperfect_visibility: true,
            min_distance: 0.05,
            downsample: 2,
            interleave: [2, 3],
            ..base
        },
    ]
}

#[test]
fn each_igi_option_changes_the_kernel_only_when_enabled() {
    let prepared = cornell();
    let tracer = tracer(&prepared, Sampling::Mis);
    let mut params = FrameParams::new(8, 8, 1, prepared.camera);
    let path = tracer.kernel_defines(&params);
    assert!(path.iter().all(|d| !d.contains("IGI")), "{path:?}");
    let with = |o: IgiOptions| {
        let mut p = params.clone();
        p.method = Method::new(o);
        let d = tracer.kernel_defines(&p);
        let mut added: Vec<&str> = d.into_iter().filter(|d| !path.contains(d)).collect();
        added.sort();
        added
    };
    let base = IgiOptions::with_vpls(48);
    assert_eq!(with(base), ["METHOD_IGI"]);
    // Run-time knobs are push constants: the same kernel.
    assert_eq!(
        with(IgiOptions {
            paths: 7,
            bounces: 5,
            ..base
        }),
        ["METHOD_IGI"]
    );
    for (o, own) in [
        (
            IgiOptions {
                imperfect_visibility: true,
                ..base
            },
            vec!["IGI_IMPERFECT_VISIBILITY"],
        ),
        (
            IgiOptions {
                min_distance: 0.1,
                ..base
            },
            vec!["IGI_BOUNDED"],
        ),
        (
            IgiOptions {
                downsample: 4,
                ..base
            },
            vec!["IGI_DOWNSAMPLED", "IGI_FILTERED"],
        ),
        (
            IgiOptions {
                interleave: [3, 3],
                ..base
            },
            vec!["IGI_FILTERED", "IGI_INTERLEAVED"],
        ),
    ] {
        let mut want = own.clone();
        want.push("METHOD_IGI");
        want.sort();
        assert_eq!(with(o), want, "{o:?}");
    }
    params.method = Method::path_tracing();
    assert_eq!(tracer.kernel_defines(&params), path);
}

#[test]
fn igi_frames_are_bit_identical_for_one_and_three_tracers_with_every_option() {
    init();
    let prepared = cornell();
    let spec: DeviceSpec = "lavapipe:1,1,1".parse().unwrap();
    let mut tracers = create_tracers(&spec, &prepared.gpu, true, Sampling::Mis).unwrap();
    let mut one = tracer(&prepared, Sampling::Mis);
    for o in every_option() {
        let mut params = FrameParams::new(24, 20, 2, prepared.camera);
        params.method = Method::new(o);
        let reference = render_with(&mut one, &params);
        assert!(mean(&reference) > 0.0, "{o:?}: black");
        let mut renderer = Renderer::new(tracers, by_name("cost-aware").unwrap());
        // Several frames, so that the cuts move (within lines too) between them.
        for frame in 0..3 {
            let f = renderer.render_frame(&params).unwrap();
            assert!(f.film == reference, "{o:?}, frame {frame}: image differs");
            assert_eq!(f.rejected_samples, 0);
        }
        tracers = renderer.into_tracers();
    }
    for t in &tracers {
        assert_no_validation_messages(t);
    }
}

#[test]
fn the_vpls_change_with_the_frame_and_the_seed_and_not_otherwise() {
    let prepared = cornell();
    let mut tracer = tracer(&prepared, Sampling::Mis);
    let mut params = FrameParams::new(16, 16, 1, prepared.camera);
    params.method = Method::new(IgiOptions::with_vpls(12));
    let a = render_with(&mut tracer, &params);
    assert!(render_with(&mut tracer, &params) == a);
    params.frame = 1;
    assert!(render_with(&mut tracer, &params) != a);
    params.frame = 0;
    params.options.seed = 9;
    assert!(render_with(&mut tracer, &params) != a);
}

/// A box above a grey ground: light bounces between them whatever lights the scene
/// (not touching: a contact's 1/d^2 would make the VPL estimate converge too slowly to test).
fn sphere_on_ground() -> platoon::core::Scene {
    use platoon::core::scene::cornell::lambertian;
    let ground = mesh_from(&platoon_scenegen::quad(1.0, 1.0), 0);
    // A box, flat-shaded: smooth normals on a coarse sphere bend light differently in the
    // two estimators near its terminator (shading normals are not reciprocal).
    let sphere = mesh_from(&platoon_scenegen::flat_box(), 1);
    scene_of(
        vec![
            (ground, glam::Vec3::ZERO, 10.0),
            (sphere, glam::Vec3::new(0.0, 1.5, 0.0), 1.0),
        ],
        vec![
            lambertian("ground", glam::Vec3::splat(0.8)),
            lambertian("sphere", glam::Vec3::new(0.8, 0.6, 0.4)),
        ],
        glam::Vec3::new(0.0, 1.6, 3.6),
        glam::Vec3::new(0.0, 0.6, 0.0),
        0.9,
    )
}

fn with_light(kind: platoon::core::scene::LightKind, at: glam::Vec3) -> platoon::core::Scene {
    let mut scene = sphere_on_ground();
    scene.lights.push(platoon::core::scene::PunctualLight {
        name: "light".into(),
        kind,
        color: glam::Vec3::ONE,
        intensity: 4.0,
        range: 0.0,
    });
    let mut node = platoon::core::scene::Node::new("light");
    node.light = Some(0);
    node.translation = at.as_dvec3();
    // -Z (where spots and directional lights point) turned down and a little sideways.
    node.rotation = glam::Quat::from_rotation_x(-1.2);
    scene.nodes.push(node);
    scene
}

/// Every light kind shoots VPLs that carry its power: IGI's indirect light has the path
/// tracer's mean (in the Cornell box an emissive triangle's, here the others').
#[test]
fn every_light_kind_gives_the_path_tracers_indirect_light() {
    use platoon::core::scene::LightKind;
    let cases = [
        (
            "point",
            prepare(
                with_light(LightKind::Point, glam::Vec3::new(1.2, 2.5, 1.0)),
                platoon::EnvChoice::Scene,
            ),
        ),
        (
            "spot",
            prepare(
                with_light(
                    LightKind::Spot {
                        inner_cone: 0.5,
                        outer_cone: 0.8,
                    },
                    glam::Vec3::new(0.5, 3.0, 1.5),
                ),
                platoon::EnvChoice::Scene,
            ),
        ),
        (
            "directional",
            prepare(
                with_light(LightKind::Directional, glam::Vec3::new(0.0, 5.0, 0.0)),
                platoon::EnvChoice::Scene,
            ),
        ),
        (
            "environment",
            prepare(sphere_on_ground(), constant_env(1.0)),
        ),
    ];
    for (name, prepared) in cases {
        let mut tracer = tracer(&prepared, Sampling::Mis);
        let bounces = 2;
        let mut params = FrameParams::new(16, 16, 4096, prepared.camera);
        params.path_loop.max_depth = bounces + 2;
        let full = render_with(&mut tracer, &params);
        params.path_loop.max_depth = 2;
        let reference = minus(&full, &render_with(&mut tracer, &params));
        // Eight frames, eight VPL sets: the unbounded geometry term makes one set's estimate
        // heavy-tailed, their mean is closer to IGI's expectation. One sample a pixel: the
        // direct light cancels exactly, and the error is the VPLs', shared by all pixels.
        params.spp = 1;
        let frames = 8;
        let mut got = 0.0;
        for frame in 0..frames {
            params.frame = frame;
            params.path_loop.max_depth = 2;
            params.method = Method::path_tracing();
            let direct = render_with(&mut tracer, &params);
            params.path_loop.max_depth = platoon::core::frame::DEFAULT_MAX_DEPTH;
            params.method = Method::new(IgiOptions {
                paths: 4096,
                bounces,
                ..Default::default()
            });
            got += mean(&minus(&render_with(&mut tracer, &params), &direct)) / frames as f64;
        }
        let want = mean(&reference);
        println!(
            "{name}: path-traced indirect {want:.5} (of {:.5}), IGI {got:.5}",
            mean(&full)
        );
        assert!(
            want > 0.02 * mean(&full),
            "{name}: no indirect light to compare"
        );
        assert!(
            (got - want).abs() < 0.05 * want,
            "{name}: IGI {got} vs {want}"
        );
    }
}

/// In the frame driver a still view's frames each gather a VPL set of their own (keyed by the
/// frame's first sample) and the film sums them: the film is, bit for bit, the frames rendered
/// one by one onto each other's sums, and not one render of as many samples from one set.
#[test]
fn a_still_view_in_the_frame_driver_averages_over_vpl_sets() {
    use platoon::drive::{DriverOptions, FrameDriver, Pipeline};
    init();
    let scene = platoon::load_scene(None).unwrap();
    let camera =
        platoon::core::scene::camera::Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let (k, s) = (4u32, 2u32);
    let filtered = IgiOptions {
        downsample: 2,
        interleave: [2, 2],
        ..IgiOptions::with_vpls(30)
    };
    for igi in [IgiOptions::with_vpls(30), filtered] {
        let (pipeline, first) = Pipeline::new(scene.clone(), 0.0, glam::DVec3::ZERO).unwrap();
        let spec: DeviceSpec = "lavapipe:1,1".parse().unwrap();
        let tracers = create_tracers(&spec, &first, true, Sampling::Mis).unwrap();
        let offline =
            create_tracers(&"lavapipe:1".parse().unwrap(), &first, true, Sampling::Mis).unwrap();
        let mut options = DriverOptions::new(16, 16);
        options.spp = s;
        options.method = Method::new(igi);
        let cost_aware = by_name("cost-aware").unwrap();
        let mut d = FrameDriver::new(pipeline, &first, tracers, cost_aware, options).unwrap();
        for _ in 0..k {
            d.frame(camera).unwrap();
        }
        let done = d.finish().unwrap().expect("the last frame");
        assert_eq!(done.stats.film_samples, Some(k * s));

        // The same frames on one tracer, each continuing the last one's sums.
        let mut renderer = Renderer::new(offline, by_name("none").unwrap());
        let mut params = FrameParams::new(16, 16, s, camera);
        params.method = Method::new(igi);
        for i in 0..k {
            params.first_sample = i * s;
            let sums = renderer.render_frame(&params).unwrap().sums;
            params.film.accumulated = Some(sums.into());
        }
        let inv = 1.0 / (k * s) as f32;
        let sums = params.film.accumulated.as_ref().unwrap();
        let expected: Vec<[f32; 3]> = sums.iter().map(|p| p.map(|v| v * inv)).collect();
        assert!(
            done.film.pixels == expected,
            "{igi:?}: the driver's film differs"
        );

        // One render of k s samples gathers one set: another image.
        params.first_sample = 0;
        params.film.accumulated = None;
        params.spp = k * s;
        let one_set = renderer.render_frame(&params).unwrap().film;
        assert!(
            one_set.pixels != expected,
            "{igi:?}: frames shared their VPLs"
        );
    }
}

//! Issue 61's acceptance on the scenes: every golden scene alike on both traversals (the
//! per-pixel block test of `assert_within_noise`), the closed forms and the estimators'
//! agreement on the ray queries.

use super::*;
use platoon::core::method::igi::IgiOptions;
use platoon::core::Method;
use platoon::tracer::Sampling;

/// The golden images' scenes (tests/frame/golden.rs) the agreement test of the box and
/// CesiumMan leaves: RetroUFO and the teapot under their own light, the atrium's alpha-tested
/// leaves under its sun, lanterns and sky, the conference room path traced and by IGI (exact
/// visibility: its leaf boxes are the own traversal's alone), CesiumMan under the courtyard.
#[test]
fn every_golden_scene_renders_alike_on_both_traversals() {
    let load = |name: &str| platoon::load_scene(Some(&shared(&format!("scenes/{name}")))).unwrap();
    let room = prepare(
        load_generated(&platoon_scenegen::conference_room()),
        platoon::EnvChoice::Scene,
    );
    let mut igi = FrameParams::new(24, 16, 4, room.camera);
    igi.method = Method::new(IgiOptions::with_vpls(30));
    let scenes = [
        (
            "RetroUFO",
            prepare(load("RetroUFO.glb"), platoon::EnvChoice::Scene),
            16,
        ),
        (
            "the teapot",
            prepare(load("teapot.gltf"), platoon::EnvChoice::Scene),
            16,
        ),
        (
            "CesiumMan, courtyard.exr",
            prepare(
                load("CesiumMan.glb"),
                platoon::EnvChoice::File(shared("envmaps/courtyard.exr")),
            ),
            16,
        ),
        (
            "the atrium",
            prepare(
                load_generated(&platoon_scenegen::atrium::atrium()),
                platoon::EnvChoice::Color(Vec3::new(0.5, 0.6, 0.8)),
            ),
            8,
        ),
    ];
    for (what, prepared, spp) in &scenes {
        let params = FrameParams::new(32, 32, *spp, prepared.camera);
        let (own, queried) = both(prepared, &params);
        assert_within_noise(what, &own, &queried);
    }
    let params = FrameParams::new(32, 24, 8, room.camera);
    let (own, queried) = both(&room, &params);
    assert_within_noise("the conference room", &own, &queried);
    let own = render_once(&mut tracer_by(&room, Traversal::Own), &igi);
    let queried = render_once(&mut tracer_by(&room, Traversal::RayQuery), &igi);
    assert_within_noise("the conference room by IGI", &own, &queried);
}

/// tests/kernel/closed_form.rs' answers on the ray queries: a white Lambertian sphere and a
/// smooth glass one in a furnace give the sky, a Lambertian plane under a uniform sky gives its
/// albedo times the sky.
#[test]
fn the_closed_forms_hold_with_ray_queries() {
    const L: f32 = 0.8;
    let on_queries = |scene, spp| {
        let prepared = prepare(scene, constant_env(L));
        let params = FrameParams::new(32, 32, spp, prepared.camera);
        render_with(&mut tracer_by(&prepared, Traversal::RayQuery), &params)
    };
    for (what, material, slack) in [
        ("white furnace", lambertian("white", Vec3::ONE), 0.005),
        ("smooth glass furnace", smooth_glass(), 0.01),
    ] {
        let film = on_queries(sphere_scene(material), 64);
        let inside = sphere_pixels(32, 32, 0.9);
        let (m, se) = mean_and_stderr(inside.iter().map(|&i| luminance(film.pixels[i])));
        eprintln!("{what}: {m} ± {se}");
        assert!(
            (m - L as f64).abs() < slack + 4.0 * se,
            "{what}: sphere mean {m} ± {se} vs the sky {L}"
        );
    }
    let rho = 0.5f32;
    let plane = scene_of(
        vec![(
            mesh_from(&platoon_scenegen::quad(1.0, 1.0), 0),
            Vec3::ZERO,
            100.0,
        )],
        vec![lambertian("plane", Vec3::splat(rho))],
        Vec3::new(0.01, 1.0, 0.0),
        Vec3::ZERO,
        0.6,
    );
    let film = on_queries(plane, 64);
    let want = (rho * L) as f64;
    let (m, se) = mean_and_stderr(film.pixels.iter().map(|p| luminance(*p)));
    eprintln!("plane: {m} ± {se}, want {want}");
    assert!(
        (m - want).abs() < 0.002 + 4.0 * se,
        "plane mean {m} ± {se}, want {want}"
    );
}

/// BSDF sampling alone, light sampling alone and MIS (tests/kernel/estimators.rs) agree on
/// the ray queries too, block by block over seeds: the glossy Cornell box.
#[test]
fn the_estimators_agree_on_ray_queries() {
    const SEEDS: u32 = 4;
    let prepared = glossy_cornell();
    let blocks = |sampling: Sampling| -> Vec<Vec<f64>> {
        let options = TracerOptions {
            device: devices().1,
            validation: true,
            traversal: Traversal::RayQuery,
            sampling,
            ..Default::default()
        };
        let mut tracer = Tracer::new(&options, &prepared.gpu).expect("a tracer");
        (0..SEEDS)
            .map(|seed| {
                let mut params = FrameParams::new(32, 32, 64, prepared.camera);
                params.options.seed = seed;
                block_means(&render_once(&mut tracer, &params), 8)
            })
            .collect()
    };
    let mis = blocks(Sampling::Mis);
    let (bsdf, light) = (blocks(Sampling::Bsdf), blocks(Sampling::Light));
    assert_blocks_agree(&mis, &[("bsdf", &bsdf), ("light", &light)]);
}

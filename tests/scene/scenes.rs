//! The shared glTF assets load with the right contents, and each gets the kernel it calls for.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::frame::FrameParams;
use platoon::core::scene::animation::Property;
use platoon::tracer::{kernel_label, Sampling};

#[test]
fn cesium_man_loads_with_skin_texture_and_animation() {
    let scene = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.triangle_count(), 4672);
    assert_eq!(scene.textures.len(), 1);
    assert_eq!(scene.materials.len(), 1);
    assert!(scene.materials[0].base_color_texture.is_some());
    assert_eq!(scene.skins.len(), 1);
    assert_eq!(scene.skins[0].joints.len(), 19);
    assert_eq!(scene.animations.len(), 1);
    let anim = &scene.animations[0];
    assert_eq!(anim.channels.len(), 57);
    assert!(
        (anim.duration() - 2.0).abs() < 1e-3,
        "duration {}",
        anim.duration()
    );
    assert_eq!(
        anim.channels
            .iter()
            .filter(|c| c.property == Property::Rotation)
            .count(),
        19
    );
    // The animation moves the skinned vertices.
    let (a, b) = (scene.pose(0.0), scene.pose(0.5));
    assert_ne!(a.bounds(), b.bounds());
    let mesh_a = &a.meshes[a.instances[0].mesh];
    let mesh_b = &b.meshes[b.instances[0].mesh];
    let moved = mesh_a
        .positions
        .iter()
        .zip(&mesh_b.positions)
        .filter(|(p, q)| p.distance(**q) > 1e-3)
        .count();
    assert!(moved > 1000, "only {moved} vertices moved");
    // Skinning keeps the figure its size (about 1.5 units tall).
    let (lo, hi) = a.bounds();
    let height = (hi - lo).max_element();
    assert!((1.0..2.5).contains(&height), "posed height {height}");
}

#[test]
fn retro_ufo_and_teapot_load_with_their_counts() {
    let ufo = platoon::load_scene(Some(&shared("scenes/RetroUFO.glb"))).unwrap();
    assert_eq!(ufo.meshes.len(), 77);
    assert_eq!(ufo.triangle_count(), 16428);
    assert_eq!(ufo.materials.len(), 7);
    assert!(ufo.textures.is_empty());
    let teapot = platoon::load_scene(Some(&shared("scenes/teapot.gltf"))).unwrap();
    assert_eq!(teapot.triangle_count(), 9128);
    // No material in the file: the glTF default (white, metallic 1, roughness 1).
    assert_eq!(teapot.materials.len(), 1);
    assert_eq!(teapot.materials[0].metallic, 1.0);
}

#[test]
fn scenes_without_lights_get_a_default_sky_and_say_so() {
    let p = prepare(
        platoon::load_scene(Some(&shared("scenes/teapot.gltf"))).unwrap(),
        platoon::EnvChoice::Scene,
    );
    assert!(p.note.as_deref().unwrap_or("").contains("no lights"));
    assert_eq!(p.gpu.env.kind, 1);
    let cornell = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    );
    assert!(cornell.note.is_none());
    assert_eq!(cornell.gpu.env.kind, 0);
}

#[test]
fn each_scene_gets_the_kernel_its_features_call_for() {
    let env = || platoon::EnvChoice::File(shared("envmaps/forest.exr"));
    let load = |s: &str| platoon::load_scene(Some(&shared(s))).unwrap();
    let cesium = prepare(load("scenes/CesiumMan.glb"), platoon::EnvChoice::Scene);
    let cesium_env = prepare(load("scenes/CesiumMan.glb"), env());
    let ufo = prepare(load("scenes/RetroUFO.glb"), platoon::EnvChoice::Scene);
    let teapot_env = prepare(load("scenes/teapot.gltf"), env());
    let cornell = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    );
    // A base colour texture alone: the other slots' fetches are not compiled in.
    assert_eq!(
        cesium.gpu.features.defines(),
        [
            "HAS_SPECULAR_LOBES",
            "HAS_TEXTURES",
            "HAS_BASE_COLOR_TEXTURES"
        ]
    );
    assert_eq!(
        cesium_env.gpu.features.defines(),
        [
            "HAS_SPECULAR_LOBES",
            "HAS_TEXTURES",
            "HAS_BASE_COLOR_TEXTURES",
            "HAS_ENVIRONMENT_MAP"
        ]
    );
    assert_eq!(ufo.gpu.features.defines(), ["HAS_SPECULAR_LOBES"]);
    assert_eq!(
        teapot_env.gpu.features.defines(),
        ["HAS_SPECULAR_LOBES", "HAS_ENVIRONMENT_MAP"]
    );
    // Lambertian walls (KHR_materials_specular factor 0): no GGX code.
    assert_eq!(cornell.gpu.features.defines(), ["HAS_EMISSIVE_TRIANGLES"]);
    let labels: std::collections::HashSet<String> =
        [&cesium, &cesium_env, &ufo, &teapot_env, &cornell]
            .iter()
            .map(|p| kernel_label(p.gpu.features))
            .collect();
    assert_eq!(labels.len(), 5);
    // The compiled kernels differ too: each variant is its own SPIR-V, smaller without features.
    init();
    let spirv: Vec<Vec<u32>> = [&cesium, &cesium_env, &ufo, &teapot_env, &cornell]
        .iter()
        .map(|p| platoon::tracer::kernel_spirv(p.gpu.features, Sampling::Mis).unwrap())
        .collect();
    let distinct: std::collections::HashSet<&Vec<u32>> = spirv.iter().collect();
    assert_eq!(distinct.len(), 5);
    assert!(
        spirv[2].len() < spirv[1].len(),
        "the kernel with fewer features is not smaller"
    );
    assert!(
        spirv[4].len() < spirv[2].len(),
        "the Lambertian kernel is not smaller"
    );
}

#[test]
fn the_generated_conference_room_loads_and_renders_lit_by_its_point_lights() {
    // The IGI scene (issue 11): platoon-scenegen --conference-room.
    init();
    let scene = load_generated(&platoon_scenegen::conference_room());
    assert!(
        scene.triangle_count() > 100_000,
        "{}",
        scene.triangle_count()
    );
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    let f = prepared.gpu.features;
    assert!(f.punctual_lights && !f.emissive_triangles && !f.transmission && !f.textures);
    // Lit by its own lights (platoon added no sky), seen from inside the room.
    assert!(prepared.note.is_none(), "{:?}", prepared.note);
    let params = platoon::core::frame::FrameParams::new(32, 24, 4, prepared.camera);
    let film = render(&prepared, &params, Sampling::Mis);
    assert_eq!(film.count_non_finite(), 0);
    let lit = film
        .pixels
        .iter()
        .filter(|p| p[0] + p[1] + p[2] > 0.0)
        .count();
    assert!(
        lit > film.pixels.len() * 3 / 4,
        "{lit} of {} pixels lit",
        film.pixels.len()
    );
}

#[test]
fn a_pass_past_the_loop_limit_is_finished_by_the_streaming_kernels() {
    // A thicket of 4,000 triangles that each cross the whole cube: every ray tests nearly all
    // of them whatever the BVH, so at 8 samples a pixel llvmpipe's loop limit (65,535 iterations
    // an invocation, path/pathtrace.comp) cuts the megakernel's SIMD groups short, while one
    // traversal (about 5,000 iterations) stays within it in the streaming kernels.
    init();
    let scene = load_generated(&platoon_scenegen::adversarial::thicket(4000));
    let prepared = prepare(scene, constant_env(0.5));
    let params = platoon::core::frame::FrameParams::new(16, 12, 8, prepared.camera);
    let mut t = tracer(&prepared, Sampling::Mis);
    let r = platoon::render_bands(
        &mut t,
        &params,
        &[platoon::whole_frame(&params)],
        &mut |_| {},
    )
    .expect("render");
    if t.device_info().cpu {
        assert_eq!(r.kernel_fallbacks, 1, "the cut-short pass was not noticed");
    }
    // render() checks that the image is the streaming kernels' bits.
    let film = render(&prepared, &params, Sampling::Mis);
    assert!(r.film == film);
    assert_eq!(film.count_non_finite(), 0);
    let lit = film
        .pixels
        .iter()
        .filter(|p| p[0] + p[1] + p[2] > 0.0)
        .count();
    assert_eq!(
        lit,
        film.pixels.len(),
        "every pixel sees the thicket or the sky"
    );
}

/// The scene prepared with its objects that never move merged into one bottom level, and
/// without (an instance per node).
fn merged_and_not(scene: platoon::core::Scene, env: platoon::EnvChoice) -> [platoon::Prepared; 2] {
    [true, false].map(|merge_static| {
        platoon::prepare(
            scene.clone(),
            &platoon::PrepareOptions {
                env: env.clone(),
                merge_static,
                ..Default::default()
            },
        )
        .unwrap()
    })
}

#[test]
fn merged_static_geometry_renders_the_image_of_its_instances() {
    let generated = |data| load_generated(&data);
    let cases = [
        (
            "cornell, a node per object",
            generated(platoon_scenegen::bench::cornell_nodes()),
            platoon::EnvChoice::Scene,
        ),
        (
            "teapot",
            platoon::load_scene(Some(&shared("scenes/teapot.gltf"))).unwrap(),
            platoon::EnvChoice::Scene,
        ),
        (
            "RetroUFO",
            platoon::load_scene(Some(&shared("scenes/RetroUFO.glb"))).unwrap(),
            constant_env(1.0),
        ),
    ];
    for (name, scene, env) in cases {
        let nodes = scene.nodes.iter().filter(|n| n.mesh.is_some()).count();
        let [merged, instanced] = merged_and_not(scene, env);
        assert_eq!(instanced.gpu.instances.len(), nodes, "{name}");
        // Nothing here moves: one instance of the merged mesh.
        assert_eq!(merged.gpu.instances.len(), 1, "{name}");
        assert_eq!(
            merged.gpu.triangle_count, instanced.gpu.triangle_count,
            "{name}"
        );
        let params = FrameParams::new(32, 32, 16, merged.camera);
        let (a, b) = (
            render(&merged, &params, Sampling::Mis),
            render(&instanced, &params, Sampling::Mis),
        );
        // The same random numbers meet the same surfaces: most pixels keep every bit, the
        // rest moved by rounding (a hit in object space against one in render space).
        let same = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .filter(|(x, y)| x == y)
            .count();
        let (ma, mb) = (a.mean(), b.mean());
        let rel = (0..3)
            .map(|c| (ma[c] - mb[c]).abs() / mb[c].max(1e-6))
            .fold(0.0, f64::max);
        eprintln!(
            "{name}: {same} of {} pixels identical, means differ by {rel:.2e}",
            a.pixels.len()
        );
        assert!(rel < 1e-4, "{name}: means {ma:?} against {mb:?}");
    }
}

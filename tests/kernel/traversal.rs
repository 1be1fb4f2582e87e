//! The two traversals (issue 61): platoon's own BVH and the device's ray queries over the
//! acceleration structures built on it. They run on bookworm-backports' Mesa 25 lavapipe
//! (`tools/mesa25.sh` unpacks it beside Debian 12's 22.3, which offers no ray queries): the
//! same scenes within noise, a closed form on the ray queries, the same bits on one and three
//! tracers, a frame split between one tracer of each, a living scene's commits followed, and a
//! clear refusal where a device has none.

#[path = "../common/mod.rs"]
mod common;
#[path = "traversal/refits.rs"]
mod refits;
#[path = "traversal/scenes.rs"]
mod scenes;

use std::sync::OnceLock;

use common::*;
use glam::Vec3;
use platoon::core::balance::by_name;
use platoon::core::frame::FrameParams;
use platoon::core::output::Film;
use platoon::core::scene::cornell::lambertian;
use platoon::core::scene::{AlphaMode, Material};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::{Tracer, TracerOptions, Traversal};
use platoon::Prepared;

/// The devices of both drivers: (Debian 12's lavapipe, Mesa 25's), by their index.
fn devices() -> (usize, usize) {
    static DEVICES: OnceLock<(usize, usize)> = OnceLock::new();
    *DEVICES.get_or_init(|| {
        init();
        let both = format!("{LAVAPIPE_ICD}:{}", mesa25_icd());
        let both = std::ffi::OsStr::new(&both);
        platoon::tracer::set_environment(&[("VK_DRIVER_FILES", both), ("VK_ICD_FILENAMES", both)]);
        let list = platoon::tracer::list_devices().expect("the devices");
        let index = |queries: bool| {
            list.iter()
                .find(|d| d.ray_queries == queries)
                .unwrap_or_else(|| panic!("no device with ray queries {queries}: {list:?}"))
                .index
        };
        (index(false), index(true))
    })
}

/// A tracer on Mesa 25's lavapipe traversing by `traversal`, with validation.
fn tracer_by(prepared: &Prepared, traversal: Traversal) -> Tracer {
    let options = TracerOptions {
        device: devices().1,
        validation: true,
        traversal,
        ..Default::default()
    };
    Tracer::new(&options, &prepared.gpu).expect("a tracer")
}

/// `params` rendered by each traversal on Mesa 25 (each in both path kernels, the same bits:
/// `render_with`).
fn both(prepared: &Prepared, params: &FrameParams) -> (Film, Film) {
    let own = render_with(&mut tracer_by(prepared, Traversal::Own), params);
    let queried = render_with(&mut tracer_by(prepared, Traversal::RayQuery), params);
    (own, queried)
}

/// The two images agree within noise: the same random numbers walk the same paths but where
/// the two intersection tests round a hit apart, so the pixels' paired differences average to
/// zero within four standard errors, over the image and in each 8x8 block of it (a missing or
/// misplaced object moves its block though the image's mean may hide it); and they are images
/// of something.
fn assert_within_noise(what: &str, own: &Film, queried: &Film) {
    let diffs = |pixels: &mut dyn Iterator<Item = usize>| {
        let d: Vec<f64> = pixels
            .map(|i| luminance(own.pixels[i]) - luminance(queried.pixels[i]))
            .collect();
        mean_and_stderr(d.into_iter())
    };
    let (m, se) = diffs(&mut (0..own.pixels.len()));
    let level = mean(own);
    eprintln!(
        "{what}: own {level}, ray queries {}, difference {m} ± {se}",
        mean(queried)
    );
    assert!(level > 0.01, "{what}: a black image");
    assert!(
        m.abs() <= 4.0 * se + 1e-4 * level,
        "{what}: the traversals differ by {m} ± {se} (image {level})"
    );
    let (w, h) = (own.width as usize, own.height as usize);
    for (by, bx) in (0..h.div_ceil(BLOCK)).flat_map(|y| (0..w.div_ceil(BLOCK)).map(move |x| (y, x)))
    {
        let mut pixels = (by * BLOCK..h.min((by + 1) * BLOCK))
            .flat_map(|y| (bx * BLOCK..w.min((bx + 1) * BLOCK)).map(move |x| y * w + x));
        let (m, se) = diffs(&mut pixels);
        assert!(
            m.abs() <= 4.5 * se + 1e-4 * level,
            "{what}: the traversals differ in the block at ({}, {}) by {m} ± {se} (image {level})",
            bx * BLOCK,
            by * BLOCK
        );
    }
}

/// The side of the blocks `assert_within_noise` holds to noise one by one.
const BLOCK: usize = 8;

/// A ground lit by a sky under a cover whose alpha is under its mask's cutoff (the ray passes)
/// beside one above it (the ray stops), and a blended pane: the candidates a ray query tests,
/// on four meshes.
fn alpha_tested() -> Prepared {
    alpha_tested_with(1.2, false)
}

/// `alpha_tested` with the opaque-enough cover at `x`, and with `more`, a fifth mesh (a cover
/// beside the others).
fn alpha_tested_with(x: f32, more: bool) -> Prepared {
    let quad = platoon_scenegen::quad(1.0, 1.0);
    let cover = |alpha: f32, alpha_mode: AlphaMode| Material {
        name: "cover".into(),
        base_color: Vec3::splat(0.6).extend(alpha),
        alpha_mode,
        ..lambertian("cover", Vec3::ONE)
    };
    // At three heights: two alpha-tested triangles coplanar where both cover a ray are where
    // the own traversal, which moves past the one it let through by distance, may take the
    // wrong one (an opaque one it keeps: features.rs' decal).
    let mut meshes = vec![
        (mesh_from(&quad, 0), Vec3::ZERO, 8.0),
        (mesh_from(&quad, 1), Vec3::new(-1.2, 0.6, 0.0), 1.5),
        (mesh_from(&quad, 2), Vec3::new(x, 0.9, 0.0), 1.5),
        (mesh_from(&quad, 3), Vec3::new(0.0, 1.2, 0.0), 1.5),
    ];
    if more {
        meshes.push((mesh_from(&quad, 2), Vec3::new(0.0, 0.3, 2.0), 0.5));
    }
    let scene = scene_of(
        meshes,
        vec![
            lambertian("ground", Vec3::splat(0.7)),
            cover(0.3, AlphaMode::Mask(0.5)),
            cover(0.9, AlphaMode::Mask(0.5)),
            cover(0.4, AlphaMode::Blend),
        ],
        Vec3::new(0.0, 4.0, 4.0),
        Vec3::ZERO,
        0.9,
    );
    // Unmerged: a mesh and an instance each, so a hit's triangle is its mesh's first plus the
    // primitive's index (static geometry merged would be one mesh).
    let options = platoon::PrepareOptions {
        env: constant_env(1.0),
        merge_static: false,
        ..Default::default()
    };
    let prepared = platoon::prepare(scene, &options).expect("prepare");
    assert!(prepared.gpu.features.alpha_mask && prepared.gpu.features.alpha_blend);
    assert_eq!(prepared.gpu.regions.len(), 4 + more as usize);
    prepared
}

#[test]
fn the_traversals_agree_on_the_box_a_character_and_alpha_tested_covers() {
    let box_ = prepare(platoon::core::scene::cornell::scene(), constant_env(0.0));
    let cesium = prepare(
        platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap(),
        platoon::EnvChoice::File(shared("envmaps/forest.exr")),
    );
    for (what, prepared, spp) in [
        ("the box", box_, 32),
        ("CesiumMan", cesium, 16),
        ("alpha-tested covers", alpha_tested(), 16),
    ] {
        let params = FrameParams::new(32, 32, spp, prepared.camera);
        let (own, queried) = both(&prepared, &params);
        assert_within_noise(what, &own, &queried);
    }
}

#[test]
fn ray_query_tracers_split_a_frame_as_one_and_beside_the_own_traversal() {
    let prepared = alpha_tested();
    let params = FrameParams::new(24, 24, 8, prepared.camera);
    let render = |traversals: &[Traversal]| {
        let tracers = traversals
            .iter()
            .map(|&t| tracer_by(&prepared, t))
            .collect();
        let mut renderer = Renderer::new(tracers, by_name("none").unwrap());
        renderer.render_frame(&params).unwrap().sums
    };
    use Traversal::{Own, RayQuery};
    let queried = render(&[RayQuery]);
    assert!(
        render(&[RayQuery, RayQuery, RayQuery]) == queried,
        "three ray-query tracers changed the bits"
    );
    // One of each: the halves are each traversal's own image's.
    let own = render(&[Own]);
    let split = render(&[Own, RayQuery]);
    let half = 12 * 24;
    assert!(split[..half] == own[..half], "the own traversal's half");
    assert!(split[half..] == queried[half..], "the ray queries' half");
}

#[test]
fn a_device_without_ray_queries_is_refused_naming_it() {
    let prepared = prepare(platoon::core::scene::cornell::scene(), constant_env(0.0));
    let options = TracerOptions {
        device: devices().0,
        traversal: Traversal::RayQuery,
        ..Default::default()
    };
    let Err(e) = Tracer::new(&options, &prepared.gpu) else {
        panic!("Mesa 22.3's lavapipe took the ray-query traversal");
    };
    let e = e.to_string();
    assert!(
        e.contains("llvmpipe") && e.contains("no ray queries"),
        "{e}"
    );
    assert!(e.contains("--traversal own"), "{e}");
}

/// CesiumMan posed at `time` under a white sky, unmerged.
fn cesium_at(time: f32) -> Prepared {
    let options = platoon::PrepareOptions {
        env: constant_env(1.0),
        time,
        merge_static: false,
        ..Default::default()
    };
    let scene = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    platoon::prepare(scene, &options).expect("prepare")
}

/// A ray-query tracer's structures follow a living scene's commits: a cover moved (its
/// instance), a skin deforming (its mesh's triangles), a mesh added (every mesh's place): the
/// image after the commit is the bits of a tracer made on the changed scene, and within noise
/// of the own traversal's after the same commit.
#[test]
fn ray_query_structures_follow_a_living_scenes_commits() {
    let cases = [
        (
            "a cover moved",
            alpha_tested(),
            alpha_tested_with(0.4, false),
        ),
        ("a skin deforming", cesium_at(0.0), cesium_at(0.6)),
        ("a mesh added", alpha_tested(), alpha_tested_with(1.2, true)),
    ];
    for (what, before, after) in cases {
        let commit = platoon::core::flatten::commit::Commit::between(&before.gpu, &after.gpu);
        assert!(!commit.arrays.is_empty(), "{what}: no change");
        let params = FrameParams::new(24, 24, 8, after.camera);
        let mut followed = tracer_by(&before, Traversal::RayQuery);
        followed.apply_commit(&commit).expect("the commit");
        let followed = render_with(&mut followed, &params);
        let fresh = render_with(&mut tracer_by(&after, Traversal::RayQuery), &params);
        assert!(
            followed == fresh,
            "{what}: the followed structures' image differs"
        );
        let mut own = tracer_by(&before, Traversal::Own);
        own.apply_commit(&commit).expect("the commit");
        assert_within_noise(what, &render_with(&mut own, &params), &followed);
    }
}

/// A living scene on ray queries: CesiumMan walking through the tessellated box (its skin and
/// its placement each step), a box added and then removed, generation by generation from the
/// game loop's updater: each generation's image, on tracers that followed every commit, is the
/// bits of a ray-query tracer made on that generation, and within noise of the own traversal's.
#[test]
fn a_living_scene_on_ray_queries_walks_as_the_own_traversal_does() {
    use platoon::core::scene::camera::Camera;
    use platoon::drive::walk::{walk_edits, walk_in_a_room};
    use platoon::drive::{Edit, Updater};
    let man = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    let (scene, node) = walk_in_a_room(&man, 4).unwrap();
    let camera = Camera::look_at(Vec3::new(2.8, 2.2, -3.0), Vec3::new(2.4, 1.2, 2.8), 0.9);
    let mut updater = Updater::new(scene, 0.0, glam::DVec3::ZERO).unwrap();
    let by = |traversal: Traversal, scene: &platoon::core::flatten::GpuScene| {
        let options = TracerOptions {
            device: devices().1,
            validation: true,
            traversal,
            ..Default::default()
        };
        Tracer::new(&options, scene).unwrap()
    };
    let mut own = by(Traversal::Own, updater.flattened());
    let mut queried = by(Traversal::RayQuery, updater.flattened());
    let mut prop = None;
    for step in 1..5 {
        for e in walk_edits(node, step) {
            updater.apply(e).unwrap();
        }
        match step {
            2 => {
                let placement =
                    platoon::core::scene::Placement::at(glam::DVec3::new(2.0, 0.3, 1.5));
                let added = Edit::AddInstance { mesh: 0, placement };
                prop = updater.apply(added).unwrap();
            }
            4 => {
                let removed = Edit::RemoveInstance(prop.expect("the box added"));
                updater.apply(removed).unwrap();
            }
            _ => {}
        }
        let g = updater.update().unwrap();
        own.apply_commit(&g.commit).unwrap();
        queried.apply_commit(&g.commit).unwrap();
        let mut params = FrameParams::new(24, 24, 16, camera);
        params.frame = step as u32;
        let followed = render_with(&mut queried, &params);
        let fresh = render_with(&mut by(Traversal::RayQuery, updater.flattened()), &params);
        assert!(
            followed == fresh,
            "step {step}: the followed structures' image differs"
        );
        assert_within_noise(
            &format!("step {step}"),
            &render_with(&mut own, &params),
            &followed,
        );
    }
    // The skin's bottom level was built to be refitted at its first step and refitted after,
    // where the core refitted its BVH.
    let counts = queried.structure_counts().expect("structures");
    eprintln!("the walk's structures: {counts:?}");
    assert!(counts.refitted > 0, "{counts:?}");
}

/// The other methods trace through the same `trace()`: IGI's particles and gathers, vertex
/// links' shots and layered hit buffers' paths give, on ray queries, the built-in box's image
/// within noise of their own traversal's (IGI), or within 1% where a method's solution is
/// shared by many pixels (a link's light at a vertex, a buffer's texel), so that a shot
/// rounded apart moves a region together rather than one pixel.
#[test]
fn the_other_methods_render_with_ray_queries_as_with_the_own_traversal() {
    let device = devices().1;
    for (name, per_pixel) in [("igi", true), ("links", false), ("lhb", false)] {
        let kind = platoon::core::method::registry::kind(name).expect("a built-in method");
        let method = kind.build(&Default::default()).expect("its defaults");
        let render = |traversal: Traversal| {
            let request = platoon::Request {
                width: 24,
                height: 24,
                spp: 8,
                method: method.clone(),
                devices: platoon::devices::DeviceSpec::Indices(vec![device]),
                traversal,
                ..Default::default()
            };
            request.render(&mut |_| {}).expect("a render").image
        };
        let (own, queried) = (render(Traversal::Own), render(Traversal::RayQuery));
        if per_pixel {
            assert_within_noise(name, &own, &queried);
        } else {
            let (a, b) = (mean(&own), mean(&queried));
            eprintln!("{name}: own {a}, ray queries {b}");
            assert!(
                a > 0.01 && (a - b).abs() < 0.01 * a,
                "{name}: {a} against {b}"
            );
        }
    }
}

/// The metadata names what each device traced with, in the devices' order: `auto` is the own
/// traversal on lavapipe (Mesa 25's ray queries measured slower there), the ray queries where
/// asked for.
#[test]
fn the_metadata_names_each_devices_traversal() {
    let (old, new) = devices();
    let render = |devices: Vec<usize>, traversal: Traversal| {
        let request = platoon::Request {
            width: 8,
            height: 8,
            spp: 1,
            devices: platoon::devices::DeviceSpec::Indices(devices),
            traversal,
            ..Default::default()
        };
        let still = request.render(&mut |_| {}).expect("a render");
        let entry = still.metadata.iter().find(|(k, _)| k == "traversal");
        entry.expect("a traversal entry").1.clone()
    };
    assert_eq!(render(vec![new], Traversal::RayQuery), "ray-query");
    assert_eq!(render(vec![new, old], Traversal::Auto), "own, own");
    assert_eq!(render(vec![old], Traversal::Own), "own");
}

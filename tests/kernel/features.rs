//! Effects beyond the basic path: punctual lights against their closed forms, alpha masks,
//! textures larger than lavapipe's 128 MiB storage-buffer range, and the thin lens.

#[path = "../common/mod.rs"]
mod common;

use std::f32::consts::PI;

use common::*;
use glam::{Vec2, Vec3};
use platoon::core::frame::FrameParams;
use platoon::core::method::path::PathKernel;
use platoon::core::output::Film;
use platoon::core::scene::cornell::lambertian;
use platoon::core::scene::texture_levels::{TextureLod, TextureOptions};
use platoon::core::scene::{AlphaMode, LightKind, Material, Texture, TextureRef, Wrap};
use platoon::tracer::{MemoryPath, Sampling};

const RHO: f32 = 0.5;

/// A 20 x 20 Lambertian ground seen straight down from height 2 (plus a tiny offset so the
/// view is not exactly parallel to an axis).
fn ground(
    extra: Vec<(platoon::core::scene::Mesh, Vec3, f32)>,
    mut materials: Vec<Material>,
) -> platoon::core::Scene {
    let mut meshes = vec![(
        mesh_from(&platoon_scenegen::quad(1.0, 1.0), 0),
        Vec3::ZERO,
        10.0,
    )];
    meshes.extend(extra);
    materials.insert(0, lambertian("ground", Vec3::splat(RHO)));
    scene_of(
        meshes,
        materials,
        Vec3::new(0.001, 2.0, 0.0),
        Vec3::ZERO,
        1.0,
    )
}

/// Ground point under the centre of pixel (x, y) of a w x h view from `sphere_scene`-like
/// camera at (0.001, 2, 0) looking down with vertical fov 1.0.
fn ground_point(prepared: &platoon::Prepared, x: u32, y: u32, w: u32, h: u32) -> Vec3 {
    let cam = prepared.camera.camera_to_world;
    let tan = (prepared.camera.yfov * 0.5).tan();
    let ndc = Vec2::new(
        2.0 * (x as f32 + 0.5) / w as f32 - 1.0,
        1.0 - 2.0 * (y as f32 + 0.5) / h as f32,
    );
    let d = (cam.transform_vector3(Vec3::new(
        ndc.x * tan * w as f32 / h as f32,
        ndc.y * tan,
        -1.0,
    )))
    .normalize();
    let o = cam.transform_point3(Vec3::ZERO);
    o + d * (-o.y / d.y)
}

fn check_against(prepared: &platoon::Prepared, expected: impl Fn(Vec3) -> f32, tolerance: f32) {
    let (w, h) = (24, 24);
    let film = render(
        prepared,
        &FrameParams::new(w, h, 16, prepared.camera),
        Sampling::Mis,
    );
    for y in 0..h {
        for x in 0..w {
            let want = expected(ground_point(prepared, x, y, w, h));
            let got = film.pixels[(y * w + x) as usize][0];
            assert!(
                (got - want).abs() <= tolerance * want.max(0.05),
                "pixel {x},{y}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn point_light_matches_inverse_square_cosine_law() {
    let mut scene = ground(vec![], vec![]);
    let (i, height) = (3.0, 1.0);
    add_light(&mut scene, LightKind::Point, i, Vec3::new(0.3, height, 0.2));
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    assert!(prepared.gpu.features.punctual_lights);
    check_against(
        &prepared,
        |p| {
            let d = Vec3::new(0.3, height, 0.2) - p;
            RHO / PI * i * (d.y / d.length()) / d.length_squared()
        },
        0.05,
    );
}

/// Resampled light by emitted luminance weighs lights in solid angle, where a point light has
/// no density: the tracer refuses it on a scene with one (the rule the lab skips such a
/// technique by), and by contribution it renders the light's closed form.
#[test]
fn resampled_light_by_luminance_is_refused_where_punctual_lights_are() {
    use platoon::core::method::path::ResampledLight;
    let mut scene = ground(vec![], vec![]);
    let (i, at) = (3.0, Vec3::new(0.3, 1.0, 0.2));
    add_light(&mut scene, LightKind::Point, i, at);
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    let (w, h) = (16, 16);
    let with = |contribution: bool| {
        let mut params = FrameParams::new(w, h, 16, prepared.camera);
        let mut r = ResampledLight::new(4);
        r.contribution = contribution;
        params.method.path_mut().unwrap().resampled_light = Some(r);
        params
    };
    let mut t = tracer(&prepared, Sampling::Mis);
    let refused = t.render(&with(false), 0, h, &mut |_| {}).unwrap_err();
    assert!(refused.to_string().contains("punctual"), "{refused}");
    let film = render_with(&mut t, &with(true));
    for y in 0..h {
        for x in 0..w {
            let d = at - ground_point(&prepared, x, y, w, h);
            let want = RHO / PI * i * (d.y / d.length()) / d.length_squared();
            let got = film.pixels[(y * w + x) as usize][0];
            assert!(
                (got - want).abs() <= 0.05 * want.max(0.05),
                "{x},{y}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn directional_and_spot_lights_match_their_closed_forms() {
    let mut scene = ground(vec![], vec![]);
    add_light(
        &mut scene,
        LightKind::Directional,
        2.0,
        Vec3::new(0.0, 5.0, 0.0),
    );
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    check_against(&prepared, |_| RHO / PI * 2.0, 0.01);

    // Spot straight down at height 1: full intensity inside the inner cone, none outside the outer.
    let mut scene = ground(vec![], vec![]);
    let (inner, outer) = (0.3f32, 0.4f32);
    add_light(
        &mut scene,
        LightKind::Spot {
            inner_cone: inner,
            outer_cone: outer,
        },
        3.0,
        Vec3::new(0.0, 1.0, 0.0),
    );
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    let (w, h) = (24, 24);
    let film = render(
        &prepared,
        &FrameParams::new(w, h, 16, prepared.camera),
        Sampling::Mis,
    );
    let (mut inside, mut outside) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let p = ground_point(&prepared, x, y, w, h);
            let d = Vec3::new(0.0, 1.0, 0.0) - p;
            let angle = (d.y / d.length()).acos();
            let got = film.pixels[(y * w + x) as usize][0];
            if angle < inner * 0.8 {
                let want = RHO / PI * 3.0 * (d.y / d.length()) / d.length_squared();
                assert!((got - want).abs() < 0.05 * want, "inside: {got} vs {want}");
                inside += 1;
            } else if angle > outer * 1.2 {
                assert_eq!(got, 0.0, "outside the cone");
                outside += 1;
            }
        }
    }
    assert!(
        inside > 10 && outside > 10,
        "{inside} inside, {outside} outside"
    );
}

#[test]
fn alpha_masked_geometry_neither_shows_nor_shadows() {
    const L: f32 = 0.8;
    let cover = mesh_from(&platoon_scenegen::quad(1.0, 1.0), 1);
    let masked = Material {
        name: "masked".into(),
        base_color: Vec3::ONE.extend(0.3),
        alpha_mode: AlphaMode::Mask(0.5),
        ..lambertian("m", Vec3::ONE)
    };
    let prepared = prepare(
        ground(
            vec![(cover.clone(), Vec3::new(0.0, 1.0, 0.0), 20.0)],
            vec![masked.clone()],
        ),
        constant_env(L),
    );
    assert!(prepared.gpu.features.alpha_mask);
    let film = render(
        &prepared,
        &FrameParams::new(16, 16, 32, prepared.camera),
        Sampling::Mis,
    );
    let (m, se) = mean_and_stderr(film.pixels.iter().map(|p| luminance(*p)));
    assert!(
        (m - (RHO * L) as f64).abs() < 0.003 + 4.0 * se,
        "masked cover changed the ground: {m}"
    );
    // An opaque cover (alpha above the cutoff) hides the ground and shadows it.
    let opaque = Material {
        base_color: Vec3::splat(0.2).extend(0.9),
        ..masked
    };
    let prepared = prepare(
        ground(vec![(cover, Vec3::new(0.0, 1.0, 0.0), 20.0)], vec![opaque]),
        constant_env(L),
    );
    let film = render(
        &prepared,
        &FrameParams::new(16, 16, 32, prepared.camera),
        Sampling::Mis,
    );
    assert!(film.mean()[0] < 0.5 * (RHO * L) as f64);
}

/// A fully transparent alpha-masked quad lying on an opaque one (a decal on its wall, coplanar)
/// changes nothing: the traversal that moves past the masked triangle keeps the opaque one at
/// the same distance, whether both are one merged mesh (the same distance, to the bit) or two
/// instances (distances that round apart in each instance's space). The device's ray queries
/// showed it: the image was brighter where rays went through both (tests/kernel/traversal.rs).
#[test]
fn a_transparent_decal_on_a_wall_leaves_the_wall_whole() {
    let quad = platoon_scenegen::quad(1.0, 1.0);
    let decal = Material {
        name: "decal".into(),
        base_color: Vec3::ONE.extend(0.2),
        alpha_mode: AlphaMode::Mask(0.5),
        ..lambertian("decal", Vec3::ONE)
    };
    // A far alpha-tested speck, so that both scenes compile the alpha test.
    let speck = Material {
        alpha_mode: AlphaMode::Mask(0.5),
        ..lambertian("speck", Vec3::ONE)
    };
    let scene = |with_decal: bool| {
        let mut meshes = vec![
            (mesh_from(&quad, 0), Vec3::ZERO, 8.0),
            (mesh_from(&quad, 1), Vec3::new(0.4, 0.6, 0.0), 1.5),
            (mesh_from(&quad, 3), Vec3::new(0.0, -50.0, 0.0), 0.1),
        ];
        if with_decal {
            meshes.push((mesh_from(&quad, 2), Vec3::new(-1.2, 0.6, 0.0), 1.5));
        }
        let materials = vec![
            lambertian("ground", Vec3::splat(0.7)),
            lambertian("wall", Vec3::splat(0.6)),
            decal.clone(),
            speck.clone(),
        ];
        scene_of(meshes, materials, Vec3::new(0.0, 4.0, 4.0), Vec3::ZERO, 0.9)
    };
    for merge_static in [true, false] {
        let image = |with_decal: bool| {
            let options = platoon::PrepareOptions {
                env: constant_env(1.0),
                merge_static,
                ..Default::default()
            };
            let prepared = platoon::prepare(scene(with_decal), &options).unwrap();
            assert!(prepared.gpu.features.alpha_mask);
            let mut params = FrameParams::new(24, 24, 16, prepared.camera);
            params.path_loop.max_depth = 3;
            render(&prepared, &params, Sampling::Mis)
        };
        assert!(
            image(true) == image(false),
            "merged {merge_static}: the decal changed the image"
        );
    }
}

#[test]
fn texture_larger_than_the_storage_buffer_range_renders_on_every_path() {
    const L: f32 = 1.0;
    // 6,100^2 RGBA8 texels = 148.8 MB, beyond lavapipe's 128 MiB maxStorageBufferRange.
    let side = 6100u32;
    let texture = Texture {
        name: "big".into(),
        width: side,
        height: side,
        rgba8: [128u8, 128, 128, 255].repeat((side * side) as usize),
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::Repeat,
        nearest: false,
        mips: Vec::new(),
    };
    assert!(texture.rgba8.len() > 128 << 20);
    let mut scene = ground(vec![], vec![]);
    std::sync::Arc::make_mut(&mut scene.meshes[0]).uvs =
        vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    scene.textures.push(texture);
    scene.materials[0].base_color_texture = Some(TextureRef::new(0));
    scene.materials[0].base_color = Vec3::ONE.extend(1.0);
    let prepared = prepare(scene, constant_env(L));
    assert!(prepared.gpu.features.textures);
    let params = FrameParams::new(12, 12, 16, prepared.camera);
    // By default (lavapipe) the 37 M-texel array fits a texel buffer; with storage buffers forced
    // it goes by device address while the other arrays keep their storage-buffer bindings.
    let cases = [
        (MemoryPath::Auto, "TEXEL_TEXELS", "TEXEL_VERTICES"),
        (MemoryPath::StorageBuffers, "", "SSBO_VERTICES"),
    ];
    for (memory, texels, vertices) in cases {
        let mut t = tracer_reading(&prepared.gpu, memory);
        let defines = t.kernel_defines(&params);
        assert!(defines.contains(&vertices), "{memory:?}: {defines:?}");
        if texels.is_empty() {
            let bound = ["SSBO_TEXELS", "TEXEL_TEXELS"];
            assert!(!defines.iter().any(|d| bound.contains(d)), "{defines:?}");
        } else {
            assert!(defines.contains(&texels), "{memory:?}: {defines:?}");
        }
        let film = render_with(&mut t, &params);
        let srgb_128 = ((128.0f64 / 255.0 + 0.055) / 1.055).powf(2.4);
        let (m, se) = mean_and_stderr(film.pixels.iter().map(|p| luminance(*p)));
        assert!(
            (m - srgb_128 * L as f64).abs() < 0.003 + 4.0 * se,
            "{memory:?}: textured ground {m}, want {}",
            srgb_128 * L as f64
        );
    }
}

/// A checkered plane running to the horizon at a grazing angle, unlit (each pixel is the
/// texture's mean over the pixel) under a black sky, with textures as `lod` makes them.
fn grazing_checker(lod: TextureLod) -> platoon::Prepared {
    let (side, cell) = (256u32, 8u32);
    let rgba8 = (0..side * side)
        .flat_map(|i| {
            let (x, y) = (i % side / cell, i / side / cell);
            let v = if (x + y) % 2 == 0 { 230u8 } else { 20 };
            [v, v, v, 255]
        })
        .collect();
    let checker = Texture {
        name: "checker".into(),
        width: side,
        height: side,
        rgba8,
        wrap_s: Wrap::Repeat,
        wrap_t: Wrap::Repeat,
        nearest: false,
        mips: Vec::new(),
    };
    let plane = Material {
        name: "plane".into(),
        base_color: glam::Vec4::ONE,
        base_color_texture: Some(TextureRef::new(0)),
        unlit: true,
        ..Default::default()
    };
    let mut scene = ground(vec![], vec![]);
    scene.materials[0] = plane;
    // 2 repeats across the 20-unit plane: 64 checks, 3.2 a unit.
    std::sync::Arc::make_mut(&mut scene.meshes[0]).uvs =
        vec![Vec2::ZERO, Vec2::X * 2.0, Vec2::ONE * 2.0, Vec2::Y * 2.0];
    scene.textures.push(checker);
    let eye = Vec3::new(0.0, 0.35, 9.5);
    let camera =
        platoon::core::scene::camera::Camera::look_at(eye, Vec3::new(0.0, 0.0, -10.0), 0.6);
    let camera_node = scene.nodes.iter_mut().find(|n| n.camera.is_some()).unwrap();
    let (_, r, t) = camera.camera_to_world.to_scale_rotation_translation();
    (camera_node.rotation, camera_node.translation) = (r, t.as_dvec3());
    TextureOptions { lod, budget: None }
        .apply(&mut scene)
        .unwrap();
    prepare(scene, constant_env(0.0))
}

#[test]
fn mip_levels_by_ray_cone_bring_a_grazing_plane_closer_to_its_supersampled_image() {
    let (image, mipped) = (
        grazing_checker(TextureLod::Off),
        grazing_checker(TextureLod::RayCone),
    );
    assert!(!image.gpu.features.texture_lod && mipped.gpu.features.texture_lod);
    let render_at = |prepared: &platoon::Prepared, spp, kernel| {
        let mut params = FrameParams::new(64, 48, spp, prepared.camera);
        params.method = in_kernel(&params.method, kernel);
        render(prepared, &params, Sampling::Mis)
    };
    let reference = render_at(&image, 256, PathKernel::Mega);
    let image = render_at(&image, 2, PathKernel::Mega);
    // Both kernels carry the cone (the streaming one in its path slots).
    let streamed = render_at(&mipped, 2, PathKernel::Streaming);
    let mipped = render_at(&mipped, 2, PathKernel::Mega);
    assert!(
        rmse(&streamed, &mipped) < 1e-4,
        "kernels differ: {}",
        rmse(&streamed, &mipped)
    );
    // Rows 24-47 are the plane (the horizon at the middle), far to near.
    let rows = |f: &Film, r: std::ops::Range<usize>| Film {
        pixels: f.pixels[64 * r.start..64 * r.end].to_vec(),
        ..f.clone()
    };
    let error =
        |f: &Film, r: std::ops::Range<usize>| rmse(&rows(f, r.clone()), &rows(&reference, r));
    let (plain, filtered) = (error(&image, 0..48), error(&mipped, 0..48));
    let (far_plain, far_filtered) = (error(&image, 24..28), error(&mipped, 24..28));
    let (near_plain, near_filtered) = (error(&image, 40..48), error(&mipped, 40..48));
    eprintln!(
        "rmse against 256 spp, ray-cone / image: all {filtered:.4} / {plain:.4}, far \
         {far_filtered:.4} / {far_plain:.4}, near {near_filtered:.4} / {near_plain:.4}"
    );
    // Measured 0.066 / 0.108 and 0.069 / 0.258: the image itself aliases where a pixel covers
    // many checks, the levels hold their mean there.
    assert!(filtered < 0.75 * plain && far_filtered < 0.5 * far_plain);
    // Near the camera a texel covers more than a pixel's cone: the image itself is read.
    assert!(near_filtered < 1.05 * near_plain);
}

#[test]
fn a_ktx2_texture_of_basis_universal_loads_and_renders_its_colours() {
    // Issue 59: KHR_texture_basisu. A UASTC KTX2 of 2 x 2 solid blocks (made by
    // platoon-scenegen, read by the Basis Universal transcoder) on an unlit quad: each
    // quarter of the image is its block's colour, decoded from sRGB.
    let colours = [
        [200u8, 40, 40, 255],
        [40, 200, 40, 255],
        [40, 40, 200, 255],
        [220, 220, 60, 255],
    ];
    let scene = load_generated(&platoon_scenegen::ktx2::basisu_quad(colours));
    let t = &scene.textures[0];
    assert_eq!((t.width, t.height), (8, 8));
    for (i, c) in colours.iter().enumerate() {
        let (bx, by) = (i % 2, i / 2);
        let texel = 4 * ((4 * by + 1) * 8 + 4 * bx + 2);
        assert_eq!(&t.rgba8[texel..texel + 4], c, "block {i}");
    }
    let prepared = prepare(scene, constant_env(0.0));
    let film = render(
        &prepared,
        &FrameParams::new(16, 16, 4, prepared.camera),
        Sampling::Mis,
    );
    let linear = |v: u8| ((v as f32 / 255.0 + 0.055) / 1.055).powf(2.4);
    for (i, c) in colours.iter().enumerate() {
        let (x, y) = (4 + 8 * (i % 2), 4 + 8 * (i / 2));
        let p = film.pixels[y * 16 + x];
        for k in 0..3 {
            assert!(
                (p[k] - linear(c[k])).abs() < 1e-3,
                "block {i} at ({x}, {y}): {p:?}, want {c:?}"
            );
        }
    }
    // A damaged file (cut short, bytes of its header, descriptor or blocks changed) loads or
    // is refused naming the file and image, never panics.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("damaged.glb");
    let good = platoon_scenegen::ktx2::uastc_solid(2, 2, |x, y| colours[(2 * y + x) as usize]);
    let mut damaged: Vec<Vec<u8>> = [12, 60, 100, 140, good.len() - 1]
        .map(|n| good[..n].to_vec())
        .to_vec();
    for at in [
        12,
        20,
        44,
        48,
        52,
        80,
        88,
        104 + 12,
        104 + 28,
        good.len() - 16,
    ] {
        for v in [0u8, 0x7f, 0xff] {
            let mut d = good.clone();
            d[at] = v;
            damaged.push(d);
        }
    }
    let mut refused = 0;
    for (k, bytes) in damaged.into_iter().enumerate() {
        let mut data = platoon_scenegen::ktx2::basisu_quad(colours);
        data.images[0] = bytes;
        std::fs::write(&path, platoon_scenegen::to_glb(&data)).unwrap();
        if let Err(e) = platoon::load_scene(Some(&path)) {
            let e = format!("{e:#}");
            assert!(
                e.contains("damaged.glb") && e.contains("image 0"),
                "{k}: {e}"
            );
            refused += 1;
        }
    }
    assert!(refused >= 5, "only {refused} damaged files refused");
}

#[test]
fn thin_lens_compiles_its_variant_and_keeps_a_uniform_plane_uniform() {
    const L: f32 = 1.0;
    let mut prepared = prepare(ground(vec![], vec![]), constant_env(L));
    prepared.camera.aperture_radius = 0.2;
    prepared.camera.focus_distance = 2.0;
    let params = FrameParams::new(16, 16, 16, prepared.camera);
    let t = tracer(&prepared, Sampling::Mis);
    assert!(t.kernel_defines(&params).contains(&"HAS_THIN_LENS"));
    drop(t);
    let film = render(&prepared, &params, Sampling::Mis);
    let (m, se) = mean_and_stderr(film.pixels.iter().map(|p| luminance(*p)));
    assert!((m - (RHO * L) as f64).abs() < 0.003 + 4.0 * se, "{m}");
}

#[test]
fn max_depth_one_compiles_the_bounce_away_and_sees_only_emitters() {
    // The Cornell box at max depth 1: each pixel is the light's radiance (17, 12, 4) times the
    // fraction of its 16 jittered samples that hit the light, and black elsewhere.
    let prepared = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    );
    let mut params = FrameParams::new(32, 32, 16, prepared.camera);
    params.path_loop.max_depth = 1;
    let mut t = tracer(&prepared, Sampling::Mis);
    assert!(t.kernel_defines(&params).contains(&"CAMERA_RAYS_ONLY"));
    let film = render_with(&mut t, &params);
    let lit: Vec<_> = film.pixels.iter().filter(|p| p[0] > 0.0).collect();
    assert!(
        !lit.is_empty() && lit.len() < film.pixels.len() / 4,
        "{}",
        lit.len()
    );
    for p in &film.pixels {
        let hits = p[0] / 17.0 * 16.0;
        assert!((hits - hits.round()).abs() < 1e-3, "{p:?}");
        assert!(
            (p[1] - 12.0 / 17.0 * p[0]).abs() < 1e-4 && (p[2] - 4.0 / 17.0 * p[0]).abs() < 1e-4
        );
    }
    // One bounce more lights the walls, through the kernel with bounce code.
    params.path_loop.max_depth = 2;
    assert!(!t.kernel_defines(&params).contains(&"CAMERA_RAYS_ONLY"));
    let film = render_with(&mut t, &params);
    assert!(film.pixels.iter().filter(|p| p[0] > 0.0).count() > film.pixels.len() / 2);
}

#[test]
fn a_blended_cover_passes_camera_and_shadow_rays_with_its_transparency() {
    // A black BLEND cover of alpha a between a camera and a ground lit by a sun straight down:
    // the sun's light reaches the ground through it with probability 1 - a, and the camera sees
    // the ground through it with the same: (1 - a)^2 rho / pi E, the cover itself black.
    let (alpha, e) = (0.4f32, 2.0f32);
    let cover = Material {
        name: "blended".into(),
        base_color: Vec3::ZERO.extend(alpha),
        alpha_mode: AlphaMode::Blend,
        ..lambertian("b", Vec3::ZERO)
    };
    let mut scene = ground(
        vec![(
            mesh_from(&platoon_scenegen::quad(1.0, 1.0), 1),
            Vec3::new(0.0, 1.0, 0.0),
            20.0,
        )],
        vec![cover],
    );
    add_light(
        &mut scene,
        LightKind::Directional,
        e,
        Vec3::new(0.0, 5.0, 0.0),
    );
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    assert!(prepared.gpu.features.alpha_blend);
    let film = render(
        &prepared,
        &FrameParams::new(16, 16, 64, prepared.camera),
        Sampling::Mis,
    );
    let (m, se) = mean_and_stderr(film.pixels.iter().map(|p| p[0] as f64));
    let expected = ((1.0 - alpha) * (1.0 - alpha) * RHO / PI * e) as f64;
    assert!(
        (m - expected).abs() < 4.0 * se + 1e-3,
        "{m:.4} +- {se:.4}, expected (1 - a)^2 rho E / pi = {expected:.4}"
    );
}

#[test]
fn a_blended_or_masked_emitter_lights_as_much_as_rays_find_of_it() {
    // A panel facing down beside the view lights the ground. Of a BLEND panel of alpha a, BSDF
    // rays find it with probability a: every estimator must give what an opaque panel of a
    // times its emission gives. A MASK panel cut out everywhere lights nothing.
    let panel = |alpha_mode: AlphaMode, alpha: f32, emission: f32| Material {
        name: "panel".into(),
        base_color: Vec3::ZERO.extend(alpha),
        emissive: Vec3::splat(emission),
        alpha_mode,
        ..lambertian("p", Vec3::ZERO)
    };
    let lit_by = |m: Material, sampling: Sampling| {
        let scene = ground(
            vec![(
                mesh_from(&platoon_scenegen::quad(1.0, -1.0), 1),
                Vec3::new(1.8, 0.6, 0.0),
                0.5,
            )],
            vec![m],
        );
        let prepared = prepare(scene, platoon::EnvChoice::Scene);
        let film = render(
            &prepared,
            &FrameParams::new(16, 16, 64, prepared.camera),
            sampling,
        );
        mean_and_stderr(film.pixels.iter().map(|p| p[0] as f64))
    };
    let a = 0.35;
    for sampling in [Sampling::Mis, Sampling::Light, Sampling::Bsdf] {
        let (blended, se0) = lit_by(panel(AlphaMode::Blend, a, 4.0), sampling);
        let (opaque, se1) = lit_by(panel(AlphaMode::Opaque, 1.0, 4.0 * a), sampling);
        assert!(opaque > 0.01, "the panel lights nothing");
        assert!(
            (blended - opaque).abs() < 4.0 * (se0 * se0 + se1 * se1).sqrt() + 0.01 * opaque,
            "{sampling:?}: a blended panel lights {blended:.4}, an opaque one of a x its emission {opaque:.4}"
        );
    }
    let (masked, _) = lit_by(panel(AlphaMode::Mask(0.5), 0.3, 4.0), Sampling::Light);
    assert!(masked == 0.0, "a cut-out emitter lights {masked}");
}

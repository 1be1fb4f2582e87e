//! glTF as the files are written: each feature proved by a twin scene (tools/scenegen's
//! `twins`) that writes the same scene without it and must render alike.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::frame::FrameParams;
use platoon::core::output::Film;
use platoon::drive::Edit;
use platoon::tracer::Sampling;
use platoon_scenegen::twins::edited_glb;

/// A .glb's bytes loaded through the glTF loader, as a user's file is.
fn load_glb(bytes: &[u8]) -> platoon::core::Scene {
    let dir = tempfile::tempdir().expect("temporary folder");
    let path = dir.path().join("twin.glb");
    std::fs::write(&path, bytes).expect("write the glb");
    platoon::load_scene(Some(&path)).expect("load the twin")
}

fn load_error(bytes: &[u8]) -> String {
    let dir = tempfile::tempdir().expect("temporary folder");
    let path = dir.path().join("twin.glb");
    std::fs::write(&path, bytes).expect("write the glb");
    match platoon::load_scene(Some(&path)) {
        Ok(_) => panic!("the file loaded"),
        Err(e) => e.to_string(),
    }
}

/// The twin rendered at `size` x `size` pixels and `spp` samples under a uniform sky of `sky`.
fn render_twin(bytes: &[u8], size: u32, spp: u32, sky: f32, sampling: Sampling) -> Film {
    let scene = load_glb(bytes);
    assert!(scene.warnings.is_empty(), "warnings: {:?}", scene.warnings);
    let prepared = prepare(scene, constant_env(sky));
    let params = FrameParams::new(size, size, spp, prepared.camera);
    render(&prepared, &params, sampling)
}

fn mean(film: &Film) -> f64 {
    film.mean().iter().sum::<f64>() / 3.0
}

#[test]
fn strips_and_fans_render_the_bits_of_their_triangle_lists() {
    let (strips, lists) = platoon_scenegen::twins::strips_and_fans();
    let a = render_twin(&strips, 24, 4, 1.0, Sampling::Mis);
    let b = render_twin(&lists, 24, 4, 1.0, Sampling::Mis);
    assert!(mean(&a) > 0.05, "nothing was drawn");
    assert!(a == b, "a strip or fan renders unlike its triangle list");
}

#[test]
fn a_room_baked_far_from_the_origin_renders_as_the_room_at_the_origin() {
    // The image's mean and its standard error over pixels.
    let measure = |offset: f64, sampling| {
        let film = render_twin(
            &platoon_scenegen::twins::baked_room(offset),
            16,
            64,
            0.0,
            sampling,
        );
        mean_and_stderr(
            film.pixels
                .iter()
                .map(|p| (p[0] + p[1] + p[2]) as f64 / 3.0),
        )
    };
    for sampling in [Sampling::Mis, Sampling::Bsdf, Sampling::Light] {
        let (at_origin, se0) = measure(0.0, sampling);
        assert!(at_origin > 0.05, "the room is dark: {at_origin}");
        for offset in [1e6, 1e7] {
            // Render space differs by the camera's place, so the paths differ in their last
            // bits and decorrelate: the two are compared as independent estimates.
            let (far, se) = measure(offset, sampling);
            let bound = 4.0 * (se0 * se0 + se * se).sqrt() + 0.002 * at_origin;
            assert!(
                (far - at_origin).abs() < bound,
                "{sampling:?}: the room at {offset:e} renders {far:.4}, at the origin {at_origin:.4} (bound {bound:.4})"
            );
        }
    }
}

#[test]
fn assets_of_another_gltf_major_version_are_refused() {
    for version in ["1.0", "3.0", "two"] {
        let message = load_error(&platoon_scenegen::twins::with_version(version));
        assert!(
            message.contains(version) && message.contains("twin.glb"),
            "{message}"
        );
    }
    load_glb(&platoon_scenegen::twins::with_version("2.1"));
}

/// Means of the film's 4 x 4 blocks of pixels (channel-averaged): where a texture lookup went
/// shows in them, unlike in the whole image's mean.
fn block_means(film: &Film) -> Vec<f64> {
    let (w, h) = (film.width as usize, film.height as usize);
    let (bw, bh) = (w / 4, h / 4);
    let mut out = [0.0; 16];
    for y in 0..h {
        for x in 0..w {
            let p = film.pixels[y * w + x];
            out[(y / bh).min(3) * 4 + (x / bw).min(3)] += (p[0] + p[1] + p[2]) as f64 / 3.0;
        }
    }
    out.iter().map(|s| s / (bw * bh) as f64).collect()
}

/// The twins render alike: every block's mean within `tolerance` (relative to the image mean).
fn assert_alike(with: &[u8], without: &[u8], tolerance: f64, what: &str) {
    let a = render_twin(with, 32, 8, 1.0, Sampling::Mis);
    let b = render_twin(without, 32, 8, 1.0, Sampling::Mis);
    let scale = mean(&b);
    assert!(scale > 0.05, "{what}: nothing was drawn");
    for (k, (x, y)) in block_means(&a).iter().zip(block_means(&b)).enumerate() {
        assert!(
            (x - y).abs() <= tolerance * scale,
            "{what}: block {k} renders {x:.5} with the feature, {y:.5} without"
        );
    }
}

#[test]
fn vertex_colours_multiply_the_base_colour_as_the_same_factor_would() {
    use platoon_scenegen::twins::{FLOAT, UNSIGNED_BYTE, UNSIGNED_SHORT};
    for (component, name) in [
        (FLOAT, "float RGB"),
        (UNSIGNED_BYTE, "unorm8 RGBA"),
        (UNSIGNED_SHORT, "unorm16 RGBA"),
    ] {
        let (with, without) = platoon_scenegen::twins::vertex_colors(component);
        assert_alike(&with, &without, 2e-3, name);
    }
}

#[test]
fn a_texture_read_at_texcoord_1_is_the_texture_at_those_uvs_in_texcoord_0() {
    let (with, without) = platoon_scenegen::twins::second_uv_set();
    assert_alike(&with, &without, 1e-3, "TEXCOORD_1");
}

#[test]
fn a_texture_transform_renders_as_the_uvs_transformed_in_the_buffer() {
    let (with, without) = platoon_scenegen::twins::texture_transform();
    assert_alike(&with, &without, 2e-3, "KHR_texture_transform");
}

#[test]
fn a_webp_texture_renders_the_bits_of_its_png_twin() {
    let (webp, png) = platoon_scenegen::twins::webp_texture();
    let a = render_twin(&webp, 16, 2, 1.0, Sampling::Mis);
    let b = render_twin(&png, 16, 2, 1.0, Sampling::Mis);
    assert!(a == b, "the WebP texture renders unlike its PNG");
}

#[test]
fn a_quantized_mesh_renders_as_its_float_twin_within_quantization() {
    let (quantized, float) = platoon_scenegen::twins::quantized();
    assert_alike(&quantized, &float, 1e-2, "KHR_mesh_quantization");
}

#[test]
fn an_orthographic_camera_sees_a_quad_at_its_size_whatever_its_distance() {
    for z in [0.0, -2.0] {
        let film = render_twin(
            &platoon_scenegen::twins::orthographic(z),
            32,
            4,
            0.0,
            Sampling::Mis,
        );
        // xmag = ymag = 1: the view is [-1, 1]^2, the quad [-0.5, 0.5]^2 its middle 16 x 16 pixels.
        for y in 0..32 {
            for x in 0..32 {
                let inside = (8..24).contains(&x) && (8..24).contains(&y);
                let v = film.pixels[y * 32 + x][1];
                let expected = if inside { 1.0 } else { 0.0 };
                assert!(
                    (v - expected).abs() < 1e-4,
                    "z = {z}: pixel ({x}, {y}) is {v}"
                );
            }
        }
    }
}

#[test]
fn a_blended_quad_shows_alpha_of_itself_and_the_rest_of_what_is_behind() {
    let alpha = 0.3;
    let film = render_twin(
        &platoon_scenegen::twins::blended(alpha, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        32,
        64,
        0.0,
        Sampling::Mis,
    );
    // The front quad covers [-0.5, 0.5]^2 at z = 1, two units from the camera (yfov 0.8): the
    // middle pixels see it.
    let middle: Vec<[f32; 3]> = (12..20)
        .flat_map(|y| (12..20).map(move |x| (x, y)))
        .map(|(x, y)| film.pixels[y * 32 + x])
        .collect();
    for (c, expected) in [(0, alpha as f64), (1, 1.0 - alpha as f64)] {
        let (m, se) = mean_and_stderr(middle.iter().map(|p| p[c] as f64));
        assert!(
            (m - expected).abs() < 4.0 * se + 1e-3,
            "channel {c}: {m:.4} +- {se:.4}, expected {expected}"
        );
    }
}

#[test]
fn an_unlit_surface_shows_its_base_colour_under_any_light() {
    let colour = [0.3f32, 0.6, 0.9];
    for sky in [0.0, 5.0] {
        let film = render_twin(
            &platoon_scenegen::twins::unlit(colour),
            16,
            4,
            sky,
            Sampling::Mis,
        );
        let p = film.pixels[8 * 16 + 8];
        for c in 0..3 {
            assert!((p[c] - colour[c]).abs() < 1e-5, "sky {sky}: {p:?}");
        }
    }
}

/// The twin rendered at animation time `time`.
fn render_twin_at(bytes: &[u8], time: f32) -> Film {
    let scene = load_glb(bytes);
    assert!(scene.warnings.is_empty(), "warnings: {:?}", scene.warnings);
    let prepared = platoon::prepare(
        scene,
        &platoon::PrepareOptions {
            env: constant_env(1.0),
            time,
            ..Default::default()
        },
    )
    .expect("prepare");
    let params = FrameParams::new(32, 32, 8, prepared.camera);
    render(&prepared, &params, Sampling::Mis)
}

#[test]
fn a_morph_at_its_weights_renders_as_the_mesh_baked_at_them() {
    for animated in [false, true] {
        let (morphed, baked) = platoon_scenegen::twins::morphed(animated);
        let a = block_means(&render_twin_at(&morphed, 0.5));
        let b = block_means(&render_twin_at(&baked, 0.0));
        let scale = b.iter().sum::<f64>() / 16.0;
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(
                (x - y).abs() <= 2e-3 * scale,
                "animated {animated}: block {k} renders {x:.5} morphed, {y:.5} baked"
            );
        }
    }
}

#[test]
fn animated_weights_deform_a_living_scene_through_commits() {
    use platoon::core::scene::environment::Environment;
    use platoon::drive::Updater;
    let (morphed, baked) = platoon_scenegen::twins::morphed(true);
    let mut scene = load_glb(&morphed);
    scene.environment = Some(Environment::Constant(glam::Vec3::ONE));
    let camera =
        platoon::core::scene::camera::Camera::from_scene(&scene, &scene.pose(0.0), None).unwrap();
    let mut updater = Updater::new(scene, 0.0, glam::DVec3::ZERO).unwrap();
    let mut followed = tracer_reading(updater.flattened(), Default::default());
    let params = FrameParams::new(32, 32, 8, camera);
    let flat = render_with(&mut followed, &params);
    updater.apply(Edit::Time(0.5)).unwrap();
    let g = updater.update().unwrap();
    assert!(g.refitted + g.rebuilt > 0, "the weights deformed nothing");
    assert!(g.commit.mesh_bytes() > 0);
    followed.apply_commit(&g.commit).unwrap();
    let after = render_with(&mut followed, &params);
    let mut fresh = tracer_reading(updater.flattened(), Default::default());
    assert!(
        after == render_with(&mut fresh, &params),
        "commits drifted from the scene"
    );
    assert!(after != flat, "the animation moved nothing");
    let (a, b) = (
        block_means(&after),
        block_means(&render_twin_at(&baked, 0.0)),
    );
    let scale = b.iter().sum::<f64>() / 16.0;
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (x - y).abs() <= 2e-3 * scale,
            "{x:.5} morphed against {y:.5} baked"
        );
    }
}

#[test]
fn gpu_instancing_draws_each_instance_as_a_node_of_its_transform_would() {
    let (instanced, explicit) = platoon_scenegen::twins::gpu_instancing();
    let a = render_twin(&instanced, 24, 4, 1.0, Sampling::Mis);
    let b = render_twin(&explicit, 24, 4, 1.0, Sampling::Mis);
    assert_eq!(load_glb(&instanced).triangle_count(), 3 * 32);
    assert!(a == b, "instances render unlike the nodes they stand for");
}

#[test]
fn a_nearest_magnification_filter_keeps_texels_sharp() {
    // Pixels where red and blue both show: bilinear blends the two texels across the quad,
    // NEAREST only in the pixels that straddle the texels' edge.
    let mixed = |nearest: bool| {
        let film = render_twin(
            &platoon_scenegen::twins::magnified(nearest),
            32,
            4,
            1.0,
            Sampling::Mis,
        );
        film.pixels
            .iter()
            .filter(|p| p[0].min(p[2]) > 0.05 * p[0].max(p[2]) && p[1] < 0.5 * p[0].max(p[2]))
            .count()
    };
    let (sharp, blended) = (mixed(true), mixed(false));
    assert!(
        sharp <= 2 * 32,
        "{sharp} pixels mix the texels under NEAREST"
    );
    assert!(blended > 400, "only {blended} pixels blend under LINEAR");
}

/// KHR_materials_clearcoat (issue 25): the generated clearcoat spheres load without a warning,
/// each coat as the file writes it, and render finite under an environment map, the coats
/// brightening what they cover; a coat naming a texture the file lacks is refused, naming it.
#[test]
fn clearcoat_spheres_load_as_written_and_render_under_a_map() {
    let data = platoon_scenegen::materials::clearcoat();
    let scene = load_generated(&data);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let coats: Vec<(f32, f32)> = scene
        .materials
        .iter()
        .map(|m| (m.clearcoat, m.clearcoat_roughness))
        .collect();
    assert_eq!(&coats[..3], &[(0.0, 0.0), (0.5, 0.0), (1.0, 0.0)]);
    assert_eq!(coats[5], (1.0, 0.6));
    assert_eq!(
        scene.materials[7].clearcoat_texture.map(|t| t.texture),
        Some(0)
    );
    assert_eq!(
        scene.materials[8]
            .clearcoat_roughness_texture
            .map(|t| t.texture),
        Some(0)
    );
    renders_finite_under_a_map(scene, |f| f.clearcoat && f.clearcoat_textures);
    refuses_a_texture_past_the_files(&data, 7, "KHR_materials_clearcoat", "clearcoatTexture");
}

/// An extension's generated spheres under the courtyard map: the kernel has the extension's
/// features (`has`) and the image is finite.
fn renders_finite_under_a_map(
    scene: platoon::core::Scene,
    has: impl Fn(&platoon::core::SceneFeatures) -> bool,
) {
    let prepared = prepare(
        scene,
        platoon::EnvChoice::File(shared("envmaps/courtyard.exr")),
    );
    assert!(has(&prepared.gpu.features), "{}", prepared.gpu.features);
    let film = render(
        &prepared,
        &FrameParams::new(48, 48, 8, prepared.camera),
        Sampling::Mis,
    );
    assert_eq!(film.count_non_finite(), 0);
}

/// `data` with material `m`'s `extension` texture `key` pointing past the file's textures is
/// refused, naming the key and the texture.
fn refuses_a_texture_past_the_files(
    data: &platoon_scenegen::SceneData,
    m: usize,
    extension: &str,
    key: &str,
) {
    let e = load_error(&edited_glb(&platoon_scenegen::to_glb(data), |json| {
        json["materials"][m]["extensions"][extension][key]["index"] = 9.into();
    }));
    assert!(
        e.contains(&format!("{extension} {key}")) && e.contains("texture 9"),
        "{e}"
    );
}

/// KHR_materials_variants (issue 25): the file's variants are listed; loaded without one the
/// quad keeps its own material, with one it takes the mapped material (a variant that maps
/// nothing keeps the own one); an unknown variant is refused naming the file's; a mapping that
/// names a variant the file lacks is refused whichever variant is chosen.
#[test]
fn a_material_variant_renders_the_material_it_maps() {
    let bytes = platoon_scenegen::twins::variants();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("variants.glb");
    std::fs::write(&path, &bytes).unwrap();
    let load = |variant: Option<&str>| {
        platoon::load_scene_with(
            Some(&path),
            &platoon::core::scene::gltf_load::LoadOptions {
                variant: variant.map(str::to_string),
                ..Default::default()
            },
        )
    };
    for (variant, colour) in [
        (None, [0.5f32, 0.5, 0.5]),
        (Some("red"), [1.0, 0.0, 0.0]),
        (Some("blue"), [0.0, 0.0, 1.0]),
        (Some("plain"), [0.5, 0.5, 0.5]),
    ] {
        let scene = load(variant).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        assert_eq!(scene.variants, vec!["red", "blue", "plain"]);
        let prepared = prepare(scene, constant_env(1.0));
        let film = render(
            &prepared,
            &FrameParams::new(16, 16, 2, prepared.camera),
            Sampling::Mis,
        );
        let p = film.pixels[8 * 16 + 8];
        for c in 0..3 {
            assert!((p[c] - colour[c]).abs() < 1e-5, "{variant:?}: {p:?}");
        }
    }
    let e = load(Some("green")).unwrap_err().to_string();
    assert!(
        e.contains("variants.glb") && e.contains("\"green\"") && e.contains("red, blue, plain"),
        "{e}"
    );
    let bad = edited_glb(&bytes, |json| {
        json["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][1]
            ["variants"][0] = 7.into();
    });
    std::fs::write(&path, bad).unwrap();
    let e = load(None).unwrap_err().to_string();
    assert!(e.contains("names variant 7") && e.contains("has 3"), "{e}");
}

/// KHR_materials_pbrSpecularGlossiness (archived, in many older assets) is converted on load to
/// the metallic-roughness material it describes: a dielectric of specular colour 0.04 and
/// glossiness 0.3, from factors or from a texture's RGB and alpha, renders as the core
/// dielectric of roughness 0.7 at ior 1.5 (whose f0 is 0.04), not as the file's fallback
/// (green) metallic-roughness.
#[test]
fn a_specular_glossiness_material_renders_as_the_dielectric_it_describes() {
    for textured in [false, true] {
        let (with, without) = platoon_scenegen::twins::spec_gloss(textured);
        let scene = load_glb(&with);
        let m = &scene.materials[0];
        assert_eq!((m.metallic, m.specular, m.ior), (0.0, 1.0, 1000.0));
        assert_eq!(m.metallic_roughness_texture.is_some(), textured);
        assert_alike(
            &with,
            &without,
            0.02,
            &format!("spec-gloss, textured {textured}"),
        );
    }
}

/// KHR_materials_diffuse_transmission (issue 25): the generated spheres load without a warning,
/// each share and colour as written, and render finite under an environment map; a texture
/// the file lacks is refused naming the property.
#[test]
fn diffuse_transmission_spheres_load_as_written_and_render_under_a_map() {
    let data = platoon_scenegen::materials::diffuse_transmission();
    let scene = load_generated(&data);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let shares: Vec<f32> = scene
        .materials
        .iter()
        .map(|m| m.diffuse_transmission)
        .collect();
    assert_eq!(shares, vec![0.0, 0.5, 1.0, 0.8, 0.8, 1.0]);
    assert_eq!(
        scene.materials[3].diffuse_transmission_color,
        glam::Vec3::new(0.2, 0.9, 0.2)
    );
    assert!(scene.materials[5].diffuse_transmission_texture.is_some());
    renders_finite_under_a_map(scene, |f| {
        f.diffuse_transmission && f.diffuse_transmission_textures
    });
    refuses_a_texture_past_the_files(
        &data,
        5,
        "KHR_materials_diffuse_transmission",
        "diffuseTransmissionTexture",
    );
}

/// KHR_materials_sheen (issue 25): the colour, roughness and textures load as written (a zero
/// colour is no sheen) and the spheres render; a colour that is not three numbers is refused.
#[test]
fn sheen_spheres_load_as_written_and_render_under_a_map() {
    let data = platoon_scenegen::materials::sheen();
    let scene = load_generated(&data);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let roughness: Vec<f32> = scene.materials.iter().map(|m| m.sheen_roughness).collect();
    assert_eq!(&roughness[..3], &[0.1, 0.4, 0.8]);
    assert_eq!(
        scene.materials[3].sheen_color,
        glam::Vec3::new(0.1, 0.3, 1.0)
    );
    assert!(scene.materials[5].has_clearcoat() && scene.materials[5].has_sheen());
    assert!(scene.materials[6].sheen_color_texture.is_some());
    assert!(scene.materials[7].sheen_roughness_texture.is_some());
    assert!(!scene.materials[8].has_sheen());
    renders_finite_under_a_map(scene, |f| f.sheen && f.sheen_textures);
    refuses_a_texture_past_the_files(&data, 6, "KHR_materials_sheen", "sheenColorTexture");
    let e = load_error(&edited_glb(&platoon_scenegen::to_glb(&data), |json| {
        json["materials"][0]["extensions"]["KHR_materials_sheen"]["sheenColorFactor"][1] =
            "white".into();
    }));
    assert!(e.contains("sheenColorFactor is not three numbers"), "{e}");
}

/// KHR_materials_volume (issue 25): thickness, attenuation colour and distance load as written
/// (the spec's default distance is infinite, a zero thickness a thin wall that absorbs nothing),
/// the spheres render, and a distance that is not above 0 is refused.
#[test]
fn volume_spheres_load_as_written_and_render_under_a_map() {
    let data = platoon_scenegen::materials::volume();
    let scene = load_generated(&data);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let distances: Vec<f32> = scene
        .materials
        .iter()
        .map(|m| m.attenuation_distance)
        .collect();
    assert_eq!(&distances[..3], &[0.5, 1.0, 2.0]);
    assert_eq!(
        scene.materials[3].attenuation_color,
        glam::Vec3::new(0.9, 0.5, 0.1)
    );
    assert!(!scene.materials[6].has_volume() && !scene.materials[6].absorbs());
    assert!(scene.materials[7].has_volume() && !scene.materials[7].absorbs());
    renders_finite_under_a_map(scene, |f| f.volume && f.transmission);
    let e = load_error(&edited_glb(&platoon_scenegen::to_glb(&data), |json| {
        json["materials"][0]["extensions"]["KHR_materials_volume"]["attenuationDistance"] =
            0.into();
    }));
    assert!(e.contains("attenuationDistance is not above 0"), "{e}");
}

/// KHR_materials_iridescence (issue 25): strength, the film's index and thickness range and
/// both textures load as written (the spec's key iridescenceIor, and the drafts'
/// iridescenceIOR), a factor of 0 is no film, the spheres render; an index below 1 and a texture
/// past the file's are refused.
#[test]
fn iridescence_spheres_load_as_written_and_render_under_a_map() {
    let data = platoon_scenegen::materials::iridescence();
    let scene = load_generated(&data);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let films: Vec<(f32, f32)> = scene
        .materials
        .iter()
        .map(|m| (m.iridescence_ior, m.iridescence_thickness_max))
        .collect();
    assert_eq!(&films[..3], &[(1.3, 250.0), (1.3, 400.0), (1.8, 700.0)]);
    assert!(scene.materials[6].has_clearcoat() && scene.materials[6].has_iridescence());
    let textured = &scene.materials[7];
    assert!(textured.iridescence_thickness_texture.is_some());
    assert_eq!(textured.iridescence_thickness_min, 200.0);
    assert!(scene.materials[8].iridescence_texture.is_some());
    assert!(!scene.materials[9].has_iridescence());
    renders_finite_under_a_map(scene, |f| f.iridescence && f.iridescence_textures);
    refuses_a_texture_past_the_files(
        &data,
        7,
        "KHR_materials_iridescence",
        "iridescenceThicknessTexture",
    );
    let glb = platoon_scenegen::to_glb(&data);
    let draft = edited_glb(&glb, |json| {
        let film = &mut json["materials"][0]["extensions"]["KHR_materials_iridescence"];
        film.as_object_mut().unwrap().remove("iridescenceIor");
        film["iridescenceIOR"] = 2.1.into();
    });
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("draft.glb");
    std::fs::write(&path, &draft).unwrap();
    let scene = platoon::load_scene(Some(&path)).unwrap();
    assert_eq!(scene.materials[0].iridescence_ior, 2.1);
    let e = load_error(&edited_glb(&glb, |json| {
        json["materials"][0]["extensions"]["KHR_materials_iridescence"]["iridescenceIor"] =
            0.5.into();
    }));
    assert!(e.contains("iridescenceIor is below 1"), "{e}");
}

/// KHR_materials_anisotropy (issue 25): strength, rotation and texture load as written, the
/// spheres (which carry no TANGENT) get MikkTSpace tangents from their UVs, the spheres render;
/// a texture past the file's is refused; a mesh with neither TANGENT nor UVs is warned about.
#[test]
fn anisotropy_spheres_load_as_written_and_render_under_a_map() {
    let data = platoon_scenegen::materials::anisotropy();
    let scene = load_generated(&data);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let strengths: Vec<f32> = scene
        .materials
        .iter()
        .map(|m| m.anisotropy_strength)
        .collect();
    assert_eq!(&strengths[..4], &[0.0, 0.3, 0.6, 1.0]);
    assert_eq!(
        scene.materials[5].anisotropy_rotation,
        std::f32::consts::FRAC_PI_2
    );
    assert!(scene.materials[8].anisotropy_texture.is_some());
    assert!(!scene.materials[0].has_anisotropy());
    for mesh in &scene.meshes[1..] {
        assert_eq!(mesh.tangents.len(), mesh.positions.len(), "{}", mesh.name);
    }
    renders_finite_under_a_map(scene, |f| f.anisotropy && f.anisotropy_textures);
    refuses_a_texture_past_the_files(&data, 8, "KHR_materials_anisotropy", "anisotropyTexture");
    let mut bare = platoon_scenegen::materials::anisotropy();
    for (mesh, _) in &mut bare.meshes {
        mesh.uvs.clear();
    }
    let scene = load_generated(&bare);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("anisotropic") && w.contains("TANGENT") && w.contains(".glb: ")),
        "{:?}",
        scene.warnings
    );
}

/// KHR_materials_dispersion (issue 25): the dispersions load as written; a thin wall (thickness
/// 0) does not disperse; the spheres render; a dispersion below 0 is refused.
#[test]
fn dispersion_spheres_load_as_written_and_render_under_a_map() {
    let data = platoon_scenegen::materials::dispersion();
    let scene = load_generated(&data);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let dispersions: Vec<f32> = scene.materials.iter().map(|m| m.dispersion).collect();
    assert_eq!(&dispersions[..4], &[0.0, 0.33, 1.0, 2.04]);
    assert_eq!(scene.materials[4].ior, 2.42);
    assert!(!scene.materials[0].has_dispersion());
    assert!(scene.materials[6].has_dispersion() && scene.materials[6].absorbs());
    assert!(!scene.materials[7].has_dispersion());
    renders_finite_under_a_map(scene, |f| f.dispersion && f.volume);
    let e = load_error(&edited_glb(&platoon_scenegen::to_glb(&data), |json| {
        json["materials"][1]["extensions"]["KHR_materials_dispersion"]["dispersion"] =
            (-0.5).into();
    }));
    assert!(e.contains("dispersion is below 0"), "{e}");
}

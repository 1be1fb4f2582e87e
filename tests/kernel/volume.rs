//! KHR_materials_volume against Beer-Lambert's closed form: a cube of index-matched glass (ior
//! 1: no Fresnel, no bending) seen straight through by an orthographic camera under a sky of 1
//! shows exactly colour^(d / distance), d the cube's width, in the megakernel and the streaming
//! path tracer alike; a thin wall (thickness 0) and an infinite attenuation distance absorb
//! nothing, the latter with the very bits of a file without the extension.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use glam::Vec3;
use platoon::core::frame::FrameParams;
use platoon::core::method::path::PathKernel;
use platoon::core::scene::Material;
use platoon::tracer::Sampling;

/// The cube [-h, h]^3 of `material`, seen along -z by an orthographic camera whose view lies
/// inside the cube's face.
fn cube_seen_through(material: Material, h: f32) -> platoon::Prepared {
    let mut scene = scene_of(
        vec![(mesh_from(&platoon_scenegen::flat_box(), 0), Vec3::ZERO, h)],
        vec![material],
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::ZERO,
        0.5,
    );
    scene.cameras[0].orthographic = Some([0.4 * h, 0.4 * h]);
    prepare(scene, constant_env(1.0))
}

fn index_matched_glass() -> Material {
    Material {
        name: "index-matched glass".into(),
        metallic: 0.0,
        roughness: 0.0,
        transmission: 1.0,
        ior: 1.0,
        ..Material::default()
    }
}

fn pixels(prepared: &platoon::Prepared, kernel: PathKernel) -> Vec<[f32; 3]> {
    let mut params = FrameParams::new(8, 8, 4, prepared.camera);
    params.method = in_kernel(&params.method, kernel);
    render(prepared, &params, Sampling::Mis).pixels
}

#[test]
fn a_cube_of_index_matched_glass_lets_through_what_beer_lambert_says() {
    let (color, distance, h) = (Vec3::new(0.5, 0.25, 0.8), 1.5f32, 0.6f32);
    let absorbing = Material {
        thickness: 1.0,
        attenuation_distance: distance,
        attenuation_color: color,
        ..index_matched_glass()
    };
    let prepared = cube_seen_through(absorbing.clone(), h);
    assert!(prepared.gpu.features.volume);
    let expected = color.map(|c| c.powf(2.0 * h / distance));
    let megakernel = pixels(&prepared, PathKernel::Mega);
    for p in &megakernel {
        for k in 0..3 {
            assert!(
                (p[k] - expected[k]).abs() < 1e-5,
                "{p:?}: Beer-Lambert gives {expected}"
            );
        }
    }
    assert_eq!(megakernel, pixels(&prepared, PathKernel::Streaming));

    // A thin wall (thickness 0: no volume) absorbs nothing; nor does an endless distance, and
    // that gives the bits of the same glass without the extension.
    let thin = cube_seen_through(
        Material {
            thickness: 0.0,
            ..absorbing.clone()
        },
        h,
    );
    let endless = cube_seen_through(
        Material {
            attenuation_distance: f32::INFINITY,
            ..absorbing
        },
        h,
    );
    let plain = cube_seen_through(index_matched_glass(), h);
    for p in [&thin, &endless, &plain] {
        assert!(!p.gpu.features.volume);
    }
    let plain = pixels(&plain, PathKernel::Mega);
    assert!(plain
        .iter()
        .all(|p| p.iter().all(|&c| (c - 1.0).abs() < 1e-6)));
    assert_eq!(pixels(&thin, PathKernel::Mega), plain);
    assert_eq!(pixels(&endless, PathKernel::Mega), plain);
}

/// What a medium lets through goes with the distance inside: a cube twice as wide lets through
/// the square of what the first did, in each channel.
#[test]
fn a_cube_twice_as_wide_lets_through_the_square() {
    let material = Material {
        thickness: 1.0,
        attenuation_distance: 2.0,
        attenuation_color: Vec3::new(0.6, 0.3, 0.9),
        ..index_matched_glass()
    };
    let narrow = pixels(&cube_seen_through(material.clone(), 0.5), PathKernel::Mega);
    let wide = pixels(&cube_seen_through(material, 1.0), PathKernel::Mega);
    for (n, w) in narrow.iter().zip(&wide) {
        for k in 0..3 {
            assert!(
                (n[k] * n[k] - w[k]).abs() < 1e-5,
                "{n:?} squared is not {w:?}"
            );
        }
    }
}

/// Next-event estimation inside a medium: a white Lambertian card at the centre of an absorbing
/// cube of index-matched glass, lit by a point light inside the cube 0.5 above it and seen from
/// outside through the cube's top with no sky, shows ρ/π I e^(-a 0.5) / 0.5² (the shadow ray's
/// way through the medium) times e^(-a) (the camera ray's, from the card to the top face).
#[test]
fn a_light_inside_a_medium_is_absorbed_on_its_way_to_the_card_and_to_the_eye() {
    use platoon::core::scene::LightKind;
    let (color, distance, rho, intensity) = (Vec3::new(0.5, 0.7, 0.9), 0.8f32, 0.8f32, 2.0f32);
    let medium = Material {
        thickness: 1.0,
        attenuation_distance: distance,
        attenuation_color: color,
        ..index_matched_glass()
    };
    let card = platoon::core::scene::cornell::lambertian("card", Vec3::splat(rho));
    let mut scene = scene_of(
        vec![
            (mesh_from(&platoon_scenegen::flat_box(), 0), Vec3::ZERO, 1.0),
            (
                mesh_from(&platoon_scenegen::quad(1.0, 1.0), 1),
                Vec3::ZERO,
                0.3,
            ),
        ],
        vec![medium, card],
        Vec3::new(0.001, 10.0, 0.0),
        Vec3::ZERO,
        0.5,
    );
    scene.cameras[0].orthographic = Some([0.005, 0.005]);
    add_light(
        &mut scene,
        LightKind::Point,
        intensity,
        Vec3::new(0.0, 0.5, 0.0),
    );
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    assert!(prepared.gpu.features.volume && prepared.gpu.features.punctual_lights);
    let a = color.map(|c| -c.ln() / distance);
    let expected = rho / std::f32::consts::PI * intensity / 0.25
        * (a * -0.5).map(f32::exp)
        * (a * -1.0).map(f32::exp);
    for kernel in [PathKernel::Mega, PathKernel::Streaming] {
        for p in pixels(&prepared, kernel) {
            for k in 0..3 {
                assert!(
                    (p[k] / expected[k] - 1.0).abs() < 2e-3,
                    "{kernel:?}: {p:?} where the closed form gives {expected}"
                );
            }
        }
    }
}

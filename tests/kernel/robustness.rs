//! Hard cases stay numerically stable: no NaN or Inf reaches the film, whatever the geometry.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use glam::Vec3;
use platoon::core::frame::FrameParams;
use platoon::core::scene::cornell::{lambertian, push_quad};
use platoon::core::scene::{Material, Mesh};
use platoon::tracer::Sampling;

/// Degenerate and extreme geometry: zero-area and needle triangles (some emissive), zero
/// normals, a tiny and a huge instance, a light inside a closed box, grazing planes,
/// index-of-refraction 1 glass and perfectly smooth surfaces.
fn adversarial() -> platoon::core::Scene {
    let mut mesh = Mesh::default();
    let v = Vec3::new;
    // Ground, and a closed box with an emitter inside it.
    push_quad(
        &mut mesh,
        [
            v(-5., 0., -5.),
            v(-5., 0., 5.),
            v(5., 0., 5.),
            v(5., 0., -5.),
        ],
        0,
    );
    let b = |x: f32, y: f32, z: f32| v(x * 0.5 + 2.0, y * 0.5 + 0.5, z * 0.5);
    for f in [
        [
            b(-1., 1., -1.),
            b(-1., 1., 1.),
            b(1., 1., 1.),
            b(1., 1., -1.),
        ],
        [
            b(-1., -1., 1.),
            b(1., -1., 1.),
            b(1., 1., 1.),
            b(-1., 1., 1.),
        ],
        [
            b(1., -1., -1.),
            b(-1., -1., -1.),
            b(-1., 1., -1.),
            b(1., 1., -1.),
        ],
        [
            b(1., -1., 1.),
            b(1., -1., -1.),
            b(1., 1., -1.),
            b(1., 1., 1.),
        ],
        [
            b(-1., -1., -1.),
            b(-1., -1., 1.),
            b(-1., 1., 1.),
            b(-1., 1., -1.),
        ],
        [
            b(-1., -1., -1.),
            b(1., -1., -1.),
            b(1., -1., 1.),
            b(-1., -1., 1.),
        ],
    ] {
        push_quad(&mut mesh, f, 1);
    }
    push_quad(
        &mut mesh,
        [
            b(-0.2, 0., -0.2),
            b(0.2, 0., -0.2),
            b(0.2, 0., 0.2),
            b(-0.2, 0., 0.2),
        ],
        2,
    );
    // Degenerate triangles: a point, a line, a needle; two of them emissive.
    let base = mesh.positions.len() as u32;
    mesh.positions.extend([
        v(0., 1., 0.),
        v(0., 1., 0.),
        v(0., 1., 0.),
        v(-1., 1., 0.),
        v(0., 1., 0.),
        v(1., 1., 0.),
        v(0., 2., 0.),
        v(1e-7, 2., 0.),
        v(0., 3., 1e-7),
    ]);
    mesh.normals.extend([Vec3::ZERO; 9]);
    mesh.indices.extend([
        [base, base + 1, base + 2],
        [base + 3, base + 4, base + 5],
        [base + 6, base + 7, base + 8],
    ]);
    mesh.triangle_materials.extend([2, 2, 3]);
    // Grazing glass sliver with ior 1 and a mirror.
    push_quad(
        &mut mesh,
        [
            v(-3., 0.001, -1.),
            v(-3., 0.001, 1.),
            v(-1., 0.0011, 1.),
            v(-1., 0.0011, -1.),
        ],
        3,
    );
    push_quad(
        &mut mesh,
        [
            v(-1., 0., -3.),
            v(1., 0., -3.),
            v(1., 2., -3.),
            v(-1., 2., -3.),
        ],
        4,
    );

    let sphere = mesh_from(&platoon_scenegen::uv_sphere(12, 16), 5);
    let mut light = lambertian("light", Vec3::splat(0.5));
    light.emissive = Vec3::splat(50.0);
    light.double_sided = true;
    let glass = Material {
        name: "ior1".into(),
        metallic: 0.0,
        roughness: 0.0,
        transmission: 1.0,
        ior: 1.0,
        ..Material::default()
    };
    let mirror = Material {
        name: "mirror".into(),
        metallic: 1.0,
        roughness: 0.0,
        ..Material::default()
    };
    let rough_glass = Material {
        name: "glass".into(),
        metallic: 0.0,
        roughness: 0.02,
        transmission: 1.0,
        ior: 2.4,
        ..Material::default()
    };
    scene_of(
        vec![
            (mesh, Vec3::ZERO, 1.0),
            (sphere.clone(), Vec3::new(0.0, 0.5, 1.5), 1e-4),
            (sphere.clone(), Vec3::new(0.0, 0.0, -2000.0), 1000.0),
            (sphere, Vec3::new(-0.5, 0.6, 0.5), 0.5),
        ],
        vec![
            lambertian("ground", Vec3::splat(0.5)),
            lambertian("box", Vec3::splat(1.0)),
            light,
            glass,
            mirror,
            rough_glass,
        ],
        Vec3::new(0.3, 2.5, 5.0),
        Vec3::new(0.0, 0.5, 0.0),
        1.0,
    )
}

#[test]
fn adversarial_scene_produces_no_nan_or_inf() {
    // Without an environment the only lights are sealed in a box or have zero area: black.
    for (env, lit) in [
        (platoon::EnvChoice::Scene, false),
        (constant_env(2.0), true),
        (platoon::EnvChoice::File(shared("envmaps/sunset.exr")), true),
    ] {
        let prepared = prepare(adversarial(), env);
        for sampling in [Sampling::Mis, Sampling::Bsdf, Sampling::Light] {
            let params = FrameParams::new(32, 32, 16, prepared.camera);
            // `render` asserts zero rejected samples and no validation message.
            let film = render(&prepared, &params, sampling);
            assert_eq!(film.count_non_finite(), 0);
            assert_eq!(
                film.mean().iter().all(|&m| m > 0.0),
                lit,
                "{sampling:?}: lit {lit}, mean {:?}",
                film.mean()
            );
        }
    }
}

#[test]
fn shared_scenes_render_finite_images_with_every_environment() {
    for scene in [
        "scenes/CesiumMan.glb",
        "scenes/RetroUFO.glb",
        "scenes/teapot.gltf",
    ] {
        for env in [
            "envmaps/forest.exr",
            "envmaps/interior.exr",
            "envmaps/sunset.exr",
            "envmaps/courtyard.exr",
        ] {
            let prepared = prepare(
                platoon::load_scene(Some(&shared(scene))).unwrap(),
                platoon::EnvChoice::File(shared(env)),
            );
            let params = FrameParams::new(16, 16, 4, prepared.camera);
            let film = render(&prepared, &params, Sampling::Mis);
            assert_eq!(film.count_non_finite(), 0, "{scene} under {env}");
        }
    }
}

//! The environment map seen directly must follow the documented equirectangular mapping, and
//! its importance sampling must agree with BSDF sampling.

#[path = "../common/mod.rs"]
mod common;

use std::f32::consts::PI;

use glam::Vec3;
use platoon::core::frame::FrameParams;
use platoon::core::output::{write_image, Film};
use platoon::core::Scene;
use platoon::tracer::Sampling;
use platoon::EnvChoice;

/// A gradient map: red = u, green = v, blue = 1 (so it is never black).
fn gradient_map(dir: &std::path::Path, w: u32, h: u32) -> std::path::PathBuf {
    let pixels = (0..w * h)
        .map(|i| {
            [
                ((i % w) as f32 + 0.5) / w as f32,
                ((i / w) as f32 + 0.5) / h as f32,
                1.0,
            ]
        })
        .collect();
    let path = dir.join("gradient.exr");
    write_image(
        &path,
        &Film {
            width: w,
            height: h,
            pixels,
        },
        &[],
    )
    .unwrap();
    path
}

fn uv_of(d: Vec3) -> (f32, f32) {
    (
        d.x.atan2(-d.z) / (2.0 * PI) + 0.5,
        d.y.clamp(-1.0, 1.0).acos() / PI,
    )
}

#[test]
fn background_follows_the_equirectangular_mapping() {
    let dir = tempfile::tempdir().unwrap();
    let map = gradient_map(dir.path(), 64, 32);
    // An empty scene with a camera: every pixel sees the environment.
    let mut scene = Scene::default();
    let mut node = platoon::core::scene::Node::new("camera");
    node.camera = Some(0);
    scene.nodes.push(node);
    scene.cameras.push(platoon::core::scene::CameraModel {
        name: "c".into(),
        yfov: 1.2,
        aspect_ratio: None,
        orthographic: None,
    });
    let prepared = common::prepare(scene, EnvChoice::File(map));
    let (w, h) = (32u32, 16u32);
    let mut params = FrameParams::new(w, h, 1, prepared.camera);
    params.path_loop.max_depth = 1;
    let film = common::render(&prepared, &params, Sampling::Mis);
    // Pixel centres are jittered by up to half a pixel; compare with a tolerance of one texel
    // plus the pixel footprint.
    let tan = (1.2f32 * 0.5).tan();
    let mut worst = 0.0f32;
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let ndc = Vec3::new(
                (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * tan * 2.0,
                (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * tan,
                -1.0,
            );
            let (u, v) = uv_of(ndc.normalize());
            let p = film.pixels[(y * w + x) as usize];
            worst = worst.max((p[0] - u).abs()).max((p[1] - v).abs());
            assert_eq!(p[2], 1.0);
        }
    }
    assert!(
        worst < 0.08,
        "environment lookup differs from the mapping by {worst}"
    );
}

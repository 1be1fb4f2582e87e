//! KHR_materials_dispersion against the spectrum integrated by this file: smooth glass of a
//! strong dispersion over a black floor under a sky of 1 shows only its reflection, whose colour
//! is the Fresnel reflectance at each wavelength's index (the spec's Cauchy equation) averaged
//! over each channel's sensitivity (the linear Rec. 709 colour-matching functions clamped at 0,
//! after Wyman, Sloan and Shirley's fit): blue reflects more than red. The megakernel and the
//! streaming path tracer converge to it; a thin wall (no volume) does not disperse and keeps the
//! bits of glass without the extension.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use glam::Vec3;
use platoon::core::frame::FrameParams;
use platoon::core::method::path::PathKernel;
use platoon::core::scene::Material;
use platoon::tracer::Sampling;

/// The CIE 1931 colour-matching functions, Wyman, Sloan and Shirley's multi-lobe fit.
fn cie_xyz(l: f64) -> [f64; 3] {
    let g = |mu: f64, below: f64, above: f64| {
        let t = (l - mu) / if l < mu { below } else { above };
        (-0.5 * t * t).exp()
    };
    [
        1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) - 0.065 * g(501.1, 20.4, 26.2),
        0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1),
        1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8),
    ]
}

/// Channel `k`'s sensitivity at `l`: linear Rec. 709 of the matching functions, at least 0.
fn sensitivity(l: f64, k: usize) -> f64 {
    let m = [
        [3.2404542, -1.5371385, -0.4985314],
        [-0.9692660, 1.8760108, 0.0415560],
        [0.0556434, -0.2040259, 1.0572252],
    ][k];
    let xyz = cie_xyz(l);
    (m[0] * xyz[0] + m[1] * xyz[1] + m[2] * xyz[2]).max(0.0)
}

/// The spec's index at wavelength `l` (nm) of index `ior` at 587.6 nm and `dispersion` = 20 / V.
fn index_at(ior: f64, dispersion: f64, l: f64) -> f64 {
    (ior + (ior - 1.0) * dispersion / 20.0 * (523655.0 / (l * l) - 1.5168)).max(1.0)
}

/// Unpolarised Fresnel reflectance from outside at cos `c` of index `eta`.
fn fresnel(c: f64, eta: f64) -> f64 {
    let sin2_t = (1.0 - c * c) / (eta * eta);
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (c - eta * cos_t) / (c + eta * cos_t);
    let rp = (eta * c - cos_t) / (eta * c + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// Channel `k` of `f(λ)` averaged over the channel's sensitivity on 380-780 nm.
fn channel_mean(k: usize, f: impl Fn(f64) -> f64) -> f64 {
    let n = 4000;
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..n {
        let l = 380.0 + 400.0 * (i as f64 + 0.5) / n as f64;
        let s = sensitivity(l, k);
        num += s * f(l);
        den += s;
    }
    num / den
}

fn glass(dispersion: f32, thickness: f32) -> Material {
    Material {
        name: "dispersive glass".into(),
        metallic: 0.0,
        roughness: 0.0,
        transmission: 1.0,
        ior: 1.5,
        thickness,
        dispersion,
        ..Material::default()
    }
}

#[test]
fn dispersive_glass_reflects_the_spectrum_of_its_indices() {
    let (ior, dispersion) = (1.5, 5.0);
    for cos_view in [0.95, 0.5] {
        let prepared = over_black_floor(glass(dispersion as f32, 1.0), cos_view);
        assert!(prepared.gpu.features.dispersion);
        let expected: Vec<f64> = (0..3)
            .map(|k| channel_mean(k, |l| fresnel(cos_view, index_at(ior, dispersion, l))))
            .collect();
        let plain = fresnel(cos_view, ior);
        for kernel in [PathKernel::Mega, PathKernel::Streaming] {
            let mut params = FrameParams::new(16, 16, 1024, prepared.camera);
            params.method = in_kernel(&params.method, kernel);
            let film = render(&prepared, &params, Sampling::Mis);
            for (k, &want) in expected.iter().enumerate() {
                let (m, se) = mean_and_stderr(film.pixels.iter().map(|p| p[k] as f64));
                eprintln!(
                    "cos {cos_view} {kernel:?} channel {k}: {m:.5} +- {se:.5}, spectrum {want:.5}, without dispersion {plain:.5}"
                );
                assert!(
                    (m - want).abs() < 4.0 * se + 5e-3 * want,
                    "cos {cos_view}, {kernel:?}, channel {k}: {m:.5} +- {se:.5} where the spectrum gives {want:.5}"
                );
            }
        }
        // The dispersion must show: blue (higher indices) reflects more than red.
        assert!(
            expected[2] > 1.15 * expected[0],
            "red {} blue {}",
            expected[0],
            expected[2]
        );
    }
}

#[test]
fn a_thin_wall_does_not_disperse() {
    // The spec disperses in a volume: a thin wall (thickness 0) compiles no dispersion and
    // renders the bits of the same glass without the extension.
    let thin = over_black_floor(glass(1.0, 0.0), 0.8);
    assert!(!thin.gpu.features.dispersion);
    let plain = over_black_floor(glass(0.0, 0.0), 0.8);
    let params = FrameParams::new(16, 16, 16, thin.camera);
    let a = render(&thin, &params, Sampling::Mis);
    let b = render(&plain, &params, Sampling::Mis);
    assert!(a.pixels == b.pixels);
}

#[test]
fn the_streaming_path_tracer_carries_the_wavelength_between_its_kernels() {
    // A cube of dispersive glass seen obliquely: paths refract in and out (and reflect inside),
    // each time at their wavelength's index; a kernel that lost the wavelength between its
    // kernels would draw another at the next surface and weigh the path twice.
    let mut scene = scene_of(
        vec![(mesh_from(&platoon_scenegen::flat_box(), 0), Vec3::ZERO, 1.0)],
        vec![glass(2.0, 2.0)],
        Vec3::new(6.0, 5.0, 8.0),
        Vec3::ZERO,
        0.5,
    );
    scene.cameras[0].orthographic = Some([0.8, 0.8]);
    let prepared = prepare(scene, constant_env(1.0));
    let mut params = FrameParams::new(24, 24, 16, prepared.camera);
    params.method = in_kernel(&params.method, PathKernel::Mega);
    let mega = render(&prepared, &params, Sampling::Mis);
    params.method = in_kernel(&params.method, PathKernel::Streaming);
    let streaming = render(&prepared, &params, Sampling::Mis);
    assert_eq!(mega.count_non_finite(), 0);
    assert!(mega.pixels == streaming.pixels);
}

#[test]
fn a_spectral_path_keeps_white_white() {
    // Dispersive glass of index 1 bends nothing and reflects nothing, at every wavelength: under
    // a sky of 1 it shows 1 in every channel, the expectation of the wavelength's weight (each
    // channel's sensitivity over its integral and the pdf).
    let mut material = glass(1.0, 1.0);
    material.ior = 1.0;
    let prepared = under_unit_sky(
        vec![(
            mesh_from(&platoon_scenegen::quad(1.0, 1.0), 0),
            Vec3::ZERO,
            1000.0,
        )],
        vec![material],
        vec![],
        Vec3::new(0.3, 1.0, 0.0) * 10.0,
    );
    assert!(prepared.gpu.features.dispersion);
    let film = render(
        &prepared,
        &FrameParams::new(32, 32, 256, prepared.camera),
        Sampling::Mis,
    );
    for k in 0..3 {
        let (m, se) = mean_and_stderr(film.pixels.iter().map(|p| p[k] as f64));
        eprintln!("channel {k}: {m:.5} +- {se:.5}");
        assert!(
            (m - 1.0).abs() < 4.0 * se + 1e-3,
            "channel {k}: {m:.5} +- {se:.5}"
        );
        // The wavelengths differ from pixel to pixel: the test sees their weights.
        assert!(se > 1e-4);
    }
}

//! Adaptive sampling and the variance AOV (issue 24) against what cannot be faked. In the white
//! furnace under light sampling the sky's pixels are exact from the first sample (they converge
//! at the minimum and must stay exactly the sky) while the sphere's are noisy (they take more
//! samples, and their mean is still the sky: unbiased); every sphere pixel has the same
//! distribution, so the spread of their values is what the variance AOV must estimate; and the
//! batches, the mask and the sample counts have the same bits on one tracer and on three, and
//! through the streaming kernels.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use glam::Vec3;
use platoon::core::frame::adaptive::{Adaptive, Batching};
use platoon::core::frame::FrameParams;
use platoon::core::method::path::PathKernel;
use platoon::core::scene::cornell::lambertian;
use platoon::devices::{tracer_options, DeviceSpec};
use platoon::tracer::Sampling;
use platoon::{Prepared, Rendered, Tracers};

const SKY: f32 = 0.8;
const MIN_SPP: u32 = 16;

fn furnace() -> Prepared {
    prepare(
        sphere_scene(lambertian("white", Vec3::ONE)),
        constant_env(SKY),
    )
}

fn adaptive(threshold: f32) -> Batching {
    Batching {
        adaptive: Some(Adaptive {
            threshold,
            min_spp: Some(MIN_SPP),
        }),
        variance: true,
    }
}

fn render_on(
    devices: &str,
    sampling: Sampling,
    prepared: &Prepared,
    params: &FrameParams,
    batching: &Batching,
) -> Rendered {
    let spec: DeviceSpec = devices.parse().unwrap();
    let options = tracer_options(&spec, false, sampling).unwrap();
    let mut tracers = Tracers::new(&options, "cost-aware", &prepared.gpu).unwrap();
    tracers
        .render_batched(&prepared.gpu, params, batching, &mut |_| {})
        .unwrap()
}

#[test]
fn converged_sky_stops_at_the_minimum_and_the_noisy_sphere_stays_unbiased() {
    let prepared = furnace();
    let (w, h) = (32, 32);
    let params = FrameParams::new(w, h, 128, prepared.camera);
    // A strict threshold (the sphere takes every sample) and a loose one (its pixels stop at
    // several counts, on their own noise: the mean must still be the sky).
    for threshold in [0.01, 0.4] {
        let r = render_on(
            "0",
            Sampling::Light,
            &prepared,
            &params,
            &adaptive(threshold),
        );
        let samples = &r.batched.as_ref().unwrap().samples;
        let near_sphere = sphere_pixels(w, h, 1.25);
        let mut sky = 0;
        for i in (0..(w * h) as usize).filter(|i| !near_sphere.contains(i)) {
            sky += 1;
            assert_eq!(
                samples[i], MIN_SPP,
                "sky pixel {i} took {} samples",
                samples[i]
            );
            for c in r.film.pixels[i] {
                assert!((c - SKY).abs() < 1e-5, "sky pixel {i} is {c}, not {SKY}");
            }
        }
        assert!(sky > 200);
        let inside = sphere_pixels(w, h, 0.9);
        let counts: Vec<u32> = inside.iter().map(|&i| samples[i]).collect();
        let mean_samples = counts.iter().map(|&n| n as f64).sum::<f64>() / counts.len() as f64;
        assert!(
            mean_samples > 4.0 * MIN_SPP as f64,
            "{threshold}: the noisy sphere took only {mean_samples} samples a pixel"
        );
        if threshold > 0.1 {
            assert!(
                counts.iter().filter(|&&n| n < params.spp).count() > counts.len() / 4,
                "{threshold}: the sphere's pixels did not stop on their noise: {counts:?}"
            );
        }
        assert!(r.mean_spp() < 0.75 * params.spp as f64, "{}", r.mean_spp());
        let (m, se) = mean_and_stderr(inside.iter().map(|&i| luminance(r.film.pixels[i])));
        eprintln!(
            "adaptive furnace {threshold}: sphere {m} ± {se}, {mean_samples} samples a pixel"
        );
        assert!(
            (m - SKY as f64).abs() < 0.005 + 4.0 * se,
            "{threshold}: sphere mean {m} ± {se}, not the sky {SKY}"
        );
    }
}

#[test]
fn the_variance_aov_matches_the_spread_of_identically_distributed_pixels() {
    let prepared = furnace();
    let (w, h) = (32, 32);
    let params = FrameParams::new(w, h, 64, prepared.camera);
    let batching = Batching {
        adaptive: None,
        variance: true,
    };
    let r = render_on("0", Sampling::Light, &prepared, &params, &batching);
    // Batches continue the sums: the beauty is the unbatched render's, bit for bit.
    let plain = render_on(
        "0",
        Sampling::Light,
        &prepared,
        &params,
        &Batching::default(),
    );
    assert!(
        r.film.pixels == plain.film.pixels,
        "batching changed the beauty"
    );
    let variance = r.batched.as_ref().unwrap().variance.as_ref().unwrap();
    let inside = sphere_pixels(w, h, 0.9);
    let values: Vec<f64> = inside.iter().map(|&i| r.film.pixels[i][0] as f64).collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let spread = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (values.len() - 1) as f64;
    let estimated =
        inside.iter().map(|&i| variance[i][0] as f64).sum::<f64>() / inside.len() as f64;
    eprintln!("variance of a pixel's mean: spread {spread}, AOV {estimated}");
    assert!(spread > 1e-5, "the sphere is not noisy: {spread}");
    assert!(
        (estimated / spread - 1.0).abs() < 0.25,
        "the AOV says {estimated}, the pixels' spread {spread}"
    );
}

#[test]
fn adaptive_sampling_has_the_same_bits_on_one_tracer_on_three_and_streaming() {
    let prepared = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    );
    let mut params = FrameParams::new(24, 20, 64, prepared.camera);
    params.method = in_kernel(&params.method, PathKernel::Mega);
    let batching = adaptive(0.05);
    let one = render_on("0", Sampling::Mis, &prepared, &params, &batching);
    let three = render_on(
        "lavapipe:1,1,1",
        Sampling::Mis,
        &prepared,
        &params,
        &batching,
    );
    params.method = in_kernel(&params.method, PathKernel::Streaming);
    let streaming = render_on("0", Sampling::Mis, &prepared, &params, &batching);
    let samples = |r: &Rendered| r.batched.as_ref().unwrap().samples.clone();
    assert!(
        samples(&one).iter().any(|&n| n < params.spp),
        "nothing converged: the test shows nothing"
    );
    for (name, other) in [("three tracers", &three), ("streaming", &streaming)] {
        assert_eq!(
            samples(&one),
            samples(other),
            "{name}: sample counts differ"
        );
        assert!(
            one.film.pixels == other.film.pixels,
            "{name}: the image differs"
        );
    }
}

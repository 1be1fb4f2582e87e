//! The à-trous denoiser on the device (shaders/denoise/atrous.comp, issue 43) against its CPU
//! reference (`denoise::atrous`): the same image to float rounding, a constant image kept
//! constant, no blur across a normal edge.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::denoise::{atrous, Guides};
use platoon::core::output::Film;
use platoon::tracer::Sampling;

/// A `w` x `h` frame of two faces meeting at the middle column (normals +z and +x), the left
/// of radiance `left`, the right of `right`, each pixel off by up to +-`noise` (an LCG's), and
/// its guides; a band of sky (no surface) along the top line.
fn two_faces(w: u32, h: u32, left: f32, right: f32, noise: f32) -> (Film, Guides) {
    let mut state = 7u32;
    let mut jitter = || {
        state = state.wrapping_mul(1664525).wrapping_add(1013904223);
        ((state >> 8) as f32 / (1u32 << 24) as f32 - 0.5) * 2.0 * noise
    };
    let n = (w * h) as usize;
    let (mut pixels, mut albedo, mut normal, mut depth) = (vec![], vec![], vec![], vec![]);
    for i in 0..n {
        let (x, y) = (i as u32 % w, i as u32 / w);
        let l = if x < w / 2 { left } else { right };
        pixels.push([l + jitter(), l + jitter(), l + jitter()]);
        albedo.push([0.5, 0.6, 0.7]);
        normal.push(if x < w / 2 {
            [0.0, 0.0, 1.0]
        } else {
            [1.0, 0.0, 0.0]
        });
        depth.push(if y == 0 {
            f32::INFINITY
        } else {
            2.0 + 0.01 * x as f32
        });
    }
    let film = Film {
        width: w,
        height: h,
        pixels,
    };
    (
        film,
        Guides {
            albedo,
            normal,
            depth,
            variance: None,
        },
    )
}

fn device_filter(film: &Film, guides: &Guides) -> Film {
    let mut tracer = tracer(
        &prepare(
            platoon::core::scene::cornell::scene(),
            platoon::EnvChoice::Scene,
        ),
        Sampling::Mis,
    );
    let (out, _) = tracer
        .filter_atrous_timed(film, guides)
        .expect("device filter");
    assert_no_validation_messages(&tracer);
    out
}

#[test]
fn the_device_filter_is_the_cpu_filter_to_float_rounding() {
    let (film, guides) = two_faces(40, 24, 0.3, 2.0, 0.25);
    let (device, cpu) = (
        device_filter(&film, &guides),
        atrous::filter(&film, &guides),
    );
    let mut worst = 0.0f32;
    for (d, c) in device.pixels.iter().zip(&cpu.pixels) {
        for k in 0..3 {
            worst = worst.max((d[k] - c[k]).abs() / c[k].abs().max(1e-3));
        }
    }
    assert!(worst < 1e-3, "largest relative difference {worst}");
    // The filter did filter: the noise is much lower than the frame's.
    let spread = |f: &Film| {
        let left: Vec<f64> = (0..f.pixels.len())
            .filter(|i| i % 40 < 18 && i / 40 > 0)
            .map(|i| f.pixels[i][0] as f64)
            .collect();
        let mean = left.iter().sum::<f64>() / left.len() as f64;
        (left.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / left.len() as f64).sqrt()
    };
    assert!(
        spread(&device) < 0.3 * spread(&film),
        "{} vs {}",
        spread(&device),
        spread(&film)
    );
}

#[test]
fn the_device_filter_keeps_a_constant_image_and_its_normal_edge() {
    let (mut film, mut guides) = two_faces(32, 16, 0.7, 0.7, 0.0);
    // Guides that vary: equal values must still average to themselves.
    for (i, a) in guides.albedo.iter_mut().enumerate() {
        *a = [0.2 + 0.01 * (i % 7) as f32; 3];
    }
    for p in &device_filter(&film, &guides).pixels {
        for c in p {
            assert!((c - 0.7).abs() < 1e-5, "{c}");
        }
    }
    // Two faces of 0.1 and 1.0 without noise: nothing crosses the normal edge between them
    // (the sky's line has no normals: only its radiance weight stops it there).
    (film, guides) = two_faces(32, 16, 0.1, 1.0, 0.0);
    let out = device_filter(&film, &guides);
    for (i, p) in out.pixels.iter().enumerate().skip(32) {
        let want = if i % 32 < 16 { 0.1 } else { 1.0 };
        assert!(
            (p[0] - want).abs() < 1e-3 * want,
            "pixel {i}: {} for {want}",
            p[0]
        );
    }
}

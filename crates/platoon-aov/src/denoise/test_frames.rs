//! Frames the denoisers' tests share: two faces meeting at a normal edge, with noise.

use super::Guides;
use platoon_image::Film;

/// A w x h frame, left half facing +x and right half +y, with radiance `left` and `right`
/// plus a fixed pattern of noise of amplitude `noise`.
pub fn two_faces(w: usize, h: usize, left: f32, right: f32, noise: f32) -> (Film, Guides) {
    let n = w * h;
    let wobble = |i: usize| ((i as u32).wrapping_mul(2654435761) >> 16) as f32 / 65536.0 - 0.5;
    let pixels = (0..n)
        .map(|i| {
            let base = if i % w < w / 2 { left } else { right };
            [base + noise * wobble(i); 3]
        })
        .collect();
    let guides = Guides {
        variance: None,
        albedo: vec![[0.5; 3]; n],
        normal: (0..n)
            .map(|i| {
                if i % w < w / 2 {
                    [1.0, 0.0, 0.0]
                } else {
                    [0.0, 1.0, 0.0]
                }
            })
            .collect(),
        depth: vec![2.0; n],
    };
    let film = Film {
        width: w as u32,
        height: h as u32,
        pixels,
    };
    (film, guides)
}

pub fn spread(film: &Film, pixels: impl Iterator<Item = usize>) -> (f32, f32) {
    let v: Vec<f32> = pixels.map(|i| film.pixels[i][0]).collect();
    let mean = v.iter().sum::<f32>() / v.len() as f32;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f32>() / v.len() as f32;
    (mean, var)
}

/// `denoise` run on two faces (0.2 and 0.8, noise 0.1) of a `w` x `h` frame smooths the noise
/// (the left face's variance down 4x) without carrying light across their normal edge, each
/// face's mean staying within `tolerance` of its radiance.
pub fn assert_smoothed_not_across_the_edge(
    w: usize,
    h: usize,
    tolerance: f32,
    denoise: impl Fn(&Film, &Guides) -> Film,
) {
    let (film, guides) = two_faces(w, h, 0.2, 0.8, 0.1);
    let out = denoise(&film, &guides);
    let left = || (0..w * h).filter(move |i| i % w < w / 2);
    let right = || (0..w * h).filter(move |i| i % w >= w / 2);
    for (side, want) in [(spread(&out, left()), 0.2), (spread(&out, right()), 0.8)] {
        assert!(
            (side.0 - want).abs() < tolerance,
            "mean {} not {want}",
            side.0
        );
    }
    for p in left() {
        assert!(out.pixels[p][0] < 0.4, "light leaked across the edge");
    }
    let (_, before) = spread(&film, left());
    let (_, after) = spread(&out, left());
    assert!(
        after < before / 4.0,
        "variance {before} -> {after}: not smoothed"
    );
}

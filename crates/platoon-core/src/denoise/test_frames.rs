//! Frames the denoisers' tests share: two faces meeting at a normal edge, with noise.

use super::Guides;
use crate::output::Film;

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

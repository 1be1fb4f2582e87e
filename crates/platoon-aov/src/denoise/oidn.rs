//! Intel Open Image Denoise's ray-tracing filter (`--denoise oidn`; the cargo feature `oidn`,
//! linked against the library found by `OIDN_DIR` or pkg-config): a neural network trained on
//! path-traced images, guided by the albedo and normal AOVs (Cycles' conventions, which are
//! OIDN's), on the HDR image after assembly.

use super::Guides;
use platoon_image::Film;

/// `film` denoised by OIDN's `RT` filter with `guides`' albedo and normal.
pub fn filter(film: &Film, guides: &Guides) -> Result<Film, String> {
    let flat = |v: &[[f32; 3]]| v.iter().flatten().copied().collect::<Vec<f32>>();
    let color = flat(&film.pixels);
    let albedo = flat(&guides.albedo);
    let normal = flat(&guides.normal);
    let mut output = vec![0.0f32; color.len()];
    let device = oidn::Device::cpu();
    oidn::RayTracing::new(&device)
        .hdr(true)
        .albedo_normal(&albedo, &normal)
        .image_dimensions(film.width as usize, film.height as usize)
        .filter(&color, &mut output)
        .map_err(|e| format!("Open Image Denoise: {e:?}"))?;
    if let Err((_, message)) = device.get_error() {
        return Err(format!("Open Image Denoise: {message}"));
    }
    Ok(Film {
        width: film.width,
        height: film.height,
        pixels: output.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::denoise::test_frames::{assert_smoothed_not_across_the_edge, spread, two_faces};

    /// A network, not a filter of normalised weights: a constant image stays constant within
    /// 1.5% away from the borders; within 16 pixels of them OIDN itself (its own oidnDenoise on
    /// the same image too) strays by up to a fifth, so only their mean is held there.
    #[test]
    fn a_constant_image_stays_constant() {
        let (w, h) = (128, 96);
        let (film, guides) = two_faces(w, h, 0.7, 0.7, 0.0);
        let out = filter(&film, &guides).unwrap();
        let interior = |i: &usize| {
            let (x, y) = (i % w, i / w);
            (16..w - 16).contains(&x) && (16..h - 16).contains(&y)
        };
        for i in (0..w * h).filter(interior) {
            for c in out.pixels[i] {
                assert!((c - 0.7).abs() < 0.7 * 0.015, "pixel {i}: {c}");
            }
        }
        let (mean, _) = spread(&out, 0..w * h);
        assert!((mean - 0.7).abs() < 0.7 * 0.03, "mean {mean}");
    }

    #[test]
    fn noise_is_smoothed_but_not_across_a_normal_edge() {
        assert_smoothed_not_across_the_edge(48, 32, 0.03, |film, guides| {
            filter(film, guides).unwrap()
        });
    }
}

//! The display-referred writers read back: their pixels are the view's encoding at their
//! bits, their metadata comes back whole (non-ASCII too), a damaged file is an error.

use std::path::Path;

use super::*;
use crate::colour::ViewTransform;

/// A smooth ramp over three decades of radiance, so that the encodings differ between bits.
fn ramp() -> Film {
    let (width, height) = (37u32, 11u32);
    let pixels = (0..width * height)
        .map(|i| {
            let (x, y) = ((i % width) as f32, (i / width) as f32);
            [0.001 * 1.2f32.powf(x), 0.05 * (y + 1.0), 0.3]
        })
        .collect();
    Film {
        width,
        height,
        pixels,
    }
}

fn meta() -> Vec<(String, String)> {
    vec![
        ("scene".into(), "Café/ø.glb".into()),
        ("spp".into(), "64".into()),
    ]
}

fn options(bits: u8) -> ImageOptions {
    ImageOptions {
        view: View {
            transform: ViewTransform::Agx,
            exposure: 1.0,
        },
        display: DisplayOptions {
            bits,
            jpeg_quality: 95,
        },
        ..Default::default()
    }
}

fn written(name: &str, bits: u8) -> (tempfile::TempDir, std::path::PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    write_image_as(&path, &ramp(), &[], &meta(), &options(bits)).unwrap();
    (dir, path)
}

fn expected_meta() -> Vec<(String, String)> {
    let mut m: Vec<_> = meta()
        .into_iter()
        .map(|(k, v)| (format!("platoon:{k}"), v))
        .collect();
    m.sort();
    m
}

fn tiff_pixels(path: &Path) -> ::tiff::decoder::DecodingResult {
    let file = std::fs::File::open(path).unwrap();
    ::tiff::decoder::Decoder::new(file)
        .unwrap()
        .read_image()
        .unwrap()
}

#[test]
fn a_16_bit_png_and_tiff_hold_the_views_16_bit_encoding() {
    let want = ramp().srgb16_viewed(&options(16).view);
    let (_d, png) = written("a.png", 16);
    let mut reader =
        ::png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()))
            .read_info()
            .unwrap();
    let mut bytes = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut bytes).unwrap();
    assert_eq!(info.bit_depth, ::png::BitDepth::Sixteen);
    let got: Vec<u16> = bytes
        .chunks(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]))
        .collect();
    assert_eq!(got, want);
    assert_eq!(read_metadata(&png).unwrap(), expected_meta());

    let (_d, tif) = written("a.tif", 16);
    match tiff_pixels(&tif) {
        ::tiff::decoder::DecodingResult::U16(got) => assert_eq!(got, want),
        _ => panic!("not a 16-bit TIFF"),
    }
    assert_eq!(read_metadata(&tif).unwrap(), expected_meta());
    // The 16 bits are finer than the 8: not the 8-bit values scaled.
    let eight = ramp().srgb8_viewed(&options(8).view);
    assert!(want.iter().zip(&eight).any(|(w, e)| *w != *e as u16 * 257));
}

#[test]
fn an_8_bit_tiff_and_a_jpeg_hold_the_views_8_bit_encoding() {
    let want = ramp().srgb8_viewed(&options(8).view);
    let (_d, tif) = written("a.tiff", 8);
    match tiff_pixels(&tif) {
        ::tiff::decoder::DecodingResult::U8(got) => assert_eq!(got, want),
        _ => panic!("not an 8-bit TIFF"),
    }
    let (_d, jpg) = written("a.jpg", 8);
    let got = image::open(&jpg).unwrap().to_rgb8().into_raw();
    assert_eq!(got.len(), want.len());
    // Lossy: close on average, at quality 95.
    let mean = got
        .iter()
        .zip(&want)
        .map(|(g, w)| (*g as f64 - *w as f64).abs())
        .sum::<f64>()
        / want.len() as f64;
    assert!(mean < 2.0, "mean difference {mean}");
    assert_eq!(read_metadata(&jpg).unwrap(), expected_meta());
}

#[test]
fn a_damaged_file_is_an_error_and_bits_the_format_cannot_hold_are_refused() {
    for name in ["a.jpg", "a.tif", "a.png"] {
        let (_d, path) = written(name, 8);
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() * 2 / 3]).unwrap();
        assert!(read_metadata(&path).is_err(), "{name}: truncated, read");
    }
    let dir = tempfile::tempdir().unwrap();
    for (name, bits, says) in [
        ("a.jpg", 16, "8 bits"),
        ("a.exr", 16, "--exr-half"),
        ("a.png", 12, "8 or 16"),
    ] {
        let path = dir.path().join(name);
        let e = write_image_as(&path, &ramp(), &[], &[], &options(bits)).unwrap_err();
        assert!(e.to_string().contains(says), "{name}: {e}");
        assert!(!path.exists());
    }
}

#[test]
fn an_exrs_texts_past_latin_1_come_back_whole() {
    // A scene's path or an object's name (Cryptomatte's manifest) can be any text.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("names.exr");
    let meta = vec![("scene".to_string(), "シーン/木.glb".to_string())];
    write_image(&path, &ramp(), &meta).unwrap();
    let (_, back) = read_exr(&path).unwrap();
    let want = ("platoon:scene".to_string(), "シーン/木.glb".to_string());
    assert!(back.contains(&want), "{back:?}");
}

#[test]
fn a_png_and_a_tiff_hold_straight_alpha_and_an_exr_premultiplied() {
    // A pixel half covered by a surface of 0.2: its premultiplied colour is 0.1.
    let film = Film {
        width: 2,
        height: 1,
        pixels: vec![[0.1; 3], [0.0; 3]],
    };
    let alpha = [0.5, 0.0];
    let dir = tempfile::tempdir().unwrap();
    let options = ImageOptions::default();
    let shown = options.view.srgb8([0.2; 3]);
    for name in ["a.png", "a.tiff"] {
        let path = dir.path().join(name);
        write_rgba_as(&path, &film, Some(&alpha), &[], &[], &options).unwrap();
        let rgba = ::image::open(&path).unwrap().to_rgba8();
        assert_eq!(
            rgba.get_pixel(0, 0).0,
            [shown[0], shown[1], shown[2], 128],
            "{name}"
        );
        assert_eq!(rgba.get_pixel(1, 0).0, [0, 0, 0, 0], "{name}");
    }
    let path = dir.path().join("a.exr");
    write_rgba_as(&path, &film, Some(&alpha), &[], &[], &options).unwrap();
    let channels = read_exr_channels(&path).unwrap();
    let channel = |n: &str| channels.iter().find(|(c, _)| c == n).unwrap().1.clone();
    assert_eq!(
        (channel("R"), channel("A")),
        (vec![0.1, 0.0], vec![0.5, 0.0])
    );
    let jpeg = dir.path().join("a.jpg");
    let refused = write_rgba_as(&jpeg, &film, Some(&alpha), &[], &[], &options);
    assert!(refused
        .unwrap_err()
        .to_string()
        .contains("no alpha channel"));
}

//! How an EXR is written: its samples' type (float or half, as Blender and Cycles offer) and
//! its compression (the ones the `exr` crate writes; DWAA and DWAB it does not).

use exr::prelude::{Blocks, Compression, Encoding, LineOrder};

/// An EXR's compression.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ExrCompression {
    None,
    /// Run-length, in 64 x 64 tiles (lossless, fast: the default, platoon's before the choice).
    #[default]
    Rle,
    /// zlib a scan line (lossless).
    Zips,
    /// zlib 16 scan lines at once (lossless; Blender's default).
    Zip,
    /// Wavelets and Huffman (lossless; best on noisy renders).
    Piz,
    /// Floats rounded to 24 bits, then zlib (lossy for float, lossless for half).
    Pxr24,
    /// 4 x 4 blocks of half floats (lossy; half only).
    B44,
}

impl ExrCompression {
    pub const ALL: [ExrCompression; 7] = [
        ExrCompression::None,
        ExrCompression::Rle,
        ExrCompression::Zips,
        ExrCompression::Zip,
        ExrCompression::Piz,
        ExrCompression::Pxr24,
        ExrCompression::B44,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ExrCompression::None => "none",
            ExrCompression::Rle => "rle",
            ExrCompression::Zips => "zips",
            ExrCompression::Zip => "zip",
            ExrCompression::Piz => "piz",
            ExrCompression::Pxr24 => "pxr24",
            ExrCompression::B44 => "b44",
        }
    }

    pub fn parse(name: &str) -> Result<ExrCompression, String> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|c| c.name()).collect();
                format!(
                    "unknown EXR compression {name:?} (one of {})",
                    names.join(", ")
                )
            })
    }
}

/// An EXR's sample type and compression.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExrOptions {
    /// Half floats (16 bits) instead of floats (32).
    pub half: bool,
    pub compression: ExrCompression,
}

impl ExrOptions {
    /// What is wrong with the pair, if anything.
    pub fn check(&self) -> Result<(), String> {
        if self.compression == ExrCompression::B44 && !self.half {
            return Err("b44 compresses half floats only (with the half sample type)".into());
        }
        Ok(())
    }

    pub fn describe(&self) -> String {
        let depth = if self.half { "half" } else { "float" };
        format!("{depth}, {}", self.compression.name())
    }

    pub(super) fn encoding(&self) -> Encoding {
        let scan_lines = |compression| Encoding {
            compression,
            blocks: Blocks::ScanLines,
            line_order: LineOrder::Increasing,
        };
        match self.compression {
            ExrCompression::Rle => Encoding::FAST_LOSSLESS,
            ExrCompression::None => scan_lines(Compression::Uncompressed),
            ExrCompression::Zips => scan_lines(Compression::ZIP1),
            ExrCompression::Zip => scan_lines(Compression::ZIP16),
            ExrCompression::Piz => scan_lines(Compression::PIZ),
            ExrCompression::Pxr24 => scan_lines(Compression::PXR24),
            ExrCompression::B44 => scan_lines(Compression::B44),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{read_exr, write_image_as, Film, ImageOptions};

    /// A smooth image over a render's range (B44's 4 x 4 blocks and PXR24's rounding are
    /// judged on it), with a few values past half's precision.
    fn film() -> Film {
        let (w, h) = (37u32, 23u32);
        let pixels = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                [
                    0.01 + 0.03 * x,
                    0.5 + 0.011 * y,
                    1.0 / (1.0 + x + y) + 1e-4 * x,
                ]
            })
            .collect();
        Film {
            width: w,
            height: h,
            pixels,
        }
    }

    #[test]
    fn every_compression_reads_back_all_it_may_keep() {
        let dir = tempfile::tempdir().unwrap();
        let f = film();
        let mut size = std::collections::HashMap::new();
        for half in [false, true] {
            for compression in ExrCompression::ALL {
                let exr = ExrOptions { half, compression };
                let path = dir
                    .path()
                    .join(format!("{}-{half}.exr", compression.name()));
                let options = ImageOptions {
                    exr,
                    ..Default::default()
                };
                let meta = [("what".to_string(), "a ramp".to_string())];
                let written = write_image_as(&path, &f, &[], &meta, &options);
                if compression == ExrCompression::B44 && !half {
                    let e = written.unwrap_err().to_string();
                    assert!(e.contains("half floats only"), "{e}");
                    continue;
                }
                written.unwrap();
                let (back, read_meta) = read_exr(&path).unwrap();
                let said = ("platoon:what".to_string(), "a ramp".to_string());
                assert!(read_meta.contains(&said), "{exr:?}: {read_meta:?}");
                // What each may lose: half's rounding, PXR24's 24-bit floats, B44's blocks.
                let (relative, absolute) = match (compression, half) {
                    (ExrCompression::Pxr24, false) => (3e-5, 0.0),
                    (ExrCompression::B44, true) => (0.02, 1e-3),
                    _ => (0.0, 0.0),
                };
                for (p, q) in f.pixels.iter().zip(&back.pixels) {
                    for k in 0..3 {
                        let want = if half {
                            exr::prelude::f16::from_f32(p[k]).to_f32()
                        } else {
                            p[k]
                        };
                        assert!(
                            (q[k] - want).abs() <= relative * want.abs() + absolute,
                            "{exr:?}: {} read back as {}",
                            p[k],
                            q[k]
                        );
                    }
                }
                size.insert((compression, half), std::fs::metadata(&path).unwrap().len());
            }
        }
        let none = size[&(ExrCompression::None, false)];
        assert!(size[&(ExrCompression::Zip, false)] < none, "{size:?}");
        assert!(
            size[&(ExrCompression::None, true)] < none * 6 / 10,
            "{size:?}"
        );
    }

    #[test]
    fn names_round_trip_and_an_unknown_one_lists_them() {
        for c in ExrCompression::ALL {
            assert_eq!(ExrCompression::parse(c.name()), Ok(c));
        }
        let e = ExrCompression::parse("dwaa").unwrap_err();
        assert!(e.contains("none, rle, zips, zip, piz, pxr24, b44"), "{e}");
    }
}

//! JPEG outputs: 8-bit sRGB under the view at a quality, the metadata as comment (COM)
//! segments after the start of the image, one `platoon:KEY=VALUE` each.

use std::io::{Seek, Write};
use std::path::Path;

use super::film::Film;
use crate::colour::View;
use platoon_scene::error::{Error, Result};

const SOI: [u8; 2] = [0xff, 0xd8];
const COM: u8 = 0xfe;
/// Start of scan: the entropy-coded data follows, no more segments to read.
const SOS: u8 = 0xda;

pub(super) fn write_jpeg(
    path: &Path,
    w: &mut (impl Write + Seek),
    film: &Film,
    metadata: &[(String, String)],
    view: &View,
    quality: u8,
) -> Result<()> {
    let mut encoded = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut encoded, quality)
        .encode(
            &film.srgb8_viewed(view),
            film.width,
            film.height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| Error::file(path, format!("cannot write JPEG: {e}")))?;
    let mut out = SOI.to_vec();
    for (k, v) in metadata {
        let text = format!("platoon:{k}={v}");
        // A segment's length (two bytes) counts itself.
        let length = u16::try_from(text.len() + 2)
            .map_err(|_| Error::file(path, format!("metadata {k} is too long for a JPEG")))?;
        out.extend_from_slice(&[0xff, COM]);
        out.extend_from_slice(&length.to_be_bytes());
        out.extend_from_slice(text.as_bytes());
    }
    out.extend_from_slice(&encoded[SOI.len()..]);
    w.write_all(&out)
        .map_err(|e| Error::file(path, format!("cannot write: {e}")))
}

/// A JPEG's `platoon:` comments, after decoding it whole (a truncated file is an error).
pub(super) fn read_jpeg_metadata(path: &Path) -> Result<Vec<(String, String)>> {
    let bytes = std::fs::read(path).map_err(|e| Error::file(path, format!("cannot read: {e}")))?;
    image::load_from_memory_with_format(&bytes, image::ImageFormat::Jpeg)
        .map_err(|e| Error::file(path, format!("cannot read JPEG: {e}")))?;
    let mut meta = Vec::new();
    let mut at = SOI.len();
    while at + 4 <= bytes.len() && bytes[at] == 0xff && bytes[at + 1] != SOS {
        let length = u16::from_be_bytes([bytes[at + 2], bytes[at + 3]]) as usize;
        let body = bytes.get(at + 4..at + 2 + length).unwrap_or(&[]);
        if bytes[at + 1] == COM {
            let text = String::from_utf8_lossy(body);
            if let Some((k, v)) = text.split_once('=') {
                meta.push((k.to_string(), v.to_string()));
            }
        }
        at += 2 + length;
    }
    Ok(meta)
}

//! PNG outputs: 8 or 16 bits a channel, sRGB under the view (with a straight alpha for a
//! transparent film), metadata as iTXt chunks (the image crate writes none).

use std::io::{Seek, Write};
use std::path::Path;

use super::film::Film;
use crate::colour::View;
use platoon_scene::error::{Error, Result};

pub(super) fn write_png(
    path: &Path,
    w: &mut (impl Write + Seek),
    film: &Film,
    alpha: Option<&[f32]>,
    metadata: &[(String, String)],
    view: &View,
    bits: u8,
) -> Result<()> {
    let failed = |e: png::EncodingError| Error::file(path, format!("cannot write PNG: {e}"));
    let mut encoder = png::Encoder::new(w, film.width, film.height);
    encoder.set_color(match alpha {
        Some(_) => png::ColorType::Rgba,
        None => png::ColorType::Rgb,
    });
    encoder.set_depth(match bits {
        16 => png::BitDepth::Sixteen,
        _ => png::BitDepth::Eight,
    });
    for (k, v) in metadata {
        encoder
            .add_itxt_chunk(format!("platoon:{k}"), v.clone())
            .map_err(failed)?;
    }
    let mut writer = encoder.write_header().map_err(failed)?;
    let data = match bits {
        // PNG's samples are big-endian.
        16 => (film.display16(alpha, view).iter())
            .flat_map(|v| v.to_be_bytes())
            .collect(),
        _ => film.display8(alpha, view),
    };
    writer.write_image_data(&data).map_err(failed)?;
    writer.finish().map_err(failed)
}

/// A PNG's iTXt chunks, read through to its last pixel.
pub(super) fn read_png_metadata(path: &Path) -> Result<Vec<(String, String)>> {
    let failed = |e: png::DecodingError| Error::file(path, format!("cannot read PNG: {e}"));
    let file =
        std::fs::File::open(path).map_err(|e| Error::file(path, format!("cannot open: {e}")))?;
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .map_err(failed)?;
    let mut meta = Vec::new();
    for chunk in &reader.info().utf8_text {
        meta.push((chunk.keyword.clone(), chunk.get_text().map_err(failed)?));
    }
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| Error::file(path, "PNG too large"))?;
    let mut pixels = vec![0; size];
    reader.next_frame(&mut pixels).map_err(failed)?;
    reader.finish().map_err(failed)?;
    Ok(meta)
}

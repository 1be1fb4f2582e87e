//! TIFF outputs: 8 or 16 bits a channel of sRGB under the view, the metadata as one JSON
//! object (ASCII, other characters escaped) in the ImageDescription tag.

use std::io::{Seek, Write};
use std::path::Path;

use tiff::encoder::{colortype, TiffEncoder};
use tiff::tags::Tag;

use super::film::Film;
use crate::colour::View;
use platoon_scene::error::{Error, Result};

pub(super) fn write_tiff(
    path: &Path,
    w: &mut (impl Write + Seek),
    film: &Film,
    alpha: Option<&[f32]>,
    metadata: &[(String, String)],
    view: &View,
    bits: u8,
) -> Result<()> {
    let failed = |e: tiff::TiffError| Error::file(path, format!("cannot write TIFF: {e}"));
    let mut encoder = TiffEncoder::new(w).map_err(failed)?;
    let description = ascii_json(metadata);
    let d = &description;
    let (e, rgba) = (&mut encoder, alpha.is_some());
    let written = match (bits, rgba) {
        (16, false) => write_rgb::<_, colortype::RGB16>(e, film, d, &film.display16(alpha, view)),
        (16, true) => write_rgb::<_, colortype::RGBA16>(e, film, d, &film.display16(alpha, view)),
        (_, false) => write_rgb::<_, colortype::RGB8>(e, film, d, &film.display8(alpha, view)),
        (_, true) => write_rgb::<_, colortype::RGBA8>(e, film, d, &film.display8(alpha, view)),
    };
    written.map_err(failed)
}

/// One RGB or RGBA image of `film`'s size, its samples `data`, described by `description`.
fn write_rgb<W: Write + Seek, C: colortype::ColorType>(
    encoder: &mut TiffEncoder<W>,
    film: &Film,
    description: &str,
    data: &[C::Inner],
) -> tiff::TiffResult<()>
where
    [C::Inner]: tiff::encoder::TiffValue,
{
    let mut image = encoder.new_image::<C>(film.width, film.height)?;
    image
        .encoder()
        .write_tag(Tag::ImageDescription, description)?;
    image.write_data(data)
}

/// `metadata` as a JSON object whose keys are prefixed `platoon:`, every character outside
/// ASCII escaped (a TIFF's ASCII tags hold 7-bit text).
fn ascii_json(metadata: &[(String, String)]) -> String {
    let object: serde_json::Map<String, serde_json::Value> = metadata
        .iter()
        .map(|(k, v)| (format!("platoon:{k}"), serde_json::Value::String(v.clone())))
        .collect();
    let mut out = String::new();
    for c in serde_json::Value::Object(object).to_string().chars() {
        if c.is_ascii() {
            out.push(c);
        } else {
            let mut units = [0u16; 2];
            for u in c.encode_utf16(&mut units) {
                out.push_str(&format!("\\u{u:04x}"));
            }
        }
    }
    out
}

/// A TIFF's metadata, after decoding it whole (a truncated file is an error).
pub(super) fn read_tiff_metadata(path: &Path) -> Result<Vec<(String, String)>> {
    let failed = |e: tiff::TiffError| Error::file(path, format!("cannot read TIFF: {e}"));
    let file =
        std::fs::File::open(path).map_err(|e| Error::file(path, format!("cannot open: {e}")))?;
    let mut decoder = tiff::decoder::Decoder::new(std::io::BufReader::new(file)).map_err(failed)?;
    decoder.read_image().map_err(failed)?;
    let description = decoder
        .get_tag_ascii_string(Tag::ImageDescription)
        .unwrap_or_default();
    let object: serde_json::Map<String, serde_json::Value> =
        serde_json::from_str(&description).unwrap_or_default();
    Ok(object
        .into_iter()
        .filter_map(|(k, v)| v.as_str().map(|v| (k, v.to_string())))
        .collect())
}

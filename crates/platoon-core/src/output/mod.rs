//! Image outputs: linear float EXR with render metadata, tone-mapped sRGB PNG. Both are written
//! to a temporary file beside the target and renamed, so a failed write leaves no partial file.

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::view::View;

mod exr_options;

pub use exr_options::{ExrCompression, ExrOptions};

/// How an image is written: the view its display-referred formats (PNG) show it through, the
/// sample type and compression of an EXR.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageOptions {
    pub view: View,
    pub exr: ExrOptions,
}

/// A rendered frame: linear RGB radiance, row-major from the top row.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 3]>,
}

impl Film {
    pub fn mean(&self) -> [f64; 3] {
        let mut s = [0.0f64; 3];
        for p in &self.pixels {
            for k in 0..3 {
                s[k] += p[k] as f64;
            }
        }
        s.map(|v| v / self.pixels.len().max(1) as f64)
    }
    /// The image as 8-bit sRGB under the default view, three bytes a pixel.
    pub fn srgb8(&self) -> Vec<u8> {
        self.srgb8_viewed(&View::default())
    }

    /// The image as 8-bit sRGB under `view`, three bytes a pixel (a PNG's pixels).
    pub fn srgb8_viewed(&self, view: &View) -> Vec<u8> {
        self.pixels.iter().flat_map(|&p| view.srgb8(p)).collect()
    }

    pub fn count_non_finite(&self) -> usize {
        self.pixels
            .iter()
            .filter(|p| p.iter().any(|v| !v.is_finite()))
            .count()
    }
}

fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<&mut std::fs::File>) -> Result<()>,
) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut tmp = tempfile::Builder::new()
        .prefix(".platoon-")
        .suffix(".part")
        .tempfile_in(dir)
        .map_err(|e| Error::file(path, format!("cannot create output: {e}")))?;
    {
        let mut w = BufWriter::new(tmp.as_file_mut());
        write(&mut w)?;
        w.flush()
            .map_err(|e| Error::file(path, format!("cannot write output: {e}")))?;
    }
    // Temporary files are created private (0600); an image is an ordinary file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o644));
    }
    tmp.persist(path)
        .map_err(|e| Error::file(path, format!("cannot write output: {}", e.error)))?;
    Ok(())
}

/// Writes a text file (CSV, JSON) through a temporary file and a rename.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, |w| {
        w.write_all(text.as_bytes())
            .map_err(|e| Error::file(path, format!("cannot write: {e}")))
    })
}

/// A layer of an output image: named channels, each a plane of `width * height` values.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    pub name: String,
    pub channels: Vec<(String, Vec<f32>)>,
}

impl Layer {
    /// The channel `name` of the layer.
    pub fn channel(&self, name: &str) -> Option<&[f32]> {
        self.channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }
}

/// Writes `film` as EXR or PNG according to the extension, with `metadata` (key, value) pairs
/// stored as EXR string attributes or PNG iTXt chunks, each key prefixed `platoon:`.
pub fn write_image(path: &Path, film: &Film, metadata: &[(String, String)]) -> Result<()> {
    write_image_with_layers(path, film, &[], metadata)
}

/// The same with `layers` beside the beauty (EXR only: channels `layer.channel`, as Cycles'
/// multilayer files name them).
pub fn write_image_with_layers(
    path: &Path,
    film: &Film,
    layers: &[Layer],
    metadata: &[(String, String)],
) -> Result<()> {
    write_image_as(path, film, layers, metadata, &ImageOptions::default())
}

/// The same, written as `options` say: a PNG's pixels under their view (an EXR stays
/// scene-linear whatever the view), an EXR's samples and compression.
pub fn write_image_as(
    path: &Path,
    film: &Film,
    layers: &[Layer],
    metadata: &[(String, String)],
    options: &ImageOptions,
) -> Result<()> {
    let exr = &options.exr;
    match image_format(path)? {
        ImageFormat::Exr => {
            exr.check().map_err(|e| Error::file(path, e))?;
            write_atomically(path, |w| write_exr(path, w, film, layers, metadata, exr))
        }
        ImageFormat::Png if layers.is_empty() => {
            write_atomically(path, |w| write_png(path, w, film, metadata, &options.view))
        }
        ImageFormat::Png => Err(Error::file(
            path,
            "AOVs are written as layers of an EXR: the output must end in .exr",
        )),
    }
}

pub enum ImageFormat {
    Exr,
    Png,
}

/// The format an image path names by its extension, in a folder that exists: what writing and
/// reading an image need.
pub fn image_format(path: &Path) -> Result<ImageFormat> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let format = match ext.as_str() {
        "exr" => ImageFormat::Exr,
        "png" => ImageFormat::Png,
        _ => return Err(Error::file(path, "output must end in .exr or .png")),
    };
    let dir = output_folder(path);
    if !dir.is_dir() {
        return Err(Error::file(
            path,
            format!("output folder {} does not exist", dir.display()),
        ));
    }
    Ok(format)
}

/// The folder an image path writes into.
fn output_folder(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// The format of an output path, or why it cannot be written: checked before a render starts,
/// so that a long render is not lost to a typo or a folder it may not write into.
pub fn check_image_path(path: &Path) -> Result<ImageFormat> {
    let format = image_format(path)?;
    // The image is written through a temporary file in its folder: try one now.
    let dir = output_folder(path);
    if let Err(e) = tempfile::Builder::new()
        .prefix(".platoon-")
        .tempfile_in(dir)
    {
        return Err(Error::file(
            path,
            format!("cannot write into {}: {e}", dir.display()),
        ));
    }
    Ok(format)
}

/// `metadata` as EXR string attributes, each key prefixed `platoon:`.
fn insert_metadata(
    attributes: &mut std::collections::HashMap<exr::prelude::Text, exr::prelude::AttributeValue>,
    metadata: &[(String, String)],
) {
    use exr::prelude::*;
    for (k, v) in metadata {
        attributes.insert(
            Text::from(format!("platoon:{k}").as_str()),
            AttributeValue::Text(Text::from(v.as_str())),
        );
    }
}

/// The beauty's R, G, B and `layers`' channels (`layer.channel`, as Cycles' multilayer files
/// name them) as one EXR layer, in the sample type and compression of `exr`.
fn write_exr(
    path: &Path,
    w: &mut (impl Write + std::io::Seek),
    film: &Film,
    layers: &[Layer],
    metadata: &[(String, String)],
    exr: &ExrOptions,
) -> Result<()> {
    use exr::prelude::*;
    let samples = |plane: Vec<f32>| {
        if exr.half {
            FlatSamples::F16(plane.into_iter().map(f16::from_f32).collect())
        } else {
            FlatSamples::F32(plane)
        }
    };
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
        let plane = film.pixels.iter().map(|p| p[c]).collect();
        channels.push(AnyChannel::new(name, samples(plane)));
    }
    for layer in layers {
        for (name, plane) in &layer.channels {
            if plane.len() != film.pixels.len() {
                return Err(crate::Error::file(
                    path,
                    format!("layer {} has the wrong size", layer.name),
                ));
            }
            let full = format!("{}.{name}", layer.name);
            channels.push(AnyChannel::new(full.as_str(), samples(plane.clone())));
        }
    }
    let size = (film.width as usize, film.height as usize);
    let layer = exr::image::Layer::new(
        size,
        LayerAttributes::default(),
        exr.encoding(),
        AnyChannels::sort(channels),
    );
    let mut image = Image::from_layer(layer);
    insert_metadata(&mut image.attributes.other, metadata);
    image
        .write()
        .to_buffered(w)
        .map_err(|e| crate::Error::file(path, format!("cannot write EXR: {e}")))
}

/// Every channel of an EXR's first layer by name (`R`, `albedo.R`, ...): tests and tools.
pub fn read_exr_channels(path: &Path) -> Result<Vec<(String, Vec<f32>)>> {
    use exr::prelude::*;
    let image = read_all_flat_layers_from_file(path)
        .map_err(|e| crate::Error::file(path, format!("cannot read EXR: {e}")))?;
    let layer = image
        .layer_data
        .first()
        .ok_or_else(|| crate::Error::file(path, "the EXR has no layer"))?;
    Ok(layer
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
        .collect())
}

fn write_png(
    path: &Path,
    w: &mut (impl Write + std::io::Seek),
    film: &Film,
    metadata: &[(String, String)],
    view: &View,
) -> Result<()> {
    let failed = |e: png::EncodingError| Error::file(path, format!("cannot write PNG: {e}"));
    let mut encoder = png::Encoder::new(w, film.width, film.height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    for (k, v) in metadata {
        encoder
            .add_itxt_chunk(format!("platoon:{k}"), v.clone())
            .map_err(failed)?;
    }
    let mut writer = encoder.write_header().map_err(failed)?;
    writer
        .write_image_data(&film.srgb8_viewed(view))
        .map_err(failed)?;
    writer.finish().map_err(failed)
}

/// The `platoon:` metadata of an image written by [`write_image`], read through to its last
/// pixel, so that a truncated or damaged file is an error (a render farm's resume redoes it).
pub fn read_metadata(path: &Path) -> Result<Vec<(String, String)>> {
    match image_format(path)? {
        ImageFormat::Exr => Ok(read_exr(path)?.1),
        ImageFormat::Png => {
            let failed = |e: png::DecodingError| Error::file(path, format!("cannot read PNG: {e}"));
            let file = std::fs::File::open(path)
                .map_err(|e| Error::file(path, format!("cannot open: {e}")))?;
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
            meta.sort();
            Ok(meta)
        }
    }
}

/// Reads an EXR written by [`write_image`] back (tests and tools).
pub fn read_exr(path: &Path) -> Result<(Film, Vec<(String, String)>)> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |res, _| (res.width(), vec![[0.0f32; 3]; res.width() * res.height()]),
        |(w, px), pos, (r, g, b, _a): (f32, f32, f32, f32)| px[pos.y() * *w + pos.x()] = [r, g, b],
    )
    .map_err(|e| crate::Error::file(path, format!("cannot read EXR: {e}")))?;
    let size = image.layer_data.size;
    // Custom attributes of a single-part file may come back as image or as layer attributes.
    let mut meta: Vec<(String, String)> = image
        .attributes
        .other
        .iter()
        .chain(image.layer_data.attributes.other.iter())
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(t) => Some((k.to_string(), t.to_string())),
            _ => None,
        })
        .collect();
    meta.sort();
    Ok((
        Film {
            width: size.width() as u32,
            height: size.height() as u32,
            pixels: image.layer_data.channel_data.pixels.1,
        },
        meta,
    ))
}

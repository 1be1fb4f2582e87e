//! EXR outputs: scene-linear RGB and AOV layers as one part, floats or half floats in a
//! compression, the metadata as string attributes; and reading them back (tests and tools).

use std::io::Write;
use std::path::Path;

use super::exr_options::ExrOptions;
use super::film::{Film, Layer};
use platoon_scene::error::Result;

/// `s` as an EXR text: its UTF-8 bytes (what OpenEXR and Blender write; the `exr` crate's
/// `Text::from` panics past Latin-1, a scene's path or an object's name can be anything).
fn text(s: &str) -> exr::prelude::Text {
    exr::prelude::Text::from_slice_unchecked(s.as_bytes())
}

/// An EXR text read back as UTF-8 (lossy where it is not).
fn string(t: &exr::prelude::Text) -> String {
    String::from_utf8_lossy(t.bytes()).into_owned()
}

/// `metadata` as EXR string attributes, each key prefixed `platoon:`.
fn insert_metadata(
    attributes: &mut std::collections::HashMap<exr::prelude::Text, exr::prelude::AttributeValue>,
    metadata: &[(String, String)],
) {
    use exr::prelude::*;
    for (k, v) in metadata {
        attributes.insert(text(&format!("platoon:{k}")), AttributeValue::Text(text(v)));
    }
}

/// The beauty's R, G, B (and A, given `alpha`) and `layers`' channels (`layer.channel`, as Cycles' multilayer files
/// name them) as one EXR layer, in the sample type and compression of `exr`.
pub(super) fn write_exr(
    path: &Path,
    w: &mut (impl Write + std::io::Seek),
    film: &Film,
    alpha: Option<&[f32]>,
    layers: &[Layer],
    metadata: &[(String, String)],
    exr: &ExrOptions,
) -> Result<()> {
    use exr::prelude::*;
    let samples = |plane: Vec<f32>, full_float: bool| {
        if exr.half && !full_float {
            FlatSamples::F16(plane.into_iter().map(f16::from_f32).collect())
        } else {
            FlatSamples::F32(plane)
        }
    };
    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
        let plane = film.pixels.iter().map(|p| p[c]).collect();
        channels.push(AnyChannel::new(name, samples(plane, false)));
    }
    if let Some(a) = alpha {
        channels.push(AnyChannel::new("A", samples(a.to_vec(), false)));
    }
    for layer in layers {
        for (name, plane) in &layer.channels {
            if plane.len() != film.pixels.len() {
                return Err(platoon_scene::Error::file(
                    path,
                    format!("layer {} has the wrong size", layer.name),
                ));
            }
            let full = format!("{}.{name}", layer.name);
            channels.push(AnyChannel::new(
                full.as_str(),
                samples(plane.clone(), layer.full_float),
            ));
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
    for (k, v) in layers.iter().flat_map(|l| &l.attributes) {
        image
            .attributes
            .other
            .insert(text(k), AttributeValue::Text(text(v)));
    }
    image
        .write()
        .to_buffered(w)
        .map_err(|e| platoon_scene::Error::file(path, format!("cannot write EXR: {e}")))
}

/// Every channel of an EXR's first layer by name (`R`, `albedo.R`, ...): tests and tools.
pub fn read_exr_channels(path: &Path) -> Result<Vec<(String, Vec<f32>)>> {
    use exr::prelude::*;
    let image = read_all_flat_layers_from_file(path)
        .map_err(|e| platoon_scene::Error::file(path, format!("cannot read EXR: {e}")))?;
    let layer = image
        .layer_data
        .first()
        .ok_or_else(|| platoon_scene::Error::file(path, "the EXR has no layer"))?;
    Ok(layer
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
        .collect())
}

/// Reads an EXR written by [`write_image`] back (tests and tools).
pub fn read_exr(path: &Path) -> Result<(Film, Vec<(String, String)>)> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |res, _| (res.width(), vec![[0.0f32; 3]; res.width() * res.height()]),
        |(w, px), pos, (r, g, b, _a): (f32, f32, f32, f32)| px[pos.y() * *w + pos.x()] = [r, g, b],
    )
    .map_err(|e| platoon_scene::Error::file(path, format!("cannot read EXR: {e}")))?;
    let size = image.layer_data.size;
    // Custom attributes of a single-part file may come back as image or as layer attributes.
    let mut meta: Vec<(String, String)> = image
        .attributes
        .other
        .iter()
        .chain(image.layer_data.attributes.other.iter())
        .filter_map(|(k, v)| match v {
            AttributeValue::Text(t) => Some((string(k), string(t))),
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

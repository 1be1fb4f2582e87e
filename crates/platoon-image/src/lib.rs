//! platoon-image: films and image outputs: scene-linear EXR (`exr`), and sRGB under a view
//! transform ([`colour`]) as PNG, JPEG or TIFF (`png`, `jpeg`, `tiff`), each with the render's
//! metadata. All are written to a temporary file beside the target and renamed, so a failed
//! write leaves no partial file. platoon-core re-exports it as `platoon_core::output` (and the
//! colour module as `platoon_core::colour`).

use std::io::{BufWriter, Write};
use std::path::Path;

use crate::colour::View;
use platoon_scene::error::{Error, Result};

pub mod colour;
mod display;
mod exr;
mod exr_options;
mod film;
mod format;
mod jpeg;
mod png;
mod tiff;

pub use display::DisplayOptions;
pub use exr::{read_exr, read_exr_channels};
pub use exr_options::{ExrCompression, ExrOptions};
pub use film::{Film, Layer};
pub use format::ImageFormat;

/// How an image is written: the view its display-referred formats (PNG, JPEG, TIFF) show it
/// through and their bits, the sample type and compression of an EXR.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImageOptions {
    pub view: View,
    pub exr: ExrOptions,
    pub display: DisplayOptions,
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

/// Writes a file of `bytes` through a temporary file and a rename.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomically(path, |w| {
        w.write_all(bytes)
            .map_err(|e| Error::file(path, format!("cannot write: {e}")))
    })
}

/// Writes a text file (CSV, JSON) through a temporary file and a rename.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, |w| {
        w.write_all(text.as_bytes())
            .map_err(|e| Error::file(path, format!("cannot write: {e}")))
    })
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
    write_rgba_as(path, film, None, layers, metadata, options)
}

/// The same with an alpha channel when `alpha` is given (a transparent film's, the colour
/// premultiplied by it): an EXR's `A` (premultiplied, as OpenEXR's convention is), a PNG's or
/// a TIFF's fourth channel (straight: the colour is divided by it before the view). JPEG has
/// none: refused.
pub fn write_rgba_as(
    path: &Path,
    film: &Film,
    alpha: Option<&[f32]>,
    layers: &[Layer],
    metadata: &[(String, String)],
    options: &ImageOptions,
) -> Result<()> {
    let (exr, display, view) = (&options.exr, &options.display, &options.view);
    let format = image_format(path)?;
    display.check(&format).map_err(|e| Error::file(path, e))?;
    if alpha.is_some() && matches!(format, ImageFormat::Jpeg) {
        return Err(Error::file(
            path,
            "a JPEG has no alpha channel for a transparent film: write PNG, TIFF or EXR",
        ));
    }
    if !layers.is_empty() && !matches!(format, ImageFormat::Exr) {
        return Err(Error::file(
            path,
            "AOVs are written as layers of an EXR: the output must end in .exr",
        ));
    }
    match format {
        ImageFormat::Exr => {
            exr.check().map_err(|e| Error::file(path, e))?;
            write_atomically(path, |w| {
                exr::write_exr(path, w, film, alpha, layers, metadata, exr)
            })
        }
        ImageFormat::Png => write_atomically(path, |w| {
            png::write_png(path, w, film, alpha, metadata, view, display.bits)
        }),
        ImageFormat::Jpeg => write_atomically(path, |w| {
            jpeg::write_jpeg(path, w, film, metadata, view, display.jpeg_quality)
        }),
        ImageFormat::Tiff => write_atomically(path, |w| {
            tiff::write_tiff(path, w, film, alpha, metadata, view, display.bits)
        }),
    }
}

/// The format an image path names by its extension, in a folder that exists: what writing and
/// reading an image need.
pub fn image_format(path: &Path) -> Result<ImageFormat> {
    let format = ImageFormat::of(path)?;
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

/// The `platoon:` metadata of an image written by [`write_image`], read through to its last
/// pixel, so that a truncated or damaged file is an error (a render farm's resume redoes it).
pub fn read_metadata(path: &Path) -> Result<Vec<(String, String)>> {
    let mut meta = match image_format(path)? {
        ImageFormat::Exr => read_exr(path)?.1,
        ImageFormat::Png => png::read_png_metadata(path)?,
        ImageFormat::Jpeg => jpeg::read_jpeg_metadata(path)?,
        ImageFormat::Tiff => tiff::read_tiff_metadata(path)?,
    };
    meta.sort();
    Ok(meta)
}

#[cfg(test)]
mod tests;

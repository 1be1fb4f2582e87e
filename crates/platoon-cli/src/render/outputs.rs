//! What a rendered frame writes: the image (denoised when asked, the raw one kept beside it as
//! `NAME.noisy.EXT`), with the AOV layers asked for (`platoon::Still`).

use std::path::{Path, PathBuf};

use anyhow::Result;
use platoon::core::output::{write_rgba_as, ImageFormat, ImageOptions};
use platoon::Still;

/// Writes `still`'s image to `path` (and the raw one beside it), each with its metadata and a
/// transparent film's alpha, atomically; a PNG's pixels under `view`.
pub fn write(still: &Still, path: &Path, options: &ImageOptions) -> Result<()> {
    let alpha = still.alpha.as_deref();
    if let Some(raw) = &still.raw {
        let (meta, layers) = (&still.raw_metadata, &still.layers);
        write_rgba_as(&noisy_path(path), raw, alpha, layers, meta, options)?;
    }
    let (meta, layers) = (&still.metadata, &still.layers);
    write_rgba_as(path, &still.image, alpha, layers, meta, options)?;
    Ok(())
}

/// The metadata entries saying how an image is shown (an EXR's too: what its PNG would be)
/// and, for an EXR at `path`, how it is encoded.
pub fn entries(options: &ImageOptions, path: &Path) -> Vec<(String, String)> {
    let mut out = vec![("view".into(), options.view.describe())];
    match ImageFormat::of(path) {
        Ok(ImageFormat::Exr) => out.push(("exr".into(), options.exr.describe())),
        Ok(format) => out.push(("encoding".into(), options.display.describe(&format))),
        Err(_) => {}
    }
    out
}

/// Where the raw image of a denoised `path` goes: `NAME.noisy.EXT`.
pub fn noisy_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    let ext = path.extension().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}.noisy.{ext}"))
}

//! What a rendered frame writes: the image (denoised when asked, the raw one kept beside it as
//! `NAME.noisy.EXT`), with the AOV layers asked for (`platoon::Still`).

use std::path::{Path, PathBuf};

use anyhow::Result;
use platoon::core::output::write_image_with_layers;
use platoon::Still;

/// Writes `still`'s image to `path` (and the raw one beside it), each with its metadata,
/// atomically.
pub fn write(still: &Still, path: &Path) -> Result<()> {
    if let Some(raw) = &still.raw {
        write_image_with_layers(&noisy_path(path), raw, &still.layers, &still.raw_metadata)?;
    }
    write_image_with_layers(path, &still.image, &still.layers, &still.metadata)?;
    Ok(())
}

/// Where the raw image of a denoised `path` goes: `NAME.noisy.EXT`.
pub fn noisy_path(path: &Path) -> PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    let ext = path.extension().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}.noisy.{ext}"))
}

//! The image formats, by the extension of an output's path.

use std::path::Path;

use platoon_scene::error::{Error, Result};

/// What an image path's extension names.
pub enum ImageFormat {
    /// Scene-linear floats.
    Exr,
    /// sRGB under the view, 8 or 16 bits.
    Png,
    /// sRGB under the view, 8 bits, lossy.
    Jpeg,
    /// sRGB under the view, 8 or 16 bits.
    Tiff,
}

impl ImageFormat {
    /// The format `path`'s extension names.
    pub fn of(path: &Path) -> Result<ImageFormat> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        Ok(match ext.as_str() {
            "exr" => ImageFormat::Exr,
            "png" => ImageFormat::Png,
            "jpg" | "jpeg" => ImageFormat::Jpeg,
            "tif" | "tiff" => ImageFormat::Tiff,
            _ => {
                return Err(Error::file(
                    path,
                    "output must end in .exr, .png, .jpg or .tif",
                ))
            }
        })
    }
}

//! How an image is shown: the view transform and exposure of a PNG, JPEG or TIFF, a video's
//! frames and the viewer's window (`platoon::core::colour`), their bits; an EXR's samples and
//! compression (EXR output stays scene-linear).

use anyhow::{bail, Result};
use platoon::core::colour::{View, ViewTransform};
use platoon::core::output::{DisplayOptions, ExrCompression, ExrOptions, ImageOptions};

#[derive(clap::Args)]
pub struct DisplayArgs {
    /// How radiance becomes the sRGB of a PNG, JPEG or TIFF, a video's frames and the viewer: standard
    /// (clipped), agx (Blender's default), pbr-neutral (Khronos PBR Neutral) or aces. An EXR
    /// stays scene-linear.
    #[arg(long, default_value = "aces", value_parser = ViewTransform::parse)]
    pub view_transform: ViewTransform,
    /// Exposure in stops, applied before the view transform (EXR untouched).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub exposure: f32,
    /// EXR samples as half floats (16 bits), not floats.
    #[arg(long)]
    pub exr_half: bool,
    /// EXR compression: none, rle (the default), zips, zip, piz, pxr24 (lossy for floats), b44
    /// (lossy, half only).
    #[arg(long, default_value = "rle", value_parser = ExrCompression::parse)]
    pub exr_compression: ExrCompression,
    /// Bits a channel of a PNG or TIFF: 8 or 16.
    #[arg(long, default_value_t = 8)]
    pub bit_depth: u8,
    /// A JPEG's quality, 1 (smallest) to 100 (best).
    #[arg(long, default_value_t = 90)]
    pub jpeg_quality: u8,
}

impl DisplayArgs {
    /// The EXR's sample type and compression, checked.
    pub fn exr(&self) -> Result<ExrOptions> {
        let exr = ExrOptions {
            half: self.exr_half,
            compression: self.exr_compression,
        };
        exr.check()
            .map_err(|e| anyhow::anyhow!("--exr-compression: {e} (add --exr-half)"))?;
        Ok(exr)
    }

    /// How an image is written, checked for the format of `out`.
    pub fn image(&self, out: &std::path::Path) -> Result<ImageOptions> {
        let display = DisplayOptions {
            bits: self.bit_depth,
            jpeg_quality: self.jpeg_quality,
        };
        let format = platoon::core::output::ImageFormat::of(out)?;
        let refused = |flag: &str, e: String| anyhow::anyhow!("{}: {flag}: {e}", out.display());
        display
            .check_quality()
            .map_err(|e| refused("--jpeg-quality", e))?;
        display
            .check_bits(&format)
            .map_err(|e| refused("--bit-depth", e))?;
        Ok(ImageOptions {
            view: self.view()?,
            exr: self.exr()?,
            display,
        })
    }

    pub fn view(&self) -> Result<View> {
        if !(self.exposure.is_finite() && self.exposure.abs() <= 64.0) {
            bail!(
                "--exposure: a number of stops within -64..64, not {}",
                self.exposure
            );
        }
        Ok(View {
            transform: self.view_transform,
            exposure: self.exposure,
        })
    }
}

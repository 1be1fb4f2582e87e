//! How an image is shown: the view transform and exposure of a PNG, a video's frames and the
//! viewer's window (`platoon::core::view`). EXR output stays scene-linear.

use anyhow::{bail, Result};
use platoon::core::output::{ExrCompression, ExrOptions};
use platoon::core::view::{View, ViewTransform};

#[derive(clap::Args)]
pub struct DisplayArgs {
    /// How radiance becomes the sRGB of a PNG, a video's frames and the viewer: standard
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

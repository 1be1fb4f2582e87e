//! How a display-referred file (PNG, JPEG, TIFF) holds its pixels: bits a channel, JPEG's
//! quality. Its pixels are the view's (`crate::colour::View`) sRGB encoding.

/// Bits a channel and JPEG quality.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplayOptions {
    /// 8 or 16 (PNG and TIFF; JPEG is 8).
    pub bits: u8,
    /// 1 (smallest) to 100 (best).
    pub jpeg_quality: u8,
}

impl Default for DisplayOptions {
    fn default() -> Self {
        DisplayOptions {
            bits: 8,
            jpeg_quality: 90,
        }
    }
}

impl DisplayOptions {
    /// What the image metadata says of a file of `format` so written.
    pub fn describe(&self, format: &super::format::ImageFormat) -> String {
        match format {
            super::format::ImageFormat::Jpeg => format!("8 bits, quality {}", self.jpeg_quality),
            _ => format!("{} bits", self.bits),
        }
    }

    /// What is wrong with these options for `format`, if anything.
    pub fn check(&self, format: &super::format::ImageFormat) -> Result<(), String> {
        self.check_quality()?;
        self.check_bits(format)
    }

    /// What is wrong with the JPEG quality, if anything.
    pub fn check_quality(&self) -> Result<(), String> {
        match self.jpeg_quality {
            1..=100 => Ok(()),
            q => Err(format!("JPEG quality runs from 1 to 100, not {q}")),
        }
    }

    /// What is wrong with the bits for `format`, if anything.
    pub fn check_bits(&self, format: &super::format::ImageFormat) -> Result<(), String> {
        use super::format::ImageFormat::*;
        match (self.bits, format) {
            (8, _) => Ok(()),
            (16, Png | Tiff) => Ok(()),
            (16, Jpeg) => Err("a JPEG holds 8 bits a channel: use PNG or TIFF for 16".into()),
            (16, Exr) => Err("an EXR holds floats: --exr-half makes them 16 bits".into()),
            (b, _) => Err(format!("8 or 16 bits a channel, not {b}")),
        }
    }
}

//! KTX2 images (KHR_texture_basisu): Basis Universal's ETC1S or UASTC, Zstandard-supercompressed
//! or not, transcoded to RGBA8 like every other image. The kernel reads one texel array of
//! RGBA8 (textures.glsl), so a block format the device samples would have no reader there.

use super::validate::Check;

/// The 12 bytes every KTX2 file starts with.
const MAGIC: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// Whether `bytes` are a KTX2 file.
pub fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC)
}

/// Image `index`, a KTX2 file, as width, height and RGBA8 texels: its first level (the levels
/// below are made again from it when textures are mip-mapped: texture_levels), first layer and
/// first face.
pub fn decode(bytes: &[u8], index: usize) -> Check<(u32, u32, Vec<u8>)> {
    // The transcoder is young (basisu 0.1): a panic on a hostile file becomes this image's
    // error, as a failure of the image crate's decoders is.
    std::panic::catch_unwind(|| transcode(bytes, index)).unwrap_or_else(|_| {
        Err(format!(
            "cannot decode KTX2 image {index}: the transcoder failed on its data"
        ))
    })
}

fn transcode(bytes: &[u8], index: usize) -> Check<(u32, u32, Vec<u8>)> {
    let bad = |e: basisu::Error| format!("cannot decode KTX2 image {index}: {e:?}");
    let file = basisu::Transcoder::new(bytes).map_err(|e| match e {
        basisu::Error::InvalidData => format!(
            "KTX2 image {index} is no Basis Universal texture KHR_texture_basisu can show (an \
             ETC1S or UASTC payload), or it is corrupt"
        ),
        e => bad(e),
    })?;
    let (width, height) = file.base_dimensions();
    if width == 0 || height == 0 {
        return Err(format!("KTX2 image {index} is empty"));
    }
    let pixels = file
        .transcode(0, basisu::TargetFormat::Rgba32, basisu::DecodeFlags::NONE)
        .map_err(bad)?;
    if pixels.len() != 4 * width as usize * height as usize {
        return Err(format!(
            "KTX2 image {index}: {} bytes transcoded for {width} x {height} texels",
            pixels.len()
        ));
    }
    Ok((width, height, pixels))
}

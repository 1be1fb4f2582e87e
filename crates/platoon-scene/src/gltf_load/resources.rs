//! The files a glTF refers to: buffers and images, read by platoon rather than by the `gltf`
//! crate so that every URI passes one policy. URIs are relative to the asset, as glTF viewers
//! treat them: one that is absolute or resolves outside the scene's folder (after
//! canonicalisation, so `..`, percent-encoded `..` and symlinks count) is refused unless the
//! user allows external files.

use std::path::{Path, PathBuf};

use base64::Engine as _;
use percent_encoding::percent_decode_str;
use rayon::prelude::*;

use super::validate::Check;
use super::LoadOptions;
use crate::input::read_regular_file;

/// Where a scene's relative URIs resolve, and whether they may leave its folder.
pub struct UriPolicy<'a> {
    pub base: &'a Path,
    pub options: &'a LoadOptions,
}

impl UriPolicy<'_> {
    /// The bytes behind `uri` (at most `limit` of them from a file: a buffer needs no more
    /// than it declares): a base64 data URI, or a file inside the scene's folder.
    pub fn read(&self, uri: &str, what: &str, limit: Option<u64>) -> Check<Vec<u8>> {
        if let Some(data) = uri.strip_prefix("data:") {
            return decode_data_uri(data).map_err(|e| format!("{what} data URI: {e}"));
        }
        let file = self.resolve(uri, what)?;
        read_regular_file(&file, limit)
            .map_err(|e| format!("cannot read {what} file {}: {e}", file.display()))
    }

    fn resolve(&self, uri: &str, what: &str) -> Check<PathBuf> {
        let relative = match uri.split_once(':') {
            // `file:` URIs name absolute paths; any other scheme (http:, ...) is not a file.
            Some((scheme, rest)) if scheme.len() > 1 && is_scheme(scheme) => {
                if !scheme.eq_ignore_ascii_case("file") {
                    return Err(format!(
                        "{what} URI '{uri}' uses the unsupported scheme {scheme}:"
                    ));
                }
                rest.trim_start_matches("//")
            }
            _ => uri,
        };
        let decoded = percent_decode_str(relative)
            .decode_utf8()
            .map_err(|_| format!("{what} URI '{uri}' is not UTF-8 once percent-decoded"))?;
        if decoded.contains('\0') {
            return Err(format!("{what} URI '{uri}' contains a NUL character"));
        }
        // Refuse what leaves the folder by its text before touching the file system, so that
        // error messages do not tell which files exist outside it; symlinks are caught below.
        if !self.options.allow_external_files && !stays_inside(Path::new(&*decoded)) {
            return Err(self.outside(uri, what, &self.base.join(&*decoded)));
        }
        let file = self.base.join(&*decoded);
        let canonical = file
            .canonicalize()
            .map_err(|_| format!("missing {what} file {}", file.display()))?;
        if !canonical.is_file() {
            return Err(format!("{what} URI '{uri}' is not a file"));
        }
        if !self.options.allow_external_files {
            let folder = self
                .base
                .canonicalize()
                .map_err(|e| format!("cannot resolve the scene's folder: {e}"))?;
            if !canonical.starts_with(&folder) {
                return Err(self.outside(uri, what, &canonical));
            }
        }
        Ok(canonical)
    }

    fn outside(&self, uri: &str, what: &str, path: &Path) -> String {
        format!(
            "{what} URI '{uri}' resolves to {}, outside the scene's folder {} \
             (pass --allow-external-files to read it)",
            path.display(),
            self.base.display()
        )
    }
}

/// Whether a relative path stays inside its folder by its components alone (no root, never
/// more `..` than names before them).
fn stays_inside(path: &Path) -> bool {
    use std::path::Component;
    let mut depth = 0usize;
    for c in path.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth > 0 => depth -= 1,
            _ => return false,
        }
    }
    true
}

fn is_scheme(s: &str) -> bool {
    s.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))
}

/// `[<mediatype>][;base64],<data>`: glTF embeds binary data as base64 only.
fn decode_data_uri(data: &str) -> Check<Vec<u8>> {
    let (header, payload) = data
        .split_once(',')
        .ok_or_else(|| "no ',' before the data".to_string())?;
    if !header.ends_with(";base64") {
        return Err("not base64-encoded".into());
    }
    base64::engine::general_purpose::STANDARD
        .decode(payload)
        .map_err(|e| format!("invalid base64: {e}"))
}

/// Every buffer's bytes, at least as many as it declares.
pub fn buffers(
    doc: &gltf::Document,
    blob: Option<Vec<u8>>,
    policy: &UriPolicy,
) -> Check<Vec<Vec<u8>>> {
    let mut blob = blob;
    let mut out = Vec::new();
    for buffer in doc.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| {
                format!(
                    "buffer {} refers to a missing GLB BIN chunk",
                    buffer.index()
                )
            })?,
            gltf::buffer::Source::Uri(uri) => {
                policy.read(uri, "buffer", Some(buffer.length() as u64))?
            }
        };
        if data.len() < buffer.length() {
            return Err(format!(
                "buffer {} holds {} bytes but declares {}",
                buffer.index(),
                data.len(),
                buffer.length()
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// A decoded image as 8-bit RGBA.
pub struct Rgba8 {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

/// Every image decoded to RGBA8 (PNG, JPEG or WebP, the image crate's default limits bounding
/// the memory a hostile header can ask for; KTX2 through Basis Universal's transcoder), on
/// every core.
pub fn images(doc: &gltf::Document, buffers: &[Vec<u8>], policy: &UriPolicy) -> Check<Vec<Rgba8>> {
    let mut read = Vec::new();
    for image in doc.images() {
        read.push(match image.source() {
            gltf::image::Source::View { view, .. } => {
                // In range: validate::buffer_views ran first.
                let bytes = &buffers[view.buffer().index()];
                std::borrow::Cow::Borrowed(&bytes[view.offset()..view.offset() + view.length()])
            }
            gltf::image::Source::Uri { uri, .. } => {
                std::borrow::Cow::Owned(policy.read(uri, "texture", None)?)
            }
        });
    }
    let decoded: Vec<Check<Rgba8>> = read
        .par_iter()
        .enumerate()
        .map(|(index, encoded)| decode(encoded, index))
        .collect();
    // The first image's error, whichever thread met it first.
    decoded.into_iter().collect()
}

/// Image `index` from its file's bytes.
fn decode(encoded: &[u8], index: usize) -> Check<Rgba8> {
    if super::ktx2::is_ktx2(encoded) {
        let (width, height, pixels) = super::ktx2::decode(encoded, index)?;
        return Ok(Rgba8 {
            width,
            height,
            pixels,
        });
    }
    let decoded = image::load_from_memory(encoded)
        .map_err(|e| format!("cannot decode image {index}: {e}"))?;
    let rgba = decoded.to_rgba8();
    if rgba.width() == 0 || rgba.height() == 0 {
        return Err(format!("image {index} is empty"));
    }
    Ok(Rgba8 {
        width: rgba.width(),
        height: rgba.height(),
        pixels: rgba.into_raw(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_that_climb_or_are_rooted_leave_the_folder() {
        for inside in ["a.bin", "./a.bin", "sub/../a.bin", "sub/deeper/../../a.bin"] {
            assert!(stays_inside(Path::new(inside)), "{inside}");
        }
        for outside in ["../a.bin", "/etc/passwd", "sub/../../a.bin", "./../a.bin"] {
            assert!(!stays_inside(Path::new(outside)), "{outside}");
        }
    }
}

//! What the `gltf` crate assumes and does not check, checked before it is relied on: a GLB
//! header that covers itself, indices that its validation code follows without a bounds check,
//! and accessors that its readers slice and decode (count, stride, byte range, component type).
//! A file that breaks any of these is refused with a message naming the offending object.

use gltf::accessor::{DataType, Dimensions};
use gltf::json;

use crate::error::Result;

/// `Err(message)` without the file name; the loader adds it.
pub type Check<T = ()> = std::result::Result<T, String>;

/// A GLB's header must cover at least itself and one chunk header and at most the bytes there
/// are (the crate subtracts its header size from the declared length without a check).
pub fn glb_header(bytes: &[u8]) -> Check {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    if bytes.len() < 20 {
        return Err(format!(
            "truncated GLB: {} bytes, less than its headers",
            bytes.len()
        ));
    }
    let declared = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize;
    if !(20..=bytes.len()).contains(&declared) {
        return Err(format!(
            "GLB header declares a length of {declared} bytes; the file has {}",
            bytes.len()
        ));
    }
    Ok(())
}

/// Indices the crate's own validation dereferences before checking them.
pub fn references(root: &json::Root) -> Check {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let targets = prim.targets.iter().flatten().flat_map(|t| {
                [&t.positions, &t.normals, &t.tangents]
                    .into_iter()
                    .flatten()
            });
            let accessors = prim
                .attributes
                .values()
                .chain(prim.indices.as_ref())
                .chain(targets)
                .map(|i| i.value());
            for a in accessors {
                if a >= root.accessors.len() {
                    return Err(format!(
                        "mesh {m} primitive {p} uses accessor {a}; the file has {}",
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Every buffer view lies inside its buffer's data.
pub fn buffer_views(doc: &gltf::Document, buffers: &[Vec<u8>]) -> Check {
    for view in doc.views() {
        let end = view.offset().checked_add(view.length());
        let have = buffers[view.buffer().index()].len();
        if end.is_none_or(|e| e > have) {
            return Err(format!(
                "buffer view {} ends past its buffer ({} + {} bytes of {have})",
                view.index(),
                view.offset(),
                view.length()
            ));
        }
        if view.stride().is_some_and(|s| s == 0) {
            return Err(format!("buffer view {} has a zero stride", view.index()));
        }
    }
    Ok(())
}

/// The component types and dimensions platoon reads an accessor as.
pub struct Expect {
    pub what: &'static str,
    pub types: &'static [DataType],
    pub dims: Dimensions,
}

pub const FLOAT: &[DataType] = &[DataType::F32];
pub const UNORM_OR_FLOAT: &[DataType] = &[DataType::F32, DataType::U8, DataType::U16];
pub const INDEX: &[DataType] = &[DataType::U8, DataType::U16, DataType::U32];
pub const JOINT: &[DataType] = &[DataType::U8, DataType::U16];
/// Floats or the signed normalized integers KHR_mesh_quantization allows for unit vectors.
pub const SNORM_OR_FLOAT: &[DataType] = &[DataType::F32, DataType::I8, DataType::I16];
pub const NORM_OR_FLOAT: &[DataType] = &[
    DataType::F32,
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
];

/// An accessor the crate's readers will decode: the expected type, at least one element, a
/// stride no smaller than an element, and every byte (dense and sparse) inside its view.
pub fn accessor(accessor: &gltf::Accessor, expect: &Expect) -> Check {
    let name = || format!("{} accessor {}", expect.what, accessor.index());
    if !expect.types.contains(&accessor.data_type()) || accessor.dimensions() != expect.dims {
        return Err(format!(
            "{} is {:?} {:?}; expected {:?} of {:?}",
            name(),
            accessor.data_type(),
            accessor.dimensions(),
            expect.dims,
            expect.types
        ));
    }
    if accessor.count() == 0 {
        return Err(format!("{} has a count of 0", name()));
    }
    let elem = accessor.size();
    match (accessor.view(), accessor.sparse()) {
        (None, None) => return Err(format!("{} has no buffer view", name())),
        (Some(view), _) => in_view(&view, accessor.offset(), accessor.count(), elem)
            .map_err(|e| format!("{}: {e}", name()))?,
        (None, Some(_)) => {}
    }
    if let Some(sparse) = accessor.sparse() {
        let n = sparse.count();
        if n == 0 || n > accessor.count() {
            return Err(format!("{} has {n} sparse entries", name()));
        }
        let indices = sparse.indices();
        in_view(
            &indices.view(),
            indices.offset(),
            n,
            indices.index_type().size(),
        )
        .map_err(|e| format!("{} sparse indices: {e}", name()))?;
        let values = sparse.values();
        in_view(&values.view(), values.offset(), n, elem)
            .map_err(|e| format!("{} sparse values: {e}", name()))?;
    }
    Ok(())
}

/// `count` elements of `elem` bytes from `offset`, at the view's stride, inside the view.
fn in_view(view: &gltf::buffer::View, offset: usize, count: usize, elem: usize) -> Check {
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "stride {stride} is smaller than an element ({elem} bytes)"
        ));
    }
    let end = stride
        .checked_mul(count - 1)
        .and_then(|b| b.checked_add(offset))
        .and_then(|b| b.checked_add(elem));
    match end {
        Some(end) if end <= view.length() => Ok(()),
        _ => Err(format!(
            "{count} elements from byte {offset} run past buffer view {} ({} bytes)",
            view.index(),
            view.length()
        )),
    }
}

/// Converts a [`Check`] into the loader's error, naming the file.
pub fn in_file<T>(path: &std::path::Path, check: Check<T>) -> Result<T> {
    check.map_err(|m| crate::error::Error::file(path, m))
}

/// glTF 2.x only: `asset.version` is "major.minor" and a 2.x reader must refuse another major
/// version, or a `minVersion` it does not know (above 2.0).
pub fn asset_version(asset: &json::Asset) -> Check {
    let major_minor = |v: &str| -> Option<(u32, u32)> {
        let (major, minor) = v.split_once('.')?;
        Some((major.parse().ok()?, minor.parse().ok()?))
    };
    match major_minor(&asset.version) {
        Some((2, _)) => {}
        Some(_) => {
            return Err(format!(
                "glTF version {} is not supported (platoon reads glTF 2.x)",
                asset.version
            ))
        }
        None => {
            return Err(format!(
                "asset.version '{}' is not MAJOR.MINOR",
                asset.version
            ))
        }
    }
    if let Some(min) = &asset.min_version {
        if major_minor(min) != Some((2, 0)) {
            return Err(format!(
                "asset.minVersion {min} is newer than glTF 2.0, which platoon reads"
            ));
        }
    }
    Ok(())
}

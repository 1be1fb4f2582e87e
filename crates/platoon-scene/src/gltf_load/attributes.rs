//! Vertex attributes decoded to f32 whatever their component type: floats, and the integers
//! KHR_mesh_quantization allows (normalized or not, as gltfpack writes them), with the view's
//! stride and sparse substitution. The `gltf` crate's readers assume floats for positions,
//! normals and tangents, so platoon reads every float attribute here.
//!
//! Only after `validate::accessor` accepted the accessor: every byte read lies inside its view.

use gltf::accessor::DataType;

use super::validate::Check;

/// Component `i` of the element at byte `at` of `bytes`, as glTF 2.0 (3.11) converts it: a
/// normalized integer to [0, 1] or [-1, 1] (signed ones clamped at -1), an unnormalized one as is.
fn component(bytes: &[u8], at: usize, ty: DataType, normalized: bool) -> f32 {
    let b = |k: usize| bytes[at + k];
    match ty {
        DataType::F32 => f32::from_le_bytes([b(0), b(1), b(2), b(3)]),
        DataType::I8 => {
            let v = b(0) as i8 as f32;
            if normalized {
                (v / 127.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U8 => {
            let v = b(0) as f32;
            if normalized {
                v / 255.0
            } else {
                v
            }
        }
        DataType::I16 => {
            let v = i16::from_le_bytes([b(0), b(1)]) as f32;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = u16::from_le_bytes([b(0), b(1)]) as f32;
            if normalized {
                v / 65535.0
            } else {
                v
            }
        }
        DataType::U32 => u32::from_le_bytes([b(0), b(1), b(2), b(3)]) as f32,
    }
}

/// `count` elements of N components from `bytes[offset..]` at `stride`.
fn elements<const N: usize>(
    bytes: &[u8],
    offset: usize,
    stride: usize,
    count: usize,
    ty: DataType,
    normalized: bool,
) -> Vec<[f32; N]> {
    let size = ty.size();
    (0..count)
        .map(|e| {
            std::array::from_fn(|i| {
                component(bytes, offset + e * stride + i * size, ty, normalized)
            })
        })
        .collect()
}

fn view_bytes<'b>(view: &gltf::buffer::View, buffers: &'b [Vec<u8>]) -> &'b [u8] {
    &buffers[view.buffer().index()][view.offset()..view.offset() + view.length()]
}

/// The accessor's elements (N components each) as f32, sparse entries substituted.
pub fn read<const N: usize>(
    accessor: &gltf::Accessor,
    buffers: &[Vec<u8>],
) -> Check<Vec<[f32; N]>> {
    let (ty, normalized) = (accessor.data_type(), accessor.normalized());
    let size = ty.size() * N;
    let mut out = match accessor.view() {
        Some(view) => elements::<N>(
            view_bytes(&view, buffers),
            accessor.offset(),
            view.stride().unwrap_or(size),
            accessor.count(),
            ty,
            normalized,
        ),
        None => vec![[0.0; N]; accessor.count()],
    };
    if let Some(sparse) = accessor.sparse() {
        let indices = sparse.indices();
        let index_bytes = view_bytes(&indices.view(), buffers);
        let index_size = indices.index_type().size();
        let values = sparse.values();
        let values = elements::<N>(
            view_bytes(&values.view(), buffers),
            values.offset(),
            size,
            sparse.count(),
            ty,
            normalized,
        );
        for (k, value) in values.into_iter().enumerate() {
            let at = indices.offset() + k * index_size;
            let b = |i: usize| index_bytes[at + i];
            let index = match index_size {
                1 => b(0) as usize,
                2 => u16::from_le_bytes([b(0), b(1)]) as usize,
                _ => u32::from_le_bytes([b(0), b(1), b(2), b(3)]) as usize,
            };
            let slot = out.get_mut(index).ok_or_else(|| {
                format!(
                    "accessor {}: sparse index {index} is past its {} elements",
                    accessor.index(),
                    accessor.count()
                )
            })?;
            *slot = value;
        }
    }
    Ok(out)
}

/// The elements of `accessor`, if there is one, each converted (to a glam vector).
pub fn read_as<const N: usize, T>(
    accessor: Option<gltf::Accessor>,
    buffers: &[Vec<u8>],
    convert: fn([f32; N]) -> T,
) -> Check<Option<Vec<T>>> {
    accessor
        .map(|a| read::<N>(&a, buffers).map(|v| v.into_iter().map(convert).collect()))
        .transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_integers_convert_as_the_spec_says() {
        assert_eq!(component(&[127], 0, DataType::I8, true), 1.0);
        assert_eq!(component(&[0x80], 0, DataType::I8, true), -1.0);
        assert_eq!(component(&[255], 0, DataType::U8, true), 1.0);
        assert_eq!(component(&[0xff, 0x7f], 0, DataType::I16, true), 1.0);
        assert_eq!(component(&[0x00, 0x80], 0, DataType::I16, true), -1.0);
        assert_eq!(component(&[0xff, 0xff], 0, DataType::U16, true), 1.0);
        assert_eq!(component(&[0xfe, 0xff], 0, DataType::I16, false), -2.0);
        assert_eq!(component(&[200], 0, DataType::U8, false), 200.0);
    }

    #[test]
    fn sparse_entries_replace_their_elements_with_or_without_a_view() {
        // Buffer: four VEC2 floats (0,1) (2,3) (4,5) (6,7), then sparse indices u8 [1, 3]
        // (padded to 4 bytes), then their values (9,9) (7,7).
        let mut bin: Vec<u8> = (0..8).flat_map(|v| (v as f32).to_le_bytes()).collect();
        bin.extend([1u8, 3, 0, 0]);
        bin.extend([9.0f32, 9.0, 7.0, 7.0].iter().flat_map(|v| v.to_le_bytes()));
        let json = r#"{"asset": {"version": "2.0"},
            "buffers": [{"byteLength": 52}],
            "bufferViews": [{"buffer": 0, "byteLength": 32}, {"buffer": 0, "byteOffset": 32, "byteLength": 4},
                            {"buffer": 0, "byteOffset": 36, "byteLength": 16}],
            "accessors": [
                {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC2",
                 "sparse": {"count": 2, "indices": {"bufferView": 1, "componentType": 5121}, "values": {"bufferView": 2}}},
                {"componentType": 5126, "count": 4, "type": "VEC2",
                 "sparse": {"count": 2, "indices": {"bufferView": 1, "componentType": 5121}, "values": {"bufferView": 2}}}]}"#;
        let gltf = gltf::Gltf::from_slice_without_validation(json.as_bytes()).unwrap();
        let accessors: Vec<_> = gltf.document.accessors().collect();
        let buffers = [bin];
        assert_eq!(
            read::<2>(&accessors[0], &buffers).unwrap(),
            [[0.0, 1.0], [9.0, 9.0], [4.0, 5.0], [7.0, 7.0]]
        );
        assert_eq!(
            read::<2>(&accessors[1], &buffers).unwrap(),
            [[0.0, 0.0], [9.0, 9.0], [0.0, 0.0], [7.0, 7.0]]
        );
    }
}

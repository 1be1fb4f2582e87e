//! Malformed and hostile files, each a small edit of one valid triangle: what crashed readers
//! (indices out of range, float indices, views past their buffer, overflowing counts, a GLB
//! length of 4, a stride smaller than an element, non-UTF-8 URIs) and what reads outside the
//! scene's folder (absolute, climbing, percent-encoded and symlinked URIs).

use base64::Engine as _;
use serde_json::{json, Value};

use super::{Case, Expect, File};
use crate::{glb, quad, to_json, NodeData, SceneData};

/// One lit quad: JSON and binary chunk. Accessors: 0 POSITION, 1 NORMAL, 2 indices.
fn base() -> (Value, Vec<u8>) {
    let scene = SceneData {
        meshes: vec![(quad(1.0, 1.0), 0)],
        materials: vec![json!({"name": "white"})],
        nodes: vec![NodeData::mesh(0, [0.0; 3], 1.0)],
        ..Default::default()
    };
    let mut bin = Vec::new();
    let json = to_json(&scene, &mut bin);
    (json, bin)
}

fn edited(name: &'static str, expect: Expect, edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> Case {
    let (mut json, mut bin) = base();
    edit(&mut json, &mut bin);
    Case::glb(name, glb(&json, &bin), expect)
}

/// A .gltf whose buffer is at `uri`, in its own folder `name/`, plus extra files.
fn external(name: &'static str, uri: &str, expect: Expect, extra: Vec<(String, File)>) -> Case {
    let (mut json, bin) = base();
    json["buffers"][0]["uri"] = json!(uri);
    let mut files = vec![(
        format!("{name}/scene.gltf"),
        File::Bytes(serde_json::to_vec(&json).unwrap()),
    )];
    files.push((format!("{name}/inside.bin"), File::Bytes(bin)));
    files.extend(extra);
    Case {
        name: name.into(),
        files,
        expect,
    }
}

pub fn malformed() -> Vec<Case> {
    use Expect::Refused;
    let (_, bin) = base();
    let outside = || vec![("outside.bin".to_string(), File::Bytes(base().1))];
    let mut cases = vec![
        edited(
            "accessor_index_out_of_range",
            Refused("accessor 99"),
            |j, _| j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99),
        ),
        edited("float_indices", Refused("index accessor"), |j, _| {
            j["accessors"][2]["componentType"] = json!(5126)
        }),
        edited("count_zero", Refused("count of 0"), |j, _| {
            j["accessors"][0]["count"] = json!(0)
        }),
        edited("count_2_pow_62", Refused("run past"), |j, _| {
            j["accessors"][0]["count"] = json!(1u64 << 62)
        }),
        edited("stride_smaller_than_element", Refused("stride"), |j, _| {
            j["bufferViews"][0]["byteStride"] = json!(4)
        }),
        edited("index_count_past_buffer", Refused("run past"), |j, _| {
            j["accessors"][2]["count"] = json!(600)
        }),
        edited(
            "index_out_of_range",
            Refused("index out of range"),
            |_, b| {
                let at = b.len() - 24; // the first index of the index buffer (6 u32s at the end)
                b[at..at + 4].copy_from_slice(&77u32.to_le_bytes());
            },
        ),
        edited(
            "view_past_buffer",
            Refused("ends past its buffer"),
            |j, _| j["bufferViews"][1]["byteLength"] = json!(1 << 20),
        ),
        edited(
            "image_view_past_buffer",
            Refused("ends past its buffer"),
            |j, b| {
                let n = j["bufferViews"].as_array().unwrap().len();
                j["bufferViews"]
                    .as_array_mut()
                    .unwrap()
                    .push(json!({"buffer": 0, "byteOffset": 8, "byteLength": b.len() * 4}));
                j["images"] = json!([{"bufferView": n, "mimeType": "image/png"}]);
                j["textures"] = json!([{"source": 0}]);
                j["materials"][0]["pbrMetallicRoughness"] =
                    json!({"baseColorTexture": {"index": 0}});
            },
        ),
        edited("infinite_emission", Refused("not finite"), |j, _| {
            j["materials"][0]["emissiveFactor"] = json!([1, 1, 1]);
            j["materials"][0]["extensions"] =
                json!({"KHR_materials_emissive_strength": {"emissiveStrength": 1e39}});
        }),
        edited("non_finite_positions", Expect::Finite, |_, b| {
            b[0..4].copy_from_slice(&f32::NAN.to_le_bytes());
            b[12..16].copy_from_slice(&f32::INFINITY.to_le_bytes());
        }),
        edited("zero_matrix", Expect::Finite, |j, _| {
            let node = &mut j["nodes"][0];
            *node = json!({"mesh": 0, "matrix": vec![0.0; 16]});
        }),
        edited("huge_scale", Expect::Finite, |j, _| {
            j["nodes"][0]["scale"] = json!([1e38, 1e38, 1e38])
        }),
        edited("bad_base64", Refused("base64"), |j, _| {
            j["buffers"][0]["uri"] = json!("data:application/octet-stream;base64,!!!")
        }),
        edited("http_uri", Refused("unsupported scheme"), |j, _| {
            j["buffers"][0]["uri"] = json!("http://example.invalid/a.bin")
        }),
        Case::glb(
            "glb_length_4",
            {
                let mut g = glb(&base().0, &bin);
                g[8..12].copy_from_slice(&4u32.to_le_bytes());
                g
            },
            Refused("GLB"),
        ),
        Case::glb(
            "glb_truncated",
            {
                let g = glb(&base().0, &bin);
                g[..g.len() / 2].to_vec()
            },
            Refused(""),
        ),
        external("uri_not_utf8", "%FF%FE.bin", Refused("not UTF-8"), vec![]),
        external(
            "uri_multibyte_after_percent",
            "%\u{e9}.bin",
            Refused("missing buffer"),
            vec![],
        ),
        external(
            "uri_absolute",
            "/etc/passwd",
            Refused("outside the scene's folder"),
            vec![],
        ),
        external(
            "uri_climbing",
            "../outside.bin",
            Refused("outside the scene's folder"),
            outside(),
        ),
        external(
            "uri_climbing_encoded",
            "%2E%2E/outside.bin",
            Refused("outside the scene's folder"),
            outside(),
        ),
        external(
            "uri_file_scheme",
            "file:///etc/passwd",
            Refused("outside the scene's folder"),
            vec![],
        ),
        external(
            "uri_symlink_out",
            "link.bin",
            Refused("outside the scene's folder"),
            vec![(
                "uri_symlink_out/link.bin".into(),
                File::Symlink("../outside.bin".into()),
            )]
            .into_iter()
            .chain(outside())
            .collect(),
        ),
        external("uri_inside", "inside.bin", Expect::Finite, vec![]),
    ];
    let data_uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bin)
    );
    cases.push(edited("data_uri_buffer", Expect::Finite, move |j, _| {
        j["buffers"][0]["uri"] = json!(data_uri)
    }));
    cases
}

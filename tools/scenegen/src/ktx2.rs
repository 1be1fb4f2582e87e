//! KTX2 textures of Basis Universal's UASTC (KHR_texture_basisu) made without its encoder:
//! every 4 x 4 block one solid colour, which UASTC codes as its mode 8 (the mode's 5-bit code,
//! then R, G, B and A in 8 bits each; the encoder's hints for faster ETC1 transcoding may stay
//! zero). Enough for a test to know each texel's colour after a real transcoder has read the
//! file: the KTX2 container, the data format descriptor and the UASTC stream are the real ones.

use serde_json::json;

use crate::{MeshData, NodeData, SceneData};

/// The 12 bytes every KTX2 file starts with.
const MAGIC: [u8; 12] = [
    0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A,
];

/// The Khronos data format descriptor's colour model for UASTC, and its sRGB transfer.
const MODEL_UASTC: u32 = 166;
const TRANSFER_SRGB: u32 = 2;

/// A KTX2 file of one level, `blocks_x` x `blocks_y` UASTC blocks of 4 x 4 texels, block
/// (x, y) of colour `colour(x, y)` (sRGB-encoded RGBA; one level, no supercompression).
pub fn uastc_solid(blocks_x: u32, blocks_y: u32, colour: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
    let mut data = Vec::with_capacity(16 * (blocks_x * blocks_y) as usize);
    for y in 0..blocks_y {
        for x in 0..blocks_x {
            data.extend(solid_block(colour(x, y)));
        }
    }
    let dfd = descriptor();
    let dfd_offset = 80 + 24; // the header, then one level's index entry
    let data_offset = (dfd_offset + dfd.len()).next_multiple_of(16);
    let mut file = Vec::with_capacity(data_offset + data.len());
    file.extend(MAGIC);
    let words = [
        0,            // vkFormat: VK_FORMAT_UNDEFINED, as Basis payloads have
        1,            // typeSize
        4 * blocks_x, // pixelWidth
        4 * blocks_y, // pixelHeight
        0,            // pixelDepth
        0,            // layerCount
        1,            // faceCount
        1,            // levelCount
        0,            // supercompressionScheme: none
        dfd_offset as u32,
        dfd.len() as u32,
        0, // kvdByteOffset
        0, // kvdByteLength
    ];
    for w in words {
        file.extend(u32::to_le_bytes(w));
    }
    file.extend(0u64.to_le_bytes()); // sgdByteOffset
    file.extend(0u64.to_le_bytes()); // sgdByteLength
    for v in [data_offset as u64, data.len() as u64, data.len() as u64] {
        file.extend(v.to_le_bytes()); // level 0: offset, length, uncompressed length
    }
    file.extend(dfd);
    file.resize(data_offset, 0);
    file.extend(data);
    file
}

/// A UASTC block of one colour (mode 8), its bits least significant first.
fn solid_block([r, g, b, a]: [u8; 4]) -> [u8; 16] {
    let bits: u128 =
        0x17 | (r as u128) << 5 | (g as u128) << 13 | (b as u128) << 21 | (a as u128) << 29;
    bits.to_le_bytes()
}

/// The data format descriptor of a UASTC RGBA texture in sRGB (one 128-bit sample).
fn descriptor() -> Vec<u8> {
    let words = [
        44,                                         // the descriptor's total size
        0,                                          // vendor 0 (Khronos), descriptor type 0
        2 | 40 << 16,                               // version 2, a block of 40 bytes
        MODEL_UASTC | 1 << 8 | TRANSFER_SRGB << 16, // model, BT.709 primaries, transfer
        3 | 3 << 8,                                 // texel blocks of 4 x 4
        16,                                         // 16 bytes a block in plane 0
        0,
        127 << 16 | 3 << 24, // sample 0: 128 bits from bit 0, channel RGBA
        0,                   // sample positions
        0,                   // sample lower
        u32::MAX,            // sample upper
    ];
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// One unlit quad facing the camera, showing a KTX2 (KHR_texture_basisu) texture of 2 x 2
/// blocks: `colours` left to right, top to bottom, each 4 x 4 texels, sRGB-encoded.
pub fn basisu_quad(colours: [[u8; 4]; 4]) -> SceneData {
    let texture = uastc_solid(2, 2, |x, y| colours[(2 * y + x) as usize]);
    let quad = MeshData {
        positions: vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 4],
        uvs: vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]],
        indices: vec![0, 1, 2, 0, 2, 3],
    };
    let mut camera = NodeData::new();
    camera.translation = [0.0, 0.0, 3.0];
    camera.camera_yfov = Some(0.6);
    SceneData {
        meshes: vec![(quad, 0)],
        materials: vec![json!({"name": "basisu", "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0}}, "extensions": {"KHR_materials_unlit": {}}})],
        nodes: vec![NodeData::mesh(0, [0.0; 3], 1.0), camera],
        lights: Vec::new(),
        extensions_used: vec!["KHR_materials_unlit".into()],
        images: vec![texture],
    }
}

/// Whether `bytes` are a KTX2 file (what the glTF writer shows through KHR_texture_basisu).
pub fn is_ktx2(bytes: &[u8]) -> bool {
    bytes.starts_with(&MAGIC)
}

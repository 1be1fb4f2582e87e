//! The Khronos sample models that show each material extension (issue 25), as small scenes of
//! our own: rows of spheres over the extension's parameters, lit by whatever environment the
//! render gives them (`platoon render --env`), after the spirit of Khronos' ClearCoatTest.

use serde_json::{json, Value};

use crate::bench::{checker_png, facing};

/// A 4 x 4 checker of 16-texel cells in RGB and alpha alike (`checker_png`'s alpha is opaque):
/// for the extensions that read a texture's alpha.
fn checker_with_alpha_png() -> Vec<u8> {
    let n = 64;
    let px = (0..n * n)
        .flat_map(|k| {
            let v = if (k % n / 16 + k / n / 16) % 2 == 0 {
                200
            } else {
                70
            };
            [v, v, v, v]
        })
        .collect();
    crate::twins::png(n, n, px)
}
use crate::{uv_sphere, NodeData, SceneData};

/// What makes one of the scenes.
pub type MakeScene = fn() -> SceneData;

/// Each scene by its `platoon-scenegen` flag.
pub const SCENES: &[(&str, MakeScene)] = &[
    ("--clearcoat", clearcoat),
    ("--diffuse-transmission", diffuse_transmission),
    ("--sheen", sheen),
    ("--volume", volume),
    ("--iridescence", iridescence),
    ("--anisotropy", anisotropy),
    ("--dispersion", dispersion),
];

/// Spheres of `materials` in rows of `per_row`, before a camera that sees them all.
fn rows_of_spheres(materials: Vec<Value>, per_row: usize, extensions: &[&str]) -> SceneData {
    let rows = materials.len().div_ceil(per_row);
    let mut meshes = Vec::new();
    let mut nodes = Vec::new();
    for k in 0..materials.len() {
        let (col, row) = ((k % per_row) as f64, (k / per_row) as f64);
        let x = (col - (per_row as f64 - 1.0) / 2.0) * 2.4;
        let y = ((rows as f64 - 1.0) / 2.0 - row) * 2.4;
        meshes.push((uv_sphere(24, 48), k));
        nodes.push(NodeData::mesh(k, [x, y, 0.0], 1.0));
    }
    let mut camera = NodeData::new();
    camera.translation = [0.0, 0.0, 4.0 + 2.4 * per_row.max(rows) as f64];
    camera.rotation = facing([0.0, 0.0, -1.0]);
    camera.camera_yfov = Some(0.6);
    nodes.push(camera);
    SceneData {
        meshes,
        materials,
        nodes,
        extensions_used: extensions.iter().map(|e| e.to_string()).collect(),
        ..Default::default()
    }
}

/// KHR_materials_clearcoat: a rough red dielectric under coats of factor 0, 0.5 and 1 (a
/// mirror coat, the extension's default roughness); full coats of roughness 0.15, 0.3 and 0.6;
/// a coated gold, a coat whose weight a checker texture sets (red channel) and one whose
/// roughness it sets (green channel).
pub fn clearcoat() -> SceneData {
    let red = |coat: Value| {
        json!({"name": "coated red", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.08, 0.06, 1], "metallicFactor": 0, "roughnessFactor": 0.6},
               "extensions": {"KHR_materials_clearcoat": coat}})
    };
    let mut materials: Vec<Value> = [0.0, 0.5, 1.0]
        .into_iter()
        .map(|f| red(json!({"clearcoatFactor": f})))
        .collect();
    for r in [0.15, 0.3, 0.6] {
        materials.push(red(
            json!({"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": r}),
        ));
    }
    materials.push(json!({"name": "coated gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1, "roughnessFactor": 0.45},
        "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.05}}}));
    materials.push(red(
        json!({"clearcoatFactor": 1.0, "clearcoatTexture": {"index": 0}}),
    ));
    materials.push(red(
        json!({"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.8,
        "clearcoatRoughnessTexture": {"index": 0}}),
    ));
    let mut scene = rows_of_spheres(materials, 3, &["KHR_materials_clearcoat"]);
    scene.images = vec![checker_png(4, 16)];
    scene
}

/// KHR_materials_diffuse_transmission: a white rough dielectric passing on 0, 0.5 and 1 of its
/// diffuse light; a green-transmitting leaf, a red one, and one whose share a checker texture
/// sets (alpha channel).
pub fn diffuse_transmission() -> SceneData {
    let leaf = |dt: Value| {
        json!({"name": "leaf", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.7},
               "extensions": {"KHR_materials_diffuse_transmission": dt}})
    };
    let mut materials: Vec<Value> = [0.0, 0.5, 1.0]
        .into_iter()
        .map(|f| leaf(json!({"diffuseTransmissionFactor": f})))
        .collect();
    materials.push(leaf(json!({"diffuseTransmissionFactor": 0.8,
        "diffuseTransmissionColorFactor": [0.2, 0.9, 0.2]})));
    materials.push(leaf(json!({"diffuseTransmissionFactor": 0.8,
        "diffuseTransmissionColorFactor": [0.9, 0.15, 0.1]})));
    materials.push(leaf(json!({"diffuseTransmissionFactor": 1.0,
        "diffuseTransmissionTexture": {"index": 0}})));
    let mut scene = rows_of_spheres(materials, 3, &["KHR_materials_diffuse_transmission"]);
    scene.images = vec![checker_with_alpha_png()];
    scene
}

/// KHR_materials_sheen, after Khronos' SheenTestGrid: a dark red velvet-like dielectric under
/// a white sheen of roughness 0.1, 0.4 and 0.8; coloured sheens (blue over white, gold over a
/// metal); a sheen under a clear coat; sheens whose colour (RGB) and roughness (alpha) a
/// checker texture sets.
pub fn sheen() -> SceneData {
    let velvet = |sheen: Value| {
        json!({"name": "velvet", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.03, 0.04, 1], "metallicFactor": 0, "roughnessFactor": 0.9},
               "extensions": {"KHR_materials_sheen": sheen}})
    };
    let mut materials: Vec<Value> = [0.1, 0.4, 0.8]
        .into_iter()
        .map(|r| velvet(json!({"sheenColorFactor": [1.0, 1.0, 1.0], "sheenRoughnessFactor": r})))
        .collect();
    materials.push(json!({"name": "blue sheen", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 0.8},
        "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [0.1, 0.3, 1.0], "sheenRoughnessFactor": 0.5}}}));
    materials.push(json!({"name": "sheened gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1, "roughnessFactor": 0.5},
        "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1.0, 0.9, 0.6], "sheenRoughnessFactor": 0.3}}}));
    materials.push(json!({"name": "coated velvet", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.03, 0.04, 1], "metallicFactor": 0, "roughnessFactor": 0.9},
        "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1.0, 1.0, 1.0], "sheenRoughnessFactor": 0.4},
                       "KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.1}}}));
    materials.push(velvet(
        json!({"sheenColorFactor": [1.0, 1.0, 1.0], "sheenRoughnessFactor": 0.5,
        "sheenColorTexture": {"index": 0}}),
    ));
    materials.push(velvet(
        json!({"sheenColorFactor": [1.0, 1.0, 1.0], "sheenRoughnessFactor": 1.0,
        "sheenRoughnessTexture": {"index": 0}}),
    ));
    materials.push(velvet(json!({"sheenColorFactor": [0.0, 0.0, 0.0]})));
    let mut scene = rows_of_spheres(
        materials,
        3,
        &["KHR_materials_sheen", "KHR_materials_clearcoat"],
    );
    scene.images = vec![checker_with_alpha_png()];
    scene
}

/// KHR_materials_volume, after Khronos' AttenuationTest: smooth glass spheres (diameter 2)
/// whose inside leaves a colour after a distance: a teal at distances 0.5, 1 and 2, an amber and
/// a deep blue at 1, a rough one, a thin-walled one (thickness 0: no absorption), one at the
/// spec's default infinite distance, and a slightly rough teal at 2.
pub fn volume() -> SceneData {
    let glass = |roughness: f64, thickness: f64, volume: Value| {
        let mut v = volume;
        v["thicknessFactor"] = json!(thickness);
        json!({"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": roughness},
               "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                              "KHR_materials_volume": v}})
    };
    let teal = |d: f64| json!({"attenuationColor": [0.2, 0.7, 0.6], "attenuationDistance": d});
    let mut materials: Vec<Value> = [0.5, 1.0, 2.0]
        .into_iter()
        .map(|d| glass(0.0, 2.0, teal(d)))
        .collect();
    materials.push(glass(
        0.0,
        2.0,
        json!({"attenuationColor": [0.9, 0.5, 0.1], "attenuationDistance": 1.0}),
    ));
    materials.push(glass(
        0.0,
        2.0,
        json!({"attenuationColor": [0.1, 0.2, 0.8], "attenuationDistance": 1.0}),
    ));
    materials.push(glass(0.3, 2.0, teal(1.0)));
    materials.push(glass(0.0, 0.0, teal(0.5)));
    materials.push(glass(
        0.0,
        2.0,
        json!({"attenuationColor": [0.2, 0.7, 0.6]}),
    ));
    materials.push(glass(0.1, 2.0, teal(2.0)));
    rows_of_spheres(
        materials,
        3,
        &["KHR_materials_transmission", "KHR_materials_volume"],
    )
}

/// KHR_materials_iridescence, after Khronos' IridescenceDielectricSpheres, MetallicSpheres and
/// Lamp: films of index 1.3 and 1.8, 250, 400 and 700 nm thick, over a dark glossy dielectric;
/// over a silver and a rough gold; a soap bubble (a film of index 1.33 in air: thin-walled glass
/// of index 1); a film under a clear coat; a film whose thickness (green, 200-700 nm) and one
/// whose strength (red) a checker texture sets; a factor of 0 (no film).
pub fn iridescence() -> SceneData {
    let film = |base: [f64; 3], metallic: f64, roughness: f64, film: Value| {
        json!({"name": "iridescent", "pbrMetallicRoughness": {"baseColorFactor": [base[0], base[1], base[2], 1], "metallicFactor": metallic, "roughnessFactor": roughness},
               "extensions": {"KHR_materials_iridescence": film}})
    };
    let dark = [0.02, 0.02, 0.03];
    let mut materials: Vec<Value> = [(1.3, 250.0), (1.3, 400.0), (1.8, 700.0)]
        .into_iter()
        .map(|(ior, nm)| {
            film(dark, 0.0, 0.15, json!({"iridescenceFactor": 1.0, "iridescenceIor": ior, "iridescenceThicknessMaximum": nm}))
        })
        .collect();
    materials.push(film([0.95, 0.95, 0.95], 1.0, 0.2, json!({"iridescenceFactor": 1.0, "iridescenceIor": 1.8, "iridescenceThicknessMaximum": 450.0})));
    materials.push(film([1.0, 0.78, 0.34], 1.0, 0.5, json!({"iridescenceFactor": 0.8, "iridescenceIor": 1.5, "iridescenceThicknessMaximum": 550.0})));
    let mut bubble = film(
        [1.0, 1.0, 1.0],
        0.0,
        0.0,
        json!({"iridescenceFactor": 1.0, "iridescenceIor": 1.33, "iridescenceThicknessMaximum": 380.0}),
    );
    bubble["extensions"]["KHR_materials_transmission"] = json!({"transmissionFactor": 1.0});
    bubble["extensions"]["KHR_materials_ior"] = json!({"ior": 1.0});
    materials.push(bubble);
    let mut coated = film(
        dark,
        0.0,
        0.4,
        json!({"iridescenceFactor": 1.0, "iridescenceIor": 1.3, "iridescenceThicknessMaximum": 500.0}),
    );
    coated["extensions"]["KHR_materials_clearcoat"] =
        json!({"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.05});
    materials.push(coated);
    materials.push(film(dark, 0.0, 0.15, json!({"iridescenceFactor": 1.0, "iridescenceIor": 1.3,
        "iridescenceThicknessMinimum": 200.0, "iridescenceThicknessMaximum": 700.0, "iridescenceThicknessTexture": {"index": 0}})));
    materials.push(film(
        [0.95, 0.95, 0.95],
        1.0,
        0.2,
        json!({"iridescenceFactor": 1.0, "iridescenceIor": 1.8,
        "iridescenceThicknessMaximum": 450.0, "iridescenceTexture": {"index": 0}}),
    ));
    materials.push(film(
        dark,
        0.0,
        0.15,
        json!({"iridescenceFactor": 0.0, "iridescenceThicknessMaximum": 400.0}),
    ));
    let mut scene = rows_of_spheres(
        materials,
        5,
        &[
            "KHR_materials_iridescence",
            "KHR_materials_transmission",
            "KHR_materials_ior",
            "KHR_materials_clearcoat",
        ],
    );
    scene.images = vec![checker_png(4, 16)];
    scene
}

/// A 64 x 64 anisotropy texture whose direction circles its centre (red-green: the direction
/// in tangent space, blue: strength 1), as a brushed disc's (after Khronos' AnisotropyDiscTest).
fn swirl_png() -> Vec<u8> {
    let n = 64u32;
    let half = n as f32 / 2.0;
    let px = (0..n * n)
        .flat_map(|k| {
            let (x, y) = ((k % n) as f32 + 0.5 - half, (k / n) as f32 + 0.5 - half);
            let r = (x * x + y * y).sqrt();
            let unorm = |c: f32| ((c * 0.5 + 0.5) * 255.0).round() as u8;
            [unorm(-y / r), unorm(x / r), 255, 255]
        })
        .collect();
    crate::twins::png(n, n, px)
}

/// KHR_materials_anisotropy, after Khronos' AnisotropyStrengthTest, RotationTest and DiscTest:
/// a silver of roughness 0.3 stretched by strengths 0, 0.3, 0.6 and 1 along the tangent (the
/// sphere's u, around its axis), by 0.8 turned 45 and 90 degrees; a brushed dark dielectric;
/// anisotropic rough glass; a gold whose direction circles (a texture) and a silver whose
/// direction and strength a checker sets. The spheres carry no TANGENT: the loader makes
/// MikkTSpace's from their UVs.
pub fn anisotropy() -> SceneData {
    let brushed = |base: [f64; 3], metallic: f64, roughness: f64, anisotropy: Value| {
        json!({"name": "brushed", "pbrMetallicRoughness": {"baseColorFactor": [base[0], base[1], base[2], 1], "metallicFactor": metallic, "roughnessFactor": roughness},
               "extensions": {"KHR_materials_anisotropy": anisotropy}})
    };
    let silver = [0.95, 0.95, 0.95];
    let mut materials: Vec<Value> = [0.0, 0.3, 0.6, 1.0]
        .into_iter()
        .map(|s| brushed(silver, 1.0, 0.3, json!({"anisotropyStrength": s})))
        .collect();
    for rotation in [std::f64::consts::FRAC_PI_4, std::f64::consts::FRAC_PI_2] {
        materials.push(brushed(
            silver,
            1.0,
            0.3,
            json!({"anisotropyStrength": 0.8, "anisotropyRotation": rotation}),
        ));
    }
    materials.push(brushed(
        [0.05, 0.05, 0.08],
        0.0,
        0.2,
        json!({"anisotropyStrength": 0.8}),
    ));
    let mut glass = brushed(
        [1.0, 1.0, 1.0],
        0.0,
        0.2,
        json!({"anisotropyStrength": 0.7}),
    );
    glass["extensions"]["KHR_materials_transmission"] = json!({"transmissionFactor": 1.0});
    materials.push(glass);
    materials.push(brushed(
        [1.0, 0.78, 0.34],
        1.0,
        0.3,
        json!({"anisotropyStrength": 1.0, "anisotropyTexture": {"index": 0}}),
    ));
    materials.push(brushed(
        silver,
        1.0,
        0.3,
        json!({"anisotropyStrength": 1.0, "anisotropyTexture": {"index": 1}}),
    ));
    let mut scene = rows_of_spheres(
        materials,
        5,
        &["KHR_materials_anisotropy", "KHR_materials_transmission"],
    );
    scene.images = vec![swirl_png(), checker_png(4, 16)];
    scene
}

/// KHR_materials_dispersion, after Khronos' DispersionTest and DiamondDispersion: smooth glass
/// spheres (diameter 2, thickness 2) of index 1.5 with no dispersion, a crown glass's (0.33),
/// 1 (an Abbe number of 20) and rutile's 2.04; a diamond (index 2.42, 0.36); a rough one; a
/// tinted absorbing one; and a thin wall (thickness 0: the spec disperses in a volume only).
pub fn dispersion() -> SceneData {
    let glass = |ior: f64, roughness: f64, dispersion: f64, volume: Value| {
        json!({"name": "dispersive glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0, "roughnessFactor": roughness},
               "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                              "KHR_materials_ior": {"ior": ior},
                              "KHR_materials_volume": volume,
                              "KHR_materials_dispersion": {"dispersion": dispersion}}})
    };
    let solid = json!({"thicknessFactor": 2.0});
    let mut materials: Vec<Value> = [0.0, 0.33, 1.0, 2.04]
        .into_iter()
        .map(|d| glass(1.5, 0.0, d, solid.clone()))
        .collect();
    materials.push(glass(2.42, 0.0, 0.36, solid.clone()));
    materials.push(glass(1.5, 0.2, 1.0, solid.clone()));
    materials.push(glass(
        1.5,
        0.0,
        1.0,
        json!({"thicknessFactor": 2.0, "attenuationColor": [0.9, 0.6, 0.3], "attenuationDistance": 2.0}),
    ));
    materials.push(glass(1.5, 0.0, 1.0, json!({"thicknessFactor": 0.0})));
    rows_of_spheres(
        materials,
        4,
        &[
            "KHR_materials_transmission",
            "KHR_materials_ior",
            "KHR_materials_volume",
            "KHR_materials_dispersion",
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clearcoat_scene_names_its_extension_and_texture() {
        let s = clearcoat();
        assert_eq!(s.materials.len(), 9);
        assert_eq!(s.meshes.len(), 9);
        assert_eq!(s.extensions_used, vec!["KHR_materials_clearcoat"]);
        assert_eq!(s.images.len(), 1);
        let json = crate::to_json(&s, &mut Vec::new());
        assert_eq!(json["textures"].as_array().map(|t| t.len()), Some(1));
    }
}

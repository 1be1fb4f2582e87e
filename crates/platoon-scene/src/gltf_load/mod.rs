//! glTF 2.0 loader (.gltf with external or embedded buffers, .glb). Errors name the file and
//! the problem; unsupported optional features become warnings kept on the scene.
//!
//! Hostile files are expected: what the `gltf` crate assumes is checked first ([`validate`]),
//! every URI passes one policy (`resources.rs`), and a panic that still happens inside a
//! dependency becomes an error (`guard.rs`).

mod attributes;
mod guard;
mod ktx2;
mod material;
mod mesh;
mod nodes;
mod options;
mod resources;
pub mod validate;

use std::path::Path;
use std::sync::Arc;

use gltf::Gltf;

use crate::error::{Error, Result};
use crate::*;

pub use options::LoadOptions;

/// Extensions that platoon implements; a file that *requires* any other is refused.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_clearcoat",
    "KHR_materials_variants",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_diffuse_transmission",
    "KHR_materials_sheen",
    "KHR_materials_volume",
    "KHR_materials_iridescence",
    "KHR_materials_anisotropy",
    "KHR_materials_dispersion",
    "KHR_mesh_quantization",
    "EXT_texture_webp",
    "KHR_texture_basisu",
    "KHR_texture_transform",
    "KHR_materials_unlit",
    "EXT_mesh_gpu_instancing",
];

/// Extensions that change nothing a path tracer renders (metadata), ignored without a warning.
pub const INERT_EXTENSIONS: &[&str] = &["KHR_xmp_json_ld"];

/// Loads a scene with the default options (URIs confined to the scene's folder).
pub fn load(path: &Path) -> Result<Scene> {
    load_with(path, &LoadOptions::default())
}

pub fn load_with(path: &Path, options: &LoadOptions) -> Result<Scene> {
    let bytes = crate::input::read_regular_file(path, None)
        .map_err(|e| Error::file(path, format!("cannot read scene: {e}")))?;
    check_is_gltf(path, &bytes)?;
    let base = folder_of(path);
    let mut scene = guard::catching_panics(path, || load_from_slice(path, &bytes, base, options))?;
    // A warning names its file: scenes are merged, and a render's log outlives its command.
    for w in &mut scene.warnings {
        *w = format!("{}: {w}", path.display());
    }
    Ok(scene)
}

/// Refuses what is not a glTF file before the parser's messages about it ("EOF while
/// parsing", "expected value"): an empty file, or another format (platoon reads glTF alone).
fn check_is_gltf(path: &Path, bytes: &[u8]) -> Result<()> {
    if bytes.is_empty() {
        return Err(Error::file(path, "the file is empty, not a glTF scene"));
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let binary = bytes.starts_with(b"glTF");
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let json = text.iter().find(|b| !b.is_ascii_whitespace()) == Some(&b'{');
    if !binary && !json {
        let what = match ext.as_str() {
            "gltf" | "glb" => "it is neither JSON nor binary glTF".to_string(),
            "" => "it is not glTF".to_string(),
            other => format!("a .{other} file is not glTF"),
        };
        return Err(Error::file(
            path,
            format!("{what}: platoon reads glTF scenes (.gltf, .glb) only"),
        ));
    }
    Ok(())
}

/// The index of the material variant `name` among the file's, or why there is none.
fn chosen_variant(name: &str, variants: &[String]) -> validate::Check<u32> {
    match variants.iter().position(|v| v == name) {
        Some(i) => Ok(i as u32),
        None if variants.is_empty() => Err(format!(
            "has no material variants (KHR_materials_variants); --variant {name:?} names none"
        )),
        None => Err(format!(
            "has no material variant {name:?}; its variants: {}",
            variants.join(", ")
        )),
    }
}

/// The folder a scene's relative URIs resolve against: a bare file name lives in the current
/// directory (`Path::parent` gives the empty path for it, which names no folder).
pub fn folder_of(path: &Path) -> &Path {
    path.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Loads a scene from the bytes of `path`, resolving URIs against `base`. Unlike
/// [`load_with`], a panic inside a dependency is not caught: this is what the fuzz target
/// calls, so that such a panic is found rather than hidden.
pub fn load_from_slice(
    path: &Path,
    bytes: &[u8],
    base: &Path,
    options: &LoadOptions,
) -> Result<Scene> {
    validate::in_file(path, validate::glb_header(bytes))?;
    let unvalidated = Gltf::from_slice_without_validation(bytes)
        .map_err(|e| Error::file(path, format!("not a valid glTF file: {e}")))?;
    validate::in_file(
        path,
        validate::asset_version(&unvalidated.document.as_json().asset),
    )?;
    for ext in unvalidated.extensions_required() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            return Err(Error::file(
                path,
                format!("requires the unsupported glTF extension {ext}"),
            ));
        }
    }
    let mut warnings = Vec::new();
    for ext in unvalidated.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) && !INERT_EXTENSIONS.contains(&ext) {
            warnings.push(format!(
                "uses the glTF extension {ext}, which platoon ignores (docs/GLTF.md)"
            ));
        }
    }
    validate::in_file(path, validate::references(unvalidated.document.as_json()))?;
    let Gltf { document, blob } = unvalidated;
    let mut json = document.into_json();
    // Every required extension was checked against platoon's own list above; the crate's
    // validation would refuse those it does not model itself (KHR_mesh_quantization, ...).
    json.extensions_required.clear();
    let doc = gltf::Document::from_json(json)
        .map_err(|e| Error::file(path, format!("invalid glTF: {e}")))?;

    let policy = resources::UriPolicy { base, options };
    let buffers = validate::in_file(path, resources::buffers(&doc, blob, &policy))?;
    validate::in_file(path, validate::buffer_views(&doc, &buffers))?;
    let mut images = validate::in_file(path, resources::images(&doc, &buffers, &policy))?;

    let mut scene = Scene {
        source: Some(path.to_path_buf()),
        warnings,
        ..Default::default()
    };
    let shown: Vec<usize> = doc
        .textures()
        .map(|t| validate::in_file(path, material::texture_image(&t, images.len())))
        .collect::<Result<_>>()?;
    // An image's last texture takes its texels; only images that several textures show are
    // copied (hundreds of megabytes in a scene of large textures).
    let mut uses = vec![0usize; images.len()];
    for &i in &shown {
        uses[i] += 1;
    }
    for (t, &i) in doc.textures().zip(&shown) {
        uses[i] -= 1;
        let image = &mut images[i];
        let pixels = match uses[i] {
            0 => std::mem::take(&mut image.pixels),
            _ => image.pixels.clone(),
        };
        scene
            .textures
            .push(material::texture(&t, image.width, image.height, pixels));
    }
    let mut glossiness = material::GlossinessTextures::default();
    for m in doc.materials() {
        let m = validate::in_file(
            path,
            material::material(&m, &mut scene.textures, &mut glossiness),
        )?;
        scene.materials.push(m);
    }
    // Primitives without a material use the glTF default material, appended last when needed.
    let default_material = scene.materials.len() as u32;
    if doc
        .meshes()
        .flat_map(|m| m.primitives())
        .any(|p| p.material().index().is_none())
    {
        scene.materials.push(Material::default());
    }
    scene.variants = doc
        .variants()
        .map(|v| v.map(|v| v.name().to_string()).collect())
        .unwrap_or_default();
    let variant = mesh::Variant {
        chosen: match &options.variant {
            None => None,
            Some(name) => Some(validate::in_file(
                path,
                chosen_variant(name, &scene.variants),
            )?),
        },
        count: scene.variants.len() as u32,
    };
    scene.variant = options.variant.clone();
    for m in doc.meshes() {
        let m = mesh::load_mesh(
            &m,
            &buffers,
            default_material,
            variant,
            &scene.materials,
            &mut scene.warnings,
        );
        let m = validate::in_file(path, m)?;
        scene.meshes.push(Arc::new(m));
    }
    validate::in_file(path, nodes::load_nodes(&doc, &buffers, &mut scene))?;
    Ok(scene)
}

//! What a caller chooses about loading a glTF file.

#[derive(Clone, Debug, Default)]
pub struct LoadOptions {
    /// Read buffers and images whose URI is absolute or leaves the scene's folder.
    pub allow_external_files: bool,
    /// KHR_materials_variants: the variant whose materials the primitives take (None: each
    /// primitive's own material, the file's default look).
    pub variant: Option<String>,
    /// Mip maps and a memory budget for the textures (applied by the facade after any load,
    /// `crate::texture_levels`).
    pub textures: crate::texture_levels::TextureOptions,
}

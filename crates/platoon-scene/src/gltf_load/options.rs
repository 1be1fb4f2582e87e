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

impl LoadOptions {
    /// What these options make of the scene's look, said as a person reads it (part of a
    /// render job's identity). Reading files from outside the scene's folder only lets a file
    /// load, so it is left out; a new option fails to build here until it is said.
    pub fn describe(&self) -> String {
        let LoadOptions {
            allow_external_files: _,
            variant,
            textures,
        } = self;
        let crate::texture_levels::TextureOptions { lod, budget } = textures;
        let budget = budget.map_or("no texture budget".into(), |b| {
            format!("textures within {b} bytes")
        });
        format!(
            "variant {}, texture LOD {}, {budget}",
            variant.as_deref().unwrap_or("(default)"),
            lod.name()
        )
    }
}

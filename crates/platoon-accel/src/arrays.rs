//! The scene arrays, one table: their order (upload, binding and commit order), their names,
//! the kernel defines that choose each one's memory path and the `Globals` field holding its
//! address. Every place that names an array by position indexes this table; shaders/
//! scene_arrays.glsl is checked against it by a test ("Must match GPU side").

/// One scene array of [`super::GpuScene`], by its position in every array list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneArray {
    Vertices,
    TrianglePositions,
    Triangles,
    TriangleLights,
    Blas,
    Tlas,
    Instances,
    Materials,
    Textures,
    Texels,
    Lights,
    LightCdf,
    EnvTexels,
    EnvMarginal,
    EnvConditional,
    VertexExtras,
}

/// What the kernel and the tracer need to know of an array.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArrayInfo {
    pub array: SceneArray,
    pub name: &'static str,
    /// The define that reads it through a uniform texel buffer, and through a storage buffer.
    pub texel_define: &'static str,
    pub storage_define: &'static str,
    /// Its `Globals` field (buffer device address) in shaders/common/scene.glsl.
    pub globals_field: &'static str,
    /// Bytes of one texel: 16 for arrays of vec4-sized structs, 4 for arrays of scalars.
    pub texel_bytes: u64,
}

const fn info(
    array: SceneArray,
    name: &'static str,
    texel_define: &'static str,
    storage_define: &'static str,
    globals_field: &'static str,
    texel_bytes: u64,
) -> ArrayInfo {
    ArrayInfo {
        array,
        name,
        texel_define,
        storage_define,
        globals_field,
        texel_bytes,
    }
}

/// Every array, in order.
pub const ARRAYS: [ArrayInfo; 16] = {
    use SceneArray::*;
    [
        info(
            Vertices,
            "vertices",
            "TEXEL_VERTICES",
            "SSBO_VERTICES",
            "vertices",
            16,
        ),
        info(
            TrianglePositions,
            "triangle positions",
            "TEXEL_TRI_POS",
            "SSBO_TRI_POS",
            "tri_pos",
            16,
        ),
        info(
            Triangles,
            "triangles",
            "TEXEL_TRIANGLES",
            "SSBO_TRIANGLES",
            "triangles",
            16,
        ),
        info(
            TriangleLights,
            "triangle lights",
            "TEXEL_TRI_LIGHTS",
            "SSBO_TRI_LIGHTS",
            "tri_lights",
            4,
        ),
        info(Blas, "blas", "TEXEL_BLAS", "SSBO_BLAS", "blas", 16),
        info(Tlas, "tlas", "TEXEL_TLAS", "SSBO_TLAS", "tlas", 16),
        info(
            Instances,
            "instances",
            "TEXEL_INSTANCES",
            "SSBO_INSTANCES",
            "instances",
            16,
        ),
        info(
            Materials,
            "materials",
            "TEXEL_MATERIALS",
            "SSBO_MATERIALS",
            "materials",
            16,
        ),
        info(
            Textures,
            "textures",
            "TEXEL_TEXTURES",
            "SSBO_TEXTURES",
            "textures",
            16,
        ),
        info(Texels, "texels", "TEXEL_TEXELS", "SSBO_TEXELS", "texels", 4),
        info(
            Lights,
            "lights",
            "TEXEL_LIGHTS",
            "SSBO_LIGHTS",
            "lights",
            16,
        ),
        info(
            LightCdf,
            "light cdf",
            "TEXEL_LIGHT_CDF",
            "SSBO_LIGHT_CDF",
            "light_cdf",
            4,
        ),
        info(
            EnvTexels,
            "environment",
            "TEXEL_ENV_TEXELS",
            "SSBO_ENV_TEXELS",
            "env_texels",
            16,
        ),
        info(
            EnvMarginal,
            "environment marginal",
            "TEXEL_ENV_MARGINAL",
            "SSBO_ENV_MARGINAL",
            "env_marginal",
            4,
        ),
        info(
            EnvConditional,
            "environment conditional",
            "TEXEL_ENV_CONDITIONAL",
            "SSBO_ENV_CONDITIONAL",
            "env_conditional",
            4,
        ),
        info(
            VertexExtras,
            "vertex extras",
            "TEXEL_VERTEX_EXTRAS",
            "SSBO_VERTEX_EXTRAS",
            "vertex_extras",
            16,
        ),
    ]
};

/// How many arrays there are.
pub const ARRAY_COUNT: usize = ARRAYS.len();

impl SceneArray {
    /// Its position in every array list.
    pub const fn index(self) -> usize {
        self as usize
    }
}

const _: () = {
    // The table's rows are in the enum's order.
    let mut k = 0;
    while k < ARRAY_COUNT {
        assert!(ARRAYS[k].array as usize == k);
        k += 1;
    }
};

#[cfg(test)]
mod tests {
    use super::*;

    /// shaders/common/scene_arrays.glsl declares each array's accessor under its two defines, at its
    /// binding, with its Globals field; and scene.glsl's Globals has that field.
    #[test]
    fn the_kernels_array_declarations_follow_the_table() {
        let arrays = include_str!("../../../shaders/common/scene_arrays.glsl");
        let globals = include_str!("../../../shaders/common/scene.glsl");
        for info in ARRAYS {
            let k = info.array.index();
            let texel = format!("#if defined({})\nTEXEL_ARRAY(", info.texel_define);
            let at = arrays
                .find(&texel)
                .unwrap_or_else(|| panic!("{}: no {texel:?}", info.name));
            let block: Vec<&str> = arrays[at..].lines().take(6).collect();
            assert!(
                block[1].contains(&format!(", {k}, ")),
                "{}: {block:?}",
                info.name
            );
            assert_eq!(block[2], format!("#elif defined({})", info.storage_define));
            assert!(
                block[3].ends_with(&format!(", {k})")),
                "{}: {block:?}",
                info.name
            );
            assert!(
                block[5].ends_with(&format!(", {})", info.globals_field)),
                "{}: {block:?}",
                info.name
            );
            assert!(
                globals.contains(&format!(" {};", info.globals_field)),
                "Globals has no {}",
                info.globals_field
            );
        }
    }
}

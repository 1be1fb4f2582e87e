//! The GPU structs of the scene arrays: std430 layouts that shaders/common/scene.glsl mirrors ("Must
//! match GPU side"); each asserts its size.

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuVertex {
    /// xyz position, w = u
    pub position_u: [f32; 4],
    /// xyz normal (zero when the mesh has none), w = v
    pub normal_v: [f32; 4],
    /// xyz tangent, w = bitangent sign
    pub tangent: [f32; 4],
}

/// What some vertices have beyond [`GpuVertex`]: the second UV set and COLOR_0 (RGBA as
/// 16-bit unorms, two to a u32). The array is empty unless some mesh has either.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuVertexExtra {
    pub uv1: [f32; 2],
    pub color: [u32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTriangle {
    /// Global vertex indices and material index.
    pub v: [u32; 3],
    pub material: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuInstance {
    /// Rows of the 3x4 world-to-object matrix.
    pub world_to_object: [[f32; 4]; 3],
    /// Rows of the 3x4 object-to-world matrix.
    pub object_to_world: [[f32; 4]; 3],
    pub blas_root: u32,
    /// First light entry of this instance's emissive triangles (u32::MAX if none).
    pub light_base: u32,
    pub _pad: [u32; 2],
}

/// The w of a triangle's first corner in the triangle positions when its material lets light
/// through by its alpha (MASK or BLEND), 0 otherwise: the kernel tests coverage only for such
/// triangles, and only at the nearest hit (shaders/common/trace.glsl).
pub const CORNER_ALPHA_TESTED: f32 = 1.0;

pub const NO_TEXTURE: i32 = -1;
pub const MATERIAL_DOUBLE_SIDED: i32 = 1;
pub const MATERIAL_ALPHA_MASK: i32 = 2;
pub const MATERIAL_ALPHA_BLEND: i32 = 4;
pub const MATERIAL_UNLIT: i32 = 8;
/// Some texture slot reads TEXCOORD_1 (the kernel then reads the vertex extras).
pub const MATERIAL_USES_UV1: i32 = 16;
pub use platoon_scene::TEXTURE_SLOTS;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuMaterial {
    pub base_color: [f32; 4],
    /// rgb emission, w = normal scale
    pub emissive: [f32; 4],
    /// metallic, roughness, transmission, ior
    pub params: [f32; 4],
    /// specular colour rgb, w = specular factor
    pub specular: [f32; 4],
    /// base colour, metallic-roughness, normal, emissive textures
    pub textures0: [i32; 4],
    /// specular, specular colour, transmission textures, flags
    pub textures1: [i32; 4],
    /// alpha cutoff, KHR_materials_anisotropy's strength and rotation (radians),
    /// KHR_materials_dispersion's 20 / Abbe number
    pub misc: [f32; 4],
    /// KHR_materials_clearcoat: factor, roughness, normal scale
    pub clearcoat: [f32; 4],
    /// clearcoat, clearcoat roughness, clearcoat normal, diffuse transmission textures
    pub textures2: [i32; 4],
    /// KHR_materials_diffuse_transmission: colour rgb, w = factor
    pub diffuse_transmission: [f32; 4],
    /// diffuse transmission colour, sheen colour, sheen roughness, iridescence textures
    pub textures3: [i32; 4],
    /// KHR_materials_sheen: colour rgb, w = roughness
    pub sheen: [f32; 4],
    /// KHR_materials_volume: absorption per unit length rgb, w = 1 with a volume (thickness
    /// above 0), else 0 (a thin wall)
    pub volume: [f32; 4],
    /// iridescence thickness, anisotropy textures
    pub textures4: [i32; 4],
    /// KHR_materials_iridescence: factor, ior, thickness minimum, maximum (nm)
    pub iridescence: [f32; 4],
    /// Per texture slot, the UV transform's two rows (xyz: the 2 x 3 matrix applied to
    /// (u, v, 1)); the first row's w is the UV set (0 or 1).
    pub uv_rows: [[f32; 4]; 2 * TEXTURE_SLOTS],
}

/// All zero, as a derived Default would be (std derives it for arrays of at most 32 elements;
/// `uv_rows` has more).
impl Default for GpuMaterial {
    fn default() -> Self {
        Zeroable::zeroed()
    }
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuTexture {
    pub offset: u32,
    pub width: u32,
    pub height: u32,
    /// wrap_s | wrap_t << 2 (0 repeat, 1 mirrored repeat, 2 clamp) | nearest << 4 (glTF
    /// magFilter NEAREST) | the mip levels below the image << TEXTURE_MIPS_SHIFT (stored after
    /// it, each half the one above)
    pub wrap: u32,
}

/// Where `GpuTexture::wrap` counts the texture's mip levels.
pub const TEXTURE_MIPS_SHIFT: u32 = 8;

pub const LIGHT_TRIANGLE: u32 = 0;
pub const LIGHT_POINT: u32 = 1;
pub const LIGHT_SPOT: u32 = 2;
pub const LIGHT_DIRECTIONAL: u32 = 3;
pub const LIGHT_ENVIRONMENT: u32 = 4;

/// One entry of the light-selection distribution.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuLight {
    /// Triangle: world v0, w = +1, or -1 when the instance mirrors (a negative determinant
    /// flips the world winding; glTF keeps the object's front face, and so does the hit shader).
    /// Punctual: position.
    pub a: [f32; 4],
    /// Triangle: world v1; spot/directional: direction. w = range
    pub b: [f32; 4],
    /// Triangle: world v2; spot: cos(outer), 1/(cos(inner) - cos(outer)).
    pub c: [f32; 4],
    /// Radiance (triangle) or intensity (punctual) rgb; w = selection probability.
    pub emission: [f32; 4],
    /// type, instance, triangle (BLAS order, global), material
    pub ids: [u32; 4],
}

/// `GpuEnvironment::kind`, the kernel's `env_kind()` (shaders/common/scene.glsl).
pub const ENV_NONE: u32 = 0;
pub const ENV_CONSTANT: u32 = 1;
pub const ENV_MAP: u32 = 2;

#[derive(Clone, Debug, Default)]
pub struct GpuEnvironment {
    /// ENV_NONE (black), ENV_CONSTANT (a colour) or ENV_MAP
    pub kind: u32,
    pub color: [f32; 3],
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
    pub marginal_cdf: Vec<f32>,
    pub conditional_cdf: Vec<f32>,
    pub integral: f32,
    /// Mean radiance over the sphere (CPU side: the environment light's power).
    pub mean_radiance: [f32; 3],
}

const _: () = {
    assert!(std::mem::size_of::<GpuVertex>() == 48);
    assert!(std::mem::size_of::<GpuTriangle>() == 16);
    assert!(std::mem::size_of::<GpuInstance>() == 112);
    assert!(std::mem::size_of::<GpuMaterial>() == 784);
    assert!(std::mem::size_of::<GpuVertexExtra>() == 16);
    assert!(std::mem::size_of::<GpuTexture>() == 16);
    assert!(std::mem::size_of::<GpuLight>() == 80);
    assert!(std::mem::size_of::<super::bvh::BvhNode>() == 64);
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Every code the kernel shares with these structs has one value on both sides.
    #[test]
    fn the_kernels_constants_match_these() {
        let glsl = include_str!("../../../shaders/common/scene.glsl");
        let uints = [
            ("ENV_NONE", ENV_NONE),
            ("ENV_CONSTANT", ENV_CONSTANT),
            ("ENV_MAP", ENV_MAP),
            ("LIGHT_TRIANGLE", LIGHT_TRIANGLE),
            ("LIGHT_POINT", LIGHT_POINT),
            ("LIGHT_SPOT", LIGHT_SPOT),
            ("LIGHT_DIRECTIONAL", LIGHT_DIRECTIONAL),
            ("LIGHT_ENVIRONMENT", LIGHT_ENVIRONMENT),
        ];
        for (name, value) in uints {
            let line = format!("const uint {name} = {value}u;");
            assert!(glsl.contains(&line), "scene.glsl lacks {line}");
        }
        let ints = [
            ("MATERIAL_DOUBLE_SIDED", MATERIAL_DOUBLE_SIDED),
            ("MATERIAL_ALPHA_MASK", MATERIAL_ALPHA_MASK),
            ("MATERIAL_ALPHA_BLEND", MATERIAL_ALPHA_BLEND),
            ("MATERIAL_UNLIT", MATERIAL_UNLIT),
            ("MATERIAL_USES_UV1", MATERIAL_USES_UV1),
        ];
        for (name, value) in ints {
            let line = format!("const int {name} = {value};");
            assert!(glsl.contains(&line), "scene.glsl lacks {line}");
        }
        assert!(glsl.contains(&format!("vec4 uv_rows[{}];", 2 * TEXTURE_SLOTS)));
        let line = format!("const float CORNER_ALPHA_TESTED = {CORNER_ALPHA_TESTED:?};");
        assert!(glsl.contains(&line), "scene.glsl lacks {line}");
    }
}

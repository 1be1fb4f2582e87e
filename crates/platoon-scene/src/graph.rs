//! The scene graph: a node hierarchy (`nodes.rs`) over shared meshes (`mesh.rs`), materials,
//! textures, lights, cameras, skins and animations, as loaded from glTF. It is posed at a time by
//! [`Scene::pose`] (`pose.rs`).

use std::path::PathBuf;
use std::sync::Arc;

use glam::{Vec3, Vec4};

use crate::environment::Environment;
use crate::{Mesh, Node, Skin};

/// A material's use of a texture: which texture, read at which UV set, through which transform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    pub texture: u32,
    /// The UV set: 0 (TEXCOORD_0) or 1 (TEXCOORD_1).
    pub tex_coord: u32,
    /// KHR_texture_transform as the rows of a 2 x 3 matrix applied to (u, v, 1).
    pub transform: [[f32; 3]; 2],
}

impl TextureRef {
    pub const IDENTITY: [[f32; 3]; 2] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

    /// Texture `texture` at TEXCOORD_0, untransformed.
    pub fn new(texture: u32) -> TextureRef {
        TextureRef {
            texture,
            tex_coord: 0,
            transform: Self::IDENTITY,
        }
    }

    /// Read at TEXCOORD_0 without a transform: what a kernel without UV transforms does.
    pub fn is_plain(&self) -> bool {
        self.tex_coord == 0 && self.transform == Self::IDENTITY
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    Opaque,
    Mask(f32),
    /// Stochastic transparency: a ray passes the surface with probability 1 - alpha (unbiased
    /// for coverage, shadow rays too).
    Blend,
}

/// Texture slots a material has, in the kernel's order (`Material::texture_slots`, the
/// `GpuMaterial` of `flatten::layout`, TEXTURE_SLOT_* in shaders/common/scene.glsl).
pub const TEXTURE_SLOTS: usize = 17;

/// glTF metallic-roughness material with the extensions platoon supports.
#[derive(Clone, Debug)]
pub struct Material {
    pub name: String,
    pub base_color: Vec4,
    pub base_color_texture: Option<TextureRef>,
    pub metallic: f32,
    pub roughness: f32,
    pub metallic_roughness_texture: Option<TextureRef>,
    pub normal_texture: Option<TextureRef>,
    pub normal_scale: f32,
    /// Emissive factor already multiplied by KHR_materials_emissive_strength.
    pub emissive: Vec3,
    pub emissive_texture: Option<TextureRef>,
    /// KHR_materials_specular.
    pub specular: f32,
    pub specular_texture: Option<TextureRef>,
    pub specular_color: Vec3,
    pub specular_color_texture: Option<TextureRef>,
    /// KHR_materials_transmission.
    pub transmission: f32,
    pub transmission_texture: Option<TextureRef>,
    /// KHR_materials_ior.
    pub ior: f32,
    /// KHR_materials_clearcoat: the coat's weight and roughness, each times its texture's red
    /// and green channel, and the coat's own normal map (without one the coat follows the
    /// mesh's normal, not the base's normal map).
    pub clearcoat: f32,
    pub clearcoat_texture: Option<TextureRef>,
    pub clearcoat_roughness: f32,
    pub clearcoat_roughness_texture: Option<TextureRef>,
    pub clearcoat_normal_texture: Option<TextureRef>,
    pub clearcoat_normal_scale: f32,
    /// KHR_materials_diffuse_transmission: the share of the dielectric's diffuse light that is
    /// transmitted (times its texture's alpha) and its colour (times its texture's RGB, sRGB).
    pub diffuse_transmission: f32,
    pub diffuse_transmission_texture: Option<TextureRef>,
    pub diffuse_transmission_color: Vec3,
    pub diffuse_transmission_color_texture: Option<TextureRef>,
    /// KHR_materials_sheen: the sheen's colour (times its texture's RGB, sRGB) and roughness
    /// (times its texture's alpha).
    pub sheen_color: Vec3,
    pub sheen_color_texture: Option<TextureRef>,
    pub sheen_roughness: f32,
    pub sheen_roughness_texture: Option<TextureRef>,
    /// KHR_materials_volume: a thickness above 0 makes the mesh's inside a medium that absorbs
    /// (Beer-Lambert) what travels through it, leaving `attenuation_color` after
    /// `attenuation_distance`; 0 is a thin wall. (The thickness texture is for rasterisers: a
    /// path tracer measures the distances through the mesh.)
    pub thickness: f32,
    pub attenuation_distance: f32,
    pub attenuation_color: Vec3,
    /// KHR_materials_iridescence: a thin film over the specular lobes, of strength
    /// `iridescence` (times its texture's red channel), index of refraction `iridescence_ior`
    /// and a thickness in nanometres: the maximum, or with a texture mixed from the minimum to
    /// the maximum by its green channel.
    pub iridescence: f32,
    pub iridescence_texture: Option<TextureRef>,
    pub iridescence_ior: f32,
    pub iridescence_thickness_min: f32,
    pub iridescence_thickness_max: f32,
    pub iridescence_thickness_texture: Option<TextureRef>,
    /// KHR_materials_anisotropy: the strength (times its texture's blue channel) by which the
    /// base's specular lobes are rougher along a direction: the tangent turned counter-clockwise
    /// by `anisotropy_rotation` radians (the texture's red-green direction in tangent space, when
    /// it has one, turned by it).
    pub anisotropy_strength: f32,
    pub anisotropy_rotation: f32,
    pub anisotropy_texture: Option<TextureRef>,
    /// KHR_materials_dispersion: 20 / the Abbe number, by which the index of refraction (`ior`
    /// at 587.6 nm) varies with the wavelength (the spec's Cauchy equation), in the volume of a
    /// transmissive material (`has_volume`); 0 none. A path that meets such a surface carries one
    /// wavelength from there on, drawn uniformly over 380-780 nm and weighed by the linear
    /// Rec. 709 colour-matching functions (clamped at 0, each channel normalised to 1 over the
    /// range: shaders/common/spectrum.glsl).
    pub dispersion: f32,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
    /// KHR_materials_unlit: the base colour is emitted radiance and nothing is reflected.
    pub unlit: bool,
}

impl Default for Material {
    /// The glTF default material.
    fn default() -> Self {
        Material {
            name: "default".into(),
            base_color: Vec4::ONE,
            base_color_texture: None,
            metallic: 1.0,
            roughness: 1.0,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            emissive: Vec3::ZERO,
            emissive_texture: None,
            specular: 1.0,
            specular_texture: None,
            specular_color: Vec3::ONE,
            specular_color_texture: None,
            transmission: 0.0,
            transmission_texture: None,
            ior: 1.5,
            clearcoat: 0.0,
            clearcoat_texture: None,
            clearcoat_roughness: 0.0,
            clearcoat_roughness_texture: None,
            clearcoat_normal_texture: None,
            clearcoat_normal_scale: 1.0,
            diffuse_transmission: 0.0,
            diffuse_transmission_texture: None,
            diffuse_transmission_color: Vec3::ONE,
            diffuse_transmission_color_texture: None,
            sheen_color: Vec3::ZERO,
            sheen_color_texture: None,
            sheen_roughness: 0.0,
            sheen_roughness_texture: None,
            thickness: 0.0,
            attenuation_distance: f32::INFINITY,
            attenuation_color: Vec3::ONE,
            iridescence: 0.0,
            iridescence_texture: None,
            iridescence_ior: 1.3,
            iridescence_thickness_min: 100.0,
            iridescence_thickness_max: 400.0,
            iridescence_thickness_texture: None,
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            anisotropy_texture: None,
            dispersion: 0.0,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            unlit: false,
        }
    }
}

impl Material {
    pub fn is_emissive(&self) -> bool {
        self.emissive.max_element() > 0.0
    }
    /// Every texture slot, in the kernel's order (`flatten::TEXTURE_SLOTS`, TEXTURE_SLOT_* in
    /// shaders/scene.glsl): base colour, metallic-roughness, normal, emissive, specular,
    /// specular colour, transmission, clearcoat, clearcoat roughness, clearcoat normal, diffuse
    /// transmission, diffuse transmission colour, sheen colour, sheen roughness, iridescence,
    /// iridescence thickness, anisotropy.
    pub fn texture_slots(&self) -> [Option<TextureRef>; TEXTURE_SLOTS] {
        [
            self.base_color_texture,
            self.metallic_roughness_texture,
            self.normal_texture,
            self.emissive_texture,
            self.specular_texture,
            self.specular_color_texture,
            self.transmission_texture,
            self.clearcoat_texture,
            self.clearcoat_roughness_texture,
            self.clearcoat_normal_texture,
            self.diffuse_transmission_texture,
            self.diffuse_transmission_color_texture,
            self.sheen_color_texture,
            self.sheen_roughness_texture,
            self.iridescence_texture,
            self.iridescence_thickness_texture,
            self.anisotropy_texture,
        ]
    }

    /// Whether its inside is a medium (thickness above 0): what enters it leaves the outside.
    pub fn has_volume(&self) -> bool {
        self.thickness > 0.0
    }

    /// The volume's absorption coefficient per unit length, -ln(colour) / distance: zero
    /// without a volume or at an infinite distance (the spec's default), which absorbs nothing.
    pub fn absorption(&self) -> Vec3 {
        let d = self.attenuation_distance;
        if !(self.has_volume() && d.is_finite() && d > 0.0) {
            return Vec3::ZERO;
        }
        // A colour of 0 would absorb all at once; 1e-6 is gone within the distance's 1/14th.
        -self
            .attenuation_color
            .clamp(Vec3::splat(1e-6), Vec3::ONE)
            .map(f32::ln)
            / d
    }

    /// Whether some light is absorbed in its volume.
    pub fn absorbs(&self) -> bool {
        self.absorption().max_element() > 0.0
    }

    /// Whether it has a sheen (the spec: a zero colour disables the layer; a texture only
    /// scales the factor).
    pub fn has_sheen(&self) -> bool {
        self.sheen_color.max_element() > 0.0
    }

    /// Whether light refracted into it disperses (a dispersion above 0 in a volume that
    /// transmits; a texture only scales the transmission).
    pub fn has_dispersion(&self) -> bool {
        self.dispersion > 0.0 && self.has_volume() && self.transmission > 0.0
    }

    /// Whether its specular lobes are anisotropic (a texture only scales the strength).
    pub fn has_anisotropy(&self) -> bool {
        self.anisotropy_strength > 0.0
    }

    /// Whether a thin film lies over it (the spec: a factor of 0 disables the layer).
    pub fn has_iridescence(&self) -> bool {
        self.iridescence > 0.0
    }

    /// Whether some of its diffuse light goes through (a texture only scales the factor).
    pub fn has_diffuse_transmission(&self) -> bool {
        self.diffuse_transmission > 0.0
    }

    /// Whether it has a clear coat (a texture only scales the factor).
    pub fn has_clearcoat(&self) -> bool {
        self.clearcoat > 0.0
    }

    /// The textures it uses.
    pub fn textures(&self) -> impl Iterator<Item = TextureRef> + '_ {
        self.texture_slots().into_iter().flatten()
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Wrap {
    Repeat,
    MirroredRepeat,
    ClampToEdge,
}

/// 8-bit RGBA texture; colour-space decoding happens where the texture is used.
#[derive(Clone, Debug)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub rgba8: Vec<u8>,
    pub wrap_s: Wrap,
    pub wrap_t: Wrap,
    /// glTF magFilter NEAREST: magnified texels stay sharp (pixel art); else bilinear.
    pub nearest: bool,
    /// The levels below the image, made at load for lookups by ray cone (empty: the image
    /// only; `texture_levels`).
    pub mips: Vec<MipLevel>,
}

/// One level below a texture's base image: half the one above on each axis (at least 1).
#[derive(Clone, Debug, PartialEq)]
pub struct MipLevel {
    pub width: u32,
    pub height: u32,
    pub rgba8: Vec<u8>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    Point,
    Spot { inner_cone: f32, outer_cone: f32 },
    Directional,
}

/// KHR_lights_punctual light. Intensity is used as radiometric (W/sr or W/m^2) one to one.
#[derive(Clone, Debug)]
pub struct PunctualLight {
    pub name: String,
    pub kind: LightKind,
    pub color: Vec3,
    pub intensity: f32,
    /// 0 = unbounded.
    pub range: f32,
}

/// A glTF camera; thin-lens parameters are platoon options (glTF has none).
#[derive(Clone, Debug)]
pub struct CameraModel {
    pub name: String,
    /// Perspective: the vertical field of view (radians).
    pub yfov: f32,
    pub aspect_ratio: Option<f32>,
    /// Orthographic: half the view's width and height in scene units (glTF's xmag, ymag); the
    /// field of view is then unused.
    pub orthographic: Option<[f32; 2]>,
}

/// The whole scene as loaded. Posing it (animation, skinning, world transforms) gives a [`Posed`](crate::Posed).
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub source: Option<PathBuf>,
    /// Nodes in topological order: a parent always comes before its children.
    pub nodes: Vec<Node>,
    pub meshes: Vec<Arc<Mesh>>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub lights: Vec<PunctualLight>,
    pub cameras: Vec<CameraModel>,
    pub skins: Vec<Skin>,
    pub animations: Vec<crate::animation::Animation>,
    pub environment: Option<Environment>,
    /// Warnings gathered while loading (unsupported but optional features).
    pub warnings: Vec<String>,
    /// KHR_materials_variants' names, and the one whose materials were loaded (None: the
    /// file's default look).
    pub variants: Vec<String>,
    pub variant: Option<String>,
    /// What the scene as loaded approximates (its textures mip-mapped or reduced to a budget,
    /// `texture_levels`): the metadata lists it among the render's approximations.
    pub approximations: Vec<String>,
}

impl Scene {
    pub fn triangle_count(&self) -> usize {
        let posed_nodes = self.nodes.iter().filter_map(|n| n.mesh);
        posed_nodes.map(|m| self.meshes[m].triangle_count()).sum()
    }
}

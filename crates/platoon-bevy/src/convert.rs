//! Bevy's data as platoon's: meshes, StandardMaterial, images, lights, cameras and transforms.
//! Each conversion keeps what platoon models and names what it drops (`Warnings`).

use std::f32::consts::PI;

use bevy::asset::{AssetId, Handle};
use bevy::camera::Projection;
use bevy::color::{Color, ColorToComponents, LinearRgba};
use bevy::image::{Image, ImageAddressMode, ImageFilterMode, ImageSampler};
use bevy::light::{DirectionalLight, PointLight, SpotLight};
use bevy::math::Affine2;
use bevy::mesh::{Indices, Mesh, PrimitiveTopology, UvChannel, VertexAttributeValues};
use bevy::pbr::StandardMaterial;
use bevy::render::render_resource::TextureFormat;
use bevy::transform::components::GlobalTransform;
use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use platoon::core::scene::camera::Camera;
use platoon::core::scene::{
    AlphaMode, LightKind, Material, Mesh as PMesh, Placement, PunctualLight, Texture, TextureRef,
    Wrap,
};

use crate::warnings::Warnings;

/// A Bevy vector as platoon's glam (Bevy links another glam release).
fn v3(v: bevy::math::Vec3) -> Vec3 {
    Vec3::from_array(v.to_array())
}

fn linear3(c: Color) -> Vec3 {
    Vec3::from_array(c.to_linear().to_f32_array_no_alpha())
}

/// Where a Bevy entity is in the world, as a placement of a platoon node without a parent.
pub fn placement(t: &GlobalTransform) -> Placement {
    let (scale, rotation, translation) = t.to_scale_rotation_translation();
    Placement {
        translation: v3(translation).as_dvec3(),
        rotation: Quat::from_array(rotation.to_array()),
        scale: v3(scale),
    }
}

/// The camera Bevy renders from: its world transform and projection, for an image of
/// `width` x `height` (platoon takes the aspect ratio from the image).
pub fn camera(t: &GlobalTransform, projection: &Projection, width: u32, height: u32) -> Camera {
    let to_world = Mat4::from_cols_array(&t.to_matrix().to_cols_array());
    let mut camera = Camera::look_at(Vec3::ZERO, -Vec3::Z, 0.8);
    camera.camera_to_world = to_world;
    match projection {
        Projection::Perspective(p) => camera.yfov = p.fov,
        Projection::Orthographic(o) => {
            // Half the view's height in world units, the width from the image's aspect.
            let half_h = (o.area.height() * 0.5).max(1e-6);
            camera.orthographic = Some([half_h * width as f32 / height.max(1) as f32, half_h]);
        }
        // A custom projection has no field of view to read: Bevy's default perspective.
        Projection::Custom(_) => camera.yfov = PI / 4.0,
    }
    camera
}

/// A mesh asset as a platoon mesh whose every triangle has material `material`; None (and a
/// warning) for what is not a triangle list with positions.
pub fn mesh(
    m: &Mesh,
    name: &str,
    material: u32,
    needs_tangents: bool,
    warnings: &mut Warnings,
) -> Option<PMesh> {
    if m.primitive_topology() != PrimitiveTopology::TriangleList {
        warnings.once(format!(
            "mesh {name}: {:?} is not rendered (platoon traces triangle lists)",
            m.primitive_topology()
        ));
        return None;
    }
    let attribute = |id| m.try_attribute_option(id).ok().flatten();
    let Some(positions) = attribute(Mesh::ATTRIBUTE_POSITION).and_then(|a| a.as_float3()) else {
        warnings.once(format!(
            "mesh {name}: no positions in the main world (its data went to the GPU only: keep RenderAssetUsages::MAIN_WORLD); not rendered"
        ));
        return None;
    };
    let positions: Vec<Vec3> = positions.iter().map(|p| Vec3::from_array(*p)).collect();
    let count = positions.len();
    let floats3 = |id| -> Vec<Vec3> {
        attribute(id)
            .and_then(|a| a.as_float3())
            .filter(|a| a.len() == count)
            .map_or(Vec::new(), |a| {
                a.iter().map(|v| Vec3::from_array(*v)).collect()
            })
    };
    let floats2 = |id| -> Vec<Vec2> {
        match attribute(id) {
            Some(VertexAttributeValues::Float32x2(a)) if a.len() == count => {
                a.iter().map(|v| Vec2::from_array(*v)).collect()
            }
            _ => Vec::new(),
        }
    };
    let floats4 = |id| -> Vec<Vec4> {
        match attribute(id) {
            Some(VertexAttributeValues::Float32x4(a)) if a.len() == count => {
                a.iter().map(|v| Vec4::from_array(*v)).collect()
            }
            _ => Vec::new(),
        }
    };
    let indices: Vec<u32> = match m.try_indices_option().ok().flatten() {
        Some(Indices::U16(i)) => i.iter().map(|&i| i as u32).collect(),
        Some(Indices::U32(i)) => i.clone(),
        None => (0..count as u32).collect(),
    };
    if indices.iter().any(|&i| i as usize >= count) {
        warnings.once(format!(
            "mesh {name}: an index past its vertices; not rendered"
        ));
        return None;
    }
    let indices: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let joints = match attribute(Mesh::ATTRIBUTE_JOINT_INDEX) {
        Some(VertexAttributeValues::Uint16x4(a)) if a.len() == count => a.clone(),
        _ => Vec::new(),
    };
    let normals = floats3(Mesh::ATTRIBUTE_NORMAL);
    let uvs = floats2(Mesh::ATTRIBUTE_UV_0);
    let mut tangents = floats4(Mesh::ATTRIBUTE_TANGENT);
    if needs_tangents && tangents.is_empty() && !normals.is_empty() && !uvs.is_empty() {
        tangents = platoon::core::scene::tangents::generate(&positions, &normals, &uvs, &indices);
    }
    if m.has_morph_targets() {
        warnings.once(format!(
            "mesh {name}: morph targets are not mirrored (the mesh renders in its base shape)"
        ));
    }
    Some(PMesh {
        name: name.into(),
        triangle_materials: vec![material; indices.len()],
        positions,
        normals,
        tangents,
        uvs,
        uvs1: floats2(Mesh::ATTRIBUTE_UV_1),
        colors: floats4(Mesh::ATTRIBUTE_COLOR),
        indices,
        weights: if joints.is_empty() {
            Vec::new()
        } else {
            floats4(Mesh::ATTRIBUTE_JOINT_WEIGHT)
        },
        joints,
        ..Default::default()
    })
}

/// An image as a platoon texture: 8-bit RGBA (sRGB or linear, decoded where it is used).
pub fn texture(image: &Image, name: &str, warnings: &mut Warnings) -> Option<Texture> {
    let format = image.texture_descriptor.format;
    if !matches!(
        format,
        TextureFormat::Rgba8UnormSrgb | TextureFormat::Rgba8Unorm
    ) {
        warnings.once(format!(
            "texture {name}: format {format:?} is not mirrored (8-bit RGBA only); the material renders without it"
        ));
        return None;
    }
    let (width, height) = (image.width(), image.height());
    let data = image.data.as_ref()?;
    if data.len() < (width * height * 4) as usize {
        return None;
    }
    let (wrap_s, wrap_t, nearest) = match &image.sampler {
        ImageSampler::Descriptor(d) => (
            wrap(d.address_mode_u),
            wrap(d.address_mode_v),
            d.mag_filter == ImageFilterMode::Nearest,
        ),
        // Bevy's default sampler: clamped and linear unless the app's ImagePlugin says otherwise.
        ImageSampler::Default => (Wrap::ClampToEdge, Wrap::ClampToEdge, false),
    };
    Some(Texture {
        name: name.into(),
        width,
        height,
        rgba8: data[..(width * height * 4) as usize].to_vec(),
        wrap_s,
        wrap_t,
        nearest,
        mips: Vec::new(),
    })
}

fn wrap(mode: ImageAddressMode) -> Wrap {
    match mode {
        ImageAddressMode::Repeat => Wrap::Repeat,
        ImageAddressMode::MirrorRepeat => Wrap::MirroredRepeat,
        _ => Wrap::ClampToEdge,
    }
}

/// StandardMaterial as a platoon material; `texture` gives the platoon index of an image
/// (None: not mirrored).
pub fn material(
    m: &StandardMaterial,
    name: &str,
    texture: &mut dyn FnMut(AssetId<Image>) -> Option<u32>,
    warnings: &mut Warnings,
) -> Material {
    let uv = uv_transform(m.uv_transform);
    let mut slot = |image: &Option<bevy::asset::Handle<Image>>, channel: &UvChannel| {
        image
            .as_ref()
            .and_then(|h| texture(h.id()))
            .map(|t| TextureRef {
                texture: t,
                tex_coord: match channel {
                    UvChannel::Uv0 => 0,
                    UvChannel::Uv1 => 1,
                },
                transform: uv,
            })
    };
    let alpha_mode = match m.alpha_mode {
        bevy::prelude::AlphaMode::Opaque => AlphaMode::Opaque,
        bevy::prelude::AlphaMode::Mask(c) => AlphaMode::Mask(c),
        bevy::prelude::AlphaMode::Blend => AlphaMode::Blend,
        other => {
            warnings.once(format!(
                "material {name}: alpha mode {other:?} renders as Blend (coverage)"
            ));
            AlphaMode::Blend
        }
    };
    if m.depth_map.is_some() {
        warnings.once(format!(
            "material {name}: parallax (depth_map) is not mirrored"
        ));
    }
    let emissive: LinearRgba = m.emissive;
    Material {
        name: name.into(),
        base_color: Vec4::from_array(m.base_color.to_linear().to_f32_array()),
        base_color_texture: slot(&m.base_color_texture, &m.base_color_channel),
        metallic: m.metallic,
        roughness: m.perceptual_roughness,
        metallic_roughness_texture: slot(
            &m.metallic_roughness_texture,
            &m.metallic_roughness_channel,
        ),
        normal_texture: slot(&m.normal_map_texture, &m.normal_map_channel),
        emissive: Vec3::new(emissive.red, emissive.green, emissive.blue),
        emissive_texture: slot(&m.emissive_texture, &m.emissive_channel),
        // Bevy's reflectance 0.5 is glTF's specular 1 (F0 = 0.04): KHR_materials_specular's
        // mapping, as Bevy's glTF loader makes it.
        specular: (m.reflectance * 2.0).max(0.0),
        specular_color: linear3(m.specular_tint),
        transmission: m.specular_transmission,
        ior: m.ior,
        clearcoat: m.clearcoat,
        clearcoat_roughness: m.clearcoat_perceptual_roughness,
        diffuse_transmission: m.diffuse_transmission,
        thickness: m.thickness,
        attenuation_distance: m.attenuation_distance,
        attenuation_color: linear3(m.attenuation_color),
        anisotropy_strength: m.anisotropy_strength,
        anisotropy_rotation: m.anisotropy_rotation,
        alpha_mode,
        double_sided: m.double_sided,
        unlit: m.unlit,
        ..Material::default()
    }
}

/// The images a StandardMaterial shows that [`material`] mirrors.
pub fn texture_handles(m: &StandardMaterial) -> impl Iterator<Item = &Handle<Image>> {
    [
        &m.base_color_texture,
        &m.metallic_roughness_texture,
        &m.normal_map_texture,
        &m.emissive_texture,
    ]
    .into_iter()
    .flatten()
}

/// KHR_texture_transform's matrix rows from Bevy's UV transform (u' = a u + b v + c).
fn uv_transform(t: Affine2) -> [[f32; 3]; 2] {
    let (x, y, c) = (t.matrix2.x_axis, t.matrix2.y_axis, t.translation);
    [[x.x, y.x, c.x], [x.y, y.y, c.y]]
}

/// Bevy's lights as KHR_lights_punctual's (what platoon reads): a point or spot light's
/// luminous power (lm) back to its intensity (cd), as Bevy's glTF loader multiplies by 4 pi.
pub fn point_light(l: &PointLight, name: &str, warnings: &mut Warnings) -> PunctualLight {
    soft_shadow_warning(l.radius, name, warnings);
    PunctualLight {
        name: name.into(),
        kind: LightKind::Point,
        color: linear3(l.color),
        intensity: l.intensity / (4.0 * PI),
        range: l.range.max(0.0),
    }
}

pub fn spot_light(l: &SpotLight, name: &str, warnings: &mut Warnings) -> PunctualLight {
    soft_shadow_warning(l.radius, name, warnings);
    let outer = l.outer_angle.clamp(1e-4, PI / 2.0);
    PunctualLight {
        name: name.into(),
        kind: LightKind::Spot {
            inner_cone: l.inner_angle.clamp(0.0, outer),
            outer_cone: outer,
        },
        color: linear3(l.color),
        intensity: l.intensity / (4.0 * PI),
        range: l.range.max(0.0),
    }
}

pub fn directional_light(l: &DirectionalLight, name: &str) -> PunctualLight {
    PunctualLight {
        name: name.into(),
        kind: LightKind::Directional,
        color: linear3(l.color),
        intensity: l.illuminance,
        range: 0.0,
    }
}

fn soft_shadow_warning(radius: f32, name: &str, warnings: &mut Warnings) {
    if radius > 0.0 {
        warnings.once(format!(
            "light {name}: its radius (soft shadows) is not mirrored; it renders as a point"
        ));
    }
}

//! Bevy's environment map light (a cubemap) as platoon's distant light (an equirectangular
//! map): every texel of the map looks up the cube the way Bevy's shader does.

use bevy::image::Image;
use bevy::math::Quat;
use bevy::render::render_resource::{TextureDataOrder, TextureFormat};
use glam::Vec3;
use platoon::core::scene::environment::EnvMap;

/// The equirectangular map of `cube` (6 square layers) scaled by `intensity` and turned by
/// `rotation` as Bevy turns its lookups; Err names what it cannot read.
pub fn equirect(cube: &Image, intensity: f32, rotation: Quat) -> Result<EnvMap, String> {
    let face = cube.width() as usize;
    let d = &cube.texture_descriptor;
    if d.size.depth_or_array_layers != 6 || cube.height() as usize != face || face == 0 {
        return Err(format!(
            "{} x {} x {} is not a cubemap",
            face,
            cube.height(),
            d.size.depth_or_array_layers
        ));
    }
    let bytes = d.format.block_copy_size(None).unwrap_or(0) as usize;
    let decode: fn(&[u8]) -> [f32; 3] = match d.format {
        TextureFormat::Rgba32Float => |b| std::array::from_fn(|k| f32_at(b, 4 * k)),
        TextureFormat::Rgba16Float => |b| std::array::from_fn(|k| f16_at(b, 2 * k)),
        TextureFormat::Rgb9e5Ufloat => rgb9e5,
        other => {
            return Err(format!(
                "format {other:?} (not Rgba32Float, Rgba16Float or Rgb9e5)"
            ))
        }
    };
    let data = cube
        .data
        .as_ref()
        .ok_or("its data is in the render world only (keep RenderAssetUsages::MAIN_WORLD)")?;
    // Where each layer's largest mip starts: layer after layer, or all largest mips first.
    let mips = d.mip_level_count.max(1) as usize;
    let level = |m: usize| (face >> m).max(1).pow(2) * bytes;
    let layer_start = |layer: usize| match cube.data_order {
        TextureDataOrder::LayerMajor => layer * (0..mips).map(level).sum::<usize>(),
        TextureDataOrder::MipMajor => layer * level(0),
    };
    if data.len() < layer_start(5) + level(0) {
        return Err(format!("{} bytes of data is short", data.len()));
    }
    let (width, height) = (
        (4 * face).clamp(64, 1024) as u32,
        (2 * face).clamp(32, 512) as u32,
    );
    let mut texels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let u = (x as f32 + 0.5) / width as f32;
            let v = (y as f32 + 0.5) / height as f32;
            // platoon's uv_to_direction (shaders/common/environment.glsl)...
            let (phi, theta) = ((u - 0.5) * std::f32::consts::TAU, v * std::f32::consts::PI);
            let dir = Vec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                -theta.sin() * phi.cos(),
            );
            // ...then Bevy's lookup (environment_map.wgsl): turned, z mirrored.
            let turned = rotation * bevy::math::Vec3::from_array(dir.to_array());
            let (layer, s, t) = cube_face([turned.x, turned.y, -turned.z]);
            let texel = |c: f32| ((c * face as f32) as usize).min(face - 1);
            let at = layer_start(layer) + (texel(t) * face + texel(s)) * bytes;
            let c = decode(&data[at..at + bytes]);
            texels.push(c.map(|c| c * intensity));
        }
    }
    Ok(EnvMap {
        path: "Bevy environment map".into(),
        width,
        height,
        texels,
    })
}

/// The cube layer a direction looks up and its texture coordinates in [0, 1] (Vulkan's and
/// wgpu's face selection: +X, -X, +Y, -Y, +Z, -Z).
fn cube_face(d: [f32; 3]) -> (usize, f32, f32) {
    let [x, y, z] = d;
    let (ax, ay, az) = (x.abs(), y.abs(), z.abs());
    let (layer, sc, tc, ma) = if ax >= ay && ax >= az {
        if x > 0.0 {
            (0, -z, -y, ax)
        } else {
            (1, z, -y, ax)
        }
    } else if ay >= az {
        if y > 0.0 {
            (2, x, z, ay)
        } else {
            (3, x, -z, ay)
        }
    } else if z > 0.0 {
        (4, x, -y, az)
    } else {
        (5, -x, -y, az)
    };
    (layer, 0.5 * (sc / ma + 1.0), 0.5 * (tc / ma + 1.0))
}

fn f32_at(b: &[u8], i: usize) -> f32 {
    f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

/// IEEE half to f32 (the map's texels are finite, non-negative radiance).
fn f16_at(b: &[u8], i: usize) -> f32 {
    let h = u16::from_le_bytes([b[i], b[i + 1]]) as u32;
    let (sign, exp, frac) = ((h >> 15) & 1, (h >> 10) & 0x1f, h & 0x3ff);
    let magnitude = match exp {
        0 => frac as f32 * (-24f32).exp2(),
        31 => f32::INFINITY,
        e => (1.0 + frac as f32 / 1024.0) * (e as f32 - 15.0).exp2(),
    };
    if sign == 1 {
        -magnitude
    } else {
        magnitude
    }
}

/// RGB9E5: three 9-bit mantissas sharing a 5-bit exponent (bias 15).
fn rgb9e5(b: &[u8]) -> [f32; 3] {
    let p = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    let scale = ((p >> 27) as f32 - 15.0 - 9.0).exp2();
    [p & 0x1ff, (p >> 9) & 0x1ff, (p >> 18) & 0x1ff].map(|m| m as f32 * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_six_faces_are_the_axes_bevy_samples() {
        // +X, -X, +Y, -Y, +Z, -Z at their centres.
        let axes = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        for (layer, d) in axes.into_iter().enumerate() {
            assert_eq!(cube_face(d), (layer, 0.5, 0.5));
        }
        assert_eq!(f16_at(&0x3c00u16.to_le_bytes(), 0), 1.0);
        assert_eq!(f16_at(&0x4500u16.to_le_bytes(), 0), 5.0);
        // 1.0 in RGB9E5: mantissa 256, exponent 16 (2^(16 - 15 - 9) * 256 = 1).
        let one = 256u32 | (256 << 9) | (256 << 18) | (16 << 27);
        assert_eq!(rgb9e5(&one.to_le_bytes()), [1.0, 1.0, 1.0]);
    }
}

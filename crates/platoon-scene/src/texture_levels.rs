//! Textures' lower levels: mip maps for lookups by ray cone (`TextureLod::RayCone`), and
//! textures halved to fit a memory budget, the largest first, as a texture cache keeps the
//! lower levels resident when memory is short. Both are approximations the metadata names
//! (`Scene::approximations`); with neither, every lookup reads the image as loaded.

use rayon::prelude::*;

use super::{MipLevel, Scene, Texture};
use crate::error::{Error, Result};

/// Which level of a texture a lookup reads.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextureLod {
    /// The full-resolution image, always: the pixel's samples integrate the texture (unbiased,
    /// aliased in the distance until enough samples land).
    #[default]
    Off,
    /// Mip maps made at load, the level chosen from the camera path's ray cone (the width a
    /// pixel's cone has where it meets the surface, over the square root of the cosine: the
    /// geometric mean of its footprint's axes, surface.glsl's `cone_lod`; after Akenine-Möller
    /// et al., "Improved Shader and Texture Level of Detail Using Ray Cones", 2021): one
    /// isotropic level, so a surface at a grazing angle blurs more than a supersampled image.
    RayCone,
}

impl TextureLod {
    pub const NAMES: [&'static str; 2] = ["off", "ray-cone"];

    pub fn name(self) -> &'static str {
        match self {
            TextureLod::Off => "off",
            TextureLod::RayCone => "ray-cone",
        }
    }

    pub fn parse(s: &str) -> std::result::Result<TextureLod, String> {
        match s {
            "off" => Ok(TextureLod::Off),
            "ray-cone" => Ok(TextureLod::RayCone),
            _ => Err(format!(
                "{s}: expected one of {}",
                TextureLod::NAMES.join(", ")
            )),
        }
    }
}

/// What loading does to a scene's textures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TextureOptions {
    pub lod: TextureLod,
    /// The bytes every texture together may take on a device, mip levels included: past it
    /// the largest textures are halved until they fit (None: as loaded).
    pub budget: Option<u64>,
}

impl TextureOptions {
    /// Gives `scene`'s textures their mip maps and fits them to the budget, recording what that
    /// approximates in `scene.approximations`. Refused when the textures cannot fit the budget
    /// even at one texel each.
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        if scene.textures.is_empty() {
            return Ok(());
        }
        let srgb = srgb_textures(scene);
        let mipped = self.lod == TextureLod::RayCone;
        if let Some(budget) = self.budget {
            // Sizes first, so that no level the budget drops is ever made.
            let sizes: Vec<(u32, u32)> =
                scene.textures.iter().map(|t| (t.width, t.height)).collect();
            let halvings = fit(&sizes, mipped, budget).map_err(|e| match &scene.source {
                Some(path) => Error::file(path, e),
                None => Error::Invalid(e),
            })?;
            scene
                .textures
                .par_iter_mut()
                .zip(&halvings)
                .zip(&srgb)
                .for_each(|((t, &k), &srgb)| {
                    for _ in 0..k {
                        let below = half(t.width, t.height, &t.rgba8, srgb);
                        (t.width, t.height, t.rgba8) = (below.width, below.height, below.rgba8);
                        t.mips.clear();
                    }
                });
            let halved: u32 = halvings.iter().sum();
            if halved > 0 {
                scene.approximations.push(format!(
                    "textures halved {halved} time{} to fit the texture budget of {} ({} as \
                     loaded)",
                    if halved == 1 { "" } else { "s" },
                    crate::byte_size::size(budget),
                    crate::byte_size::size(sizes.iter().map(|&s| bytes(s, mipped)).sum())
                ));
            }
        }
        if mipped {
            scene
                .textures
                .par_iter_mut()
                .zip(&srgb)
                .for_each(|(t, &srgb)| make_mips(t, srgb));
            scene.approximations.push(
                "textures read at a mip level chosen by the camera path's ray cone (isotropic: \
                 blurs at grazing angles)"
                    .into(),
            );
        }
        Ok(())
    }
}

/// The bytes of a `width` x `height` texture, with its mip levels where `mipped`.
fn bytes((mut width, mut height): (u32, u32), mipped: bool) -> u64 {
    let mut total = 4 * width as u64 * height as u64;
    while mipped && (width > 1 || height > 1) {
        (width, height) = ((width / 2).max(1), (height / 2).max(1));
        total += 4 * width as u64 * height as u64;
    }
    total
}

/// Per texture, whether some material reads it as colour (sRGB-encoded: filtered in linear).
fn srgb_textures(scene: &Scene) -> Vec<bool> {
    let mut srgb = vec![false; scene.textures.len()];
    for m in &scene.materials {
        let colour = [
            m.base_color_texture,
            m.emissive_texture,
            m.specular_color_texture,
            m.diffuse_transmission_color_texture,
            m.sheen_color_texture,
        ];
        for t in colour.into_iter().flatten() {
            if let Some(s) = srgb.get_mut(t.texture as usize) {
                *s = true;
            }
        }
    }
    srgb
}

/// Every level below `t`'s base, down to 1 x 1.
fn make_mips(t: &mut Texture, srgb: bool) {
    t.mips.clear();
    let (mut w, mut h) = (t.width, t.height);
    while w > 1 || h > 1 {
        let above = t.mips.last().map_or(&t.rgba8, |m| &m.rgba8);
        let level = half(w, h, above, srgb);
        (w, h) = (level.width, level.height);
        t.mips.push(level);
    }
}

/// How many times each texture of `sizes` is halved for all to fit `budget`: the largest
/// (the first of equals) each time, until they fit.
fn fit(sizes: &[(u32, u32)], mipped: bool, budget: u64) -> std::result::Result<Vec<u32>, String> {
    let mut sizes = sizes.to_vec();
    let mut halvings = vec![0; sizes.len()];
    let mut total: u64 = sizes.iter().map(|&s| bytes(s, mipped)).sum();
    while total > budget {
        let largest = (0..sizes.len())
            .filter(|&i| sizes[i] != (1, 1))
            .max_by_key(|&i| (sizes[i].0 as u64 * sizes[i].1 as u64, usize::MAX - i));
        let Some(i) = largest else {
            return Err(format!(
                "the scene's {} texture{} take {} at one texel each, more than the texture \
                 budget of {}",
                sizes.len(),
                if sizes.len() == 1 { "" } else { "s" },
                crate::byte_size::size(total),
                crate::byte_size::size(budget)
            ));
        };
        let (w, h) = sizes[i];
        let below = ((w / 2).max(1), (h / 2).max(1));
        total = total - bytes(sizes[i], mipped) + bytes(below, mipped);
        sizes[i] = below;
        halvings[i] += 1;
    }
    Ok(halvings)
}

/// The level below a `width` x `height` RGBA8 image: each texel the mean of the texels its
/// footprint covers (in part, at odd sizes), colour averaged in linear light where `srgb`.
pub fn half(width: u32, height: u32, rgba8: &[u8], srgb: bool) -> MipLevel {
    if width.is_multiple_of(2) && height.is_multiple_of(2) {
        return half_even(width, height, rgba8, srgb);
    }
    let (w, h) = ((width / 2).max(1), (height / 2).max(1));
    let decode = decode_table(srgb);
    let linear: Vec<[f32; 4]> = rgba8
        .chunks_exact(4)
        .map(|c| {
            [
                decode[c[0] as usize],
                decode[c[1] as usize],
                decode[c[2] as usize],
                c[3] as f32 / 255.0,
            ]
        })
        .collect();
    let (xs, ys) = (box_weights(width, w), box_weights(height, h));
    // Rows first (width shrinks), then columns.
    let mut rows = vec![[0f32; 4]; (w * height) as usize];
    for y in 0..height as usize {
        let src = &linear[y * width as usize..][..width as usize];
        for (x, taps) in xs.iter().enumerate() {
            rows[y * w as usize + x] = weighted(taps.iter().map(|&(i, k)| (src[i], k)));
        }
    }
    let mut out = Vec::with_capacity((4 * w * h) as usize);
    for taps in &ys {
        for x in 0..w as usize {
            let c = weighted(taps.iter().map(|&(i, k)| (rows[i * w as usize + x], k)));
            let encode = |v: f32| if srgb { linear_to_srgb(v) } else { v };
            out.extend([encode(c[0]), encode(c[1]), encode(c[2]), c[3]].map(unorm8));
        }
    }
    MipLevel {
        width: w,
        height: h,
        rgba8: out,
    }
}

/// [`half`] of an image of even sides: each texel the mean of a 2 x 2 block, read straight from
/// the bytes (the general path's float copies of a 2048 x 2048 image are 96 MiB, and their
/// page faults were most of the time it took).
fn half_even(width: u32, height: u32, rgba8: &[u8], srgb: bool) -> MipLevel {
    let (w, h) = (width / 2, height / 2);
    let decode = decode_table(true);
    let encode = srgb.then(encode_table);
    let row = 4 * width as usize;
    let mut out = Vec::with_capacity(4 * w as usize * h as usize);
    for pair in rgba8.chunks_exact(2 * row) {
        let (top, bottom) = pair.split_at(row);
        for (a, b) in top.chunks_exact(8).zip(bottom.chunks_exact(8)) {
            for c in 0..4 {
                let texels = [a[c], a[c + 4], b[c], b[c + 4]];
                out.push(match encode {
                    Some(encode) if c < 3 => {
                        let sum: f32 = texels.iter().map(|&t| decode[t as usize]).sum();
                        encode[(sum * 0.25 * 65535.0 + 0.5) as usize]
                    }
                    _ => ((texels.iter().map(|&t| t as u32).sum::<u32>() + 2) / 4) as u8,
                });
            }
        }
    }
    MipLevel {
        width: w,
        height: h,
        rgba8: out,
    }
}

/// Linear light in 65,536 steps to sRGB bytes (a step is a twentieth of a byte's step even
/// where the curve is steepest, near black).
fn encode_table() -> &'static [u8] {
    static TABLE: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        (0..65536)
            .map(|i| unorm8(linear_to_srgb(i as f32 / 65535.0)))
            .collect()
    })
}

/// For each of `to` texels along an axis of `from`, the source texels its footprint covers and
/// the share of the footprint each covers.
fn box_weights(from: u32, to: u32) -> Vec<Vec<(usize, f32)>> {
    let scale = from as f64 / to as f64;
    (0..to)
        .map(|x| {
            let (a, b) = (x as f64 * scale, (x + 1) as f64 * scale);
            (a.floor() as usize..(b.ceil() as usize).min(from as usize))
                .map(|i| {
                    let cover = (b.min(i as f64 + 1.0) - a.max(i as f64)).max(0.0);
                    (i, (cover / scale) as f32)
                })
                .filter(|&(_, k)| k > 0.0)
                .collect()
        })
        .collect()
}

fn weighted(taps: impl Iterator<Item = ([f32; 4], f32)>) -> [f32; 4] {
    let mut s = [0f32; 4];
    for (c, k) in taps {
        for (s, c) in s.iter_mut().zip(c) {
            *s += k * c;
        }
    }
    s
}

fn decode_table(srgb: bool) -> [f32; 256] {
    std::array::from_fn(|i| {
        let v = i as f32 / 255.0;
        if !srgb {
            v
        } else if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    })
}

fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.0031308 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

fn unorm8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Material, TextureRef, Wrap};

    /// The bytes of every level of the textures.
    fn texture_bytes(textures: &[Texture]) -> u64 {
        let level = |w: u32, h: u32| 4 * w as u64 * h as u64;
        textures
            .iter()
            .map(|t| {
                level(t.width, t.height)
                    + t.mips.iter().map(|m| level(m.width, m.height)).sum::<u64>()
            })
            .sum()
    }

    fn texture(width: u32, height: u32, rgba8: Vec<u8>) -> Texture {
        Texture {
            name: "t".into(),
            width,
            height,
            rgba8,
            wrap_s: Wrap::Repeat,
            wrap_t: Wrap::Repeat,
            nearest: false,
            mips: Vec::new(),
        }
    }

    #[test]
    fn a_level_is_the_mean_of_its_footprint_in_linear_light() {
        let (black, white) = ([0u8, 0, 0, 0], [255u8, 255, 255, 255]);
        let checker = [black, white, white, black].concat();
        // Data: the plain mean. Colour: the mean in linear light, 0.5 -> sRGB 188.
        assert_eq!(half(2, 2, &checker, false).rgba8, vec![128; 4]);
        assert_eq!(half(2, 2, &checker, true).rgba8, vec![188, 188, 188, 128]);
        // Odd sizes: the footprint covers one and a half texels on each side of the middle.
        let row: Vec<u8> = [[0u8; 4], [90; 4], [180; 4]].concat();
        let one = half(3, 1, &row, false);
        assert_eq!((one.width, one.height), (1, 1));
        assert_eq!(one.rgba8, vec![90; 4]);
    }

    #[test]
    fn the_even_sides_shortcut_matches_the_general_footprint_mean() {
        let rgba8: Vec<u8> = (0..8 * 6 * 4).map(|i| (i * 37 % 256) as u8).collect();
        for srgb in [false, true] {
            let fast = half(8, 6, &rgba8, srgb);
            let decode = decode_table(srgb);
            let (xs, ys) = (box_weights(8, 4), box_weights(6, 3));
            for (y, ty) in ys.iter().enumerate() {
                for (x, tx) in xs.iter().enumerate() {
                    for c in 0..4 {
                        let mut mean = 0.0;
                        for &(j, ky) in ty {
                            for &(i, kx) in tx {
                                let t = rgba8[4 * (j * 8 + i) + c];
                                let v = if c < 3 {
                                    decode[t as usize]
                                } else {
                                    t as f32 / 255.0
                                };
                                mean += kx * ky * v;
                            }
                        }
                        let want = unorm8(if srgb && c < 3 {
                            linear_to_srgb(mean)
                        } else {
                            mean
                        });
                        let got = fast.rgba8[4 * (y * 4 + x) + c];
                        assert!(got.abs_diff(want) <= 1, "{srgb} {x},{y},{c}: {got} {want}");
                    }
                }
            }
        }
    }

    #[test]
    fn mip_maps_go_down_to_one_texel() {
        let mut t = texture(5, 3, vec![7; 5 * 3 * 4]);
        make_mips(&mut t, true);
        let sizes: Vec<(u32, u32)> = t.mips.iter().map(|m| (m.width, m.height)).collect();
        assert_eq!(sizes, [(2, 1), (1, 1)]);
        assert!(t.mips.iter().all(|m| m.rgba8.iter().all(|&c| c == 7)));
    }

    #[test]
    fn a_budget_halves_the_largest_textures_first_and_says_so() {
        let mut scene = Scene {
            textures: vec![texture(8, 8, vec![0; 256]), texture(4, 4, vec![0; 64])],
            materials: vec![Material {
                base_color_texture: Some(TextureRef::new(0)),
                ..Default::default()
            }],
            ..Default::default()
        };
        // 320 bytes as loaded; 200 takes the 8 x 8 down to 4 x 4 (64 + 64 bytes).
        let options = TextureOptions {
            lod: TextureLod::Off,
            budget: Some(200),
        };
        options.apply(&mut scene).unwrap();
        let sizes: Vec<u32> = scene.textures.iter().map(|t| t.width).collect();
        assert_eq!(sizes, [4, 4]);
        assert_eq!(texture_bytes(&scene.textures), 128);
        assert!(
            scene.approximations[0].starts_with("textures halved 1 time to"),
            "{:?}",
            scene.approximations
        );
        // With mip maps the budget counts them, and halving drops the top level.
        let mut mipped = Scene {
            textures: vec![texture(8, 8, vec![0; 256])],
            ..Default::default()
        };
        let lod = TextureOptions {
            lod: TextureLod::RayCone,
            budget: Some(100),
        };
        lod.apply(&mut mipped).unwrap();
        let t = &mipped.textures[0];
        assert_eq!((t.width, t.mips.len()), (4, 2));
        assert_eq!(texture_bytes(&mipped.textures), 4 * (16 + 4 + 1));
        // A budget below one texel a texture is refused, naming both sizes.
        let e = TextureOptions {
            lod: TextureLod::Off,
            budget: Some(7),
        }
        .apply(&mut scene)
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("2 textures take 8 B") && e.contains("budget of 7 B"),
            "{e}"
        );
    }

    #[test]
    fn the_lod_names_parse_back() {
        for name in TextureLod::NAMES {
            assert_eq!(TextureLod::parse(name).unwrap().name(), name);
        }
        assert!(TextureLod::parse("trilinear")
            .unwrap_err()
            .contains("off, ray-cone"));
    }
}

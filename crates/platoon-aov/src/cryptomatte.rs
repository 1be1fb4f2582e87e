//! Cryptomatte (Friedman and Jones 2015; the public specification 1.2): per pixel, the objects
//! (or materials) its samples hit, ranked by coverage, each named by the MurmurHash3 of its
//! name stored as a float, with a manifest of the names in the EXR's header, so that Nuke's or
//! Blender's compositor picks a matte by clicking an object. Coverage counts the first hits of
//! [`SAMPLES`] of the beauty's own camera rays (`aov::AovPass::SampleIds`: the pixel filter's
//! and the lens' draws, so every sample weighs one); samples that see no surface count for
//! nothing.

use std::collections::BTreeMap;

use platoon_accel::HitNames;
use platoon_image::{Film, Layer};

/// Camera rays a pixel's coverage is counted from.
pub const SAMPLES: u32 = 16;
/// Ranks written: Blender's default depth, two to a layer (id and coverage in R, G and B, A).
pub const DEPTH: usize = 6;

/// What a Cryptomatte layer tells apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Object,
    Material,
    /// An object's topmost ancestor (Cycles' asset: the root of its parenting).
    Asset,
}

impl Kind {
    /// The layer's type name (its layers are `{name}00`, `{name}01`, ...).
    pub fn type_name(self) -> &'static str {
        match self {
            Kind::Object => "CryptoObject",
            Kind::Material => "CryptoMaterial",
            Kind::Asset => "CryptoAsset",
        }
    }
}

/// MurmurHash3 (x86, 32 bits, seed 0) of `name`'s UTF-8 bytes.
pub fn murmur3(name: &str) -> u32 {
    murmur3::murmur3_32(&mut name.as_bytes(), 0).expect("reading from memory")
}

/// The float a name's hash is stored as: its bits, but an exponent of all zeros or all ones
/// (a denormal, an infinity or a NaN, which compositing would mangle) has its low bit flipped.
pub fn id_of(name: &str) -> f32 {
    let mut bits = murmur3(name);
    let exponent = (bits >> 23) & 0xff;
    if exponent == 0 || exponent == 0xff {
        bits ^= 1 << 23;
    }
    f32::from_bits(bits)
}

/// The manifest's form of an id: its float's bits in 8 hex digits.
pub fn id_hex(id: f32) -> String {
    format!("{:08x}", id.to_bits())
}

/// The layers of `kind` from the ids of [`SAMPLES`] camera rays a pixel (`films`, one a ray),
/// named by `names`: `{type}00` to `{type}02`, the first carrying the header's attributes.
pub fn layers(kind: Kind, films: &[&Film], names: &HitNames) -> Vec<Layer> {
    let pixels = films[0].pixels.len();
    // Each name's id, hashed once (a pixel's 16 rays mostly meet the same few names).
    let mut ids: BTreeMap<&str, f32> = BTreeMap::new();
    // Per pixel, (id, rays) ranked by rays, then by the id's bits: DEPTH at most.
    let ranked: Vec<Vec<(f32, u32)>> = (0..pixels)
        .map(|i| {
            let mut seen: Vec<(f32, u32)> = Vec::new();
            for f in films {
                let [instance, material, triangle] = f.pixels[i];
                if instance == 0.0 {
                    continue;
                }
                let name = match kind {
                    Kind::Object => names.object(instance as u32 - 1, triangle as u32 - 1),
                    Kind::Material => names.material(material as u32 - 1),
                    Kind::Asset => names.asset(instance as u32 - 1, triangle as u32 - 1),
                };
                let Some(name) = name else { continue };
                let id = *ids.entry(name).or_insert_with(|| id_of(name));
                match seen.iter_mut().find(|(s, _)| s.to_bits() == id.to_bits()) {
                    Some((_, n)) => *n += 1,
                    None => seen.push((id, 1)),
                }
            }
            seen.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.to_bits().cmp(&b.0.to_bits())));
            seen.truncate(DEPTH);
            seen
        })
        .collect();
    let rays = films.len() as f32;
    let type_name = kind.type_name();
    let key = &format!("{:08x}", murmur3(type_name))[..7];
    let manifest: BTreeMap<&str, String> = ids.iter().map(|(&n, &id)| (n, id_hex(id))).collect();
    let manifest = serde_json::to_string(&manifest).expect("names serialise");
    (0..DEPTH / 2)
        .map(|l| {
            let plane = |rank: usize, coverage: bool| -> Vec<f32> {
                (ranked.iter())
                    .map(|r| match r.get(rank) {
                        Some(&(_, n)) if coverage => n as f32 / rays,
                        Some(&(id, _)) => id,
                        None => 0.0,
                    })
                    .collect()
            };
            let (a, b) = (2 * l, 2 * l + 1);
            Layer {
                name: format!("{type_name}{l:02}"),
                channels: vec![
                    ("R".into(), plane(a, false)),
                    ("G".into(), plane(a, true)),
                    ("B".into(), plane(b, false)),
                    ("A".into(), plane(b, true)),
                ],
                attributes: match l {
                    0 => [
                        ("name", type_name.to_string()),
                        ("hash", "MurmurHash3_32".into()),
                        ("conversion", "uint32_to_float32".into()),
                        ("manifest", manifest.clone()),
                    ]
                    .into_iter()
                    .map(|(k, v)| (format!("cryptomatte/{key}/{k}"), v))
                    .collect(),
                    _ => Vec::new(),
                },
                full_float: true,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_hash_as_the_specification_says() {
        // MurmurHash3_x86_32 with seed 0, against the reference implementation's values.
        assert_eq!(murmur3(""), 0);
        assert_eq!(murmur3("hello"), 0x248b_fa47);
        assert_eq!(murmur3("Hello, world!"), 0xc036_3e43);
        // The specification's example manifest.
        assert_eq!(id_hex(id_of("bunny")), "13851a76");
        assert_eq!(id_hex(id_of("default")), "42c9679f");
        // An exponent of all ones or zeros has its low bit flipped: the id is a normal float.
        for name in (0..2000).map(|i| format!("object {i}")) {
            let id = id_of(&name);
            assert!(id.is_normal(), "{name}: {id}");
            assert_eq!(id.to_bits() & !(1 << 23), murmur3(&name) & !(1 << 23));
        }
    }
}

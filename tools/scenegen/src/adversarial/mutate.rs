//! Seeded random mutations of real assets: digits changed inside the glTF JSON (counts,
//! offsets, indices, strides, factors), random bytes flipped anywhere, and truncations. Each
//! mutant either still renders a finite image or must be refused cleanly.

use std::path::Path;

use super::{Case, Expect, File};

/// xorshift64*: a fixed seed gives the same suite on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// The byte range of the JSON text: the JSON chunk of a .glb, or the whole of a .gltf.
fn json_range(bytes: &[u8]) -> std::ops::Range<usize> {
    if bytes.starts_with(b"glTF") && bytes.len() >= 20 {
        let len = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as usize;
        20..(20 + len).min(bytes.len())
    } else {
        0..bytes.len()
    }
}

fn mutate(bytes: &[u8], kind: usize, rng: &mut Rng) -> Vec<u8> {
    let mut out = bytes.to_vec();
    match kind {
        0 => {
            // Change one to three digits of the JSON.
            let range = json_range(bytes);
            let digits: Vec<usize> = range.filter(|&i| bytes[i].is_ascii_digit()).collect();
            for _ in 0..1 + rng.below(3) {
                if !digits.is_empty() {
                    out[digits[rng.below(digits.len())]] = b'0' + rng.below(10) as u8;
                }
            }
        }
        1 => {
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(out.len());
                out[i] ^= 1 << rng.below(8);
            }
        }
        _ => out.truncate(rng.below(bytes.len())),
    }
    out
}

/// `per_file` mutants of each .glb and .gltf in `folder`, in name order (none if it is absent).
pub fn mutations(folder: &Path, per_file: usize, seed: u64) -> Vec<Case> {
    let mut files: Vec<_> = std::fs::read_dir(folder)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("glb" | "gltf")));
    files.sort();
    let mut rng = Rng(seed | 1);
    let mut cases = Vec::new();
    for path in files {
        let Ok(bytes) = std::fs::read(&path) else {
            continue;
        };
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        let ext = path.extension().unwrap().to_string_lossy().to_string();
        for k in 0..per_file {
            let name = format!("mutant_{stem}_{k}");
            let mutated = mutate(&bytes, k % 3, &mut rng);
            cases.push(Case {
                files: vec![(format!("{name}.{ext}"), File::Bytes(mutated))],
                name,
                expect: Expect::FiniteOrRefused,
            });
        }
    }
    cases
}

//! The directions every element shoots (the paper's link generation): an s x s stratified
//! square of cell centres (n_C = s^2), numbered in 4 x 4 blocks when s is a multiple of 4 (two
//! blocks are the paper's 32-ray warp, so a SIMD group's rays leave in neighbouring
//! directions), mapped to the disk by Shirley and Chiu's concentric map and lifted to the
//! hemisphere: cosine-distributed about +z. The same set at every element, so the links of a
//! scene are a pure function of its geometry. A fixed set is a quadrature, not an estimator:
//! its error does not average out over elements (the mean cosine is 0.675 at 256 rays, 0.6697
//! at 1024, against 2/3), one of the floors the convergence sweep measures.

use glam::Vec3;

use crate::error::{Error, Result};

/// Side of the stratified blocks in which rays are numbered.
const BLOCK: u32 = 4;

/// The `count` directions in the element's frame (+z the normal), in ray order. `count` must
/// be a square of at least 4 (16, 64, 256 and 1024 are the sweep's).
pub fn directions(count: u32) -> Result<Vec<Vec3>> {
    let side = (count as f64).sqrt().round() as u32;
    if count < 4 || side * side != count {
        return Err(Error::Invalid(format!(
            "links: {count} directions per element is not a square of at least 4 (16, 64, 256, 1024 are)"
        )));
    }
    Ok((0..count).map(|r| direction(cell(r, side), side)).collect())
}

/// The cell (column, row) of ray `r` in a square of `side` cells.
fn cell(r: u32, side: u32) -> (u32, u32) {
    if !side.is_multiple_of(BLOCK) {
        return (r % side, r / side);
    }
    let per_block = BLOCK * BLOCK;
    let (block, within) = (r / per_block, r % per_block);
    let blocks_per_row = side / BLOCK;
    (
        (block % blocks_per_row) * BLOCK + within % BLOCK,
        (block / blocks_per_row) * BLOCK + within / BLOCK,
    )
}

/// The cosine-distributed direction through the centre of `cell`.
fn direction(cell: (u32, u32), side: u32) -> Vec3 {
    let u = (cell.0 as f64 + 0.5) / side as f64;
    let v = (cell.1 as f64 + 0.5) / side as f64;
    let (x, y) = concentric_disk(2.0 * u - 1.0, 2.0 * v - 1.0);
    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
    Vec3::new(x as f32, y as f32, z as f32).normalize()
}

/// Shirley and Chiu's map of the square [-1, 1]^2 to the unit disk, area-preserving.
fn concentric_disk(a: f64, b: f64) -> (f64, f64) {
    use std::f64::consts::FRAC_PI_4;
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if a * a > b * b {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_are_unit_and_above_the_surface() {
        for n in [16, 64, 256, 1024] {
            let d = directions(n).unwrap();
            assert_eq!(d.len(), n as usize);
            for v in &d {
                assert!((v.length() - 1.0).abs() < 1e-6 && v.z > 0.0, "{v}");
            }
        }
    }

    /// Cosine-distributed about the normal: E[cos] = 2/3, E[cos^2] = 1/2, E[x] = E[y] = 0,
    /// E[x^2] = E[y^2] = 1/4 (a uniform or a squashed set fails these), up to the cell
    /// centres' quadrature error, which shrinks with n_C (E[cos] is 0.0086 high at 256 rays,
    /// 0.0030 at 1024: no centre reaches the grazing rim).
    #[test]
    fn directions_have_the_cosine_distributions_moments() {
        let moments = |n: u32| {
            let d = directions(n).unwrap();
            let count = d.len() as f64;
            let mean = |f: &dyn Fn(&Vec3) -> f64| d.iter().map(f).sum::<f64>() / count;
            assert!(mean(&|v| v.x as f64).abs() < 1e-6 && mean(&|v| v.y as f64).abs() < 1e-6);
            [
                mean(&|v| v.z as f64) - 2.0 / 3.0,
                mean(&|v| (v.z * v.z) as f64) - 0.5,
                mean(&|v| (v.x * v.x) as f64) - 0.25,
                mean(&|v| (v.y * v.y) as f64) - 0.25,
            ]
        };
        let (coarse, fine) = (moments(256), moments(1024));
        for (c, f) in coarse.iter().zip(&fine) {
            assert!(f.abs() < 3.5e-3, "{fine:?}");
            assert!(f.abs() < c.abs() / 2.5, "{coarse:?} {fine:?}");
        }
    }

    /// Every cell once, and a block's 16 rays in neighbouring cells.
    #[test]
    fn rays_are_numbered_in_blocks_covering_every_cell_once() {
        let side = 16;
        let mut seen = vec![false; 256];
        for r in 0..256 {
            let (x, y) = cell(r, side);
            assert!(!std::mem::replace(&mut seen[(y * side + x) as usize], true));
            let first = cell(r - r % 16, side);
            assert!(x - first.0 < 4 && y - first.1 < 4);
        }
        assert_eq!(cell(16, side), (4, 0));
        assert_eq!(cell(3, 6), (3, 0));
    }

    #[test]
    fn a_count_that_is_not_a_square_is_refused() {
        for n in [0, 1, 3, 100 + 1, 255] {
            let e = directions(n).unwrap_err().to_string();
            assert!(e.contains("not a square"), "{e}");
        }
        assert!(directions(4).is_ok());
    }
}

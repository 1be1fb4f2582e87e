//! The gather (Jacobi iteration over the link groups) and the feature-preserving smoothing.
//!
//! With L_0 = rho / pi * E_d (the direct light's reflected radiance at each element),
//! E_k(x) = pi * sum_y w_xy L_{k-1}(y) and L_k = rho / pi * E_k; pi cancels:
//! E_k(x) = sum_y w_xy rho_y E_{k-1}(y), with E_0 = E_d. The indirect irradiance is
//! E_ind = E_1 + ... + E_{n_B}. Every bounce reads only the previous one (Jacobi, not
//! Gauss-Seidel), and each sum runs in group order, so the result is a pure function of the
//! groups, the albedos and the direct light.

use super::reduce::LinkGroups;

pub type Rgb = [f32; 3];

/// The indirect irradiance E_1 + ... + E_`bounces` at every element, from the direct
/// irradiance `direct` (E_d) and the diffuse albedo `albedo` (rho) of each element.
pub fn gather(links: &LinkGroups, albedo: &[Rgb], direct: &[Rgb], bounces: u32) -> Vec<Rgb> {
    let n = links.elements();
    assert!(albedo.len() == n && direct.len() == n);
    let mut indirect = vec![[0.0f32; 3]; n];
    let mut previous = direct.to_vec();
    let mut next = vec![[0.0f32; 3]; n];
    for _ in 0..bounces {
        for (x, e) in next.iter_mut().enumerate() {
            let mut sum = [0.0f32; 3];
            for (y, w) in links.group(x) {
                let (rho, ey) = (albedo[y as usize], previous[y as usize]);
                for c in 0..3 {
                    sum[c] += w * rho[c] * ey[c];
                }
            }
            *e = sum;
        }
        for (total, e) in indirect.iter_mut().zip(&next) {
            for c in 0..3 {
                total[c] += e[c];
            }
        }
        std::mem::swap(&mut previous, &mut next);
    }
    indirect
}

/// Neighbours of each element (its one-ring), as CSR: element x's are
/// `neighbours[offsets[x]..offsets[x + 1]]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rings {
    pub offsets: Vec<u32>,
    pub neighbours: Vec<u32>,
}

/// The paper's smoothing (its Eq. 5-6): each element's value averaged with those of its
/// one-ring neighbours whose normal is within the feature angle of its own
/// (n . n_i > `cos_feature`), so that light does not bleed across creases.
pub fn smooth(values: &[Rgb], normals: &[glam::Vec3], rings: &Rings, cos_feature: f32) -> Vec<Rgb> {
    assert!(values.len() == normals.len() && rings.offsets.len() == values.len() + 1);
    (0..values.len())
        .map(|x| {
            let mut sum = values[x];
            let mut count = 1.0f32;
            let range = rings.offsets[x] as usize..rings.offsets[x + 1] as usize;
            for &i in &rings.neighbours[range] {
                if normals[x].dot(normals[i as usize]) > cos_feature {
                    for c in 0..3 {
                        sum[c] += values[i as usize][c];
                    }
                    count += 1.0;
                }
            }
            sum.map(|s| s / count)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::reduce::{LinkGroups, RayHit};
    use super::*;
    use glam::Vec3;

    /// Links of `n` elements that each see every element (itself excluded) with weights from a
    /// fixed hash, summing to `reach` (1: a closed scene).
    fn all_to_all(n: u32, reach: f64) -> LinkGroups {
        let mut g = LinkGroups {
            offsets: vec![0],
            ..Default::default()
        };
        for x in 0..n {
            let raw: Vec<f64> = (0..n)
                .filter(|&y| y != x)
                .map(|y| 1.0 + ((x * 7 + y * 13) % 5) as f64)
                .collect();
            let total: f64 = raw.iter().sum();
            for (y, r) in (0..n).filter(|&y| y != x).zip(&raw) {
                g.peers.push(y);
                g.weights.push((r / total * reach) as f32);
            }
            g.offsets.push(g.peers.len() as u32);
        }
        g
    }

    /// The closed form of the brief: in a closed scene of one albedo under uniform direct
    /// light, E_k = rho^k E_d at every element, whatever the weights.
    #[test]
    fn a_closed_scene_of_one_albedo_gathers_rho_to_the_k() {
        let (n, rho, ed) = (12, 0.6f32, 2.0f32);
        let links = all_to_all(n, 1.0);
        let albedo = vec![[rho, rho * 0.5, 0.0]; n as usize];
        for bounces in 1..=4 {
            let e = gather(&links, &albedo, &vec![[ed; 3]; n as usize], bounces);
            let series = |r: f32| (1..=bounces).map(|k| r.powi(k as i32) * ed).sum::<f32>();
            for v in &e {
                assert!((v[0] - series(rho)).abs() < 1e-5 * series(rho), "{v:?}");
                assert!((v[1] - series(rho * 0.5)).abs() < 1e-5 * series(rho * 0.5));
                assert_eq!(v[2], 0.0);
            }
        }
    }

    /// Against the linear algebra done apart in f64: E_ind = sum_k (W R)^k E_d, for uneven
    /// albedos, direct light and an open scene (weights summing to 0.7).
    #[test]
    fn the_gather_is_the_sum_of_powers_of_the_transport_matrix() {
        let n = 9usize;
        let links = all_to_all(n as u32, 0.7);
        let albedo: Vec<Rgb> = (0..n).map(|i| [0.1 + 0.08 * i as f32, 0.5, 0.9]).collect();
        let direct: Vec<Rgb> = (0..n)
            .map(|i| [(i % 3) as f32, 1.0, 0.25 * i as f32])
            .collect();
        let mut w = vec![vec![0.0f64; n]; n];
        for (x, row) in w.iter_mut().enumerate() {
            for (y, weight) in links.group(x) {
                row[y as usize] = weight as f64;
            }
        }
        let e = gather(&links, &albedo, &direct, 3);
        for c in 0..3 {
            let mut prev: Vec<f64> = direct.iter().map(|d| d[c] as f64).collect();
            let mut total = vec![0.0f64; n];
            for _ in 0..3 {
                let next: Vec<f64> = (0..n)
                    .map(|x| {
                        (0..n)
                            .map(|y| w[x][y] * albedo[y][c] as f64 * prev[y])
                            .sum()
                    })
                    .collect();
                for x in 0..n {
                    total[x] += next[x];
                }
                prev = next;
            }
            for x in 0..n {
                assert!(
                    (e[x][c] as f64 - total[x]).abs() < 1e-5 * (1.0 + total[x]),
                    "{c} {x}"
                );
            }
        }
    }

    #[test]
    fn no_bounce_gathers_nothing_and_a_lone_element_nothing_either() {
        let links = LinkGroups::from_hits(1, &[None]);
        assert_eq!(gather(&links, &[[1.0; 3]], &[[5.0; 3]], 3), [[0.0; 3]]);
        let hit = RayHit {
            corners: [1, 1, 1],
            barycentrics: [1.0, 0.0, 0.0],
        };
        let links = LinkGroups::from_hits(1, &[Some(hit), None]);
        assert_eq!(
            gather(&links, &[[1.0; 3]; 2], &[[5.0; 3]; 2], 0),
            [[0.0; 3]; 2]
        );
    }

    /// A crease of 90 degrees between element 0 and 1 is kept with a 30-degree feature angle;
    /// the flat neighbour 2 is averaged in.
    #[test]
    fn smoothing_averages_across_flat_ground_and_not_across_creases() {
        let values = [[1.0, 0.0, 0.0], [9.0, 9.0, 9.0], [3.0, 2.0, 0.0]];
        let normals = [Vec3::Z, Vec3::X, Vec3::new(0.1, 0.0, 1.0).normalize()];
        let rings = Rings {
            offsets: vec![0, 2, 3, 4],
            neighbours: vec![1, 2, 0, 0],
        };
        let s = smooth(&values, &normals, &rings, 30f32.to_radians().cos());
        assert_eq!(s[0], [2.0, 1.0, 0.0]);
        assert_eq!(s[1], values[1]);
        assert_eq!(s[2], [2.0, 1.0, 0.0]);
    }
}

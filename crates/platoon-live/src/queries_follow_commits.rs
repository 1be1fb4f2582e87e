//! The core's CPU ray queries (`platoon_core::flatten::queries`) following a living scene's
//! commits.

use crate::{Edit, Updater};
use glam::DVec3;
use glam::{Vec3, Vec4};
use platoon_core::flatten::queries::*;
use platoon_core::flatten::GpuScene;
use platoon_core::scene::Placement;

/// Every triangle of the scene in world space, tested one by one: the answer the BVH
/// traversal must give.
fn brute_force(scene: &GpuScene, origin: Vec3, dir: Vec3) -> Option<f32> {
    let mut best: Option<f32> = None;
    for inst in &scene.instances {
        let m = glam::Mat4::from_cols(
            Vec4::from_array(inst.object_to_world[0]),
            Vec4::from_array(inst.object_to_world[1]),
            Vec4::from_array(inst.object_to_world[2]),
            Vec4::W,
        )
        .transpose();
        let region = scene
            .regions
            .iter()
            .find(|r| r.root == inst.blas_root)
            .expect("the instance's mesh");
        for t in region.triangle_base..region.triangle_base + region.triangle_count {
            let p = |k: usize| {
                m.transform_point3(Vec3::from_slice(
                    &scene.triangle_positions[3 * t as usize + k][..3],
                ))
            };
            if let Some((th, _, _)) =
                RayTri::new(origin, dir).intersect_triangle(p(0), p(1), p(2), f32::INFINITY)
            {
                best = Some(best.map_or(th, |b: f32| b.min(th)));
            }
        }
    }
    best
}

#[test]
fn queries_find_what_testing_every_triangle_finds_and_follow_commits() {
    let mut updater =
        Updater::new(platoon_core::scene::cornell::scene(), 0.0, DVec3::ZERO).unwrap();
    updater
        .apply(Edit::AddInstance {
            mesh: 0,
            placement: Placement {
                scale: glam::Vec3::splat(0.2),
                ..Placement::at(DVec3::new(0.1, 0.2, 0.3))
            },
        })
        .unwrap()
        .expect("an added instance has a node");
    let mut q = QueryScene::new(updater.flattened());
    let g = updater.update().unwrap();
    q.apply_commit(&g.commit);
    let scene = updater.flattened();
    let (lo, hi) = updater.scene().pose(0.0).bounds();
    let size = (hi - lo).max_element();
    let origin = (lo + hi) * 0.5 - Vec3::Z * 1.5 * size;
    let (mut hits, mut checked) = (0, 0);
    for i in 0..400 {
        let a = i as f32 * 0.61;
        let dir = Vec3::new(0.3 * a.sin(), 0.3 * (1.3 * a).cos(), 1.0).normalize();
        let expected = brute_force(scene, origin, dir);
        let got = q.closest_hit(origin, dir, f32::INFINITY);
        checked += 1;
        match (expected, got) {
            (Some(e), Some(h)) => {
                hits += 1;
                assert!(
                    (e - h.t).abs() <= 1e-4 * e.max(1.0),
                    "ray {i}: {e} vs {}",
                    h.t
                );
                assert!(q.occluded(origin, dir, h.t * 1.001));
                assert!(!q.occluded(origin, dir, h.t * 0.999));
            }
            (None, None) => {}
            (e, h) => panic!("ray {i}: brute force {e:?}, query {h:?}"),
        }
    }
    assert!(hits > checked / 2, "{hits} of {checked}");
}

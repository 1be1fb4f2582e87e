//! CPU traversal cost of the two node layouts obvhs builds, on the same triangles and rays: the
//! evidence behind the kernel's BVH2 (docs/ARCHITECTURE.md, "BVH layout"; `platoon bench
//! kernel` prints it for the field of unique spheres).

use std::time::{Duration, Instant};

use glam::{Vec3, Vec3A};
use obvhs::ray::Ray;
use obvhs::triangle::Triangle;
use platoon::Prepared;
use platoon_core::flatten::bvh::{build_params, flatten, BuildQuality, BvhNode};

/// The two layouts on a prepared scene (the bench's 100k-triangle field) flattened to world
/// space: one primary ray per pixel of a 256x256 view plus as many random rays from inside the
/// scene; with the triangle and ray counts.
pub fn on_prepared(p: &Prepared) -> (LayoutComparison, usize, usize) {
    let mut tris = Vec::new();
    for inst in &p.posed.instances {
        let mesh = &p.posed.meshes[inst.mesh];
        for t in &mesh.indices {
            let v = t.map(|i| {
                Vec3A::from(
                    inst.object_to_world
                        .transform_point3(mesh.positions[i as usize]),
                )
            });
            tris.push(obvhs::triangle::Triangle {
                v0: v[0],
                v1: v[1],
                v2: v[2],
            });
        }
    }
    let cam = p.camera.camera_to_world;
    let origin = Vec3A::from(cam.transform_point3(Vec3::ZERO));
    let tan = (p.camera.yfov * 0.5).tan();
    let mut rays = Vec::new();
    let mut state = 0x1234_5678u32;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    for y in 0..256 {
        for x in 0..256 {
            let d = Vec3::new(
                (x as f32 / 128.0 - 1.0) * tan,
                (1.0 - y as f32 / 128.0) * tan,
                -1.0,
            );
            rays.push(Ray::new_inf(
                origin,
                Vec3A::from(cam.transform_vector3(d).normalize()),
            ));
            let o = Vec3A::new(rnd() * 10.0 - 5.0, rnd() * 3.0, rnd() * 10.0 - 5.0);
            let d = Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize_or(Vec3A::Y);
            rays.push(Ray::new_inf(o, d));
        }
    }
    (compare_layouts(&tris, &rays), tris.len(), rays.len())
}

/// CPU traversal cost of the two node layouts obvhs builds, on the same triangles and rays:
/// the evidence behind the BVH2 choice (docs/ARCHITECTURE.md). lavapipe runs kernels on these
/// same CPU cores, so the CPU figures bound what each layout can reach there.
#[derive(Clone, Copy, Debug)]
pub struct LayoutComparison {
    pub bvh2_rays_per_s: f64,
    pub cwbvh_rays_per_s: f64,
    pub bvh2_node_bytes: usize,
    pub cwbvh_node_bytes: usize,
    pub bvh2_build: Duration,
    pub cwbvh_build: Duration,
    /// Both layouts found the same closest hits.
    pub hits_agree: bool,
}

pub fn compare_layouts(tris: &[Triangle], rays: &[obvhs::ray::Ray]) -> LayoutComparison {
    use obvhs::ray::RayHit;
    let mut bvh2_build = Duration::ZERO;
    let mut cwbvh_build = Duration::ZERO;
    let b2 = obvhs::bvh2::builder::build_bvh2_from_tris(
        tris,
        build_params(BuildQuality::Static),
        &mut bvh2_build,
    );
    let cw = obvhs::cwbvh::builder::build_cwbvh_from_tris(
        tris,
        build_params(BuildQuality::Static),
        &mut cwbvh_build,
    );
    let run = |trace: &dyn Fn(&obvhs::ray::Ray) -> f32| {
        let start = Instant::now();
        let hits: Vec<f32> = rays.iter().map(trace).collect();
        (rays.len() as f64 / start.elapsed().as_secs_f64(), hits)
    };
    let (bvh2_rays_per_s, h2) = run(&|ray| {
        let mut hit = RayHit::none();
        b2.ray_traverse(*ray, &mut hit, |r, i| {
            tris[b2.primitive_indices[i] as usize].intersect(r)
        });
        hit.t
    });
    let (cwbvh_rays_per_s, hc) = run(&|ray| {
        let mut hit = RayHit::none();
        cw.ray_traverse(*ray, &mut hit, |r, i| {
            tris[cw.primitive_indices[i] as usize].intersect(r)
        });
        hit.t
    });
    LayoutComparison {
        bvh2_rays_per_s,
        cwbvh_rays_per_s,
        bvh2_node_bytes: std::mem::size_of::<BvhNode>() * flatten(&b2).nodes.len(),
        cwbvh_node_bytes: std::mem::size_of_val(cw.nodes.as_slice()),
        bvh2_build,
        cwbvh_build,
        hits_agree: h2 == hc,
    }
}

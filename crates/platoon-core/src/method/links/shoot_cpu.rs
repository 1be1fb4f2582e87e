//! Link shooting on the CPU, through the core's ray queries (`flatten::queries`): the oracle the
//! devices' shooting is held to, and a way to solve small scenes without a device. Each element
//! shoots the fixed directions about its normal from just above its position (so no ray meets
//! the element's own triangles at a distance of rounding error: a flat or convex one-ring lies
//! below every direction), and a hit arriving at a surface from behind (its geometric normal
//! turned to agree with its element normals) counts as a miss, as light from behind a surface
//! does. A ray
//! that meets one of the element's own triangles at a real distance (a coarse concave surface,
//! whose faces rise above the averaged normal's tangent plane) links to its corners, the element
//! itself included: that face's light is interpolated from them. (The brief's "skip hits on
//! triangles that contain the origin vertex" would let such rays leave a closed room: inside an
//! icosahedron 44% of 64 rays did.)

use glam::Vec3;

use super::reduce::RayHit;
use super::scene_elements::SceneElements;
use crate::flatten::queries::QueryScene;
use crate::flatten::GpuScene;

/// Every element's rays, element after element, in ray order (`LinkGroups::from_hits`' input).
pub fn shoot(g: &GpuScene, elements: &SceneElements, directions: &[Vec3]) -> Vec<Option<RayHit>> {
    let queries = QueryScene::new(g);
    let mut hits = Vec::with_capacity(elements.len() * directions.len());
    for x in 0..elements.len() {
        let frame = ray_frame(elements, x);
        for &d in directions {
            let dir = ray_direction(&frame, d);
            hits.push(trace(g, &queries, elements, frame[0], dir));
        }
    }
    hits
}

fn trace(
    g: &GpuScene,
    queries: &QueryScene,
    elements: &SceneElements,
    origin: Vec3,
    dir: Vec3,
) -> Option<RayHit> {
    let hit = queries.closest_hit(origin, dir, f32::INFINITY)?;
    link_of_hit(
        g,
        elements,
        dir,
        hit.instance,
        hit.triangle,
        [hit.b1, hit.b2],
    )
}

/// The link a ray along `dir` makes by its closest hit (barycentrics `b` of corners 1 and 2 of
/// `triangle` on `instance`): None where it meets the surface from behind. Shared by the CPU's
/// shooting and the devices' (whose kernels return the bare hit).
pub fn link_of_hit(
    g: &GpuScene,
    elements: &SceneElements,
    dir: Vec3,
    instance: u32,
    triangle: u32,
    b: [f32; 2],
) -> Option<RayHit> {
    let tri = g.triangles[triangle as usize];
    let corners = tri.v.map(|v| elements.element(instance, v));
    let barycentrics = [1.0 - b[0] - b[1], b[0], b[1]];
    // The face's side from its geometry (a ray that leaves an element below one of its own
    // faces meets that face from the front at once), turned to the side its shading normals
    // call the front.
    let [a, bb, c] = tri.v.map(|v| g.world_vertex(instance, v));
    let face = (bb - a).cross(c - a);
    let shading: Vec3 = corners
        .iter()
        .zip(barycentrics)
        .map(|(&c, w)| elements.normals[c as usize] * w)
        .sum();
    if face.dot(dir) * face.dot(shading).signum() >= 0.0 {
        return None;
    }
    Some(RayHit {
        corners,
        barycentrics,
    })
}

/// Where element `x`'s rays leave from and the frame its directions turn into: just above
/// its position, by a few ULPs of the position's magnitude (so no ray meets the element's own
/// triangles at a distance of rounding error). (origin, tangent, bitangent, normal.)
pub fn ray_frame(elements: &SceneElements, x: usize) -> [Vec3; 4] {
    let (p, n) = (elements.positions[x], elements.normals[x]);
    let (t, b) = n.any_orthonormal_pair();
    let lift = 1e-5 * (1.0 + p.abs().max_element());
    [p + n * lift, t, b, n]
}

/// Direction `d` (element frame) in render space.
pub fn ray_direction(frame: &[Vec3; 4], d: Vec3) -> Vec3 {
    (frame[1] * d.x + frame[2] * d.y + frame[3] * d.z).normalize()
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::super::directions::directions;
    use super::super::gather::gather;
    use super::super::reduce::LinkGroups;
    use super::*;
    use crate::scene::{Material, Mesh, Node, Scene};

    /// An icosphere (`platoon_scenegen::icosphere`) of radius 2 about (1, 0, 0) seen from
    /// inside: normals pointing in.
    fn inward_sphere(levels: u32) -> Scene {
        let m = platoon_scenegen::icosphere(levels);
        let centre = Vec3::X;
        let sphere = Mesh {
            normals: m.normals.iter().map(|&n| -Vec3::from(n)).collect(),
            positions: m
                .positions
                .iter()
                .map(|&p| centre + Vec3::from(p) * 2.0)
                .collect(),
            triangle_materials: vec![0; m.indices.len() / 3],
            // Wound to face inwards.
            indices: m.indices.chunks(3).map(|t| [t[0], t[2], t[1]]).collect(),
            ..Default::default()
        };
        let mut node = Node::new("sphere");
        node.mesh = Some(0);
        Scene {
            nodes: vec![node],
            meshes: vec![Arc::new(sphere)],
            materials: vec![Material::default()],
            ..Default::default()
        }
    }

    /// The brief's closed form: inside a closed sphere every ray hits, so each element's weights
    /// sum to one, and under uniform direct light (a point light at the centre lights every
    /// vertex alike) the gather gives E_k = rho^k E_d, whatever n_C.
    #[test]
    fn inside_a_closed_sphere_every_element_sees_all_of_it() {
        // The icosahedron's faces rise above a vertex's tangent plane: low rays meet the
        // vertex's own faces, and link to them.
        for (levels, count) in [(0, 12), (2, 162)] {
            closed_sphere(levels, count);
        }
    }

    fn closed_sphere(levels: u32, count: usize) {
        let scene = inward_sphere(levels);
        let g = GpuScene::build(&scene, &scene.pose(0.0), None).unwrap();
        let elements = SceneElements::of(&g, 0.9).unwrap();
        assert_eq!(elements.len(), count);
        for n_c in [16, 64, 256] {
            let hits = shoot(&g, &elements, &directions(n_c).unwrap());
            let links = LinkGroups::from_hits(n_c, &hits);
            assert!(links.raw_links > links.peers.len() as u64);
            for x in 0..elements.len() {
                let sum: f32 = links.group(x).map(|l| l.1).sum();
                assert!((sum - 1.0).abs() < 1e-5, "element {x}, n_C {n_c}: {sum}");
                assert!(links.group(x).all(|l| l.1 > 0.0));
            }
            // Rays below 32 degrees of elevation meet the icosahedron's faces around their own
            // vertex (from 64 directions on), and link to it; the finer sphere's faces rise
            // less than its lowest rays.
            let own = (0..count)
                .filter(|&x| links.group(x).any(|l| l.0 == x as u32))
                .count();
            let expected = if levels == 0 && n_c >= 64 { 12 } else { 0 };
            assert_eq!(own, expected, "elements linked to themselves");
            let rho = 0.7f32;
            let e = gather(&links, &vec![[rho; 3]; count], &vec![[1.0; 3]; count], 3);
            let expected = rho + rho * rho + rho * rho * rho;
            assert!(e.iter().all(|v| (v[0] - expected).abs() < 1e-5 * expected));
        }
    }

    /// Seen from outside, the same sphere's faces turn their backs: no ray from a plane below
    /// it, pointing up, links to it; turned to face out, they do.
    #[test]
    fn back_faces_are_misses() {
        let mut scene = inward_sphere(1);
        let floor = Mesh {
            positions: vec![
                Vec3::new(-5.0, -3.0, -5.0),
                Vec3::new(5.0, -3.0, -5.0),
                Vec3::new(5.0, -3.0, 5.0),
                Vec3::new(-5.0, -3.0, 5.0),
            ],
            normals: vec![Vec3::Y; 4],
            indices: vec![[0, 2, 1], [0, 3, 2]],
            triangle_materials: vec![0, 0],
            ..Default::default()
        };
        scene.meshes.push(Arc::new(floor));
        let mut node = Node::new("floor");
        node.mesh = Some(1);
        scene.nodes.push(node);
        let linked_from_floor = |scene: &Scene| {
            let g = GpuScene::build(scene, &scene.pose(0.0), None).unwrap();
            let elements = SceneElements::of(&g, 0.9).unwrap();
            let hits = shoot(&g, &elements, &directions(64).unwrap());
            let floor_instance = (0..g.instances.len())
                .find(|&i| elements.instance_base[i + 1] - elements.instance_base[i] == 4)
                .unwrap();
            let first = elements.instance_base[floor_instance] as usize;
            hits[first * 64..(first + 4) * 64].iter().flatten().count()
        };
        assert_eq!(linked_from_floor(&scene), 0);
        let outward = {
            let m = &scene.meshes[0];
            Mesh {
                normals: m.normals.iter().map(|&n| -n).collect(),
                ..(**m).clone()
            }
        };
        scene.meshes[0] = Arc::new(outward);
        assert!(linked_from_floor(&scene) > 0);
    }
}

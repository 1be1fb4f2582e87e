//! The generated scenes of the layered-hit-buffers bench (the thesis' scaling curves): the
//! Cornell box with a central object, either `n` randomly rotated cubes (12 n triangles) or an
//! icosphere subdivided `level` times and displaced (20 * 4^level triangles). The object floats
//! above the floor in the middle of the room, white; its size does not change with its count.

use std::sync::Arc;

use glam::{Quat, Vec3};
use platoon::core::scene::cornell::push_quad;
use platoon::core::scene::{cornell, Mesh, Scene};

/// Where the object floats and how far it reaches.
const CENTRE: Vec3 = Vec3::new(2.775, 2.2, 2.775);
const REACH: f32 = 1.2;

/// The Cornell box with `add` drawing into its mesh (material 0, white).
fn room_with(add: impl FnOnce(&mut Mesh)) -> Scene {
    let mut scene = cornell::scene();
    let mut mesh = (*scene.meshes[0]).clone();
    add(&mut mesh);
    scene.meshes[0] = Arc::new(mesh);
    scene
}

/// A fixed stream of numbers in [0, 1).
fn stream(seed: u64) -> impl FnMut() -> f32 {
    let mut s = seed.max(1);
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// `n` cubes, each randomly rotated, centred at random in a ball of radius REACH, their edges
/// REACH / n^(1/3) (overlapping where they meet).
pub fn cubes(n: u32) -> Scene {
    room_with(|mesh| {
        let mut next = stream(0x9e37_79b9_7f4a_7c15);
        let half = 0.5 * REACH / (n.max(1) as f32).cbrt();
        for _ in 0..n {
            let centre = loop {
                let p = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
                if p.length_squared() <= 1.0 {
                    break CENTRE + p * REACH;
                }
            };
            let rotation = Quat::from_euler(
                glam::EulerRot::XYZ,
                next() * std::f32::consts::TAU,
                next() * std::f32::consts::TAU,
                next() * std::f32::consts::TAU,
            );
            let p = |x: f32, y: f32, z: f32| centre + rotation * (Vec3::new(x, y, z) * half);
            // Counter-clockwise seen from outside.
            for quad in [
                [
                    p(1., -1., -1.),
                    p(1., 1., -1.),
                    p(1., 1., 1.),
                    p(1., -1., 1.),
                ],
                [
                    p(-1., -1., -1.),
                    p(-1., -1., 1.),
                    p(-1., 1., 1.),
                    p(-1., 1., -1.),
                ],
                [
                    p(-1., 1., -1.),
                    p(-1., 1., 1.),
                    p(1., 1., 1.),
                    p(1., 1., -1.),
                ],
                [
                    p(-1., -1., -1.),
                    p(1., -1., -1.),
                    p(1., -1., 1.),
                    p(-1., -1., 1.),
                ],
                [
                    p(-1., -1., 1.),
                    p(1., -1., 1.),
                    p(1., 1., 1.),
                    p(-1., 1., 1.),
                ],
                [
                    p(-1., -1., -1.),
                    p(-1., 1., -1.),
                    p(1., 1., -1.),
                    p(1., -1., -1.),
                ],
            ] {
                push_quad(mesh, quad, 0);
            }
        }
    })
}

/// An icosphere subdivided `level` times, its radius REACH displaced by up to 15% (a bumpy
/// ball), with the undisplaced sphere's normals.
pub fn icosphere(level: u32) -> Scene {
    room_with(|mesh| {
        let sphere = platoon_scenegen::icosphere(level);
        let base = mesh.positions.len() as u32;
        for p in &sphere.positions {
            let d = Vec3::from(*p).normalize();
            let bump = 1.0 + 0.15 * (6.0 * d.x).sin() * (6.0 * d.y).sin() * (6.0 * d.z).sin();
            mesh.positions.push(CENTRE + d * REACH * 0.8 * bump);
            mesh.normals.push(d);
        }
        for t in sphere.indices.chunks_exact(3) {
            mesh.indices.push([base + t[0], base + t[1], base + t[2]]);
            mesh.triangle_materials.push(0);
        }
    })
}

/// The bench's scenes by name: `cubesN`, `icosphereL`, or one of `method::scenes::scenes`'.
pub fn scenes(
    names: &[String],
    shared: &std::path::Path,
) -> anyhow::Result<Vec<crate::method::scenes::MethodScene>> {
    names
        .iter()
        .map(|name| {
            let made = |what: String, scene: Scene| crate::method::scenes::MethodScene {
                name: name.clone(),
                what,
                scene,
                env: platoon::EnvChoice::Scene,
            };
            if let Some(n) = name.strip_prefix("cubes").and_then(|n| n.parse().ok()) {
                return Ok(made(
                    format!(
                        "the Cornell box with {n} rotated cubes ({} triangles)",
                        12 * n
                    ),
                    cubes(n),
                ));
            }
            if let Some(level) = name.strip_prefix("icosphere").and_then(|n| n.parse().ok()) {
                if level > 9 {
                    anyhow::bail!("{name}: at most 9 subdivisions (5M triangles)");
                }
                return Ok(made(
                    format!(
                        "the Cornell box with a bumpy icosphere ({} triangles)",
                        20 * 4u64.pow(level)
                    ),
                    icosphere(level),
                ));
            }
            let mut one = crate::method::scenes::scenes(std::slice::from_ref(name), shared)?;
            Ok(one.remove(0))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_objects_have_the_triangles_their_names_say() {
        let room = cornell::scene().meshes[0].indices.len();
        assert_eq!(cubes(10).meshes[0].indices.len(), room + 120);
        assert_eq!(icosphere(2).meshes[0].indices.len(), room + 320);
        // Closed and facing out: every cube's and the sphere's normals point away from their
        // centres.
        let m = &icosphere(1).meshes[0];
        for t in &m.indices[room..] {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).dot((a + b + c) / 3.0 - CENTRE) > 0.0);
        }
    }
}

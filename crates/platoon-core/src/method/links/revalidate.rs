//! Revalidating links after geometry moved (platoon's own: the paper regenerates every link).
//! Of an earlier shooting's rays only those that can have changed are shot again: the rays of
//! elements that moved, the rays whose hit lay on an instance that moved, and the rays whose
//! way to their hit (to infinity for a miss) crosses a moved instance's new bounds. A moved
//! instance's old bounds need no test of their own: a ray they blocked hit the instance. Every
//! other ray meets the same triangles at the same distances as before, so it hits what it hit
//! (the traversal finds the closest hit whatever the tree), and the links are those of
//! shooting every ray again, bit for bit.

use std::hash::Hasher;

use glam::Vec3;
use rayon::prelude::*;

use super::job::{ElementRays, Shot};
use super::scene_elements::SceneElements;
use super::shoot_cpu::ray_direction;
use crate::flatten::GpuScene;

/// SipHash with fixed keys: the same digest in every process.
pub(super) fn hasher() -> std::collections::hash_map::DefaultHasher {
    std::collections::hash_map::DefaultHasher::new()
}

/// What decides which triangles a ray may pass through (alpha masks and blending: materials
/// and textures), when the scene has any; else 0.
pub fn surface_digest(g: &GpuScene) -> u64 {
    let defines = g.features.defines();
    if !defines
        .iter()
        .any(|d| *d == "HAS_ALPHA_MASK" || *d == "HAS_ALPHA_BLEND")
    {
        return 0;
    }
    let mut h = hasher();
    h.write(bytemuck::cast_slice(&g.materials));
    h.write(bytemuck::cast_slice(&g.textures));
    h.write(bytemuck::cast_slice(&g.texels));
    h.finish()
}

/// A digest of where the arrays keep what a hit names (instances, triangles, vertices by mesh
/// region) and of what decides which triangles a ray may pass through: an earlier shooting's
/// hits are read against a scene with the same.
pub fn layout(g: &GpuScene, directions: &[[f32; 4]]) -> u64 {
    let mut h = hasher();
    for r in &g.regions {
        for v in [
            r.vertex_base,
            r.vertex_count,
            r.triangle_base,
            r.triangle_count,
        ] {
            h.write_u32(v);
        }
    }
    h.write_usize(g.instances.len());
    h.write_usize(g.triangles.len());
    h.write_usize(g.vertices.len());
    h.write(bytemuck::cast_slice(directions));
    h.write_u64(surface_digest(g));
    h.finish()
}

/// A digest of each instance's shape in render space: its transforms, and its mesh region's
/// vertices, triangles, corners and tree.
pub fn shapes(g: &GpuScene, elements: &SceneElements) -> Vec<u64> {
    let regions: Vec<u64> = g
        .regions
        .iter()
        .map(|r| {
            let (v, t) = (r.vertex_base as usize, r.triangle_base as usize);
            let (vn, tn) = (r.vertex_count as usize, r.triangle_count as usize);
            let nodes = r.node_base as usize..(r.node_base + r.node_capacity) as usize;
            let mut h = hasher();
            h.write(bytemuck::cast_slice(&g.vertices[v..v + vn]));
            h.write(bytemuck::cast_slice(&g.triangles[t..t + tn]));
            h.write(bytemuck::cast_slice(
                &g.triangle_positions[3 * t..3 * (t + tn)],
            ));
            h.write(bytemuck::cast_slice(g.blas_nodes.get(nodes).unwrap_or(&[])));
            h.finish()
        })
        .collect();
    g.instances
        .iter()
        .enumerate()
        .map(|(i, instance)| {
            let mut h = hasher();
            h.write_u64(regions[elements.region_of(i)]);
            h.write(bytemuck::bytes_of(instance));
            h.finish()
        })
        .collect()
}

/// What a revalidation shoots again.
pub struct Stale {
    /// The rays (element * n_C + direction), ascending.
    pub rays: Vec<u32>,
    /// Instances whose shape or place changed, and elements that moved (all their rays are
    /// stale).
    pub moved_instances: u32,
    pub moved_elements: u32,
}

/// An axis-aligned box in render space.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    min: Vec3,
    max: Vec3,
}

impl Bounds {
    /// Instance `i`'s triangles' bounds, widened by far more than the rounding of a ray taken
    /// into its object space.
    fn of_instance(g: &GpuScene, elements: &SceneElements, i: usize) -> Bounds {
        let r = &g.regions[elements.region_of(i)];
        let (mut min, mut max) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for v in r.vertex_base..r.vertex_base + r.vertex_count {
            let p = g.world_vertex(i as u32, v);
            (min, max) = (min.min(p), max.max(p));
        }
        let margin = 1e-4 * (1.0 + min.abs().max(max.abs()).max_element());
        Bounds {
            min: min - margin,
            max: max + margin,
        }
    }

    /// Whether the segment from `o` along unit `d` for lengths [0, t_end] meets the box.
    fn crossed(&self, o: Vec3, d: Vec3, t_end: f32) -> bool {
        let (mut near, mut far) = (0.0f32, t_end);
        for a in 0..3 {
            if d[a] == 0.0 {
                if o[a] < self.min[a] || o[a] > self.max[a] {
                    return false;
                }
                continue;
            }
            let (t0, t1) = ((self.min[a] - o[a]) / d[a], (self.max[a] - o[a]) / d[a]);
            near = near.max(t0.min(t1));
            far = far.min(t0.max(t1));
            if near > far {
                return false;
            }
        }
        true
    }
}

/// The rays of `shot` (an earlier shooting) that can have changed in `g`, whose elements shoot
/// `rays` and whose instances have `shapes`; None when the earlier hits cannot be read against
/// `g` (another layout: shoot every ray).
pub fn stale_rays(
    g: &GpuScene,
    elements: &SceneElements,
    rays: &ElementRays,
    shapes: &[u64],
    layout: u64,
    shot: &Shot,
) -> Option<Stale> {
    let n_c = rays.directions.len();
    if shot.layout != layout
        || shot.shapes.len() != shapes.len()
        || shot.rays.elements.len() != rays.elements.len()
        || shot.hits.len() != rays.elements.len() * n_c
    {
        return None;
    }
    let moved: Vec<bool> = shapes
        .iter()
        .zip(&shot.shapes)
        .map(|(a, b)| a != b)
        .collect();
    let bounds: Vec<Bounds> = (0..shapes.len())
        .filter(|&i| moved[i])
        .map(|i| Bounds::of_instance(g, elements, i))
        .collect();
    let directions: Vec<Vec3> = rays
        .directions
        .iter()
        .map(|d| Vec3::from_slice(&d[..3]))
        .collect();
    // Per element: whether it moved, and its stale rays.
    let per_element: Vec<(bool, Vec<u32>)> = (0..rays.elements.len())
        .into_par_iter()
        .map(|x| {
            let (new, old) = (&rays.elements[x], &shot.rays.elements[x]);
            let first = (x * n_c) as u32;
            let frame = [new.origin, new.tangent, new.bitangent, new.normal];
            if frame != [old.origin, old.tangent, old.bitangent, old.normal] {
                return (true, (first..first + n_c as u32).collect());
            }
            let frame = frame.map(|v| Vec3::from_slice(&v[..3]));
            let mut stale = Vec::new();
            for (k, &d) in directions.iter().enumerate() {
                let h = shot.hits[x * n_c + k];
                let (instance, triangle, [b1, b2]) = (h.instance, h.triangle, h.b);
                let t_end = if h.missed() {
                    f32::INFINITY
                } else if moved[instance as usize] {
                    stale.push(first + k as u32);
                    continue;
                } else {
                    let [a, b, c] = g.triangles[triangle as usize]
                        .v
                        .map(|v| g.world_vertex(instance, v));
                    let hit = a * (1.0 - b1 - b2) + b * b1 + c * b2;
                    let t = (hit - frame[0]).length();
                    t * (1.0 + 1e-4) + 1e-4 * (1.0 + hit.abs().max_element())
                };
                let dir = ray_direction(&frame, d);
                if bounds.iter().any(|b| b.crossed(frame[0], dir, t_end)) {
                    stale.push(first + k as u32);
                }
            }
            (false, stale)
        })
        .collect();
    Some(Stale {
        moved_elements: per_element.iter().filter(|e| e.0).count() as u32,
        rays: per_element.into_iter().flat_map(|e| e.1).collect(),
        moved_instances: moved.iter().filter(|&&m| m).count() as u32,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_meets_a_box_only_within_its_length() {
        let b = Bounds {
            min: Vec3::splat(1.0),
            max: Vec3::splat(2.0),
        };
        let o = Vec3::new(0.0, 1.5, 1.5);
        assert!(b.crossed(o, Vec3::X, f32::INFINITY));
        assert!(b.crossed(o, Vec3::X, 1.01));
        assert!(!b.crossed(o, Vec3::X, 0.99));
        assert!(!b.crossed(o, -Vec3::X, f32::INFINITY));
        // Parallel to a face: inside its slab or not.
        assert!(!b.crossed(Vec3::new(0.0, 3.0, 1.5), Vec3::X, f32::INFINITY));
        // From inside.
        assert!(b.crossed(Vec3::splat(1.5), Vec3::Y, 0.0));
    }
}

//! Motion vectors (Cycles' Vector pass, its motion from the previous frame): per pixel, how far
//! on the image the surface seen through the pixel's centre moved since the frame before, in
//! pixels (x right, y down): where it is now minus where the previous frame's camera saw it.
//! The hit (the Position and Ids passes) is carried back through its triangle: its barycentric
//! place on the triangle now, the same place on the triangle's vertices as the previous pose
//! has them (so skinned and morphed meshes move with their vertices), through the instance's
//! previous transform, into the previous camera. Geometry merged because it never moves stays
//! put; a pixel that sees no surface has no motion (0).

use std::collections::HashMap;

use glam::{Mat4, Vec3, Vec4};

use super::Crop;
use crate::flatten::static_merge::MERGED_NODE;
use crate::flatten::GpuScene;
use crate::output::{Film, Layer};
use crate::scene::camera::Camera;
use crate::scene::{Instance, Posed};

/// The frame before: the scene posed then (around the same render-space origin) and its camera.
#[derive(Clone, Debug)]
pub struct PreviousFrame {
    pub posed: Posed,
    pub camera: Camera,
}

/// The layer `motion` (channels X, Y) of a frame seen by `camera` (in pixels of the image it
/// frames, `crop`'s whole image), from its Position and Ids films, the flattened scene `gpu` it
/// was rendered from and the frame before.
pub fn layer(
    position: &Film,
    ids: &Film,
    gpu: &GpuScene,
    camera: &Camera,
    crop: Crop,
    previous: &PreviousFrame,
) -> Layer {
    let (w, h) = (crop.image_width, crop.image_height);
    // Each node's instance in the previous pose, found once rather than per pixel.
    let mut then: HashMap<usize, &Instance> = HashMap::new();
    for i in &previous.posed.instances {
        then.entry(i.node).or_insert(i);
    }
    let mut planes = [
        vec![0.0f32; ids.pixels.len()],
        vec![0.0f32; ids.pixels.len()],
    ];
    for (i, id) in ids.pixels.iter().enumerate() {
        if id[0] == 0.0 {
            continue;
        }
        let now = Vec3::from(position.pixels[i]);
        let (instance, triangle) = (id[0] as u32 - 1, id[2] as u32 - 1);
        let Some(before) = position_before(now, instance, triangle, gpu, previous, &then) else {
            continue;
        };
        // Where the hit is now is its own projection (the pixel's centre, to rounding): the
        // same arithmetic both ways, so a still scene moves by exactly 0.
        let (Some(seen), Some(then)) = (
            camera.project(now, w, h),
            previous.camera.project(before, w, h),
        ) else {
            continue;
        };
        let m = seen - then;
        planes[0][i] = m.x;
        planes[1][i] = m.y;
    }
    let [x, y] = planes;
    Layer {
        name: "motion".into(),
        channels: vec![("X".into(), x), ("Y".into(), y)],
        attributes: Vec::new(),
        full_float: false,
    }
}

/// Where the point `now` (render space) on `triangle` of `instance` was in the frame before,
/// whose instances by node are `instances_then`.
fn position_before(
    now: Vec3,
    instance: u32,
    triangle: u32,
    gpu: &GpuScene,
    previous: &PreviousFrame,
    instances_then: &HashMap<usize, &Instance>,
) -> Option<Vec3> {
    let names = &gpu.hit_names;
    let node = *names.instance_nodes.get(instance as usize)?;
    if node == MERGED_NODE {
        return Some(now);
    }
    let mesh = *names.instance_meshes.get(instance as usize)?;
    let rows = gpu.instances.get(instance as usize)?.world_to_object;
    let to_object = Mat4::from_cols(
        Vec4::from(rows[0]),
        Vec4::from(rows[1]),
        Vec4::from(rows[2]),
        Vec4::W,
    )
    .transpose();
    let p = to_object.transform_point3(now);
    let base = gpu.regions.get(mesh)?.vertex_base;
    let corners = gpu.triangles.get(triangle as usize)?.v;
    let at = |v: u32| Vec3::from_slice(&gpu.vertices[v as usize].position_u[..3]);
    let b = barycentric(p, corners.map(at));
    let then = *instances_then.get(&node)?;
    let mesh_then = previous.posed.meshes.get(then.mesh)?;
    let vertex = |v: u32| mesh_then.positions.get((v - base) as usize).copied();
    let [a, c, d] = [
        vertex(corners[0])?,
        vertex(corners[1])?,
        vertex(corners[2])?,
    ];
    let object = a * b[0] + c * b[1] + d * b[2];
    Some(then.object_to_world.transform_point3(object))
}

/// The barycentric coordinates of `p`'s projection onto the triangle `t`'s plane.
fn barycentric(p: Vec3, t: [Vec3; 3]) -> [f32; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let det = d11 * d22 - d12 * d12;
    if det.abs() <= f32::MIN_POSITIVE {
        return [1.0, 0.0, 0.0];
    }
    let u = (d22 * d1 - d12 * d2) / det;
    let v = (d11 * d2 - d12 * d1) / det;
    [1.0 - u - v, u, v]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_on_a_triangle_is_its_barycentric_mix() {
        let t = [Vec3::ZERO, Vec3::X * 2.0, Vec3::new(0.0, 3.0, 1.0)];
        let b = [0.2, 0.5, 0.3];
        let p = t[0] * b[0] + t[1] * b[1] + t[2] * b[2];
        let got = barycentric(p, t);
        for k in 0..3 {
            assert!((got[k] - b[k]).abs() < 1e-6, "{got:?}");
        }
    }
}

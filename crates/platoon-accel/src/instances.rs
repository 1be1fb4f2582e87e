//! Instances in top-level leaf order, each with its emissive triangles as lights in world space.

use std::f64::consts::PI;

use glam::{Mat4, Vec3};

use super::bvh::FlatBvh;
use super::layout::{GpuInstance, GpuLight, LIGHT_TRIANGLE};
use super::GpuScene;
use platoon_scene::environment::luminance;
use platoon_scene::{Instance, Scene};

fn rows(m: &Mat4) -> [[f32; 4]; 3] {
    let t = m.transpose();
    [
        t.x_axis.to_array(),
        t.y_axis.to_array(),
        t.z_axis.to_array(),
    ]
}

/// Appends the instances of the top level `tlas` (over `live`) and their emissive triangles to
/// `g`; returns each triangle light's power, in the order of `g.lights`.
pub(super) fn add(
    scene: &Scene,
    tlas: &FlatBvh,
    live: &[&Instance],
    mesh_bvhs: &[&FlatBvh],
    g: &mut GpuScene,
) -> Vec<f64> {
    let mut power: Vec<f64> = Vec::new();
    g.hit_names.instance_nodes.clear();
    g.hit_names.instance_meshes.clear();
    for (new_index, &orig) in tlas.order.iter().enumerate() {
        let inst = live[orig as usize];
        g.hit_names.instance_nodes.push(inst.node);
        g.hit_names.instance_meshes.push(inst.mesh);
        let region = g.regions[inst.mesh];
        let tb = region.triangle_base as usize;
        let tri_count = mesh_bvhs[inst.mesh].order.len();
        let first_light = g.lights.len() as u32;
        let facing = if inst.object_to_world.determinant() < 0.0 {
            -1.0
        } else {
            1.0
        };
        for t in tb..tb + tri_count {
            if g.triangle_lights[t] == u32::MAX {
                continue;
            }
            let material = g.triangles[t].material;
            let mat = &scene.materials[material as usize];
            let w: Vec<Vec3> = (0..3)
                .map(|k| {
                    inst.object_to_world
                        .transform_point3(Vec3::from_slice(&g.triangle_positions[3 * t + k][..3]))
                })
                .collect();
            let area = 0.5 * (w[1] - w[0]).cross(w[2] - w[0]).length();
            let sides = if mat.double_sided { 2.0 } else { 1.0 };
            power.push(luminance(mat.emissive) as f64 * area as f64 * PI * sides);
            g.lights.push(GpuLight {
                a: w[0].extend(facing).to_array(),
                // b.w: double-sided (the kernel's emission of an untextured emitter).
                b: w[1]
                    .extend(if mat.double_sided { 1.0 } else { 0.0 })
                    .to_array(),
                c: w[2].extend(0.0).to_array(),
                emission: mat.emissive.extend(0.0).to_array(),
                ids: [LIGHT_TRIANGLE, new_index as u32, t as u32, material],
            });
        }
        g.instances.push(GpuInstance {
            world_to_object: rows(&inst.object_to_world.inverse()),
            object_to_world: rows(&inst.object_to_world),
            blas_root: region.root,
            light_base: if g.lights.len() as u32 > first_light {
                first_light
            } else {
                u32::MAX
            },
            _pad: [0; 2],
        });
    }
    power
}

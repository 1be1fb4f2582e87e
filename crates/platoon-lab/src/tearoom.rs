//! A TEAROOM-like scene for vertex links' bench (the paper's furnished room): a room of 8 x 3 x 6
//! metres, its walls `cells` x `cells` quads, six tables with a chair on each side and a teapot
//! (the shared teapot.gltf's mesh) on each, lit by two ceiling panels. Built in code, so the
//! bench needs only the teapot file.

use std::sync::Arc;

use anyhow::{bail, Result};
use glam::{DVec3, Vec3};
use platoon::core::scene::camera::Camera;
use platoon::core::scene::cornell::{lambertian, push_box, push_grid, push_quad};
use platoon::core::scene::{CameraModel, Mesh, Node, Scene};

/// The room with `teapot`'s first mesh on every table.
pub fn tearoom(teapot: &Scene, cells: u32) -> Result<Scene> {
    let Some(pot) = teapot.meshes.first() else {
        bail!("the teapot scene has no mesh");
    };
    let (w, h, d) = (8.0f32, 3.0f32, 6.0f32);
    let v = Vec3::new;
    let (wall, floor, wood, chair, porcelain, panel) = (0, 1, 2, 3, 4, 5);
    let mut room = Mesh {
        name: "tearoom".into(),
        ..Default::default()
    };
    // Faces turned inwards: floor, ceiling, the four walls.
    let faces = [
        (
            [v(0., 0., 0.), v(0., 0., d), v(w, 0., d), v(w, 0., 0.)],
            floor,
        ),
        ([v(0., h, 0.), v(w, h, 0.), v(w, h, d), v(0., h, d)], wall),
        ([v(0., 0., d), v(0., h, d), v(w, h, d), v(w, 0., d)], wall),
        (
            [v(0., 0., 0.), v(w, 0., 0.), v(w, h, 0.), v(0., h, 0.)],
            wall,
        ),
        ([v(w, 0., 0.), v(w, 0., d), v(w, h, d), v(w, h, 0.)], wall),
        (
            [v(0., 0., 0.), v(0., h, 0.), v(0., h, d), v(0., 0., d)],
            wall,
        ),
    ];
    for (quad, material) in faces {
        push_grid(&mut room, quad, material, cells);
    }
    for x in [2.0f32, 6.0] {
        let y = h - 0.001;
        push_quad(
            &mut room,
            [
                v(x - 0.6, y, 2.4),
                v(x + 0.6, y, 2.4),
                v(x + 0.6, y, 3.6),
                v(x - 0.6, y, 3.6),
            ],
            panel,
        );
    }
    let furniture_cells = (cells / 4).max(1);
    let mut tables = Vec::new();
    for (i, x) in [1.6f32, 4.0, 6.4].into_iter().enumerate() {
        for (j, z) in [1.8f32, 4.2].into_iter().enumerate() {
            let turn = 10.0 * (i as f32 - 1.0) + 5.0 * j as f32;
            push_box(
                &mut room,
                (x, z),
                v(1.2, 0.75, 0.8),
                turn,
                wood,
                furniture_cells,
            );
            for side in [-1.0f32, 1.0] {
                push_box(
                    &mut room,
                    (x + side * 0.95, z),
                    v(0.45, 0.45, 0.45),
                    turn,
                    chair,
                    furniture_cells,
                );
            }
            tables.push((x, z));
        }
    }
    let mut pot = (**pot).clone();
    pot.triangle_materials = vec![porcelain; pot.indices.len()];
    let lowest = pot
        .positions
        .iter()
        .map(|p| p.y)
        .fold(f32::INFINITY, f32::min);
    let scale = 0.06f32;
    let mut nodes = vec![Node::new("room")];
    nodes[0].mesh = Some(0);
    for (k, (x, z)) in tables.into_iter().enumerate() {
        let mut n = Node::new(format!("teapot {k}"));
        n.mesh = Some(1);
        n.scale = Vec3::splat(scale);
        n.translation = DVec3::new(
            x as f64,
            0.75 - (lowest + pot.offset.y as f32) as f64 * scale as f64,
            z as f64,
        );
        nodes.push(n);
    }
    let camera = Camera::look_at(v(0.4, 2.2, 0.4), v(4.5, 0.6, 3.5), 60f32.to_radians());
    let (_, rotation, translation) = camera.camera_to_world.to_scale_rotation_translation();
    let mut eye = Node::new("camera");
    eye.rotation = rotation;
    eye.translation = translation.as_dvec3();
    eye.camera = Some(0);
    nodes.push(eye);
    let mut light = lambertian("panel", Vec3::splat(0.8));
    light.emissive = Vec3::new(12.0, 11.0, 9.0);
    Ok(Scene {
        nodes,
        meshes: vec![Arc::new(room), Arc::new(pot)],
        materials: vec![
            lambertian("wall", Vec3::new(0.75, 0.72, 0.65)),
            lambertian("floor", Vec3::new(0.45, 0.3, 0.2)),
            lambertian("wood", Vec3::new(0.5, 0.35, 0.2)),
            lambertian("chair", Vec3::new(0.25, 0.3, 0.45)),
            lambertian("porcelain", Vec3::splat(0.8)),
            light,
        ],
        cameras: vec![CameraModel {
            name: "tearoom".into(),
            yfov: camera.yfov,
            aspect_ratio: Some(1.0),
            orthographic: None,
        }],
        ..Default::default()
    })
}

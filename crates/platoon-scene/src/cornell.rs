//! The built-in scene: the Cornell box (Goral et al. 1984 dimensions, in metres), Lambertian
//! walls and one downward-facing area light. Built in code, so it ships inside the binary.

use std::sync::Arc;

use glam::{Mat4, Quat, Vec3};

use crate::camera::Camera;
use crate::{Material, Mesh, Node, Scene};

/// A Lambertian material in glTF terms: dielectric with KHR_materials_specular factor 0.
pub fn lambertian(name: &str, albedo: Vec3) -> Material {
    Material {
        name: name.into(),
        base_color: albedo.extend(1.0),
        metallic: 0.0,
        roughness: 1.0,
        specular: 0.0,
        ..Material::default()
    }
}

/// Adds quad (a, b, c, d), counter-clockwise seen from the side its normal points to.
pub fn push_quad(mesh: &mut Mesh, [a, b, c, d]: [Vec3; 4], material: u32) {
    let base = mesh.positions.len() as u32;
    let n = (b - a).cross(c - a).normalize();
    mesh.positions.extend([a, b, c, d]);
    mesh.normals.extend([n; 4]);
    mesh.indices.push([base, base + 1, base + 2]);
    mesh.indices.push([base, base + 2, base + 3]);
    mesh.triangle_materials.extend([material, material]);
}

/// Adds quad (a, b, c, d) as `cells` x `cells` smaller quads (one when `cells` is 1), their
/// vertices shared: a tessellated wall, whose vertices carry light for vertex links.
pub fn push_grid(mesh: &mut Mesh, [a, b, c, d]: [Vec3; 4], material: u32, cells: u32) {
    if cells <= 1 {
        return push_quad(mesh, [a, b, c, d], material);
    }
    let base = mesh.positions.len() as u32;
    let n = (b - a).cross(c - a).normalize();
    let k = cells as f32;
    // Bilinear between the corners: u along a -> b, v along a -> d.
    for j in 0..=cells {
        for i in 0..=cells {
            let (u, v) = (i as f32 / k, j as f32 / k);
            mesh.positions.push(a.lerp(b, u).lerp(d.lerp(c, u), v));
            mesh.normals.push(n);
        }
    }
    let at = |i: u32, j: u32| base + j * (cells + 1) + i;
    for j in 0..cells {
        for i in 0..cells {
            mesh.indices
                .push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            mesh.indices
                .push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            mesh.triangle_materials.extend([material, material]);
        }
    }
}

/// Adds a box of `size` standing on the floor (y = 0) at `center_xz`, turned `angle_deg` about
/// y, its faces `cells` x `cells` quads, without a bottom face.
pub fn push_box(
    mesh: &mut Mesh,
    center_xz: (f32, f32),
    size: Vec3,
    angle_deg: f32,
    material: u32,
    cells: u32,
) {
    let m = Mat4::from_rotation_translation(
        Quat::from_rotation_y(angle_deg.to_radians()),
        Vec3::new(center_xz.0, size.y * 0.5, center_xz.1),
    );
    let h = size * 0.5;
    let p = |x: f32, y: f32, z: f32| m.transform_point3(Vec3::new(x * h.x, y * h.y, z * h.z));
    let faces = [
        [
            p(-1., 1., -1.),
            p(-1., 1., 1.),
            p(1., 1., 1.),
            p(1., 1., -1.),
        ], // top
        [
            p(-1., -1., 1.),
            p(1., -1., 1.),
            p(1., 1., 1.),
            p(-1., 1., 1.),
        ], // +z
        [
            p(1., -1., -1.),
            p(-1., -1., -1.),
            p(-1., 1., -1.),
            p(1., 1., -1.),
        ], // -z
        [
            p(1., -1., 1.),
            p(1., -1., -1.),
            p(1., 1., -1.),
            p(1., 1., 1.),
        ], // +x
        [
            p(-1., -1., -1.),
            p(-1., -1., 1.),
            p(-1., 1., 1.),
            p(-1., 1., -1.),
        ], // -x
    ];
    for f in faces {
        push_grid(mesh, f, material, cells);
    }
}

pub fn scene() -> Scene {
    tessellated(1)
}

/// The Cornell box with every wall and box face cut into `cells` x `cells` quads (the light
/// stays one quad): the same surfaces and image, with vertices for vertex links to carry light
/// (issue 22's convergence sweep over tessellation).
pub fn tessellated(cells: u32) -> Scene {
    let s = 5.55; // box size in metres
    let mut mesh = Mesh {
        name: "cornell".into(),
        ..Default::default()
    };
    let (white, red, green, light) = (0, 1, 2, 3);
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    push_grid(
        &mut mesh,
        [v(0., 0., 0.), v(0., 0., s), v(s, 0., s), v(s, 0., 0.)],
        white,
        cells,
    ); // floor, +y
    push_grid(
        &mut mesh,
        [v(0., s, 0.), v(s, s, 0.), v(s, s, s), v(0., s, s)],
        white,
        cells,
    ); // ceiling, -y
    push_grid(
        &mut mesh,
        [v(0., 0., s), v(0., s, s), v(s, s, s), v(s, 0., s)],
        white,
        cells,
    ); // back, -z
    push_grid(
        &mut mesh,
        [v(s, 0., 0.), v(s, 0., s), v(s, s, s), v(s, s, 0.)],
        red,
        cells,
    ); // x = s, -x
    push_grid(
        &mut mesh,
        [v(0., 0., 0.), v(0., s, 0.), v(0., s, s), v(0., 0., s)],
        green,
        cells,
    ); // x = 0, +x
    let (l0, l1, ly) = (2.13, 3.43, s - 0.001);
    push_quad(
        &mut mesh,
        [
            v(l0, ly, 2.27),
            v(l1, ly, 2.27),
            v(l1, ly, 3.32),
            v(l0, ly, 3.32),
        ],
        light,
    );
    push_box(
        &mut mesh,
        (1.855, 1.69),
        Vec3::new(1.65, 1.65, 1.65),
        -18.0,
        white,
        cells,
    );
    push_box(
        &mut mesh,
        (3.685, 3.51),
        Vec3::new(1.65, 3.3, 1.65),
        15.0,
        white,
        cells,
    );

    let mut light_mat = lambertian("light", Vec3::splat(0.78));
    light_mat.emissive = Vec3::new(17.0, 12.0, 4.0);
    let mut node = Node::new("cornell");
    node.mesh = Some(0);
    let mut cam_node = Node::new("camera");
    let cam = Camera::look_at(
        v(s * 0.5, s * 0.5, -8.0),
        v(s * 0.5, s * 0.5, 0.0),
        39.3077f32.to_radians(),
    );
    let (_, r, t) = cam.camera_to_world.to_scale_rotation_translation();
    cam_node.rotation = r;
    cam_node.translation = t.as_dvec3();
    cam_node.camera = Some(0);
    Scene {
        nodes: vec![node, cam_node],
        meshes: vec![Arc::new(mesh)],
        materials: vec![
            lambertian("white", Vec3::new(0.73, 0.73, 0.73)),
            lambertian("red", Vec3::new(0.65, 0.05, 0.05)),
            lambertian("green", Vec3::new(0.12, 0.45, 0.15)),
            light_mat,
        ],
        cameras: vec![crate::CameraModel {
            name: "cornell".into(),
            yfov: cam.yfov,
            aspect_ratio: Some(1.0),
            orthographic: None,
        }],
        ..Default::default()
    }
}

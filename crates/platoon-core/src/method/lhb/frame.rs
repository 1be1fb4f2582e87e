//! Where the buffers see the scene from (the thesis' MVP_i): the scene's bounding sphere, with
//! a margin so a living scene's frame can stay fixed, and for each direction an orthonormal
//! view whose forward axis is the direction. Buffer i at resolution R maps the sphere's
//! disc across d_i to R x R texels (the sphere, not the box: a box's rotated corners would be
//! clipped), and a point's depth is its distance along d_i from the sphere's entry plane.

use glam::{DVec3, Vec3};

use crate::flatten::GpuScene;

/// The sphere every buffer covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BufferFrame {
    pub centre: Vec3,
    pub radius: f32,
}

/// Direction d_i's axes: texels run along `right` (x) and `up` (y), depth along `forward`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub right: Vec3,
    pub up: Vec3,
    pub forward: Vec3,
}

impl View {
    /// The view along unit `d`: a fixed choice of the other two axes (the same on every
    /// device, since the buffers must be).
    pub fn along(d: DVec3) -> View {
        let (right, _) = d.any_orthonormal_pair();
        // Right-handed: right x up = forward.
        let up = d.cross(right);
        View {
            right: right.as_vec3(),
            up: up.as_vec3(),
            forward: d.as_vec3(),
        }
    }
}

impl BufferFrame {
    /// The scene's bounding sphere grown by `margin` (a fraction of its radius).
    pub fn of_scene(g: &GpuScene, margin: f32) -> BufferFrame {
        BufferFrame {
            centre: Vec3::from(g.scene_center),
            radius: (g.scene_radius as f32).max(1e-6) * (1.0 + margin),
        }
    }

    /// Point `p` in the buffer of `view` at resolution `r`: continuous texel coordinates (texel
    /// (i, j) spans [i, i + 1) x [j, j + 1)) and depth (0 at the sphere's entry plane).
    pub fn project(&self, view: &View, p: Vec3, r: u32) -> (f32, f32, f32) {
        let q = p - self.centre;
        let scale = r as f32 / (2.0 * self.radius);
        (
            (q.dot(view.right) + self.radius) * scale,
            (q.dot(view.up) + self.radius) * scale,
            q.dot(view.forward) + self.radius,
        )
    }

    /// The ray through texel (i, j)'s centre: its origin on the entry plane, along the view.
    pub fn texel_ray(&self, view: &View, i: u32, j: u32, r: u32) -> (Vec3, Vec3) {
        let texel = 2.0 * self.radius / r as f32;
        let (x, y) = (
            (i as f32 + 0.5) * texel - self.radius,
            (j as f32 + 0.5) * texel - self.radius,
        );
        (
            self.centre + view.right * x + view.up * y - view.forward * self.radius,
            view.forward,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sphere_fills_the_buffer_and_texel_rays_meet_their_texels() {
        let frame = BufferFrame {
            centre: Vec3::new(1.0, -2.0, 0.5),
            radius: 3.0,
        };
        for d in [DVec3::Z, DVec3::new(1.0, 2.0, -3.0).normalize(), -DVec3::X] {
            let view = View::along(d);
            assert!((view.right.dot(view.up)).abs() < 1e-6);
            assert!((view.right.cross(view.up) - view.forward).length() < 1e-5);
            // The sphere's extremes across the view land on the buffer's edges; its centre in
            // the middle at depth r.
            let r = 64;
            let (x, y, z) = frame.project(&view, frame.centre, r);
            assert!((x - 32.0).abs() < 1e-4 && (y - 32.0).abs() < 1e-4 && (z - 3.0).abs() < 1e-5);
            let (x, _, _) = frame.project(&view, frame.centre + view.right * 3.0, r);
            assert!((x - 64.0).abs() < 1e-3);
            let (origin, dir) = frame.texel_ray(&view, 10, 50, r);
            let (x, y, z) = frame.project(&view, origin + dir * 2.0, r);
            assert!((x - 10.5).abs() < 1e-3 && (y - 50.5).abs() < 1e-3 && (z - 2.0).abs() < 1e-4);
        }
    }
}

//! The render camera: a glTF perspective camera, or one framed from the scene bounds.

use glam::{Mat4, Vec3};

use crate::{Posed, Scene};

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Camera {
    pub camera_to_world: Mat4,
    /// Vertical field of view in radians.
    pub yfov: f32,
    /// Thin-lens aperture radius in scene units; 0 is a pinhole.
    pub aperture_radius: f32,
    /// Distance to the plane in focus along the view direction.
    pub focus_distance: f32,
    /// An orthographic camera's half width and height (glTF's xmag, ymag): rays leave the
    /// image plane in parallel and `yfov` is unused.
    pub orthographic: Option<[f32; 2]>,
}

/// The camera's frame as the kernel builds its rays ("Must match GPU side": `camera_ray` in
/// shaders/pathtrace.comp reads these through `Globals`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    pub origin: Vec3,
    pub right: Vec3,
    pub up: Vec3,
    pub forward: Vec3,
    /// tan(yfov / 2) times the image aspect, and tan(yfov / 2); orthographic: xmag and ymag.
    pub tan_half_x: f32,
    pub tan_half_y: f32,
}

impl CameraBasis {
    /// The normalised direction through the centre of pixel (x, y) of a `width` x `height`
    /// image, as the kernel's primary-hit output traces it.
    pub fn pixel_centre_direction(&self, x: u32, y: u32, width: u32, height: u32) -> Vec3 {
        let ndc_x = 2.0 * (x as f32 + 0.5) / width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * (y as f32 + 0.5) / height as f32;
        (self.forward + ndc_x * self.tan_half_x * self.right + ndc_y * self.tan_half_y * self.up)
            .normalize()
    }
}

impl Camera {
    /// Where the point `p` falls on a `width` x `height` image, in pixels (pixel (x, y) covers
    /// [x, x + 1) x [y, y + 1), its centre at + 0.5): the inverse of the rays through pixel
    /// centres (`CameraBasis::pixel_centre_direction`), for reprojecting a frame into the
    /// previous one's image. None behind the camera.
    pub fn project(&self, p: Vec3, width: u32, height: u32) -> Option<glam::Vec2> {
        let b = self.basis(width, height);
        let d = p - b.origin;
        let z = d.dot(b.forward);
        // An orthographic camera's rays are parallel: the offset in the image plane is the
        // point's, not divided by its distance.
        let scale = if self.orthographic.is_some() { 1.0 } else { z };
        if z <= 0.0 && self.orthographic.is_none() {
            return None;
        }
        let ndc_x = d.dot(b.right) / (scale * b.tan_half_x);
        let ndc_y = d.dot(b.up) / (scale * b.tan_half_y);
        Some(glam::Vec2::new(
            (ndc_x + 1.0) * 0.5 * width as f32,
            (1.0 - ndc_y) * 0.5 * height as f32,
        ))
    }

    /// Its frame for an image of `width` x `height` pixels.
    pub fn basis(&self, width: u32, height: u32) -> CameraBasis {
        let m = self.camera_to_world;
        let tan_half_y = (self.yfov * 0.5).tan();
        let [half_x, half_y] = self.orthographic.unwrap_or([
            tan_half_y * (width as f32 / height.max(1) as f32),
            tan_half_y,
        ]);
        CameraBasis {
            origin: m.w_axis.truncate(),
            right: m.x_axis.truncate().normalize(),
            up: m.y_axis.truncate().normalize(),
            forward: -m.z_axis.truncate().normalize(),
            tan_half_x: half_x,
            tan_half_y: half_y,
        }
    }

    pub fn position(&self) -> Vec3 {
        self.camera_to_world.transform_point3(Vec3::ZERO)
    }

    /// Looks from `eye` at `target`, +Y up (glTF cameras look down their -Z).
    pub fn look_at(eye: Vec3, target: Vec3, yfov: f32) -> Camera {
        let forward = (target - eye).normalize_or(-Vec3::Z);
        let up = if forward.cross(Vec3::Y).length_squared() < 1e-8 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        Camera {
            camera_to_world: Mat4::from_cols(
                right.extend(0.0),
                up.extend(0.0),
                (-forward).extend(0.0),
                eye.extend(1.0),
            ),
            yfov,
            aperture_radius: 0.0,
            focus_distance: (target - eye).length(),
            orthographic: None,
        }
    }

    /// Frames the bounding sphere of the posed scene from a raised three-quarter view.
    pub fn framing(posed: &Posed) -> Camera {
        let (lo, hi) = posed.bounds();
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-3);
        let yfov = 45f32.to_radians();
        let distance = radius / (yfov * 0.5).sin() * 1.05;
        let dir = Vec3::new(0.45, 0.35, 1.0).normalize();
        Camera::look_at(center + dir * distance, center, yfov)
    }

    /// Camera `index` of the scene (in node order), or a framing camera when it has none.
    pub fn from_scene(
        scene: &Scene,
        posed: &Posed,
        index: Option<usize>,
    ) -> Result<Camera, String> {
        match (index, posed.cameras.len()) {
            (None, 0) => Ok(Camera::framing(posed)),
            (Some(i), n) if i >= n => Err(format!(
                "camera {i} does not exist: the scene has {n} camera(s)"
            )),
            (i, _) => {
                let placed = &posed.cameras[i.unwrap_or(0)];
                // Cameras may sit under scaled nodes: keep rotation and position only.
                let (_, rot, pos) = placed.camera_to_world.to_scale_rotation_translation();
                let camera_to_world = Mat4::from_rotation_translation(rot, pos);
                let (lo, hi) = posed.bounds();
                let focus = (pos - (lo + hi) * 0.5).length().max(1e-3);
                let model = &scene.cameras[placed.camera];
                Ok(Camera {
                    camera_to_world,
                    yfov: model.yfov,
                    aperture_radius: 0.0,
                    focus_distance: focus,
                    orthographic: model.orthographic,
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_on_a_pixel_centre_ray_projects_back_onto_that_centre() {
        let mut camera = Camera::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, 0.7);
        for ortho in [None, Some([1.5, 1.0])] {
            camera.orthographic = ortho;
            let (w, h) = (40, 30);
            let b = camera.basis(w, h);
            for (x, y) in [(0, 0), (39, 0), (17, 11), (39, 29)] {
                let d = b.pixel_centre_direction(x, y, w, h);
                // An orthographic ray starts on the image plane, offset from the eye.
                let start = match ortho {
                    None => b.origin,
                    Some([hx, hy]) => {
                        let ndc_x = 2.0 * (x as f32 + 0.5) / w as f32 - 1.0;
                        let ndc_y = 1.0 - 2.0 * (y as f32 + 0.5) / h as f32;
                        b.origin + ndc_x * hx * b.right + ndc_y * hy * b.up
                    }
                };
                let direction = if ortho.is_some() { b.forward } else { d };
                let at = camera.project(start + 3.7 * direction, w, h).unwrap();
                let want = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                assert!((at - want).length() < 1e-3, "{ortho:?} ({x}, {y}): {at}");
            }
        }
        camera.orthographic = None;
        assert_eq!(
            camera.project(camera.position() - camera.basis(4, 4).forward, 4, 4),
            None
        );
    }
}

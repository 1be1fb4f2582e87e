//! Motion vectors (Cycles' Vector pass, its motion from the previous frame): per pixel, how far
//! on the image the surface seen through the pixel's centre moved since the frame before, in
//! pixels (x right, y down): where it is now minus where the previous frame's camera saw it.
//! The hit (the Position and Ids passes) is carried back through its triangle
//! ([`HitGeometry::before`]) into the previous camera. A pixel that sees no surface,
//! or a surface the frame before did not have, has no motion (0).

use glam::Vec3;

use super::hit_geometry::{Before, HitGeometry};
use super::Crop;
use platoon_accel::GpuScene;
use platoon_image::{Film, Layer};
use platoon_scene::camera::Camera;
use platoon_scene::Posed;

/// The frame before: the scene posed then (around the same render-space origin) and its camera.
#[derive(Clone, Debug)]
pub struct PreviousFrame {
    pub posed: Posed,
    pub camera: Camera,
}

/// Where each pixel's first hit (`position`, `ids`: the kernel's passes of a frame traced in
/// `now`) was in the frame `before`: None for a miss or a surface `before` lacks.
pub fn hits_before(
    position: &Film,
    ids: &Film,
    now: &HitGeometry,
    before: &HitGeometry,
) -> Vec<Option<Before>> {
    ids.pixels
        .iter()
        .zip(&position.pixels)
        .map(|(id, p)| {
            if id[0] == 0.0 {
                return None;
            }
            let (instance, triangle) = (id[0] as u32 - 1, id[2] as u32 - 1);
            now.before(Vec3::from(*p), instance, triangle, before)
        })
        .collect()
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
    let before = hits_before(
        position,
        ids,
        &HitGeometry::of_flattened(gpu),
        &HitGeometry::of_posed(&previous.posed),
    );
    let mut planes = [
        vec![0.0f32; ids.pixels.len()],
        vec![0.0f32; ids.pixels.len()],
    ];
    for (i, before) in before.into_iter().enumerate() {
        let Some(before) = before.map(|b| b.position) else {
            continue;
        };
        let now = Vec3::from(position.pixels[i]);
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

//! The frame before, as motion vectors measure against it (`platoon_core::frame::motion`).

use anyhow::Result;
use platoon_core::frame::motion::PreviousFrame;
use platoon_core::scene::Scene;

use crate::prepare::{camera_at, PrepareOptions};
use crate::CameraChoice;

/// The frame at `time` of `scene`: posed then around `origin` (the render space of the frame
/// the motion vectors belong to), seen by the camera `options` and `choice` pick (a given
/// camera stays where it is given).
pub fn previous_frame(
    scene: &Scene,
    options: &PrepareOptions,
    choice: &CameraChoice,
    time: f32,
    origin: glam::DVec3,
) -> Result<PreviousFrame> {
    let posed = scene.pose_around(time, origin);
    let camera = choice.in_render_space(camera_at(scene, &posed, options)?, origin);
    Ok(PreviousFrame { posed, camera })
}

//! What a method learns over a game loop's frames and gives each next one (the path tracer's
//! world cache and light reuse): a learner its state makes (`RenderMethod::learning`), which a
//! frame driver holds. It gives each frame what the frames before taught, and learns from the
//! records the frame's bands left, joined in pixel order, so that what it learns is the same
//! whatever the split between devices.

use crate::frame::{FrameParams, MethodReport, PixelData};
use crate::method::Method;

pub trait FrameLearning: Send {
    /// `method` (a frame's) with what the frames so far taught; `lights` is the scene's light
    /// count where a commit changed the scene (what was learned of other lights is dropped).
    fn give(&mut self, method: &mut Method, lights: Option<usize>);
    /// Learns from the frame `params`' records (`pixels`, its bands' in pixel order); `frame`
    /// counts the driver's frames. What the frame taught comes back as the method's report
    /// (`RenderMethod::report` writes it for a user).
    fn learn(
        &mut self,
        pixels: &PixelData,
        params: &FrameParams,
        frame: u32,
    ) -> Result<MethodReport, String>;
}

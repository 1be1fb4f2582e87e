//! The film a frame continues, apart from how its samples are taken: the sums of the earlier
//! samples and the pixels that take no more.

use std::sync::Arc;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct FilmState {
    /// Radiance sums of earlier samples of every pixel (row-major, width x height) that the
    /// frame's samples are added onto, one by one in sample order, so that frames continuing a
    /// sum are bit for bit one longer render. The bands' sums then include them.
    pub accumulated: Option<Arc<[[f32; 3]]>>,
    /// Pixels (row-major) that take no samples in the frame, their sums passed through from
    /// `accumulated` (which they need): adaptive sampling's converged pixels (`adaptive`).
    /// Path tracing only.
    pub converged: Option<Arc<[bool]>>,
}

//! What a frame's tracers did and what went wrong: each tracer's part, a tracer's failure,
//! a frame that could not be rendered.

use std::time::Duration;

use platoon_frame::frame::Span;

/// One tracer's part in a frame.
#[derive(Clone, Debug)]
pub struct TracerStats {
    /// The tracer's index among those the renderer was created with.
    pub tracer: usize,
    /// The band the balancer gave it.
    pub span: Span,
    /// Pixels it rendered in total, recovery work included.
    pub pixels: u32,
    pub gpu_time: Duration,
    pub wall_time: Duration,
    /// Time it waited for the slowest tracer.
    pub idle: Duration,
    pub rays: u64,
    /// Pieces it claimed besides its band's head (`balance::steal`; 0 without stealing).
    pub pieces: u32,
    /// Pixels of other tracers' bands it rendered.
    pub stolen: u32,
}

#[derive(Clone, Debug, PartialEq)]
pub struct TracerFailure {
    pub tracer: usize,
    pub frame: u32,
    pub message: String,
}

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("no tracer left: {0}")]
    NoTracers(String),
    /// The frame breaks a rule every tracer holds it to (`FrameParams::check`): refused before
    /// any tracer renders it, so none is dropped for it.
    #[error("{0}")]
    Invalid(String),
    /// The bands came back not covering the frame once (a fault of the claims, never of a
    /// tracer): no frame rather than a wrong one.
    #[error("the frame's bands do not cover it exactly: {0}")]
    Incomplete(String),
}

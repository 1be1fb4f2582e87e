//! A frame scheduled over its tracers (`renderer::Renderer`): the balancer's plan (a band per
//! tracer), each band rendered on its tracer's own thread (`workers`), the rounds that share
//! bands' tails between tracers and re-render a failed tracer's band on the others (`rounds`),
//! and what a frame measured and lost (`outcome`). The frame contract (crate platoon-frame,
//! `platoon_frame::frame`) is what this schedules: the frame's parameters, the band, the
//! `BandTracer` a device is; no method's code.

mod outcome;
pub mod renderer;
mod rounds;
mod workers;

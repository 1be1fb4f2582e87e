//! A render request: the facade's one front door. Everything a render is asked for (the scene
//! and its light, the camera, the size and samples or a time budget, the method with its
//! options, the devices and their balancer, the outputs), checked in one place
//! ([`Request::validate`], every rule once, errors naming the option) and turned into what the
//! layers below take: the preparation's options, the frame's parameters, the tracers' options,
//! the batching. The CLI turns its arguments into one, a binding its keyword arguments;
//! [`Request::render`] renders a still in this process ([`still`]) by the request's steps
//! ([`steps`]: prepare, tracers, render a frame, its outputs), which the CLI's stills,
//! animations and farms call one by one.
//!
//! ```no_run
//! # fn main() -> anyhow::Result<()> {
//! let request = platoon::Request {
//!     width: 256,
//!     height: 256,
//!     spp: 16,
//!     ..Default::default() // the built-in Cornell box on device 0
//! };
//! let still = request.render(&mut |_spp_done| {})?;
//! platoon::core::output::write_image("box.exr".as_ref(), &still.image, &still.metadata)?;
//! # Ok(())
//! # }
//! ```

mod error;
mod form;
mod game;
pub mod options;
mod progressive;
pub mod steps;
pub mod still;
mod validate;

pub use error::{Interrupted, RequestError};
pub use form::{CameraChoice, Request, SceneSource, DEFAULT_FRAME_INTERVAL};
pub use progressive::Progressive;
pub use steps::FrameShown;
pub use still::Still;

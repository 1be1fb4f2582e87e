//! `platoon render`: one frame of a scene to an EXR or PNG, with a progress bar; with
//! `--frames`, an animation to numbered files ([`frames`]), optionally a video ([`video`]).

mod args;
mod farm;
mod frames;
mod job;
mod outputs;
mod setup;
mod still;
mod video;

use anyhow::Result;

pub use args::RenderArgs;

pub fn run(a: RenderArgs) -> Result<()> {
    if a.frames.frames.is_some() || a.frames.mpi_frames.is_some() {
        return frames::run(a);
    }
    setup::check_output(&a)?;
    let (setup, out, _) = setup::setup(a)?;
    let session = setup.session.clone();
    setup::on_every_rank(session, || still::still(setup, out))
}

//! `platoon render`: one frame of a scene to an EXR or PNG, with a progress bar; with
//! `--frames`, an animation to numbered files ([`frames`]), optionally a video ([`video`]).

mod args;
mod checkpoint;
mod farm;
mod frame_log;
mod frames;
mod job;
mod outputs;
mod setup;
mod stage;
mod still;
mod video;

use anyhow::Result;

pub use args::RenderArgs;

pub fn run(a: RenderArgs) -> Result<()> {
    if a.frames.frames.is_some() || a.frames.mpi_frames.is_some() {
        return frames::run(a);
    }
    // Before the scene is read: a Ctrl-C while loading stops the render after its first pass.
    if !a.mpi {
        stop_on_ctrl_c();
    }
    if a.resume && a.mpi {
        anyhow::bail!(
            "--resume continues a render of one device (its checkpoint): not with --mpi, whose \
             ranks' bands stop at different passes"
        );
    }
    setup::check_output(&a)?;
    let log = frame_log::FrameLog {
        json: a.frames.log_json,
    };
    let resume = a.resume;
    let (setup, out, _) = setup::setup(a)?;
    let session = setup.session.clone();
    setup::on_every_rank(session, || still::still(setup, out, log, resume))
}

/// Ctrl-C ends a still render after its current pass (its samples so far are written, as
/// Cycles and Mitsuba do); a second Ctrl-C ends the process at once. (Over MPI ranks the
/// default stays: a rank alone cannot stop the others' bands.)
fn stop_on_ctrl_c() {
    let installed = ctrlc::set_handler(|| {
        if platoon::tracer::stop::requested() {
            std::process::exit(130);
        }
        platoon::tracer::stop::request();
        eprintln!("\ninterrupted: finishing the current pass (Ctrl-C again to quit at once)");
    });
    if let Err(e) = installed {
        log::warn!("Ctrl-C will end the render without writing it: {e}");
    }
}

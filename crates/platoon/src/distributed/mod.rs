//! Frames split between processes (`platoon_distribute`): every rank of a job holds
//! the scene and its own devices; rank 0's balancer cuts each frame between the ranks, each
//! rank's renderer between its devices, and the bands are gathered on rank 0, which gets the
//! image (the others get frames of zeros and write nothing). With the feature `mpi` the ranks
//! are an MPI job's ([`mpi`]: `mpirun -n 3 platoon render ... --mpi`); without it [`join`]
//! says so.
//!
//! Every rank runs the same program on the same inputs (OSPRay's `mpiOffload` model, with the
//! application replicated rather than only on rank 0): the same calls on [`crate::Tracers`]
//! in the same order, each a collective operation. The frame's fingerprint catches ranks whose
//! arguments or scene differ; scene commits are rank 0's, broadcast.

#[cfg(feature = "mpi")]
mod deal;
pub mod game;
#[cfg(feature = "mpi")]
pub mod mpi;
mod session;

use std::rc::Rc;

use anyhow::Result;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::FrameParams;
use platoon_distribute::{Communication, RankFrame, RankRenderer, RankStats};
use platoon_tracer::Tracer;

pub use session::Session;

/// What a frame over ranks did besides its image: each rank's part and what crossed between
/// the ranks (rank 0's view).
#[derive(Clone, Debug)]
pub struct RanksReport {
    pub ranks: usize,
    /// The policy that cut the frame between the ranks.
    pub balancer: &'static str,
    /// Each rank's part, in rank order (ranks given nothing left out).
    pub parts: Vec<RankStats>,
    pub communication: Communication,
}

/// A job's ranks as a game's option (`crate::game::GameOptions::ranks`).
#[derive(Clone)]
pub struct Ranks(pub Rc<dyn Session>);

impl std::fmt::Debug for Ranks {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "rank {} of {}", self.0.rank(), self.0.size())
    }
}

/// The ranks of the job this process belongs to: MPI's world (initialised here, finalised
/// when the last handle goes). An error without the feature `mpi`, or when MPI cannot start.
pub fn join() -> Result<Rc<dyn Session>> {
    #[cfg(feature = "mpi")]
    {
        Ok(Rc::new(mpi::Mpi::init()?))
    }
    #[cfg(not(feature = "mpi"))]
    {
        anyhow::bail!(
            "this platoon was built without MPI: build it with `cargo build --release \
             --features mpi` (Debian: apt-get install libopenmpi-dev openmpi-bin libclang-dev) \
             and start it with `mpirun -n N platoon render ... --mpi`"
        )
    }
}

/// Renders a frame over the ranks after the method's preparation (each rank prepares on its
/// own devices: the same bits, as for any split); rank 0 says what failed. Returns the frame
/// and the parameters it was rendered with.
pub(crate) fn render(
    r: &mut RankRenderer<Tracer>,
    scene: &GpuScene,
    params: &FrameParams,
) -> Result<(FrameParams, RankFrame)> {
    let params = crate::method_update::on_renderer(r.local_mut(), scene, params)?;
    let frame = r.render_frame(&params)?;
    if r.rank() == 0 {
        for f in &frame.failures {
            log::warn!("{f}");
        }
    }
    Ok((params, frame))
}

//! One frame split between processes, each with its own devices: the ranks of an MPI job
//! (the facade's feature `mpi`, OSPRay's `mpiOffload` model) or threads standing in for them
//! (`local`, for tests). Two levels of balancing: rank 0's balancer cuts the frame between the
//! ranks from each rank's measured time, and each rank's own renderer cuts its share between
//! its devices (`ranks`). Because random numbers are a pure function of (pixel, sample, frame,
//! seed) and each pixel's sums are made on one device in sample order, the image is the same
//! bits as a one-process render for any number of ranks, devices and balancers.
//!
//! The transport is a [`Collective`]: a broadcast and a variable-count scatter from rank 0
//! and a variable-count gather to it (MPI_Bcast, MPI_Scatterv, MPI_Gatherv), over the bytes
//! of [`wire`] (the frame's messages in `share`). A game loop cannot be replayed on every rank:
//! there each rank is one tracer of rank 0's frame driver ([`remote`]), sent each band's
//! parameters ([`params`]) point to point.

mod collective;
pub mod local;
pub mod method_wire;
pub mod params;
pub mod ranks;
pub mod remote;
mod share;
pub mod wire;

pub use collective::Collective;
pub use ranks::{Communication, RankError, RankFrame, RankRenderer, RankStats};

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

pub mod local;
pub mod params;
pub mod ranks;
pub mod remote;
mod share;
pub mod wire;

pub use ranks::{Communication, RankError, RankFrame, RankRenderer, RankStats};

/// The collective operations the ranks of a frame take part in together, rank 0 the root.
/// Every rank calls the same operations in the same order; a rank that stops calling them
/// stops the others (MPI has no timeout: a lost rank ends the job).
pub trait Collective {
    /// This process's rank, 0..size.
    fn rank(&self) -> usize;
    fn size(&self) -> usize;
    /// Rank 0's `bytes` on every rank (the others' `bytes` are ignored).
    fn broadcast(&self, bytes: Vec<u8>) -> Vec<u8>;
    /// Part `rank` of rank 0's `parts` (one per rank) on each rank; the others' are ignored.
    fn scatter(&self, parts: Vec<Vec<u8>>) -> Vec<u8>;
    /// Every rank's `mine` on rank 0, in rank order; empty on the others.
    fn gather(&self, mine: Vec<u8>) -> Vec<Vec<u8>>;
    /// Returns once every rank has called it (what separates waiting for the slowest rank
    /// from moving bytes, in the measurements).
    fn barrier(&self);
}

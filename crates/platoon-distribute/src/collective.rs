//! What the ranks of a frame do together: the transport `ranks` runs over (MPI in the facade,
//! threads in `local`).

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

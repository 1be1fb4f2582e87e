//! A job's ranks as a program sees them: the collectives, and ending, dealing and messaging.

use std::sync::Arc;

use anyhow::Result;
use platoon_distribute::Collective;

/// A job's ranks, with what a program needs beyond the collectives: ending every rank when one
/// fails (a rank that returns leaves the others waiting in their next collective).
pub trait Session: Collective {
    /// Ends the whole job with `code` (MPI_Abort); does not return.
    fn abort(&self, code: i32) -> !;
    /// The frames of rank 0's `frames` this rank renders, dealt one at a time as the ranks
    /// finish them (rank 0's dealer answers while its own renderer takes frames too). No other
    /// call on the session until the iterator has ended.
    fn deal(&self, frames: Vec<i64>) -> Box<dyn Iterator<Item = i64>>;
    /// Messages between rank 0 and each other rank from any thread: the game loop's ranks
    /// (`platoon_distribute::remote`). An error where the library cannot talk from
    /// several threads at once.
    fn link(&self) -> Result<Arc<dyn platoon_distribute::remote::Link>>;
}

//! Frames dealt to the ranks as they finish (`--mpi-frames`): a render farm without a
//! scheduler. Rank 0 holds the queue; a dealer thread of rank 0 answers the other ranks'
//! requests (one frame each, in order, or the end) while rank 0's own renderer takes frames
//! from the same queue. During the deal no other thread of rank 0 calls MPI (MPI is started
//! serialised), and the dealer polls rather than blocks in a receive, so that Open MPI's busy
//! wait does not take a core from rank 0's devices.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Duration;

use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// The tag of the deal's messages (no other point-to-point traffic uses one).
const TAG: i32 = 26;
/// What the dealer sends when the queue is empty.
const END: i64 = i64::MIN;

type Queue = Arc<Mutex<VecDeque<i64>>>;

fn pop(queue: &Queue) -> Option<i64> {
    queue.lock().unwrap_or_else(|e| e.into_inner()).pop_front()
}

/// Rank 0's frames: from the queue, then the dealer joined (it ends once every other rank
/// has been told the end).
pub struct Dealer {
    queue: Queue,
    dealer: Option<JoinHandle<()>>,
}

impl Iterator for Dealer {
    type Item = i64;
    fn next(&mut self) -> Option<i64> {
        let f = pop(&self.queue);
        if f.is_none() {
            if let Some(d) = self.dealer.take() {
                let _ = d.join();
            }
        }
        f
    }
}

/// Another rank's frames: each asked of rank 0 when the last is done.
pub struct Dealt {
    world: SimpleCommunicator,
    done: bool,
}

impl Iterator for Dealt {
    type Item = i64;
    fn next(&mut self) -> Option<i64> {
        if self.done {
            return None;
        }
        let root = self.world.process_at_rank(0);
        root.send_with_tag(&0i64, TAG);
        let (f, _) = root.receive_with_tag::<i64>(TAG);
        self.done = f == END;
        (!self.done).then_some(f)
    }
}

/// The frames this rank renders of `frames` (rank 0's list: the others' is ignored).
pub fn deal(world: &SimpleCommunicator, frames: Vec<i64>) -> Box<dyn Iterator<Item = i64>> {
    if world.rank() != 0 {
        return Box::new(Dealt {
            world: SimpleCommunicator::world(),
            done: false,
        });
    }
    let queue: Queue = Arc::new(Mutex::new(frames.into()));
    let others = world.size() as usize - 1;
    let shared = queue.clone();
    let dealer = std::thread::spawn(move || {
        let world = SimpleCommunicator::world();
        let mut ended = 0;
        while ended < others {
            let Some(status) = world.any_process().immediate_probe_with_tag(TAG) else {
                std::thread::sleep(Duration::from_millis(2));
                continue;
            };
            let from = world.process_at_rank(status.source_rank());
            let _ = from.receive_with_tag::<i64>(TAG);
            let f = pop(&shared).unwrap_or(END);
            if f == END {
                ended += 1;
            }
            from.send_with_tag(&f, TAG);
        }
    });
    Box::new(Dealer {
        queue,
        dealer: Some(dealer),
    })
}

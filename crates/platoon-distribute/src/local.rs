//! Ranks as threads of one process: the [`Collective`] the tests split frames over (and a
//! model of what the MPI transport does), with a barrier around every exchange, and the
//! point-to-point [`Link`] of the game loop's ranks, a channel per pair.

use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Barrier, Mutex};

use super::remote::Link;
use super::Collective;

struct Shared {
    barrier: Barrier,
    /// One message per rank: what rank 0 sends to each, or what each sends to rank 0.
    slots: Mutex<Vec<Vec<u8>>>,
}

pub struct LocalGroup {
    rank: usize,
    size: usize,
    shared: Arc<Shared>,
}

impl LocalGroup {
    /// The `size` ranks of one group, to be moved one to a thread.
    pub fn new(size: usize) -> Vec<LocalGroup> {
        let shared = Arc::new(Shared {
            barrier: Barrier::new(size),
            slots: Mutex::new(vec![Vec::new(); size]),
        });
        (0..size)
            .map(|rank| LocalGroup {
                rank,
                size,
                shared: shared.clone(),
            })
            .collect()
    }

    fn slots(&self) -> std::sync::MutexGuard<'_, Vec<Vec<u8>>> {
        self.shared.slots.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Collective for LocalGroup {
    fn rank(&self) -> usize {
        self.rank
    }
    fn size(&self) -> usize {
        self.size
    }
    fn broadcast(&self, bytes: Vec<u8>) -> Vec<u8> {
        if self.rank == 0 {
            self.slots()[0] = bytes;
        }
        self.shared.barrier.wait();
        let out = self.slots()[0].clone();
        self.shared.barrier.wait();
        out
    }
    fn scatter(&self, parts: Vec<Vec<u8>>) -> Vec<u8> {
        if self.rank == 0 {
            assert_eq!(parts.len(), self.size, "one part per rank");
            *self.slots() = parts;
        }
        self.shared.barrier.wait();
        let out = std::mem::take(&mut self.slots()[self.rank]);
        self.shared.barrier.wait();
        out
    }
    fn barrier(&self) {
        self.shared.barrier.wait();
    }
    fn gather(&self, mine: Vec<u8>) -> Vec<Vec<u8>> {
        self.slots()[self.rank] = mine;
        self.shared.barrier.wait();
        let out = if self.rank == 0 {
            std::mem::replace(&mut *self.slots(), vec![Vec::new(); self.size])
        } else {
            Vec::new()
        };
        self.shared.barrier.wait();
        out
    }
}

/// Point-to-point messages between ranks as threads: a channel for every ordered pair.
pub struct LocalLink {
    rank: usize,
    mesh: Arc<Mesh>,
}

struct Mesh {
    /// `senders[from][to]`.
    senders: Vec<Vec<Mutex<Sender<Vec<u8>>>>>,
    /// `receivers[to][from]`.
    receivers: Vec<Vec<Mutex<Receiver<Vec<u8>>>>>,
}

impl LocalLink {
    /// The links of `size` ranks, rank order.
    pub fn new(size: usize) -> Vec<Arc<LocalLink>> {
        let mut senders = Vec::new();
        let mut receivers: Vec<Vec<_>> = (0..size).map(|_| Vec::new()).collect();
        for _from in 0..size {
            let mut row = Vec::new();
            for to_row in receivers.iter_mut() {
                let (tx, rx) = channel();
                row.push(Mutex::new(tx));
                // Sources in order: receivers[to][from].
                to_row.push(Mutex::new(rx));
            }
            senders.push(row);
        }
        let mesh = Arc::new(Mesh { senders, receivers });
        (0..size)
            .map(|rank| {
                Arc::new(LocalLink {
                    rank,
                    mesh: mesh.clone(),
                })
            })
            .collect()
    }
}

impl Link for LocalLink {
    fn send(&self, to: usize, bytes: Vec<u8>) {
        let tx = self.mesh.senders[self.rank][to]
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        // A rank that has ended drops nothing it still needs.
        let _ = tx.send(bytes);
    }
    fn receive(&self, from: usize) -> Vec<u8> {
        let rx = self.mesh.receivers[self.rank][from]
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        rx.recv().unwrap_or_default()
    }
}

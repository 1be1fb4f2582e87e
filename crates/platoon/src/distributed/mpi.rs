//! The ranks of an MPI job (rsmpi over the system's MPI: Debian's Open MPI): the collectives
//! of `platoon_distribute` as MPI_Bcast, MPI_Scatterv and MPI_Gatherv of bytes, each
//! preceded by the exchange of the lengths.

use anyhow::{bail, Result};
use mpi::datatype::{Partition, PartitionMut};
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Count;
use std::sync::Arc;

use mpi::Threading;
use platoon_distribute::remote::Link;
use platoon_distribute::Collective;

use super::Session;

pub struct Mpi {
    /// Finalises MPI when dropped: held for as long as the process renders.
    _universe: Universe,
    world: SimpleCommunicator,
    /// What the library grants: the game loop's ranks talk from several threads at once.
    threading: Threading,
}

impl Mpi {
    /// Joins the job `mpirun` started (a process started alone is a job of one rank), asking
    /// for MPI_THREAD_MULTIPLE (the game loop's); renders need only one thread at a time.
    pub fn init() -> Result<Mpi> {
        let Some((universe, threading)) = mpi::initialize_with_threading(Threading::Multiple)
        else {
            bail!("MPI was already initialised in this process");
        };
        if threading < Threading::Serialized {
            bail!(
                "the MPI library grants {threading:?} threading; platoon needs at least \
                 MPI_THREAD_SERIALIZED"
            );
        }
        let world = universe.world();
        Ok(Mpi {
            _universe: universe,
            world,
            threading,
        })
    }
}

/// Point-to-point messages of the game loop's ranks on MPI_COMM_WORLD under their own tag,
/// from any thread (MPI_THREAD_MULTIPLE). A receive polls rather than blocks: Open MPI's
/// blocking wait spins, and rank 0's tracers waiting on remote ranks would take the cores its
/// own devices render on.
struct MpiLink;

const LINK_TAG: i32 = 27;

impl Link for MpiLink {
    fn send(&self, to: usize, bytes: Vec<u8>) {
        let world = SimpleCommunicator::world();
        world
            .process_at_rank(to as i32)
            .send_with_tag(&bytes[..], LINK_TAG);
    }
    fn receive(&self, from: usize) -> Vec<u8> {
        let world = SimpleCommunicator::world();
        let source = world.process_at_rank(from as i32);
        while source.immediate_probe_with_tag(LINK_TAG).is_none() {
            std::thread::sleep(std::time::Duration::from_micros(100));
        }
        source.receive_vec_with_tag::<u8>(LINK_TAG).0
    }
}

/// An MPI count for a message of `n` bytes (MPI counts are 32-bit).
fn count(n: usize) -> Count {
    Count::try_from(n).expect("a message between ranks of 2 GiB or more: render smaller frames")
}

/// Offsets of messages of the given lengths laid end to end.
fn offsets(counts: &[Count]) -> Vec<Count> {
    counts
        .iter()
        .scan(0, |at, &c| {
            let here = *at;
            *at += c;
            Some(here)
        })
        .collect()
}

impl Collective for Mpi {
    fn rank(&self) -> usize {
        self.world.rank() as usize
    }
    fn size(&self) -> usize {
        self.world.size() as usize
    }
    fn broadcast(&self, mut bytes: Vec<u8>) -> Vec<u8> {
        let root = self.world.process_at_rank(0);
        let mut len = bytes.len() as u64;
        root.broadcast_into(&mut len);
        bytes.resize(len as usize, 0);
        // Open MPI refuses an empty slice's buffer (MPI_ERR_ARG): nothing to send anyway.
        if len > 0 {
            root.broadcast_into(&mut bytes[..]);
        }
        bytes
    }
    fn scatter(&self, parts: Vec<Vec<u8>>) -> Vec<u8> {
        let root = self.world.process_at_rank(0);
        let mut mine: Count = 0;
        if self.rank() == 0 {
            let counts: Vec<Count> = parts.iter().map(|p| count(p.len())).collect();
            root.scatter_into_root(&counts[..], &mut mine);
            let mut out = vec![0u8; mine as usize];
            let flat = parts.concat();
            let displs = offsets(&counts);
            let partition = Partition::new(&flat[..], &counts[..], &displs[..]);
            root.scatter_varcount_into_root(&partition, &mut out[..]);
            out
        } else {
            root.scatter_into(&mut mine);
            let mut out = vec![0u8; mine as usize];
            root.scatter_varcount_into(&mut out[..]);
            out
        }
    }
    fn barrier(&self) {
        self.world.barrier();
    }
    fn gather(&self, mine: Vec<u8>) -> Vec<Vec<u8>> {
        let root = self.world.process_at_rank(0);
        let len = count(mine.len());
        if self.rank() == 0 {
            let mut counts = vec![0 as Count; self.size()];
            root.gather_into_root(&len, &mut counts[..]);
            let displs = offsets(&counts);
            let total: usize = counts.iter().map(|&c| c as usize).sum();
            let mut flat = vec![0u8; total];
            let mut partition = PartitionMut::new(&mut flat[..], &counts[..], &displs[..]);
            root.gather_varcount_into_root(&mine[..], &mut partition);
            counts
                .iter()
                .zip(&displs)
                .map(|(&c, &d)| flat[d as usize..(d + c) as usize].to_vec())
                .collect()
        } else {
            root.gather_into(&len);
            root.gather_varcount_into(&mine[..]);
            Vec::new()
        }
    }
}

impl Session for Mpi {
    fn abort(&self, code: i32) -> ! {
        self.world.abort(code)
    }
    fn deal(&self, frames: Vec<i64>) -> Box<dyn Iterator<Item = i64>> {
        super::deal::deal(&self.world, frames)
    }
    fn link(&self) -> Result<Arc<dyn Link>> {
        if self.threading < Threading::Multiple {
            bail!(
                "the MPI library grants {:?} threading; the game loop over ranks needs \
                 MPI_THREAD_MULTIPLE (Open MPI built with thread support)",
                self.threading
            );
        }
        Ok(Arc::new(MpiLink))
    }
}

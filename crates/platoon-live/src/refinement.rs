//! The refinement of big static geometry's BVHs in a living scene: past
//! [`QUICK_BUILD_TRIANGLES`] a static mesh is built quick (binned SAH) so that the first
//! generation comes at once; its nodes are then reinserted ([`refine`]) on a thread of their own
//! and the refined tree is swapped in by the first update after it is done, as any other commit
//! (the tracers all receive it with the same generation, so a frame split between devices is
//! the same image whatever the split).
//!
//! A refinement moves nodes only: the triangles keep their places and so the lights their
//! order, and the image changes only where traversal order breaks a tie between hits at the
//! same distance. The gain is modest (the binned tree is already good): SAH 1-4% lower on the
//! generated scenes (docs/PERFORMANCE.md, "Scenes of production size").

use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::Arc;

use platoon_core::flatten::bvh::{FlatBvh, QUICK_BUILD_TRIANGLES};
use platoon_core::flatten::refine::refine;

/// When a static mesh's quick BVH is refined.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Refinement {
    /// Kept as built.
    Off,
    /// Refined on a thread of its own at batch priority and swapped in by the first update
    /// after it is done: a game's first image comes at once.
    #[default]
    Background,
    /// Refined before the generation that built it is handed over: every generation the same
    /// whatever the machine's speed (offline frames).
    Wait,
}

/// How the updater builds the BVHs of static geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StaticBuild {
    /// Meshes of more triangles than this are built quick (binned SAH), the others by obvhs'
    /// PLOC with every node reinserted.
    pub quick_above: usize,
    pub refinement: Refinement,
}

impl Default for StaticBuild {
    fn default() -> Self {
        StaticBuild {
            quick_above: QUICK_BUILD_TRIANGLES,
            refinement: Refinement::default(),
        }
    }
}

/// Whose BVH a refinement is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Target {
    /// A static mesh, by scene mesh.
    Static(usize),
    /// The merged static geometry.
    Merged,
}

struct Job {
    target: Target,
    /// The tree being refined: the refined one replaces it only if it is still the target's.
    from: Arc<FlatBvh>,
    done: Receiver<FlatBvh>,
    state: State,
}

enum State {
    Running,
    Done(FlatBvh),
    /// The refinement panicked (its sender dropped): the quick tree stays.
    Failed,
}

impl Job {
    /// Takes the refined tree if it has come (waiting for it when `block`).
    fn poll(&mut self, block: bool) {
        if matches!(self.state, State::Running) {
            let got = if block {
                self.done.recv().map_err(|_| TryRecvError::Disconnected)
            } else {
                self.done.try_recv()
            };
            match got {
                Ok(tree) => self.state = State::Done(tree),
                Err(TryRecvError::Empty) => {}
                Err(TryRecvError::Disconnected) => self.state = State::Failed,
            }
        }
    }
}

/// The refinements under way.
pub(super) struct Refiner {
    mode: Refinement,
    /// One thread at batch priority, made on the first job.
    pool: Option<rayon::ThreadPool>,
    jobs: Vec<Job>,
}

impl Refiner {
    pub(super) fn new(mode: Refinement) -> Refiner {
        Refiner {
            mode,
            pool: None,
            jobs: Vec::new(),
        }
    }

    /// `flat`, the quick tree of `target` just built: refined now ([`Refinement::Wait`]), or
    /// kept and refined in the background, or kept.
    pub(super) fn built(&mut self, target: Target, flat: FlatBvh) -> Arc<FlatBvh> {
        match self.mode {
            Refinement::Off => Arc::new(flat),
            Refinement::Wait => {
                // A refinement that panics leaves the quick tree, as in the background.
                let refined = std::panic::catch_unwind(|| refine(&flat));
                Arc::new(refined.unwrap_or(flat))
            }
            Refinement::Background => {
                let flat = Arc::new(flat);
                self.start(target, flat.clone());
                flat
            }
        }
    }

    fn start(&mut self, target: Target, from: Arc<FlatBvh>) {
        // A newer tree of the same target supersedes the refinement of the older one.
        self.jobs.retain(|j| j.target != target);
        if self.pool.is_none() {
            self.pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .thread_name(|_| "platoon refine".into())
                .start_handler(|_| {
                    super::threads::run_as_batch();
                })
                // A panic drops the job's sender: the quick tree stays (see `finished`).
                .panic_handler(|_| {})
                .build()
                .ok();
        }
        // No thread to be had: the quick tree stays.
        let Some(pool) = &self.pool else { return };
        let (send, done) = mpsc::sync_channel(1);
        let tree = from.clone();
        pool.spawn(move || {
            // The updater may be gone by now; then nobody wants the tree.
            let _ = send.send(refine(&tree));
        });
        self.jobs.push(Job {
            target,
            from,
            done,
            state: State::Running,
        });
    }

    /// The refinements done, each with the tree it was made from; those still running stay.
    pub(super) fn finished(&mut self) -> Vec<(Target, Arc<FlatBvh>, FlatBvh)> {
        for j in &mut self.jobs {
            j.poll(false);
        }
        let (ended, running): (Vec<Job>, Vec<Job>) = std::mem::take(&mut self.jobs)
            .into_iter()
            .partition(|j| !matches!(j.state, State::Running));
        self.jobs = running;
        ended
            .into_iter()
            .filter_map(|j| match j.state {
                State::Done(tree) => Some((j.target, j.from, tree)),
                _ => None,
            })
            .collect()
    }

    /// Waits for every refinement under way (the next update swaps them in).
    pub(super) fn wait(&mut self) {
        for j in &mut self.jobs {
            j.poll(true);
        }
    }

    /// Refinements started and not yet swapped in.
    pub(super) fn pending(&self) -> usize {
        self.jobs.len()
    }
}

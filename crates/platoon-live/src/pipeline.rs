//! Double buffering (Brigade): the updater runs on its own thread and builds generation N+1
//! while the tracers render generation N. The game thread [`Pipeline::push`]es its edits, each
//! checked at the call against the scene's structure (so a refused edit never reaches the
//! updater), then [`Pipeline::submit`]s them and later [`Pipeline::take`]s the generation.
//! It waits only when it asks for a generation that is not built yet, or submits while one is
//! still in flight (the one-frame-ahead throttle); both waits are measured.

use std::collections::VecDeque;
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::DVec3;

use super::edit::{Edit, Structure};
use super::{Generation, Updater};
use platoon_core::error::{Error, Result};
use platoon_core::flatten::GpuScene;
use platoon_core::frame::hit_geometry::HitGeometry;
use platoon_core::scene::Scene;

/// The updater's threads: how many, and the cores they may run on (empty: any). See
/// [`super::threads`] for why a game may want them apart from its tracers' cores.
#[derive(Clone, Debug)]
pub struct UpdaterThreads {
    pub count: usize,
    pub cpus: Vec<usize>,
}

impl Default for UpdaterThreads {
    fn default() -> Self {
        UpdaterThreads {
            count: 1,
            cpus: Vec::new(),
        }
    }
}

/// What a generation that changes the scene carries besides its commit.
#[derive(Clone, Copy, Debug, Default)]
struct Keep {
    scenes: bool,
    hit_geometry: bool,
}

pub struct Pipeline {
    /// What edits are checked against on the game thread.
    structure: Structure,
    pending: Vec<Edit>,
    to_updater: Option<SyncSender<(Vec<Edit>, Keep)>>,
    /// What each generation that changes the scene carries besides its commit.
    keep: Keep,
    from_updater: Receiver<Result<Generation>>,
    in_flight: bool,
    ready: VecDeque<Generation>,
    worker: Option<JoinHandle<()>>,
    /// Time the game thread spent waiting in each submit or take.
    blocked: Vec<Duration>,
}

impl Pipeline {
    /// Starts the updater for `scene` (see [`Updater::new`]) on one thread: the other cores are
    /// left to the tracers; returns the pipeline and the first generation's flattened scene
    /// (what the tracers are created with).
    pub fn new(scene: Scene, time: f32, origin: DVec3) -> Result<(Pipeline, Arc<GpuScene>)> {
        Pipeline::with_threads(scene, time, origin, 1)
    }

    /// The same with the updater's work (skinning, refits) spread over `threads` threads.
    pub fn with_threads(
        scene: Scene,
        time: f32,
        origin: DVec3,
        threads: usize,
    ) -> Result<(Pipeline, Arc<GpuScene>)> {
        let threads = UpdaterThreads {
            count: threads,
            ..Default::default()
        };
        Pipeline::with_updater_threads(scene, time, origin, &threads)
    }

    /// The same with the updater's threads as `threads` says: how many, and on which cores.
    pub fn with_updater_threads(
        scene: Scene,
        time: f32,
        origin: DVec3,
        threads: &UpdaterThreads,
    ) -> Result<(Pipeline, Arc<GpuScene>)> {
        let cpus = threads.cpus.clone();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.count.max(1))
            .thread_name(|i| format!("platoon updater {i}"))
            .start_handler(move |_| {
                // Best effort: where the system refuses, the threads run as any other.
                if !cpus.is_empty() {
                    super::threads::pin_current_thread(&cpus);
                }
                super::threads::run_as_batch();
            })
            .build()
            .map_err(|e| Error::Invalid(format!("starting the updater threads: {e}")))?;
        let structure = Structure::of(&scene);
        let mut updater = pool.install(|| Updater::new(scene, time, origin))?;
        let first = Arc::new(updater.flattened().clone());
        let (to_updater, edits) = mpsc::sync_channel::<(Vec<Edit>, Keep)>(1);
        let (done, from_updater) = mpsc::sync_channel::<Result<Generation>>(1);
        let worker = std::thread::Builder::new()
            .name("platoon updater".into())
            .spawn(move || {
                // The loop runs on a thread of the pool: each generation leaves from the thread
                // that built it, with no hand-back to this one (a wake-up fewer between the
                // update's end and the game thread's take).
                pool.install(move || {
                    while let Ok((batch, keep)) = edits.recv() {
                        let g = apply(&mut updater, batch)
                            .and_then(|()| updater.update())
                            .map(|mut g| {
                                if !g.commit.is_empty() {
                                    let now = updater.flattened();
                                    if keep.scenes {
                                        g.scene = Some(Arc::new(now.clone()));
                                    }
                                    if keep.hit_geometry {
                                        g.hits = Some(Arc::new(HitGeometry::of_flattened(now)));
                                    }
                                }
                                g
                            });
                        if done.send(g).is_err() {
                            break;
                        }
                    }
                })
            })
            .map_err(|e| Error::Invalid(format!("starting the updater thread: {e}")))?;
        let pipeline = Pipeline {
            structure,
            pending: Vec::new(),
            to_updater: Some(to_updater),
            keep: Keep::default(),
            from_updater,
            in_flight: false,
            ready: VecDeque::new(),
            worker: Some(worker),
            blocked: Vec::new(),
        };
        Ok((pipeline, first))
    }

    /// Checks `edit` (its values, and that it names what exists in the scene as edited so
    /// far) and queues it for the next submit; returns the node of an added instance. A refused
    /// edit never reaches the updater.
    pub fn push(&mut self, edit: Edit) -> Result<Option<usize>> {
        let edit = edit.checked()?;
        let added = self.structure.admit(&edit)?;
        self.pending.push(edit);
        Ok(added)
    }

    /// From the next submit on, each generation that changes the scene carries a snapshot of
    /// its flattened scene (`Generation::scene`): what a method's preparation on the CPU reads
    /// (vertex links' elements). A copy of the scene per generation.
    pub fn keep_scenes(&mut self) {
        self.keep.scenes = true;
    }

    /// From the next submit on, each generation that changes the scene carries what carries
    /// its hits back to the frame before (`Generation::hits`): what the denoiser's
    /// reprojection of moving objects reads. A few bytes per vertex and triangle.
    pub fn keep_hit_geometry(&mut self) {
        self.keep.hit_geometry = true;
    }

    /// Hands the edits made since the last submit to the updater, which starts building the
    /// next generation at once. Waits only if the previous submission is still being built.
    pub fn submit(&mut self) -> Result<()> {
        let start = Instant::now();
        if self.in_flight {
            let g = self.receive()?;
            self.ready.push_back(g);
        }
        let batch = std::mem::take(&mut self.pending);
        self.to_updater
            .as_ref()
            .expect("open until drop")
            .send((batch, self.keep))
            .map_err(|_| Error::Invalid("the updater thread has stopped".into()))?;
        self.in_flight = true;
        self.blocked.push(start.elapsed());
        Ok(())
    }

    /// The oldest submitted generation, waiting for it if it is not built yet.
    pub fn take(&mut self) -> Result<Generation> {
        let start = Instant::now();
        let g = match self.ready.pop_front() {
            Some(g) => g,
            None if self.in_flight => self.receive()?,
            None => return Err(Error::Invalid("take() before any submit()".into())),
        };
        self.blocked.push(start.elapsed());
        Ok(g)
    }

    /// The oldest submitted generation if it is built, without waiting: a game that must not
    /// stall renders the generation its tracers hold once more (with this frame's camera) and
    /// keeps its edits for the next submit. Not counted in [`Pipeline::blocked_times`].
    pub fn try_take(&mut self) -> Result<Option<Generation>> {
        if let Some(g) = self.ready.pop_front() {
            return Ok(Some(g));
        }
        if !self.in_flight {
            return Ok(None);
        }
        match self.from_updater.try_recv() {
            Ok(g) => {
                self.in_flight = false;
                g.map(Some)
            }
            Err(mpsc::TryRecvError::Empty) => Ok(None),
            Err(mpsc::TryRecvError::Disconnected) => {
                Err(Error::Invalid("the updater thread has stopped".into()))
            }
        }
    }

    /// Edits made since the last submit.
    pub fn has_pending(&self) -> bool {
        !self.pending.is_empty()
    }

    /// Whether a submitted generation is waiting to be taken (built or not).
    pub fn has_submitted(&self) -> bool {
        self.in_flight || !self.ready.is_empty()
    }

    /// Whether a submitted generation is still being built (then `submit` would wait for it).
    pub fn in_flight(&self) -> bool {
        self.in_flight
    }

    /// How long each submit and take kept the game thread waiting.
    pub fn blocked_times(&self) -> &[Duration] {
        &self.blocked
    }

    fn receive(&mut self) -> Result<Generation> {
        self.in_flight = false;
        self.from_updater
            .recv()
            .map_err(|_| Error::Invalid("the updater thread has stopped".into()))?
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        // Closing the channel ends the worker's loop.
        self.to_updater = None;
        while self.in_flight {
            let _ = self.receive();
        }
        if let Some(w) = self.worker.take() {
            let _ = w.join();
        }
    }
}

fn apply(updater: &mut Updater, batch: Vec<Edit>) -> Result<()> {
    for e in batch {
        updater.apply(e)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use platoon_core::scene::Placement;

    #[test]
    fn generations_arrive_in_order_with_the_edits_of_their_submission() {
        let scene = platoon_core::scene::cornell::scene();
        let node = scene.nodes.iter().position(|n| n.mesh.is_some()).unwrap();
        let (mut p, first) = Pipeline::new(scene, 0.0, DVec3::ZERO).unwrap();
        let added = p
            .push(Edit::AddInstance {
                mesh: 0,
                placement: Placement::at(DVec3::X * 3.0),
            })
            .unwrap()
            .unwrap();
        p.submit().unwrap();
        p.push(Edit::Placement {
            node,
            placement: Placement::at(DVec3::Y),
        })
        .unwrap();
        // A second submit while the first is built: it waits, and keeps the first generation.
        p.submit().unwrap();
        let a = p.take().unwrap();
        let b = p.take().unwrap();
        assert_eq!((a.id, b.id), (2, 3));
        assert_eq!(a.commit.header.instances, first.instances.len() as u32 + 1);
        assert!(b.commit.arrays.iter().any(|c| c.array == 6));
        assert_eq!(b.commit.mesh_bytes(), 0);
        assert!(p.take().is_err(), "nothing submitted");
        // Refused at the call, never reaching the updater.
        assert!(p.push(Edit::RemoveInstance(added)).is_ok());
        assert!(p.push(Edit::RemoveInstance(added)).is_err());
        assert!(p
            .push(Edit::Placement {
                node: 9999,
                placement: Placement::at(DVec3::ZERO)
            })
            .is_err());
        assert!(p
            .push(Edit::AddInstance {
                mesh: 42,
                placement: Placement::at(DVec3::ZERO)
            })
            .is_err());
        p.submit().unwrap();
        let c = p.take().unwrap();
        assert_eq!(c.commit.header.instances, first.instances.len() as u32);
        assert_eq!(p.blocked_times().len(), 6);
        // Without waiting: nothing until the generation is built, then it, once.
        p.push(Edit::Time(0.5)).unwrap();
        p.submit().unwrap();
        let start = std::time::Instant::now();
        let got = loop {
            if let Some(g) = p.try_take().unwrap() {
                break g;
            }
            assert!(start.elapsed().as_secs() < 10, "the generation never came");
        };
        assert_eq!(got.id, c.id + 1);
        assert!(!p.in_flight());
        assert!(p.try_take().unwrap().is_none());
    }
}

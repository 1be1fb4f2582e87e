//! Double buffering (Brigade): the updater runs on its own thread and builds generation N+1
//! while the tracers render generation N. The game thread edits through the pipeline, each edit
//! checked at the call against a mirror of the scene's structure (so a refused edit never reaches
//! the updater), then [`Pipeline::submit`]s them and later [`Pipeline::take`]s the generation.
//! It waits only when it asks for a generation that is not built yet, or submits while one is
//! still in flight (the one-frame-ahead throttle); both waits are measured.

use std::collections::{HashSet, VecDeque};
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::DVec3;

use super::{Generation, Updater};
use crate::error::{Error, Result};
use crate::flatten::GpuScene;
use crate::scene::environment::Environment;
use crate::scene::placement::invalid;
use crate::scene::{Material, Placement, PunctualLight, Scene};

/// One checked edit, as the updater thread replays it.
enum Edit {
    Time(f32),
    Placement(usize, Placement),
    AddInstance(usize, Placement),
    RemoveInstance(usize),
    Material(usize, Box<Material>),
    Light(usize, Box<PunctualLight>),
    Environment(Box<Option<Environment>>),
    FollowCamera(DVec3),
}

/// What the game thread knows of the scene's structure, to check edits without the updater.
struct Mirror {
    nodes: usize,
    meshes: usize,
    materials: usize,
    lights: usize,
    removed: HashSet<usize>,
    instanced: HashSet<usize>,
}

impl Mirror {
    fn of(scene: &Scene) -> Mirror {
        Mirror {
            nodes: scene.nodes.len(),
            meshes: scene.meshes.len(),
            materials: scene.materials.len(),
            lights: scene.lights.len(),
            removed: HashSet::new(),
            instanced: (0..scene.nodes.len())
                .filter(|&i| scene.nodes[i].mesh.is_some())
                .collect(),
        }
    }

    fn live(&self, node: usize) -> Result<()> {
        if self.removed.contains(&node) {
            return Err(invalid(format!(
                "node {node}'s instance was already removed"
            )));
        }
        if node >= self.nodes {
            return Err(invalid(format!(
                "no node {node} (the scene has {})",
                self.nodes
            )));
        }
        Ok(())
    }
}

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

pub struct Pipeline {
    mirror: Mirror,
    pending: Vec<Edit>,
    to_updater: Option<SyncSender<Vec<Edit>>>,
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
        let mirror = Mirror::of(&scene);
        let mut updater = pool.install(|| Updater::new(scene, time, origin))?;
        let first = Arc::new(updater.flattened().clone());
        let (to_updater, edits) = mpsc::sync_channel::<Vec<Edit>>(1);
        let (done, from_updater) = mpsc::sync_channel::<Result<Generation>>(1);
        let worker = std::thread::Builder::new()
            .name("platoon updater".into())
            .spawn(move || {
                // The loop runs on a thread of the pool: each generation leaves from the thread
                // that built it, with no hand-back to this one (a wake-up fewer between the
                // update's end and the game thread's take).
                pool.install(move || {
                    while let Ok(batch) = edits.recv() {
                        let g = apply(&mut updater, batch).and_then(|()| updater.update());
                        if done.send(g).is_err() {
                            break;
                        }
                    }
                })
            })
            .map_err(|e| Error::Invalid(format!("starting the updater thread: {e}")))?;
        let pipeline = Pipeline {
            mirror,
            pending: Vec::new(),
            to_updater: Some(to_updater),
            from_updater,
            in_flight: false,
            ready: VecDeque::new(),
            worker: Some(worker),
            blocked: Vec::new(),
        };
        Ok((pipeline, first))
    }

    pub fn set_time(&mut self, time: f32) -> Result<()> {
        crate::drive::updater::check_time(time)?;
        self.pending.push(Edit::Time(time));
        Ok(())
    }

    pub fn set_placement(&mut self, node: usize, placement: Placement) -> Result<()> {
        let p = placement.checked()?;
        self.mirror.live(node)?;
        self.pending.push(Edit::Placement(node, p));
        Ok(())
    }

    /// Returns the node the new instance will have.
    pub fn add_instance(&mut self, mesh: usize, placement: Placement) -> Result<usize> {
        let p = placement.checked()?;
        if mesh >= self.mirror.meshes {
            return Err(invalid(format!(
                "no mesh {mesh} (the scene has {})",
                self.mirror.meshes
            )));
        }
        self.pending.push(Edit::AddInstance(mesh, p));
        let node = self.mirror.nodes;
        self.mirror.nodes += 1;
        self.mirror.instanced.insert(node);
        Ok(node)
    }

    pub fn remove_instance(&mut self, node: usize) -> Result<()> {
        self.mirror.live(node)?;
        if !self.mirror.instanced.remove(&node) {
            return Err(invalid(format!("node {node} places no instance")));
        }
        self.mirror.removed.insert(node);
        self.pending.push(Edit::RemoveInstance(node));
        Ok(())
    }

    pub fn set_material(&mut self, index: usize, material: Material) -> Result<()> {
        if index >= self.mirror.materials {
            return Err(invalid(format!(
                "no material {index} (the scene has {})",
                self.mirror.materials
            )));
        }
        crate::drive::updater::check_material(index, &material)?;
        self.pending.push(Edit::Material(index, Box::new(material)));
        Ok(())
    }

    pub fn set_light(&mut self, index: usize, light: PunctualLight) -> Result<()> {
        if index >= self.mirror.lights {
            return Err(invalid(format!(
                "no light {index} (the scene has {})",
                self.mirror.lights
            )));
        }
        crate::drive::updater::check_light(index, &light)?;
        self.pending.push(Edit::Light(index, Box::new(light)));
        Ok(())
    }

    pub fn set_environment(&mut self, environment: Option<Environment>) -> Result<()> {
        crate::drive::updater::check_environment(environment.as_ref())?;
        self.pending.push(Edit::Environment(Box::new(environment)));
        Ok(())
    }

    /// Where the camera is (world space): the render origin follows it when it drifts far
    /// (see [`Updater::follow_camera`]; each generation says its origin).
    pub fn follow_camera(&mut self, camera: DVec3) -> Result<()> {
        crate::drive::updater::check_camera(camera)?;
        self.pending.push(Edit::FollowCamera(camera));
        Ok(())
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
            .send(batch)
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
        match e {
            Edit::Time(t) => updater.set_time(t)?,
            Edit::Placement(node, p) => updater.set_placement(node, p)?,
            Edit::AddInstance(mesh, p) => {
                updater.add_instance(mesh, p)?;
            }
            Edit::RemoveInstance(node) => updater.remove_instance(node)?,
            Edit::Material(i, m) => updater.set_material(i, *m)?,
            Edit::Light(i, l) => updater.set_light(i, *l)?,
            Edit::Environment(e) => updater.set_environment(*e)?,
            Edit::FollowCamera(c) => updater.follow_camera(c)?,
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generations_arrive_in_order_with_the_edits_of_their_submission() {
        let scene = crate::scene::cornell::scene();
        let node = scene.nodes.iter().position(|n| n.mesh.is_some()).unwrap();
        let (mut p, first) = Pipeline::new(scene, 0.0, DVec3::ZERO).unwrap();
        let added = p.add_instance(0, Placement::at(DVec3::X * 3.0)).unwrap();
        p.submit().unwrap();
        p.set_placement(node, Placement::at(DVec3::Y)).unwrap();
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
        assert!(p.remove_instance(added).is_ok());
        assert!(p.remove_instance(added).is_err());
        assert!(p.set_placement(9999, Placement::at(DVec3::ZERO)).is_err());
        assert!(p.add_instance(42, Placement::at(DVec3::ZERO)).is_err());
        p.submit().unwrap();
        let c = p.take().unwrap();
        assert_eq!(c.commit.header.instances, first.instances.len() as u32);
        assert_eq!(p.blocked_times().len(), 6);
        // Without waiting: nothing until the generation is built, then it, once.
        p.set_time(0.5).unwrap();
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

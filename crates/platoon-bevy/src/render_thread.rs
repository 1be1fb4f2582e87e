//! platoon's frame driver on a thread of its own: the game hands it what changed and the camera
//! and never waits; it renders frame after frame (converging while nothing moves) and leaves
//! the newest finished frame where the game picks it up.

use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use anyhow::Result;
use platoon::core::scene::camera::Camera;
use platoon::core::scene::Scene;
use platoon::drive::{Edit, FinishedFrame, FrameDriver};
use platoon::game::GameOptions;
use platoon::prepare::{EnvChoice, EnvLight};

/// One game frame's news for the render thread.
pub struct Update {
    /// Counting from 1: the game's changes so far.
    pub seq: u64,
    /// A scene built anew (the structure changed): the driver restarts on it.
    pub scene: Option<Box<Scene>>,
    pub edits: Vec<Edit>,
    pub camera: Camera,
}

/// What the render thread leaves for the game.
#[derive(Default)]
pub struct Outbox {
    pub newest: Option<Box<FinishedFrame>>,
    /// Frames finished since the thread started.
    pub frames: u64,
    /// The scene build (counting from 1) the newest frame rendered.
    pub build: u64,
    /// The newest update taken in, and whether the view has converged with it
    /// (`converge_at` samples a pixel, nothing left to apply).
    pub seq: u64,
    pub settled: bool,
    pub errors: Vec<String>,
}

/// How the thread renders.
#[derive(Clone)]
pub struct ThreadOptions {
    pub game: GameOptions,
    pub environment: EnvChoice,
    /// Stop adding samples to a still view once its film holds this many a pixel.
    pub converge_at: Option<u32>,
}

pub struct RenderThread {
    updates: Option<Sender<Update>>,
    pub outbox: Arc<Mutex<Outbox>>,
    handle: Option<JoinHandle<()>>,
}

impl RenderThread {
    pub fn start(options: ThreadOptions) -> RenderThread {
        let (updates, inbox) = mpsc::channel();
        let outbox = Arc::new(Mutex::new(Outbox::default()));
        let out = outbox.clone();
        let handle = std::thread::Builder::new()
            .name("platoon".into())
            .spawn(move || {
                if let Err(e) = run(&options, &inbox, &out) {
                    let mut o = out.lock().expect("the outbox is never poisoned");
                    o.errors.push(format!("{e:#}"));
                }
            })
            .expect("a thread starts");
        RenderThread {
            updates: Some(updates),
            outbox,
            handle: Some(handle),
        }
    }

    /// Hands the thread a frame's news; false once the thread has stopped (its error is in the
    /// outbox).
    pub fn send(&self, update: Update) -> bool {
        self.updates
            .as_ref()
            .is_some_and(|u| u.send(update).is_ok())
    }
}

impl Drop for RenderThread {
    fn drop(&mut self) {
        self.updates = None;
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

fn run(options: &ThreadOptions, inbox: &Receiver<Update>, outbox: &Mutex<Outbox>) -> Result<()> {
    let mut driver: Option<FrameDriver> = None;
    let mut camera: Option<Camera> = None;
    let mut settled = false;
    let mut builds = 0u64;
    loop {
        // Waits for news only when there is nothing to render: no scene yet, or a still view
        // converged.
        let mut news = Vec::new();
        if driver.is_none() || settled {
            match inbox.recv() {
                Ok(u) => news.push(u),
                Err(_) => return Ok(()),
            }
        }
        loop {
            match inbox.try_recv() {
                Ok(u) => news.push(u),
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => return Ok(()),
            }
        }
        // The newest scene replaces the driver; edits made before it are in it already.
        let mut edits = Vec::new();
        let mut scene = None;
        let mut seq = None;
        for u in news {
            seq = Some(u.seq);
            if u.scene.is_some() {
                scene = u.scene;
                edits.clear();
            }
            edits.extend(u.edits);
            if camera != Some(u.camera) {
                camera = Some(u.camera);
                settled = false;
            }
        }
        if let Some(mut scene) = scene {
            // The old driver ends (and its tracers with it) before the new one's start.
            drop(driver.take());
            platoon::prepare::light(&mut scene, &options.environment, &EnvLight::default())?;
            driver = Some(platoon::game::start(*scene, &options.game)?);
            builds += 1;
            settled = false;
        }
        let (Some(d), Some(cam)) = (driver.as_mut(), camera) else {
            continue;
        };
        for edit in edits {
            settled = false;
            if let Err(e) = d.scene().push(edit) {
                outbox
                    .lock()
                    .expect("never poisoned")
                    .errors
                    .push(format!("{e}"));
            }
        }
        if settled {
            let mut o = outbox.lock().expect("never poisoned");
            o.seq = seq.unwrap_or(o.seq);
            continue;
        }
        d.frame(cam)?;
        let done = d.finish()?.expect("a frame was started");
        let pipeline = d.scene();
        let quiet = !pipeline.has_pending() && !pipeline.has_submitted();
        settled = quiet
            && options
                .converge_at
                .zip(done.stats.film_samples)
                .is_some_and(|(n, s)| s >= n);
        let mut o = outbox.lock().expect("never poisoned");
        o.seq = seq.unwrap_or(o.seq);
        o.settled = settled;
        o.frames += 1;
        o.build = builds;
        o.newest = Some(Box::new(done));
    }
}

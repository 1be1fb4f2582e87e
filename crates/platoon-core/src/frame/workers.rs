//! One persistent thread per tracer. A game renders a frame every few milliseconds; spawning a
//! thread per tracer per frame would cost tens of microseconds each and lose the thread's warm
//! caches and core. Each tracer lives on its own thread for the renderer's lifetime and takes
//! work through a channel; the renderer may still reach it between frames (names, defines,
//! validation messages) through a mutex that is uncontended then.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;

use crate::flatten::commit::Commit;
use crate::frame::{Band, BandTracer, FrameParams, Span, TracerError};

enum Job {
    Render {
        params: Arc<FrameParams>,
        span: Span,
    },
    Commit(Arc<Commit>),
}

pub(crate) enum Done {
    Band(Result<Band, TracerError>),
    Committed(Result<u64, TracerError>),
}

pub(crate) struct Worker<T> {
    tracer: Arc<Mutex<T>>,
    jobs: Option<Sender<Job>>,
    done: Receiver<Done>,
    thread: Option<JoinHandle<()>>,
}

impl<T: BandTracer + Send + 'static> Worker<T> {
    /// Starts the thread of tracer `index`. It inherits the creating thread's CPU affinity.
    pub fn start(index: usize, tracer: T) -> Worker<T> {
        let tracer = Arc::new(Mutex::new(tracer));
        let (jobs, inbox) = mpsc::channel::<Job>();
        let (outbox, done) = mpsc::channel();
        let shared = Arc::clone(&tracer);
        let thread = std::thread::Builder::new()
            .name(format!("platoon tracer {index}"))
            .spawn(move || {
                for job in inbox {
                    let mut t = match shared.lock() {
                        Ok(t) => t,
                        // A tracer that panicked is never given work again (the renderer drops
                        // it); nothing to do but end.
                        Err(_) => return,
                    };
                    let result = match job {
                        Job::Render { params, span } => {
                            Done::Band(run(|| t.render_band(&params, span, &mut |_| {})))
                        }
                        Job::Commit(commit) => Done::Committed(run(|| t.apply_commit(&commit))),
                    };
                    drop(t);
                    if outbox.send(result).is_err() {
                        return;
                    }
                }
            })
            .expect("the system refused a tracer thread");
        Worker {
            tracer,
            jobs: Some(jobs),
            done,
            thread: Some(thread),
        }
    }

    /// Starts rendering `span`; [`Worker::band`] waits for the result.
    pub fn start_band(&self, params: &Arc<FrameParams>, span: Span) {
        self.send(Job::Render {
            params: Arc::clone(params),
            span,
        });
    }

    pub fn band(&self) -> Result<Band, TracerError> {
        match self.done.recv() {
            Ok(Done::Band(result)) => result,
            Ok(Done::Committed(_)) => Err("tracer thread answered out of turn".into()),
            Err(_) => Err("tracer thread panicked".into()),
        }
    }

    /// Starts applying `commit`; [`Worker::committed`] waits for the result.
    pub fn start_commit(&self, commit: &Arc<Commit>) {
        self.send(Job::Commit(Arc::clone(commit)));
    }

    pub fn committed(&self) -> Result<u64, TracerError> {
        match self.done.recv() {
            Ok(Done::Committed(result)) => result,
            Ok(Done::Band(_)) => Err("tracer thread answered out of turn".into()),
            Err(_) => Err("tracer thread panicked".into()),
        }
    }

    /// The tracer, between jobs. None if it panicked.
    pub fn lock(&self) -> Option<MutexGuard<'_, T>> {
        self.tracer.lock().ok()
    }

    fn send(&self, job: Job) {
        // A send fails only when the thread has ended (its tracer panicked); the answer that
        // then never comes reads as a panic in `band` / `committed`.
        if let Some(jobs) = &self.jobs {
            let _ = jobs.send(job);
        }
    }

    /// Ends the thread and gives the tracer back (None if it panicked).
    pub fn into_tracer(self) -> Option<T> {
        let tracer = Arc::clone(&self.tracer);
        // Ends the thread, which drops its handle on the tracer.
        drop(self);
        Arc::try_unwrap(tracer).ok()?.into_inner().ok()
    }
}

fn run<R>(job: impl FnOnce() -> Result<R, TracerError>) -> Result<R, TracerError> {
    catch_unwind(AssertUnwindSafe(job)).unwrap_or_else(|_| Err("tracer thread panicked".into()))
}

impl<T> Drop for Worker<T> {
    fn drop(&mut self) {
        self.jobs = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

//! One persistent thread per tracer. A game renders a frame every few milliseconds; spawning a
//! thread per tracer per frame would cost tens of microseconds each and lose the thread's warm
//! caches and core. Each tracer lives on its own thread for the renderer's lifetime and takes
//! work through a channel; the renderer may still reach it between frames (names, defines,
//! validation messages) through a mutex that is uncontended then.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::mpsc::{self, Receiver, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use platoon_frame::balance::steal::ClaimBoard;
use platoon_frame::flatten::commit::Commit;
use platoon_frame::frame::{Band, BandTracer, Span, TracerError, ValidatedFrame};

enum Job {
    /// A band; with `report`, the samples done so far as its passes end (`Done::Progress`).
    Render {
        params: Arc<ValidatedFrame>,
        span: Span,
        report: bool,
    },
    /// The head of band `slot` of the board, then pieces claimed until none is left.
    Steal {
        params: Arc<ValidatedFrame>,
        board: Arc<ClaimBoard>,
        slot: usize,
    },
    Commit(Arc<Commit>),
}

pub(crate) enum Done {
    /// Samples of the band in progress done so far (a `Render` job with `report`).
    Progress(u32),
    Band(Result<Band, TracerError>),
    Stolen(Stolen),
    Committed(Result<u64, TracerError>),
}

/// What a tracer rendered of a frame with stealing: its head and the pieces it claimed, in
/// the order it rendered them, until the board was empty or it failed.
#[derive(Default)]
pub(crate) struct Stolen {
    pub bands: Vec<Band>,
    /// Its head's time plus the wall time from the head's end to its last piece's: all it
    /// spent on the frame, but for the work before the head's dispatch (a kernel's first
    /// compilation), which is no part of its speed.
    pub busy: Duration,
    /// Pieces claimed besides the head.
    pub pieces: u32,
    /// Pixels of the pieces claimed from other tracers' bands.
    pub stolen: u32,
    pub error: Option<TracerError>,
}

/// Renders the head of `slot`'s band and claims pieces until none is left (`ClaimBoard`).
fn steal<T: BandTracer>(
    t: &mut T,
    params: &ValidatedFrame,
    board: &ClaimBoard,
    slot: usize,
) -> Stolen {
    let mut out = Stolen::default();
    let head = board.head(slot);
    if !head.is_empty() {
        match run(|| t.render_band(params, head, &mut |_| {})) {
            Ok(band) => {
                out.busy = band.wall_time;
                out.bands.push(band);
            }
            Err(e) => {
                out.error = Some(e);
                return out;
            }
        }
    }
    // The claims' clock starts with the head's dispatch, as `busy` does: a kernel's first
    // compilation before it would read as a slow tracer.
    let after_head = Instant::now();
    let now = |head: Duration| (head + after_head.elapsed()).as_secs_f64();
    while let Some(piece) = board.claim(slot, now(out.busy)) {
        match run(|| t.render_band(params, piece.span, &mut |_| {})) {
            Ok(band) => {
                out.bands.push(band);
                out.pieces += 1;
                if piece.stolen {
                    out.stolen += piece.span.len();
                }
            }
            Err(e) => {
                out.error = Some(e);
                break;
            }
        }
    }
    out.busy += after_head.elapsed();
    out
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
                        Job::Render {
                            params,
                            span,
                            report,
                        } => {
                            let mut progress = |done: u32| {
                                if report {
                                    let _ = outbox.send(Done::Progress(done));
                                }
                            };
                            Done::Band(run(|| t.render_band(&params, span, &mut progress)))
                        }
                        Job::Steal {
                            params,
                            board,
                            slot,
                        } => Done::Stolen(steal(&mut *t, &params, &board, slot)),
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

    /// Starts rendering `span`, reporting its samples as they are done when `report`;
    /// [`Worker::band`] waits for the result.
    pub fn start_band(&self, params: &Arc<ValidatedFrame>, span: Span, report: bool) {
        self.send(Job::Render {
            params: Arc::clone(params),
            span,
            report,
        });
    }

    /// The band started last, `progress` hearing its samples done meanwhile (when reported).
    pub fn band(&self, progress: &mut dyn FnMut(u32)) -> Result<Band, TracerError> {
        loop {
            match self.done.recv() {
                Ok(Done::Progress(done)) => progress(done),
                Ok(Done::Band(result)) => return result,
                Ok(_) => return Err("tracer thread answered out of turn".into()),
                Err(_) => return Err("tracer thread panicked".into()),
            }
        }
    }

    /// Starts rendering band `slot` of `board` with stealing; [`Worker::stolen`] waits.
    pub fn start_stealing(
        &self,
        params: &Arc<ValidatedFrame>,
        board: &Arc<ClaimBoard>,
        slot: usize,
    ) {
        self.send(Job::Steal {
            params: Arc::clone(params),
            board: Arc::clone(board),
            slot,
        });
    }

    pub fn stolen(&self) -> Stolen {
        let failed = |why: &str| Stolen {
            error: Some(why.into()),
            ..Default::default()
        };
        match self.done.recv() {
            Ok(Done::Stolen(stolen)) => stolen,
            Ok(_) => failed("tracer thread answered out of turn"),
            Err(_) => failed("tracer thread panicked"),
        }
    }

    /// Starts applying `commit`; [`Worker::committed`] waits for the result.
    pub fn start_commit(&self, commit: &Arc<Commit>) {
        self.send(Job::Commit(Arc::clone(commit)));
    }

    pub fn committed(&self) -> Result<u64, TracerError> {
        match self.done.recv() {
            Ok(Done::Committed(result)) => result,
            Ok(_) => Err("tracer thread answered out of turn".into()),
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

//! `platoon render --frames A..B[:STEP]`: an animation to numbered files, with what a render
//! farm needs: a task's share of the range from a job-array index in the environment, each
//! frame written atomically, frames already done skipped (resume), and a line per frame on
//! standard output saying what became of it (`frame N: ok|skipped|failed ...`); the exit
//! status is non-zero when any frame failed.

use std::path::Path;
use std::time::Instant;

use anyhow::{bail, Result};
use indicatif::{ProgressBar, ProgressStyle};
use platoon::animation::{frame_path, task_index, Animation};
use platoon::Tracers;

use super::args::{FrameArgs, RenderArgs};

use super::frame_log::FrameLog;
use super::job::Job;
use super::outputs;
use super::setup::{check_output, on_every_rank, setup, Setup};

pub fn run(a: RenderArgs) -> Result<()> {
    // A sequence's folder is made, as Blender and Cycles make it (a still's must exist).
    if let Some(dir) = a.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            anyhow::anyhow!("{}: cannot make the output folder: {e}", dir.display())
        })?;
    }
    check_output(&a)?;
    if a.scene.time != 0.0 {
        bail!("--time and --frames: each frame's time is its number / --fps");
    }
    if let Some(v) = &a.frames.video {
        super::video::check(v, a.frames.task_index.is_some())?;
    }
    let (setup, out, args) = setup(a)?;
    let session = setup.session.clone();
    on_every_rank(session, || animation(setup, out, args))
}

/// The frames of `run`.
fn animation(setup: Setup, out: std::path::PathBuf, args: FrameArgs) -> Result<()> {
    let speaks = setup.speaks();
    let view = setup.image.view;
    let range = args
        .frames
        .or(args.mpi_frames)
        .expect("run only with --frames or --mpi-frames");
    if !(args.fps.is_finite() && args.fps > 0.0) {
        bail!("--fps must be a positive number, not {}", args.fps);
    }
    // Each frame's time is its number / fps: refused now if one is not a finite time.
    let last = range
        .frames()
        .into_iter()
        .map(|f| f.abs())
        .max()
        .unwrap_or(0);
    if !((last as f64 / args.fps) as f32).is_finite() {
        bail!(
            "--fps {:e}: frame {last} would be at {:e} s, past what a time can hold",
            args.fps,
            last as f64 / args.fps
        );
    }
    let frames = match &args.task_index {
        Some(var) => range.chunk(args.chunk, task_index(var)?)?,
        None => range.frames(),
    };
    let paths: Vec<std::path::PathBuf> = frames.iter().map(|&f| frame_path(&out, f)).collect();
    let job = Job::new(&setup, &args);
    let log = FrameLog {
        json: args.log_json,
    };
    let mut todo = Vec::new();
    for f in frames {
        let path = frame_path(&out, f);
        if !args.overwrite && job.done(&path, f) {
            if speaks {
                println!("{}", log.skipped(f, &path));
            }
        } else {
            todo.push(f);
        }
    }
    // Over ranks, the frames are those rank 0 found to do (the others may not see its files).
    if let Some(s) = &setup.session {
        let mine: Vec<u8> = todo.iter().flat_map(|f| f.to_le_bytes()).collect();
        todo = s
            .broadcast(mine)
            .chunks_exact(8)
            .map(|b| i64::from_le_bytes(b.try_into().expect("8 bytes")))
            .collect();
    }
    if todo.is_empty() {
        eprintln!("every frame is done (--overwrite renders them again)");
        if let Some(v) = &args.video {
            super::video::encode(v, &paths, args.fps, &view)?;
        }
        return Ok(());
    }
    let farm = args.mpi_frames.is_some();
    let mut frames = Frames::new(setup, args.fresh_prepare, speaks || farm, speaks)?;
    let start = Instant::now();
    let tally = if farm {
        let session = frames
            .setup
            .session
            .clone()
            .expect("--mpi-frames joins the job");
        let (rendered, failed) = super::farm::run(&session, todo, &out, log, |f, path| {
            frames.render(&job, f, path, &mut |_| {})
        })?;
        Tally { rendered, failed }
    } else {
        in_order(&mut frames, &job, &out, &todo, log)?
    };
    if !speaks {
        return Ok(());
    }
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "{} frame(s) in {secs:.1} s ({:.2} s a frame), {} failed",
        tally.rendered,
        secs / tally.rendered.max(1) as f64,
        tally.failed
    );
    if tally.failed > 0 {
        bail!("{} of {} frame(s) failed", tally.failed, tally.rendered);
    }
    if let Some(v) = &args.video {
        super::video::encode(v, &paths, args.fps, &view)?;
    }
    Ok(())
}

/// Frames rendered and failed.
struct Tally {
    rendered: u64,
    failed: u64,
}

/// Renders `todo` in order with a progress bar; over ranks every frame is split between them,
/// and a rank failing one ends the job (it is out of step with the others).
fn in_order(
    frames: &mut Frames,
    job: &Job,
    out: &Path,
    todo: &[i64],
    log: FrameLog,
) -> Result<Tally> {
    let speaks = frames.speaks;
    let spp = frames.setup.request.spp as u64;
    let bar = if speaks {
        ProgressBar::new(todo.len() as u64 * spp)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {msg} (eta {eta})").unwrap(),
    );
    let job_of_ranks = frames.setup.session.is_some();
    let mut failed = 0;
    for (i, &f) in todo.iter().enumerate() {
        bar.set_message(format!("frame {f} ({} of {})", i + 1, todo.len()));
        bar.set_position(i as u64 * spp);
        let path = frame_path(out, f);
        let began = Instant::now();
        let done = i as u64 * spp;
        let result = frames.render(job, f, &path, &mut |s| bar.set_position(done + s as u64));
        if job_of_ranks && result.is_err() {
            return result.map(|_| Tally {
                rendered: 0,
                failed: 0,
            });
        }
        if !speaks {
            continue;
        }
        bar.suspend(|| match result {
            Ok(()) => println!("{}", log.ok(f, &path, began.elapsed().as_secs_f64(), None)),
            Err(e) => {
                failed += 1;
                println!("{}", log.failed(f, &e, None));
            }
        });
    }
    bar.finish_and_clear();
    Ok(Tally {
        rendered: todo.len() as u64,
        failed,
    })
}

/// The scene and tracers carried from frame to frame (or, with `--fresh-prepare`, made anew
/// for each).
struct Frames {
    setup: Setup,
    /// The scene read, until the animation takes it (not kept beside the animation's copy:
    /// a large scene's meshes and textures would be held twice for the whole sequence).
    to_animate: Option<platoon::core::Scene>,
    carried: Option<(Animation, Tracers)>,
    fresh: bool,
    /// Whether this process writes the frames it renders (rank 0 of a job, a process alone,
    /// every rank of a farm).
    writes: bool,
    /// Whether it reports (rank 0, or a process alone).
    speaks: bool,
}

impl Frames {
    fn new(mut setup: Setup, fresh: bool, writes: bool, speaks: bool) -> Result<Frames> {
        if speaks {
            for w in &setup.scene.warnings {
                eprintln!("warning: {w}");
            }
        }
        // Prepared anew, every frame reads the scene; carried, the animation holds it.
        let to_animate = (!fresh).then(|| std::mem::take(&mut setup.scene));
        Ok(Frames {
            setup,
            to_animate,
            carried: None,
            fresh,
            writes,
            speaks,
        })
    }

    /// Renders frame `frame` of `job` to `path` (atomically: a temporary file renamed).
    fn render(
        &mut self,
        job: &Job,
        frame: i64,
        path: &Path,
        progress: &mut dyn FnMut(u32),
    ) -> Result<()> {
        let time = job.time(frame);
        let interval = job.frame_interval();
        let request = &self.setup.request;
        let ranks = self.setup.ranks();
        // The scene at the frame's time and the tracers holding it: prepared anew, or carried
        // from the last frame by the updater.
        let mut fresh = None;
        let (shown, camera, tracers) = if self.fresh {
            let mut options = self.setup.options.clone();
            options.time = time;
            let prepared = platoon::prepare(self.setup.scene.clone(), &options)?;
            let tracers = request.tracers(&prepared.gpu, ranks)?;
            let (prepared, tracers) = fresh.insert((prepared, tracers));
            (prepared.shown(interval), prepared.camera, tracers)
        } else {
            if self.carried.is_none() {
                let mut options = self.setup.options.clone();
                options.time = time;
                // Taken by the first frame: a frame after one that could not animate the
                // scene fails too, saying so.
                let Some(scene) = self.to_animate.take() else {
                    bail!("the scene could not be animated (the first frame's error says why)");
                };
                let animation = Animation::new(scene, &options)?;
                if let (Some(note), true) = (&animation.note, self.speaks) {
                    eprintln!("note: {note}");
                }
                let tracers = request.tracers(animation.scene(), ranks)?;
                self.carried = Some((animation, tracers));
            }
            let (animation, tracers) = self.carried.as_mut().expect("made above");
            if animation.time() != time {
                let generation = animation.advance(time)?;
                tracers.apply_commit(&generation.commit, generation.id as u32)?;
            }
            let animation = &*animation;
            (animation.shown(interval), animation.camera(), tracers)
        };
        let camera = request.camera.in_render_space(camera, shown.facts.origin);
        let params = job.params(request, frame, camera);
        let rendered = request.render_frame(tracers, shown.gpu, &params, progress)?;
        let mut more = vec![
            ("animation_frame".into(), frame.to_string()),
            ("animation_time".into(), time.to_string()),
            ("job".into(), job.of_frame(frame)),
        ];
        more.extend(outputs::entries(&self.setup.image, path));
        // Every rank makes the outputs: their AOVs are split between the ranks as the image is.
        let still = request.outputs(tracers, &shown, &params, rendered, more)?;
        if !self.writes {
            return Ok(());
        }
        outputs::write(&still, path, &self.setup.image)?;
        Ok(())
    }
}

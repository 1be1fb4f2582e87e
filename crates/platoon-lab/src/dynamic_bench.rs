//! `platoon bench dynamic`: a living scene under measurement. N walking (skinned) characters
//! and M rigid movers over the 100k-triangle sphere field, driven through the double-buffered
//! pipeline for a number of frames at small resolution and 1 spp, against the same scene
//! standing still; plus the refit, rebuild and top-level figures of issue 8's targets.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{bail, Context as _, Result};
use glam::{DVec3, Quat, Vec3};
use platoon_core::flatten::instance_bvh::build_instance_bvh;
use platoon_core::flatten::refit::MeshBvh;
use platoon_core::frame::FrameParams;
use platoon_core::measure::{median, percentile};
use platoon_core::scene::camera::Camera;
use platoon_core::scene::environment::Environment;
use platoon_core::scene::{Placement, Scene};
use platoon_live::Edit;
use platoon_live::{Pipeline, UpdaterThreads};
use platoon_tracer::{Tracer, TracerOptions};

/// The bench's settings (`platoon bench dynamic ...`).
#[derive(Clone, Debug)]
pub struct Options {
    pub frames: u32,
    pub characters: u32,
    pub movers: u32,
    /// A skinned, animated glTF (CesiumMan by default).
    pub character: PathBuf,
    pub width: u32,
    pub height: u32,
    /// llvmpipe threads of the tracer: 1 leaves the other core to the updater thread.
    pub lavapipe_threads: u32,
    pub device: usize,
    /// The game never waits for a generation (`Pipeline::try_take`): a frame whose next
    /// generation is not built renders the previous one again.
    pub never_wait: bool,
    /// Keep the tracer (and the game thread) and the updater on different cores: the updater
    /// on the last core, the rest on the others (when there are two or more). Without it the
    /// system places the threads, and often puts the updater beside the render on one core.
    pub pin_threads: bool,
    /// How the tracer finds what a ray hits: with ray queries every commit also refits the
    /// skins' bottom levels and builds the top level on the device (issue 61).
    pub traversal: platoon_tracer::Traversal,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            frames: 200,
            characters: 16,
            movers: 64,
            character: crate::shared::path("scenes/CesiumMan.glb"),
            width: 64,
            height: 64,
            lavapipe_threads: 1,
            device: 0,
            never_wait: false,
            pin_threads: true,
            traversal: platoon_tracer::Traversal::Own,
        }
    }
}

/// One frame of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameRecord {
    pub skin_ms: f64,
    pub bottom_level_ms: f64,
    pub flatten_ms: f64,
    pub top_level_ms: f64,
    pub commit_build_ms: f64,
    pub blocked_ms: f64,
    pub bytes: u64,
    pub mesh_bytes: u64,
    pub apply_ms: f64,
    pub frame_ms: f64,
    /// Of which the render (dispatch to fence), the generation's commit already applied.
    pub render_ms: f64,
    /// The update of the whole scene, wall time on the updater thread: skinning, bottom levels,
    /// top level, flattening, the commit and what lies between them.
    pub update_ms: f64,
    /// Skinned meshes refitted and rebuilt in the update.
    pub refitted: usize,
    pub rebuilt: usize,
    /// The frame rendered the previous generation again (`never_wait`, next one not built).
    pub reused: bool,
}

/// The figures the targets name.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    pub skinned_triangles: usize,
    pub scene_triangles: usize,
    pub refit_mtris_per_s_per_core: f64,
    pub refit_vs_rebuild_speedup: f64,
    pub update_ms_median: f64,
    pub tlas_ms_1000_instances: f64,
    pub game_blocked_ms_p99: f64,
    pub camera_only_mesh_bytes: u64,
    pub frame_ms_still: f64,
    pub frame_ms_animated: f64,
    /// Render time alone (dispatch to fence), medians: the still scene, the animated one with
    /// the updater working beside the render, and the animated one with each generation built
    /// before its frame renders (nothing beside it). Alone against still is what the moving
    /// scene itself costs (poses, refitted BVHs); beside against alone is what the update's
    /// work costs the render running next to it.
    pub render_ms_still: f64,
    pub render_ms_animated: f64,
    pub render_ms_animated_alone: f64,
    pub bytes_per_frame_median: f64,
    pub apply_ms_median: f64,
    /// Skinning and bottom levels of the characters alone (no rendering beside it), median,
    /// on one thread and on all of them.
    pub characters_ms_one_thread: f64,
    pub characters_ms_all_threads: f64,
    /// Share of the animated frames that rendered the previous generation again.
    pub reused_frames_pct: f64,
}

pub struct Report {
    pub animated: Vec<FrameRecord>,
    /// The animated frames again, each generation built before its frame renders.
    pub animated_alone: Vec<FrameRecord>,
    pub still: Vec<FrameRecord>,
    pub summary: Summary,
}

/// The sphere field, `characters` copies of the character in a ring, `movers` spheres; returns
/// the scene, the movers' nodes and a camera over it all.
fn build_scene(o: &Options) -> Result<(Scene, Vec<usize>, Camera)> {
    let mut scene = crate::generated::load(&platoon_scenegen::sphere_field(4, false), "field")?;
    if !o.character.exists() {
        bail!(
            "{}: the character to animate is missing (pass --character with a skinned glTF)",
            o.character.display()
        );
    }
    let character = platoon::load_scene(Some(&o.character))?;
    if character.skins.is_empty() || character.animations.is_empty() {
        bail!("{}: not a skinned, animated glTF", o.character.display());
    }
    let (lo, hi) = scene.pose(0.0).bounds();
    let (center, size) = ((lo + hi) * 0.5, (hi - lo).max_element());
    for c in 0..o.characters {
        let a = c as f64 / o.characters.max(1) as f64 * std::f64::consts::TAU;
        let at = center.as_dvec3() + DVec3::new(a.cos(), 0.0, a.sin()) * 0.35 * size as f64;
        scene.append(
            &character,
            Placement::at(DVec3::new(at.x, lo.y as f64, at.z)),
        )?;
    }
    let mover_mesh = scene.nodes.iter().find_map(|n| n.mesh).context("a mesh")?;
    let movers = (0..o.movers)
        .map(|_| {
            let mut n = platoon_core::scene::Node::new("mover");
            n.mesh = Some(mover_mesh);
            n.scale = Vec3::splat(0.3);
            n.translation = center.as_dvec3();
            scene.nodes.push(n);
            scene.nodes.len() - 1
        })
        .collect();
    scene.environment = Some(Environment::Constant(Vec3::ONE));
    let eye = center + Vec3::new(0.0, 0.6, 1.1) * size;
    Ok((scene, movers, Camera::look_at(eye, center, 0.9)))
}

/// Length of the character's animation (its walk cycle), in seconds.
fn walk_duration(o: &Options) -> Result<f32> {
    let character = platoon::load_scene(Some(&o.character))?;
    let d = character.animations.first().map_or(0.0, |a| a.duration());
    if d.is_nan() || d <= 0.0 {
        bail!("{}: its animation has no duration", o.character.display());
    }
    Ok(d)
}

fn mover_placement(i: usize, n: usize, frame: u32, center: DVec3, radius: f64) -> Placement {
    let a = i as f64 / n.max(1) as f64 * std::f64::consts::TAU + 0.05 * frame as f64;
    Placement {
        translation: center + DVec3::new(a.cos() * radius, 0.2 * radius, a.sin() * radius),
        rotation: Quat::from_rotation_y(a as f32),
        scale: Vec3::splat(0.3),
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// Runs the scene animated (characters walking, movers circling) or standing still.
/// One run: its frames, the game thread's waits, and the triangles posed in its scene.
struct Run {
    records: Vec<FrameRecord>,
    blocked: Vec<Duration>,
    triangles: usize,
}

/// What a run renders and how.
#[derive(Clone, Copy, PartialEq, Eq)]
enum RunKind {
    /// Characters walking, movers circling; each generation built while the previous renders.
    Animated,
    /// The same frames, each generation built before its frame renders: nothing runs beside
    /// the render.
    AnimatedAlone,
    /// The scene standing still.
    Still,
}

fn run_frames(o: &Options, kind: RunKind) -> Result<Run> {
    let animated = kind != RunKind::Still;
    let overlap = kind != RunKind::AnimatedAlone;
    let (scene, movers, camera) = build_scene(o)?;
    let posed = scene.pose(0.0);
    let triangles = posed
        .instances
        .iter()
        .map(|i| posed.meshes[i.mesh].indices.len())
        .sum();
    let (lo, hi) = posed.bounds();
    let center = ((lo + hi) * 0.5).as_dvec3();
    let radius = 0.25 * (hi - lo).max_element() as f64;
    // Pinned before the tracer is created: its threads inherit the game thread's cores.
    let cores = o.pin_threads.then(ThreadCores::split).flatten();
    let threads = UpdaterThreads {
        count: 1,
        cpus: cores.as_ref().map_or(Vec::new(), |c| c.updater.clone()),
    };
    let (mut pipeline, first) = Pipeline::with_updater_threads(scene, 0.0, DVec3::ZERO, &threads)?;
    let options = TracerOptions {
        device: o.device,
        lavapipe_threads: Some(o.lavapipe_threads),
        traversal: o.traversal,
        ..Default::default()
    };
    let mut tracer = Tracer::new(&options, &first)?;
    let duration = walk_duration(o)?;
    let edits = |p: &mut Pipeline, f: u32| -> Result<()> {
        if animated {
            // 30 frames a second, the walk cycle looping.
            p.push(Edit::Time((f as f32 / 30.0) % duration))?;
            for (i, &node) in movers.iter().enumerate() {
                p.push(Edit::Placement {
                    node,
                    placement: mover_placement(i, movers.len(), f, center, radius),
                })?;
            }
        }
        Ok(())
    };
    edits(&mut pipeline, 1)?;
    pipeline.submit()?;
    // The game's edits for frame `f`, handed to the updater; the submit's wait is recorded.
    let hand_over = |p: &mut Pipeline, blocked: &mut Vec<Duration>, f: u32| -> Result<()> {
        edits(p, f)?;
        let wait = Instant::now();
        p.submit()?;
        blocked.push(wait.elapsed());
        Ok(())
    };
    let mut records = Vec::with_capacity(o.frames as usize);
    let mut blocked = Vec::with_capacity(2 * o.frames as usize);
    for f in 0..o.frames {
        let start = Instant::now();
        // The generation built while the last frame rendered; a game that must not stall
        // renders the one its tracers hold again when the next is not ready.
        let taken = if o.never_wait {
            pipeline.try_take()?
        } else {
            let wait = Instant::now();
            let g = pipeline.take()?;
            blocked.push(wait.elapsed());
            Some(g)
        };
        let mut record = FrameRecord {
            reused: taken.is_none(),
            ..Default::default()
        };
        if let Some(g) = &taken {
            // The next frame's generation, built while this one renders.
            if overlap {
                hand_over(&mut pipeline, &mut blocked, f + 2)?;
            }
            let apply = Instant::now();
            let stats = tracer.apply_commit(&g.commit)?;
            record = FrameRecord {
                skin_ms: ms(g.times.pose),
                bottom_level_ms: ms(g.times.bottom_level),
                flatten_ms: ms(g.times.flatten),
                top_level_ms: ms(g.times.top_level),
                commit_build_ms: ms(g.times.commit),
                update_ms: ms(g.times.total),
                bytes: stats.bytes,
                mesh_bytes: g.commit.mesh_bytes(),
                apply_ms: ms(apply.elapsed()),
                refitted: g.refitted,
                rebuilt: g.rebuilt,
                ..record
            };
        }
        let mut params = FrameParams::new(o.width, o.height, 1, camera);
        params.frame = f;
        let render = Instant::now();
        platoon::render_bands(
            &mut tracer,
            &params,
            &[platoon::whole_frame(&params)],
            &mut |_| {},
        )?;
        record.render_ms = ms(render.elapsed());
        // Or, with nothing beside the render, built after it.
        if !overlap {
            hand_over(&mut pipeline, &mut blocked, f + 2)?;
        }
        record.frame_ms = ms(start.elapsed());
        let waits = &blocked[blocked.len().saturating_sub(2)..];
        record.blocked_ms = if taken.is_some() {
            waits.iter().map(|d| ms(*d)).sum()
        } else {
            0.0
        };
        records.push(record);
    }
    Ok(Run {
        records,
        blocked,
        triangles,
    })
}

/// The game thread (and the tracer threads it starts) on every core but the last, the updater
/// on the last, for as long as this lives; then the game thread's cores as they were.
struct ThreadCores {
    before: Vec<usize>,
    updater: Vec<usize>,
}

impl ThreadCores {
    /// None with fewer than two cores, or where threads cannot be pinned.
    fn split() -> Option<ThreadCores> {
        let before = platoon_live::threads::current_cpus()?;
        let (&last, rest) = before.split_last()?;
        if rest.is_empty() || !platoon_live::threads::pin_current_thread(rest) {
            return None;
        }
        Some(ThreadCores {
            updater: vec![last],
            before,
        })
    }
}

impl Drop for ThreadCores {
    fn drop(&mut self) {
        platoon_live::threads::pin_current_thread(&self.before);
    }
}

/// Skinning and bottom levels of the walking characters (the scene without the field and the
/// movers) per update, median of `frames`, with the updater's work on `threads` threads and
/// nothing rendering beside it.
fn characters_ms(o: &Options, threads: usize) -> Result<f64> {
    let character = platoon::load_scene(Some(&o.character))?;
    let duration = walk_duration(o)?;
    let mut scene = Scene::default();
    for c in 0..o.characters {
        let at = DVec3::new(2.0 * c as f64, 0.0, 0.0);
        scene.append(&character, Placement::at(at))?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("a thread pool")?;
    pool.install(|| {
        let mut updater = platoon_live::Updater::new(scene, 0.0, DVec3::ZERO)?;
        let mut times = Vec::new();
        for f in 1..=o.frames.min(60) {
            updater.apply(Edit::Time((f as f32 / 30.0) % duration))?;
            let g = updater.update()?;
            times.push(ms(g.times.pose + g.times.bottom_level));
        }
        Ok(median(times))
    })
}

/// Refit and rebuild of the posed characters' skinned meshes, on one thread.
fn refit_figures(o: &Options) -> Result<(usize, f64, f64)> {
    let (scene, _, _) = build_scene(&Options {
        movers: 0,
        ..o.clone()
    })?;
    let base = scene.meshes.len();
    let duration = walk_duration(o)?;
    let skinned = |t: f32| -> Vec<platoon_core::scene::Mesh> {
        let t = t % duration;
        scene
            .pose(t)
            .meshes
            .iter()
            .skip(base)
            .map(|m| (**m).clone())
            .collect()
    };
    let first = skinned(0.0);
    let triangles: usize = first.iter().map(|m| m.indices.len()).sum();
    let mut bvhs: Vec<MeshBvh> = first.iter().map(MeshBvh::build).collect();
    let (mut refit, mut rebuild) = (Vec::new(), Vec::new());
    for k in 1..6 {
        let moved = skinned(k as f32 * 0.1);
        let t = Instant::now();
        for (b, m) in bvhs.iter_mut().zip(&moved) {
            if !b.refit(m) {
                bail!("a skinned mesh changed its triangles");
            }
        }
        refit.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        // What the updater does when a skinned mesh's refit is not enough: a deforming build.
        for m in &moved {
            std::hint::black_box(MeshBvh::build(m));
        }
        rebuild.push(t.elapsed().as_secs_f64());
    }
    let (refit, rebuild) = (median(refit), median(rebuild));
    Ok((triangles, triangles as f64 / refit / 1e6, rebuild / refit))
}

/// Top-level build over 1,000 instance boxes (median of 21).
fn tlas_ms_1000() -> f64 {
    let boxes: Vec<obvhs::aabb::Aabb> = (0..1000u32)
        .map(|i| {
            let p = Vec3::new(
                (i % 10) as f32 * 3.0,
                ((i / 10) % 10) as f32 * 3.0,
                (i / 100) as f32 * 3.0,
            );
            obvhs::aabb::Aabb::new(p.into(), (p + Vec3::ONE).into())
        })
        .collect();
    let times = (0..21)
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(build_instance_bvh(&boxes));
            ms(t.elapsed())
        })
        .collect();
    median(times)
}

pub fn run(o: &Options) -> Result<Report> {
    if o.frames < 2 || o.width == 0 || o.height == 0 || o.lavapipe_threads == 0 {
        bail!("--frames must be at least 2, the image and --lavapipe-threads positive");
    }
    let Run {
        records: animated,
        blocked,
        triangles: scene_triangles,
    } = run_frames(o, RunKind::Animated)?;
    let animated_alone = run_frames(o, RunKind::AnimatedAlone)?.records;
    let still = run_frames(o, RunKind::Still)?.records;
    let (skinned_triangles, refit_rate, speedup) = refit_figures(o)?;
    let all = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (characters_one, characters_all) = (characters_ms(o, 1)?, characters_ms(o, all)?);
    let field = |f: fn(&FrameRecord) -> f64, r: &[FrameRecord]| median(r.iter().map(f).collect());
    // The first frames upload the scene and compile the kernel: medians skip nothing, but the
    // blocked percentile leaves out the first submit (it precedes the loop).
    let summary = Summary {
        skinned_triangles,
        scene_triangles,
        refit_mtris_per_s_per_core: refit_rate,
        refit_vs_rebuild_speedup: speedup,
        update_ms_median: field(|r| r.update_ms, &animated),
        tlas_ms_1000_instances: tlas_ms_1000(),
        game_blocked_ms_p99: percentile(blocked.iter().skip(1).map(|d| ms(*d)).collect(), 0.99),
        camera_only_mesh_bytes: still
            .iter()
            .skip(1)
            .map(|r| r.mesh_bytes)
            .max()
            .unwrap_or(0),
        frame_ms_still: field(|r| r.frame_ms, &still),
        frame_ms_animated: field(|r| r.frame_ms, &animated),
        render_ms_still: field(|r| r.render_ms, &still),
        render_ms_animated: field(|r| r.render_ms, &animated),
        render_ms_animated_alone: field(|r| r.render_ms, &animated_alone),
        bytes_per_frame_median: field(|r| r.bytes as f64, &animated),
        apply_ms_median: field(|r| r.apply_ms, &animated),
        characters_ms_one_thread: characters_one,
        characters_ms_all_threads: characters_all,
        reused_frames_pct: 100.0 * animated.iter().filter(|r| r.reused).count() as f64
            / animated.len().max(1) as f64,
    };
    Ok(Report {
        animated,
        animated_alone,
        still,
        summary,
    })
}

/// The runs by name, in the order they ran.
fn runs(report: &Report) -> [(&'static str, &[FrameRecord]); 3] {
    [
        ("animated", &report.animated),
        ("alone", &report.animated_alone),
        ("still", &report.still),
    ]
}

/// One line per frame of every run, for people.
pub fn frames_text(report: &Report) -> String {
    let mut out = String::from(
        "run       frame  skin  bottom  top  flatten  commit  blocked  bytes      apply  frame (ms)\n",
    );
    for (name, records) in runs(report) {
        for (f, r) in records.iter().enumerate() {
            out.push_str(&format!(
                "{name:9} {f:5} {:5.2} {:6.2} {:5.2} {:7.2} {:6.2} {:7.2} {:10} {:6.2} {:6.2}\n",
                r.skin_ms,
                r.bottom_level_ms,
                r.top_level_ms,
                r.flatten_ms,
                r.commit_build_ms,
                r.blocked_ms,
                r.bytes,
                r.apply_ms,
                r.frame_ms
            ));
        }
    }
    out
}

/// Per-frame CSV of every run.
pub fn csv(report: &Report) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "run",
        "frame",
        "skin_ms",
        "bottom_level_ms",
        "flatten_ms",
        "top_level_ms",
        "commit_build_ms",
        "update_ms",
        "blocked_ms",
        "bytes",
        "mesh_bytes",
        "apply_ms",
        "render_ms",
        "frame_ms",
        "refitted",
        "rebuilt",
        "reused",
    ])?;
    for (name, records) in runs(report) {
        for (f, r) in records.iter().enumerate() {
            let ms = |v: f64| format!("{v:.4}");
            w.write_record([
                name.to_string(),
                f.to_string(),
                ms(r.skin_ms),
                ms(r.bottom_level_ms),
                ms(r.flatten_ms),
                ms(r.top_level_ms),
                ms(r.commit_build_ms),
                ms(r.update_ms),
                ms(r.blocked_ms),
                r.bytes.to_string(),
                r.mesh_bytes.to_string(),
                ms(r.apply_ms),
                ms(r.render_ms),
                ms(r.frame_ms),
                r.refitted.to_string(),
                r.rebuilt.to_string(),
                r.reused.to_string(),
            ])?;
        }
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

/// Writes the frame times of both runs and the update time per frame as a PNG.
pub fn write_png(path: &Path, report: &Report) -> Result<()> {
    let series = [
        (
            "frame, animated (ms)",
            report
                .animated
                .iter()
                .map(|r| r.frame_ms)
                .collect::<Vec<_>>(),
        ),
        (
            "frame, still (ms)",
            report.still.iter().map(|r| r.frame_ms).collect(),
        ),
        (
            "update, animated (ms)",
            report.animated.iter().map(|r| r.update_ms).collect(),
        ),
        (
            "game thread blocked (ms)",
            report.animated.iter().map(|r| r.blocked_ms).collect(),
        ),
    ];
    crate::plot::write_series_png(path, "platoon bench dynamic: per frame", &series)
}

/// The summary as one JSON object (the field names are the issue's).
pub fn json(s: &Summary) -> String {
    serde_json::json!({
        "skinned_triangles": s.skinned_triangles,
        "scene_triangles": s.scene_triangles,
        "refit_mtris_per_s_per_core": s.refit_mtris_per_s_per_core,
        "refit_vs_rebuild_speedup": s.refit_vs_rebuild_speedup,
        "update_ms_median": s.update_ms_median,
        "tlas_ms_1000_instances": s.tlas_ms_1000_instances,
        "game_blocked_ms_p99": s.game_blocked_ms_p99,
        "camera_only_mesh_bytes": s.camera_only_mesh_bytes,
        "frame_ms_still": s.frame_ms_still,
        "frame_ms_animated": s.frame_ms_animated,
        "render_ms_still": s.render_ms_still,
        "render_ms_animated": s.render_ms_animated,
        "render_ms_animated_alone": s.render_ms_animated_alone,
        "bytes_per_frame_median": s.bytes_per_frame_median,
        "apply_ms_median": s.apply_ms_median,
        "characters_ms_one_thread": s.characters_ms_one_thread,
        "characters_ms_all_threads": s.characters_ms_all_threads,
        "reused_frames_pct": s.reused_frames_pct,
    })
    .to_string()
}

/// The summary for people.
pub fn text(o: &Options, s: &Summary) -> String {
    format!(
        "platoon bench dynamic: {} frames at {}x{}, 1 spp, lavapipe with {} thread(s) + the updater thread ({})\n\
         scene: {} triangles posed ({} skinned in {} characters), {} rigid movers\n\
         refit (skinned meshes, leaf boxes included, 1 thread): {:.1} M triangles/s, {:.0}x cheaper than rebuilding them\n\
         update per frame (skin, refit, top level, flatten, commit), median: {:.2} ms\n\
         the characters alone (skin and bottom levels, nothing rendering): {:.2} ms on 1 thread, {:.2} ms on all\n\
         top-level build over 1,000 instances: {:.3} ms\n\
         game thread blocked, 99th percentile: {:.3} ms ({}; {:.1}% of the frames rendered the previous generation again)\n\
         commit per frame, median: {:.0} bytes, applied in {:.2} ms; camera-only frames: {} mesh bytes\n\
         frame time, median: {:.2} ms animated, {:.2} ms still ({:+.1}%)\n\
         render alone, median: {:.2} ms still, {:.2} ms animated with nothing beside it (the moving scene: {:+.1}%), {:.2} ms with the updater beside it (its work: {:+.1}%)\n",
        o.frames,
        o.width,
        o.height,
        o.lavapipe_threads,
        if o.pin_threads {
            "on a core of its own where there are two"
        } else {
            "threads placed by the system"
        },
        s.scene_triangles,
        s.skinned_triangles,
        o.characters,
        o.movers,
        s.refit_mtris_per_s_per_core,
        s.refit_vs_rebuild_speedup,
        s.update_ms_median,
        s.characters_ms_one_thread,
        s.characters_ms_all_threads,
        s.tlas_ms_1000_instances,
        s.game_blocked_ms_p99,
        if o.never_wait { "never waiting" } else { "waiting for each generation" },
        s.reused_frames_pct,
        s.bytes_per_frame_median,
        s.apply_ms_median,
        s.camera_only_mesh_bytes,
        s.frame_ms_animated,
        s.frame_ms_still,
        100.0 * (s.frame_ms_animated / s.frame_ms_still - 1.0),
        s.render_ms_still,
        s.render_ms_animated_alone,
        100.0 * (s.render_ms_animated_alone / s.render_ms_still - 1.0),
        s.render_ms_animated,
        100.0 * (s.render_ms_animated / s.render_ms_animated_alone - 1.0),
    )
}

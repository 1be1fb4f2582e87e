//! The layered-hit-buffers bench (`platoon bench lhb`): the thesis' scaling measured on platoon's
//! scenes. Per scene the path tracer's frame (its rays/s), then per setting (directions x
//! resolution) a frame of layered hit buffers: the build (device time, per direction, bytes,
//! layers lost), the image pass (device time, its queries: traced rays and lookups; and the
//! same pass with the paths cut after their first diffuse vertex's direct light, so the
//! lookups' share is the difference), and the
//! break-even number of queries per build, T_build / (t_ray - t_query), where t_ray is the path
//! tracer's device time per ray and t_query the image pass's per query (each a whole pass's
//! time over its queries, shading included). Each render runs once to compile, then timed.

use std::time::Duration;

use anyhow::{Context as _, Result};
use platoon::core::frame::FrameParams;
use platoon::core::method::lhb::{Lhb, LhbBuild, LhbOptions};
use platoon::core::Method;
use platoon::tracer::{Tracer, TracerOptions};

use crate::method::scenes::MethodScene;

/// One setting on one scene.
pub struct LhbRow {
    pub scene: String,
    pub triangles: usize,
    pub setting: String,
    pub build_s: f64,
    pub bytes: u64,
    pub lost: u64,
    pub image_s: f64,
    /// The image pass without lookups: camera paths to the first diffuse vertex and its
    /// direct light.
    pub direct_s: f64,
    pub queries: u64,
    pub lookups: u64,
    /// The path tracer's frame on the same scene.
    pub path_s: f64,
    pub path_rays: u64,
}

impl LhbRow {
    pub fn ms_per_direction(&self, directions: usize) -> f64 {
        self.build_s * 1e3 / directions.max(1) as f64
    }
    /// Queries per build at which the buffers pay for themselves; None when a query costs
    /// more than a traced ray.
    pub fn break_even(&self) -> Option<f64> {
        let t_ray = self.path_s / self.path_rays.max(1) as f64;
        let t_query = self.image_s / self.queries.max(1) as f64;
        (t_ray > t_query).then(|| self.build_s / (t_ray - t_query))
    }
}

fn device_time(band: &platoon::core::frame::Band) -> Duration {
    platoon::core::measure::device_time(band.gpu_time, band.wall_time)
}

/// What the build of `band` made and cost (its report).
fn build(band: &platoon::core::frame::Band) -> Result<LhbBuild> {
    (band.method_report.value::<LhbBuild>())
        .context("the band reported no layered hit buffers' build")
}

/// Measures `scene` with every one of `settings` on device 0, frames of `size` x `size` at `spp`.
pub fn measure(
    s: &MethodScene,
    settings: &[LhbOptions],
    size: u32,
    spp: u32,
) -> Result<Vec<LhbRow>> {
    let prepared = s.prepare()?;
    let mut tracer = Tracer::new(&TracerOptions::default(), &prepared.gpu)?;
    let mut params = FrameParams::new(size, size, spp, prepared.camera);
    tracer.render(&params, 0, size, &mut |_| {})?;
    let path = tracer.render(&params, 0, size, &mut |_| {})?;
    let mut rows = Vec::new();
    for o in settings {
        params.method = Method::new(Lhb::prepared(*o, &prepared.gpu));
        tracer.render(&params, 0, size, &mut |_| {})?;
        let band = tracer.render(&params, 0, size, &mut |_| {})?;
        let r = build(&band)?;
        let build_s = r.seconds;
        let mut direct = params.clone();
        direct.path_loop.max_depth = 2;
        let cut = tracer.render(&direct, 0, size, &mut |_| {})?;
        let direct_s = (device_time(&cut).as_secs_f64() - build(&cut)?.seconds).max(0.0);
        rows.push(LhbRow {
            scene: s.name.clone(),
            triangles: prepared.gpu.triangles.len(),
            setting: format!("{}@{}", o.directions, o.resolution),
            build_s,
            bytes: r.bytes,
            lost: r.lost,
            image_s: (device_time(&band).as_secs_f64() - build_s).max(0.0),
            direct_s,
            queries: band.rays,
            lookups: r.lookups as u64,
            path_s: device_time(&path).as_secs_f64(),
            path_rays: path.rays,
        });
    }
    Ok(rows)
}

/// One step of a walk: the build keeping what did not move against the full rebuild, and the
/// path tracer's frame after the updater's BVH refit.
pub struct WalkRow {
    pub step: usize,
    /// Device time of the build keeping what did not move, and what it did (`lhb_build`).
    pub kept_build_s: f64,
    pub kept_what: String,
    pub rebuild_s: f64,
    /// The frame with the kept build (device time, build included).
    pub lhb_frame_s: f64,
    /// The updater's bottom levels (refit) and the path tracer's frame.
    pub refit_s: f64,
    pub path_frame_s: f64,
    /// The two builds' images are the same bits.
    pub same: bool,
}

/// CesiumMan walking `steps` steps across the Cornell box (every face `cells` x `cells` quads),
/// a generation a step: per step the three tracers follow the commit and render a frame.
pub fn walk(
    character: &platoon::core::Scene,
    cells: u32,
    steps: usize,
    options: LhbOptions,
    size: u32,
    spp: u32,
) -> Result<Vec<WalkRow>> {
    use platoon::drive::Updater;
    let (scene, node) = platoon::drive::walk::walk_in_a_room(character, cells)?;
    let camera = platoon::core::scene::camera::Camera::from_scene(&scene, &scene.pose(0.0), None)
        .map_err(anyhow::Error::msg)?;
    let mut updater = Updater::new(scene, 0.0, glam::DVec3::ZERO)?;
    let new_tracer =
        |g: &platoon::core::flatten::GpuScene| Tracer::new(&TracerOptions::default(), g);
    let (mut kept, mut rebuilt, mut path) = (
        new_tracer(updater.flattened())?,
        new_tracer(updater.flattened())?,
        new_tracer(updater.flattened())?,
    );
    let mut params = FrameParams::new(size, size, spp, camera);
    let mut previous = None;
    let mut rows = Vec::new();
    for step in 0..=steps {
        let mut refit_s = 0.0;
        if step > 0 {
            for e in platoon::drive::walk::walk_edits(node, step) {
                updater.apply(e)?;
            }
            let generation = updater.update()?;
            refit_s = generation.times.bottom_level.as_secs_f64();
            for t in [&mut kept, &mut rebuilt, &mut path] {
                t.apply_commit(&generation.commit)?;
            }
        }
        let g = updater.flattened();
        let lhb = Lhb::prepared_after(options, g, previous.as_deref());
        previous = lhb.tables.clone();
        params.method = Method::new(lhb.clone());
        let a = kept.render(&params, 0, size, &mut |_| {})?;
        params.method = Method::new(Lhb {
            options: LhbOptions {
                rebuild: true,
                ..options
            },
            ..lhb
        });
        let b = rebuilt.render(&params, 0, size, &mut |_| {})?;
        params.method = Method::path_tracing();
        if step == 0 {
            path.render(&params, 0, size, &mut |_| {})?;
        }
        let p = path.render(&params, 0, size, &mut |_| {})?;
        rows.push(WalkRow {
            step,
            kept_build_s: build(&a)?.seconds,
            kept_what: build(&a)?
                .line()
                .split(':')
                .next()
                .unwrap_or("")
                .to_string(),
            rebuild_s: build(&b)?.seconds,
            lhb_frame_s: device_time(&a).as_secs_f64(),
            refit_s,
            path_frame_s: device_time(&p).as_secs_f64(),
            same: a.sums == b.sums,
        });
    }
    Ok(rows)
}

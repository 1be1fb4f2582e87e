//! The vertex-links bench (`platoon bench links`): Schmitz et al.'s table for platoon. Per scene
//! the update's stages timed apart from the frame (shoot, reduce, direct light, gather, smooth),
//! the links raw and compressed, their bytes, the first frame (update and one frame) and a
//! frame alone. Each update runs once to compile its kernels, then timed.

use std::time::{Duration, Instant};

use anyhow::{bail, Result};

use crate::method::scenes::MethodScene;
use platoon::core::frame::FrameParams;
use platoon::core::method::links::job::UpdateStats;
use platoon::core::method::links::{Job, Links, LinksOptions};
use platoon::core::Method;
use platoon::tracer::{Tracer, TracerOptions};

/// One scene's row.
pub struct LinksRow {
    pub scene: String,
    pub stats: UpdateStats,
    /// The update and one frame, then a frame alone (wall time, kernels compiled).
    pub first_frame: Duration,
    pub frame: Duration,
}

/// Measures `scene` with `options` on device 0, frames of `size` x `size` at `spp`.
pub fn measure(s: &MethodScene, options: LinksOptions, size: u32, spp: u32) -> Result<LinksRow> {
    let prepared = s.prepare()?;
    let mut tracer = Tracer::new(&TracerOptions::default(), &prepared.gpu)?;
    let mut params = FrameParams::new(size, size, spp, prepared.camera);
    params.method = Method::new(Links::new(options));
    // Warm-up: every kernel compiled.
    let solved = platoon::method_update::on_tracer(&mut tracer, &prepared.gpu, &params)?;
    tracer.render(&solved, 0, size, &mut |_| {})?;
    let clock = Instant::now();
    let solved = platoon::method_update::on_tracer(&mut tracer, &prepared.gpu, &params)?;
    tracer.render(&solved, 0, size, &mut |_| {})?;
    let first_frame = clock.elapsed();
    let clock = Instant::now();
    tracer.render(&solved, 0, size, &mut |_| {})?;
    let frame = clock.elapsed();
    let stats = match solved.method.state::<Links>().and_then(|l| l.job.as_ref()) {
        Some(Job::Render(solution)) => solution.stats.clone(),
        _ => bail!("the update left no solution"),
    };
    Ok(LinksRow {
        scene: s.name.clone(),
        stats,
        first_frame,
        frame,
    })
}

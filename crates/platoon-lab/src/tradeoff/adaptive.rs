//! The `adaptive=T` technique: the frame rendered in adaptive sampling's batches on the
//! technique's tracer (`platoon::batched`), the spp being each pixel's most. Its cost is the
//! batches' device time and the mask's CPU time between them.

use std::time::Instant;

use anyhow::Result;
use platoon_core::frame::adaptive::{Adaptive, Batching};
use platoon_core::frame::FrameParams;
use platoon_core::measure::device_time;
use platoon_core::output::Film;
use platoon_tracer::Tracer;

/// The frame `params` renders with adaptive sampling at `threshold`: its image, rays and the
/// seconds it cost.
pub fn render(
    tracer: &mut Tracer,
    params: &FrameParams,
    threshold: f32,
) -> Result<(Film, u64, f64)> {
    let batching = Batching {
        adaptive: Some(Adaptive {
            threshold,
            min_spp: None,
        }),
        variance: false,
    };
    let clock = Instant::now();
    let mut device = 0.0;
    let mut wall = 0.0;
    let rendered = platoon::batched::render(
        &mut |p, progress| {
            let r = platoon::render_bands(tracer, p, &[platoon::whole_frame(p)], progress)?;
            device += device_time(r.gpu_time, r.wall_time).as_secs_f64();
            wall += r.wall_time.as_secs_f64();
            Ok(r)
        },
        params,
        &batching,
        &mut |_| {},
    )?;
    // The host's share: the mask between batches and the sums' round trips.
    let host = (clock.elapsed().as_secs_f64() - wall).max(0.0);
    Ok((rendered.film, rendered.rays, device + host))
}

//! The `denoise=D` technique: the frame's guides (albedo, normal, depth) rendered on the
//! technique's tracer and the denoiser run over the assembled image. Its cost is theirs: the
//! guides' device time and the filter's CPU time.

use std::time::Instant;

use anyhow::Result;
use platoon_core::denoise::{Denoiser, Guides};
use platoon_core::frame::{assemble, FrameParams};
use platoon_core::measure::device_time;
use platoon_core::output::Film;
use platoon_tracer::Tracer;

/// `film` (the frame `params` renders) denoised by `denoiser`, and the seconds it cost.
pub fn apply(
    denoiser: Denoiser,
    tracer: &mut Tracer,
    params: &FrameParams,
    film: &Film,
) -> Result<(Film, f64)> {
    let mut device = 0.0;
    let layers = platoon::aov::render_layers_with(
        &mut |p| {
            let band = tracer.render(p, 0, p.height, &mut |_| {})?;
            device += device_time(band.gpu_time, band.wall_time).as_secs_f64();
            Ok(assemble(p, &[band]))
        },
        params,
        &Denoiser::GUIDES,
        glam::DVec3::ZERO,
        &platoon::core::frame::aov::Context::films_only(params.width, params.height),
    )?;
    let guides = Guides::from_layers(&layers).expect("the guides were rendered");
    let clock = Instant::now();
    let denoised = denoiser.apply(film, &guides).map_err(anyhow::Error::msg)?;
    Ok((denoised, device + clock.elapsed().as_secs_f64()))
}

//! `platoon bench game`'s error at equal time: the game's last frames as the player saw them
//! (denoised where the driver denoises) against still renders of the same frames (their
//! generation's scene, their camera) at many samples, by relative MSE and LDR-FLIP
//! (`platoon_lab::tradeoff::metrics`).

use anyhow::{Context as _, Result};
use platoon::core::balance::by_name;
use platoon::core::frame::FrameParams;
use platoon::devices::{create_tracers, DeviceSpec};
use platoon::schedule::renderer::Renderer;
use platoon::tracer::Sampling;
use platoon_game::KeptFrame;
use platoon_lab::tradeoff::metrics;

/// The kept frames' mean errors.
pub struct GameError {
    pub frames: usize,
    pub reference_spp: u32,
    pub relmse: f64,
    pub flip: f64,
}

/// The error of each of `kept` against its still render at `spp` samples on `devices`.
pub fn measure(kept: &[KeptFrame], devices: &str, spp: u32) -> Result<Option<GameError>> {
    if kept.is_empty() || spp == 0 {
        return Ok(None);
    }
    let spec: DeviceSpec = devices.parse().map_err(anyhow::Error::msg)?;
    let (mut relmse, mut flip) = (0.0, 0.0);
    for k in kept {
        eprintln!("reference of frame {} at {spp} spp", k.frame);
        let tracers = create_tracers(&spec, &k.scene, false, Sampling::Mis)
            .with_context(|| format!("the reference of frame {}", k.frame))?;
        let mut renderer = Renderer::new(tracers, by_name("cost-aware").expect("a balancer"));
        let mut params = FrameParams::new(k.shown.width, k.shown.height, spp, k.camera);
        // Other random numbers than the game's frames.
        params.options.seed = 0x5eed_0000 + k.frame;
        let reference = renderer
            .render_frame(&params)
            .with_context(|| format!("the reference of frame {}", k.frame))?
            .film;
        let e = metrics::errors(&k.shown, &reference);
        relmse += e.relmse / kept.len() as f64;
        flip += e.flip / kept.len() as f64;
    }
    Ok(Some(GameError {
        frames: kept.len(),
        reference_spp: spp,
        relmse,
        flip,
    }))
}

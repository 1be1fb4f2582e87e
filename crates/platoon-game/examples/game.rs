//! The game, headless: plays N frames and writes their PNG sequence, an animated preview (MP4
//! through ffmpeg when installed, else a GIF) and a CSV of each frame's time, spp, blend weight,
//! update time, bytes committed and idle share.
//!
//! ```sh
//! cargo run --release -p platoon-game --example game -- [--frames 240] [--target-ms 50] \
//!     [--size 160x120] [--devices lavapipe:1,1] [--out game-out] [--character CesiumMan.glb] \
//!     [--denoise atrous] [--resampled-light 8] [--light-reuse unbiased] [--world-cache] \
//!     [--realtime]
//! ```
//!
//! With `--denoise` the frames written are denoised with their history (the CSV's denoise_ms
//! says what it cost). `--resampled-light M` resamples next-event estimation from M candidate
//! lights, and `--light-reuse unbiased|biased` reuses the previous frame's reservoirs (ReSTIR
//! DI's temporal and spatial reuse); `--world-cache` has the bounces after the first read a world cache trained as the
//! frames go; `--realtime` is a game's setting of resampled light and the denoiser (8
//! candidates, a-trous) where the flags leave them open.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result};
use platoon::core::method::path::{LearningOptions, PathTracing, ResampledLight};
use platoon_game::{play, GameOptions, PlayOptions};

fn main() -> Result<()> {
    let mut character = PathBuf::from("../shared/scenes/CesiumMan.glb");
    let mut frames = 240;
    let mut target_ms: Option<f64> = Some(50.0);
    let mut size = (160, 120);
    let mut devices = "all".to_string();
    let mut out = PathBuf::from("game-out");
    let mut validation = false;
    let mut denoise = platoon::core::denoise::Denoiser::None;
    let mut resampled_light: Option<u32> = None;
    let mut realtime = false;
    let mut world_cache = false;
    let mut light_reuse = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().with_context(|| format!("{a} needs a value"));
        match a.as_str() {
            "--character" => character = value()?.into(),
            "--frames" => frames = value()?.parse()?,
            "--target-ms" => target_ms = Some(value()?.parse()?),
            "--fixed-spp" => target_ms = None,
            "--size" => {
                let v = value()?;
                let (w, h) = v.split_once('x').context("--size is WIDTHxHEIGHT")?;
                size = (w.parse()?, h.parse()?);
            }
            "--devices" => devices = value()?,
            "--out" => out = value()?.into(),
            "--validation" => validation = true,
            "--denoise" => denoise = value()?.parse().map_err(anyhow::Error::msg)?,
            "--resampled-light" => resampled_light = Some(value()?.parse()?),
            "--realtime" => realtime = true,
            "--world-cache" => world_cache = true,
            "--light-reuse" => light_reuse = Some(value()?.parse().map_err(anyhow::Error::msg)?),
            other => anyhow::bail!("unknown argument {other:?}"),
        }
    }
    let mut game = GameOptions::new(character);
    game.driver.width = size.0;
    game.driver.height = size.1;
    game.driver.target = target_ms.map(|t| Duration::from_secs_f64(t * 1e-3));
    game.devices = devices.parse().map_err(anyhow::Error::msg)?;
    game.validation = validation;
    game.driver.denoise = denoise;
    if resampled_light == Some(0) {
        anyhow::bail!("--resampled-light needs at least one candidate light");
    }
    game.driver.method = platoon::core::Method::new(PathTracing {
        resampled_light: resampled_light.map(ResampledLight::new),
        learning: LearningOptions {
            world_cache: world_cache.then(Default::default),
            light_reuse,
        },
        ..Default::default()
    });
    if realtime {
        game.driver.realtime();
    }
    game.driver
        .denoise
        .available()
        .map_err(|e| anyhow::anyhow!("--denoise: {e}"))?;
    let played = play(
        &PlayOptions {
            game,
            frames,
            out: Some(out.clone()),
            keep_last: 0,
        },
        true,
    )?;
    let mut busy: Vec<f64> = played.records.iter().map(|r| r.busy_ms).collect();
    busy.sort_by(f64::total_cmp);
    println!(
        "{} frames, median {:.1} ms a frame; frames in {}, numbers in {}, preview {}",
        played.records.len(),
        busy.get(busy.len() / 2).copied().unwrap_or(0.0),
        out.join("frames").display(),
        out.join("game.csv").display(),
        played
            .preview
            .map_or("none".into(), |p| p.display().to_string()),
    );
    for m in &played.device_messages {
        eprintln!("validation: {m}");
    }
    Ok(())
}

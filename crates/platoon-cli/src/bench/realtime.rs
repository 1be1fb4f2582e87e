//! `platoon bench realtime`: a game's image at its frame budget, each real-time technique
//! against converged renders of the same frames (platoon-lab's `realtime_bench`).

use anyhow::{bail, Result};
use platoon_lab::realtime_bench as rb;

/// `platoon bench realtime`'s settings.
#[derive(clap::Args)]
pub struct RealtimeArgs {
    /// The scene the game plays: hall (the many-light hall: 128 emissive panels and 48 point
    /// lights, `platoon-scenegen --many-lights`), cornell (the built-in box), walk (the
    /// character walking on a ground under a sky and a low sun), or a glTF file.
    #[arg(default_value = "hall")]
    scene: String,
    /// The skinned, animated glTF walking in front of the camera.
    #[arg(long, default_value_os_t = platoon_lab::shared::path("scenes/CesiumMan.glb"))]
    character: std::path::PathBuf,
    /// No walking character.
    #[arg(long)]
    no_character: bool,
    /// The frame size, WIDTHxHEIGHT.
    #[arg(long, default_value = "160x90", value_parser = crate::size_arg::parse_size)]
    size: (u32, u32),
    /// The frame time the game holds, in milliseconds.
    #[arg(long, default_value_t = 100.0)]
    target_ms: f64,
    /// Frames played by each technique.
    #[arg(long, default_value_t = 24)]
    frames: u32,
    /// The last frames measured.
    #[arg(long, default_value_t = 4)]
    measured: u32,
    /// Samples per pixel of each measured frame's reference render.
    #[arg(long, default_value_t = 256)]
    reference_spp: u32,
    /// The devices (see `platoon devices`).
    #[arg(long, default_value = "auto")]
    devices: String,
    /// Techniques, comma-separated: plain, or parts of resampled, reuse (resampled light
    /// reusing the previous frame's reservoirs), world-cache and atrous joined by + (the first
    /// is what the others' error is compared with).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "plain,atrous,resampled,reuse,world-cache,resampled+atrous,reuse+atrous,resampled+world-cache+atrous,reuse+world-cache+atrous"
    )]
    techniques: Vec<String>,
    /// Each technique plays this many times with other random numbers: two or more measure
    /// its bias (what is left of its error once its noise is averaged away).
    #[arg(long, default_value_t = 2)]
    repeat: u32,
    /// Print one JSON object after the text.
    #[arg(long)]
    json: bool,
}

pub fn run(a: &RealtimeArgs) -> Result<()> {
    let techniques = a
        .techniques
        .iter()
        .map(|t| rb::Technique::parse(t))
        .collect::<Result<Vec<_>>>()?;
    if !a.no_character && !a.character.is_file() {
        bail!(
            "{}: no such file (the walking character; --no-character plays without one)",
            a.character.display()
        );
    }
    let options = rb::Options {
        scene: rb::BenchScene::parse(&a.scene),
        character: (!a.no_character).then(|| a.character.clone()),
        width: a.size.0,
        height: a.size.1,
        target_ms: a.target_ms,
        frames: a.frames,
        measured: a.measured,
        reference_spp: a.reference_spp,
        devices: a.devices.clone(),
        techniques,
        repeat: a.repeat,
        ..Default::default()
    };
    let rows = rb::run(&options, &mut |s| eprintln!("{s}"))?;
    print!("{}", rb::text(&options, &rows));
    if a.json {
        println!("{}", rb::json(&rows));
    }
    Ok(())
}

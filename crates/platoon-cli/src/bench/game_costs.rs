//! `platoon bench game --record-costs DIR`: per-line cost maps of the game for
//! `platoon bench balance`'s replay. The game plays on one lavapipe thread at a fixed 2 spp (no
//! frame-time target, so the costs are the scene's, not the workload scaler's), and each frame's
//! render time is spread over its lines by the rays each traced. Two stretches of one play are
//! kept: `game.csv`, the first frames (the camera following a character, then resting while
//! bodies fall and characters walk), on which balancers are judged, and `tune/game.csv`, a later
//! stretch (the camera following another character from another angle), on which cost-aware's
//! constants are chosen, so that they are never chosen on the maps they are judged on.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context as _, Result};
use platoon::core::balance::replay::CostMap;
use platoon_game::{play, GameOptions, PlayOptions};

/// The recording's frame size and samples per pixel (96 lines, as the shipped orbit maps).
pub const SIZE: (u32, u32) = (128, 96);
pub const SPP: u32 = 2;
/// Frames of each map, and the game frames skipped between the judged and the tuning stretch.
pub const FRAMES: usize = 128;
pub const GAP: usize = 64;

pub fn record(character: &Path, dir: &Path) -> Result<()> {
    if !character.exists() {
        bail!(
            "{}: the character to animate is missing (pass --character with a skinned glTF)",
            character.display()
        );
    }
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    let mut game = GameOptions::new(PathBuf::from(character));
    game.driver.width = SIZE.0;
    game.driver.height = SIZE.1;
    game.driver.spp = SPP;
    game.driver.target = None;
    game.devices = "lavapipe:1".parse().map_err(anyhow::Error::msg)?;
    let frames = 2 * FRAMES + GAP;
    eprintln!(
        "recording line costs of {frames} game frames at {}x{}, {SPP} spp, one lavapipe thread",
        SIZE.0, SIZE.1
    );
    let played = play(
        &PlayOptions {
            game,
            frames: frames as u32,
            out: None,
            keep_last: 0,
        },
        true,
    )?;
    let maps: Vec<Vec<f64>> = played
        .records
        .iter()
        .map(|r| r.line_seconds.clone())
        .collect();
    if maps.len() < frames || maps.iter().any(|m| m.len() != SIZE.1 as usize) {
        bail!(
            "the game returned {} frames of line costs, not {frames}",
            maps.len()
        );
    }
    for (folder, first, what) in [
        (dir.to_path_buf(), 0, "judged on"),
        (
            dir.join("tune"),
            FRAMES + GAP,
            "cost-aware's constants chosen on",
        ),
    ] {
        let map = CostMap {
            width: SIZE.0,
            frames: maps[first..first + FRAMES].to_vec(),
        };
        let comment = format!(
            "the game (platoon-game), frames {first}..{}, {}x{} at {SPP} spp, one lavapipe \
             thread; {what}",
            first + FRAMES,
            SIZE.0,
            SIZE.1
        );
        std::fs::create_dir_all(&folder)
            .with_context(|| format!("{}: cannot create", folder.display()))?;
        let path = folder.join("game.csv");
        platoon::core::output::write_text(&path, &map.to_text(&comment))?;
        eprintln!("wrote {}", path.display());
    }
    Ok(())
}

//! The game example's work (issue 9) runs a few frames on two lavapipe tracers with the
//! validation layer on: bodies fall, characters walk, the CPU query highlights, and every
//! output (PNG sequence, CSV, animated preview) is written.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon_game::{play, GameOptions, PlayOptions};

#[test]
fn the_game_plays_a_few_frames_and_writes_its_outputs() {
    init();
    let mut game = GameOptions::new(shared("scenes/CesiumMan.glb"));
    game.driver.width = 48;
    game.driver.height = 32;
    game.driver.spp = 1;
    game.devices = "lavapipe:1,1".parse().unwrap();
    game.validation = true;
    game.characters = 2;
    game.toss_every = 2;
    let out = tempfile::tempdir().unwrap();
    let frames = 6;
    let played = play(
        &PlayOptions {
            game,
            frames,
            out: Some(out.path().to_path_buf()),
            keep_last: 0,
        },
        false,
    )
    .unwrap();
    assert!(
        played.device_messages.is_empty(),
        "{:?}",
        played.device_messages
    );
    assert_eq!(played.records.len(), frames as usize);
    let numbered: Vec<u32> = played.records.iter().map(|r| r.frame).collect();
    assert_eq!(numbered, (0..frames).collect::<Vec<_>>());
    // Bodies fall and characters walk: every frame after the first renders a new generation.
    assert!(played.records[1..].iter().all(|r| r.commit_bytes > 0));
    assert!(played.records[2..].iter().all(|r| r.join != "sum"));
    let last = played.last.unwrap();
    assert_eq!(last.count_non_finite(), 0);
    assert!(last.mean()[2] > 0.0);

    let pngs = std::fs::read_dir(out.path().join("frames"))
        .unwrap()
        .count();
    assert_eq!(pngs, frames as usize);
    let csv = std::fs::read_to_string(out.path().join("game.csv")).unwrap();
    assert_eq!(csv.lines().count(), frames as usize + 1);
    assert!(csv.starts_with("frame,interval_ms,busy_ms"));
    let preview = played.preview.unwrap();
    assert!(std::fs::metadata(&preview).unwrap().len() > 0);
}

//! The example game (`examples/walk.rs`) in a real window under Xvfb: Bevy opens it on
//! lavapipe, platoon's frames arrive (the title counts them), and what the screen shows is
//! not black.

#[path = "../../../tests/common/xvfb.rs"]
mod xvfb;

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::Duration;

use xvfb::{wait_for, Xvfb};

/// The example's binary, which `cargo test` builds beside the tests.
fn example() -> PathBuf {
    let deps = std::env::current_exe().unwrap();
    let path = deps
        .parent()
        .unwrap()
        .parent()
        .unwrap()
        .join("examples/walk");
    assert!(
        path.exists(),
        "{} is missing: run `cargo test` without a target filter (it builds the examples)",
        path.display()
    );
    path
}

#[test]
fn the_example_game_shows_platoons_frames_in_a_window() {
    // Displays from :300 (the viewer's test takes :90 on).
    let x = Xvfb::start(300..400, "400x240x24");
    assert_eq!(x.lit_pixels(), 0, "the screen starts black");
    let mut game = Command::new(example())
        .args(["--devices", "lavapipe:1", "--size", "160x90"])
        .env("DISPLAY", &x.display)
        .env(
            "VK_DRIVER_FILES",
            "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json",
        )
        // wgpu's own validation of Bevy's rendering is not what this tests.
        .env("WGPU_VALIDATION", "0")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Until the title has counted 30 of platoon's frames.
    let frames = wait_for(Duration::from_secs(180), || {
        if let Some(status) = game.try_wait().unwrap() {
            let err = std::io::read_to_string(game.stderr.take().unwrap()).unwrap();
            panic!("the game ended before showing frames ({status}): {err}");
        }
        let id = x.xdotool(&["search", "--name", "^platoon walk:"]);
        let title = x.xdotool(&["getwindowname", id.lines().next()?]);
        let frames: u64 = title.split_whitespace().nth(2)?.parse().ok()?;
        (frames >= 30).then_some(frames)
    });
    // The window (320 x 180, platoon's 160 x 90 image at twice its size) is mostly lit. Bevy
    // may present its first frame after platoon has rendered 30 (its own pipelines come first:
    // with Bevy unoptimised and Mesa's shader cache warm, platoon's 30 frames came within 1.5 s
    // and the screen was still black in 5 runs of 5), so the screen is watched until then.
    let lit = wait_for(Duration::from_secs(120), || {
        let lit = x.lit_pixels();
        (lit > 320 * 180 / 2).then_some(lit)
    });
    let _ = game.kill();
    let _ = game.wait();
    eprintln!("{lit} lit pixels after {frames} frames or more");
}

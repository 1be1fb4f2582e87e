//! `platoon view` (issue 9) under Xvfb: without a display it says so and fails; with one the
//! window opens, frames arrive (the title counts them), what the screen shows is not black, and
//! synthetic key presses (XTEST, through xdotool) fly the camera.

#[path = "../common/mod.rs"]
mod common;
#[path = "../common/xvfb.rs"]
mod xvfb;

use std::process::{Child, Command, Stdio};
use std::time::Duration;

use xvfb::{wait_for, Xvfb};

fn platoon() -> Command {
    common::init();
    Command::new(env!("CARGO_BIN_EXE_platoon"))
}

impl Xvfb {
    /// `view`, a `platoon view` command, started on this display.
    fn open(&self, view: &mut Command) -> Child {
        view.env("DISPLAY", &self.display)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    }

    /// The id of `view`'s window once its title contains `title`; fails saying `what` ended
    /// first if the viewer exits before.
    fn window_titled(&self, view: &mut Child, title: &str, what: &str) -> String {
        wait_for(Duration::from_secs(120), || {
            if let Some(status) = view.try_wait().unwrap() {
                let err = std::io::read_to_string(view.stderr.take().unwrap()).unwrap();
                panic!("{what} ended before its window showed frames ({status}): {err}");
            }
            let id = self.xdotool(&["search", "--name", "^platoon"]);
            let id = id.lines().next()?.to_string();
            self.xdotool(&["getwindowname", &id])
                .contains(title)
                .then_some(id)
        })
    }
}

fn camera(line: &str) -> [f32; 3] {
    let v: Vec<f32> = line
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .take(3)
        .collect();
    [v[0], v[1], v[2]]
}

/// `platoon view` with `args` on a machine without a display.
fn headless(args: &[&str]) -> std::process::Output {
    platoon()
        .arg("view")
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap()
}

#[test]
fn without_a_display_the_viewer_says_so_and_fails() {
    let o = headless(&[]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("no display"), "{err}");
}

/// A denoiser the build lacks is refused before any window or loading, saying how to get it.
#[test]
fn the_viewer_refuses_a_denoiser_the_build_lacks() {
    if cfg!(feature = "oidn") {
        return;
    }
    let o = headless(&["--denoise", "oidn"]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--denoise") && err.contains("--features oidn"),
        "{err}"
    );
}

/// What a method learns over the frames is refused before any window where it cannot hold:
/// another method's flag, light reuse without resampled light, a mode it lacks; the flag alone
/// is its first mode.
#[test]
fn the_viewer_refuses_learning_its_method_cannot_do() {
    for (args, says) in [
        (
            &["--method", "igi", "--world-cache"][..],
            "--world-cache sets path tracing: add --method path",
        ),
        (
            &["--light-reuse"],
            "--light-reuse: reuses resampled light's reservoirs",
        ),
        (
            &["--light-reuse", "sometimes"],
            "is not one of unbiased, biased",
        ),
    ] {
        let o = headless(args);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
    }
    // Learning that holds goes on to the display, which is missing.
    let o = headless(&["--resampled-light", "4", "--light-reuse", "--world-cache"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("no display"), "{err}");
}

#[test]
fn the_viewer_shows_frames_under_xvfb_and_flies_on_key_presses() {
    let x = Xvfb::start(90..200, "320x240x24");
    let black = x.lit_pixels();
    let mut view = x.open(
        platoon()
            .args([
                "view",
                "--size",
                "40x30",
                "--target-ms",
                "40",
                "--devices",
                "lavapipe:1",
            ])
            .args(["--frames", "3000"]),
    );
    // The window opens, and its title starts counting frames.
    let window = x.window_titled(&mut view, "spp", "the viewer");
    std::thread::sleep(Duration::from_millis(500));
    let lit = x.lit_pixels();
    assert!(
        lit >= black + 80 * 60 / 2,
        "the window (80x60) shows too little: {lit} lit pixels, {black} before it opened"
    );
    x.xdotool(&["windowfocus", "--sync", &window]);
    x.xdotool(&["keydown", "w"]);
    std::thread::sleep(Duration::from_millis(1500));
    x.xdotool(&["keyup", "w"]);
    std::thread::sleep(Duration::from_millis(300));
    x.xdotool(&["key", "Escape"]);
    let status = wait_for(Duration::from_secs(60), || view.try_wait().unwrap());
    let out = std::io::read_to_string(view.stdout.take().unwrap()).unwrap();
    let err = std::io::read_to_string(view.stderr.take().unwrap()).unwrap();
    assert!(status.success(), "{out}\n{err}");
    let start = out
        .lines()
        .find(|l| l.starts_with("camera starts at"))
        .unwrap();
    let end = out.lines().find(|l| l.starts_with("camera at")).unwrap();
    let (a, b) = (camera(start), camera(end));
    let moved = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f32>().sqrt();
    assert!(moved > 0.1, "W did not fly the camera: {start} / {end}");

    // The same window by instant global illumination: the title says so.
    let mut view = x.open(
        platoon()
            .args(["view", "--size", "24x16", "--devices", "lavapipe:1"])
            .args(["--method", "igi", "--vpls", "12", "--frames", "3000"]),
    );
    x.window_titled(&mut view, "IGI 12 VPLs", "the IGI viewer");
    let _ = view.kill();
    let _ = view.wait();

    // A game's real-time settings with the world cache and light reuse, denoised on the device
    // with the history reprojected: the title says all three, and the frame shown (written on closing,
    // denoised on the CPU) is finite and lit.
    let mut view = x.open(
        platoon()
            .args(["view", "--size", "24x16", "--devices", "lavapipe:1"])
            .args(["--realtime", "--world-cache", "--light-reuse"])
            .args(["--denoise", "atrous-device"])
            .args(["--frames", "3000"]),
    );
    x.window_titled(
        &mut view,
        "cells), light-reuse, denoised (atrous-device, history",
        "the real-time viewer",
    );
    let _ = view.kill();
    let _ = view.wait();
    let dir = tempfile::tempdir().unwrap();
    let shot = dir.path().join("denoised.exr");
    let mut view = x.open(
        platoon()
            .args(["view", "--size", "24x16", "--devices", "lavapipe:1"])
            .args(["--filter", "gaussian"])
            .args(["--denoise", "atrous", "--frames", "6", "--screenshot"])
            .arg(&shot),
    );
    let status = wait_for(Duration::from_secs(120), || view.try_wait().unwrap());
    let err = std::io::read_to_string(view.stderr.take().unwrap()).unwrap();
    assert!(status.success(), "{err}");
    let (film, _) = platoon::core::output::read_exr(&shot).unwrap();
    assert_eq!((film.width, film.height), (24, 16));
    assert_eq!(film.count_non_finite(), 0);
    assert!(film.mean()[0] > 0.0);

    // A scene with separate buffer and texture files, named bare from its own folder.
    let scene_dir = platoon_scenegen::twins::write_scene_folders(dir.path()).unwrap();
    let mut view = x.open(
        platoon()
            .current_dir(&scene_dir)
            .args([
                "view",
                "scene.gltf",
                "--size",
                "24x16",
                "--devices",
                "lavapipe:1",
            ])
            .args(["--frames", "3000"]),
    );
    x.window_titled(&mut view, "spp", "the viewer of scene.gltf");
    let _ = view.kill();
    let _ = view.wait();
}

//! `platoon render --frames` (issue 24): animations to numbered files as a render farm runs
//! them. Frames equal still renders at their times, bit for bit; a rerun skips the frames done
//! and redoes a damaged one; a task renders the share its job-array index names; every frame's
//! fate is a line on standard output and a failed frame fails the command.

#[path = "../common/mod.rs"]
mod common;
mod support;

use std::path::Path;

use common::shared;
use platoon::core::output::{read_exr, read_exr_channels};
use support::*;

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn pixels(path: &Path) -> Vec<[f32; 3]> {
    read_exr(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .0
        .pixels
}

fn frames(range: &str) -> Cli {
    Cli::new("render")
        .flag("--frames", range)
        .spp(2)
        .size(24, 24)
}

#[test]
fn frames_at_their_times_equal_still_renders_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let man = shared("scenes/CesiumMan.glb");
    // Into a folder that does not exist yet (the README's example: made, issue 41).
    let o = frames("0..8:4")
        .arg(&man)
        .out(dir.path().join("shots/man_####.exr"))
        .run();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("shots/man_0004.exr").is_file());
    let lines = stdout(&o);
    for f in ["0000", "0004", "0008"] {
        assert!(lines.contains(&format!("man_{f}.exr")), "{lines}");
    }
    let animated = frames("8")
        .arg(&man)
        .arg("--animated-seed")
        .out(dir.path().join("seeded_#.exr"))
        .run();
    assert!(animated.status.success(), "{}", stderr(&animated));
    // Frame F is at F / 24 s: the time a still render is given, printed as the f32 it is.
    for (frame, seed) in [(4, 0), (8, 0), (8, 8)] {
        let time = (frame as f64 / 24.0) as f32;
        let still = dir.path().join(format!("still_{frame}_{seed}.exr"));
        let o = Cli::new("render")
            .arg(&man)
            .spp(2)
            .size(24, 24)
            .flag("--time", time.to_string())
            .flag("--seed", seed.to_string())
            .out(&still)
            .run();
        assert!(o.status.success(), "{}", stderr(&o));
        let frame_file = if seed == 0 {
            dir.path().join(format!("shots/man_{frame:04}.exr"))
        } else {
            dir.path().join(format!("seeded_{frame}.exr"))
        };
        assert!(
            pixels(&frame_file) == pixels(&still),
            "frame {frame} (seed {seed}) differs from the still render at {time} s"
        );
    }
    assert!(
        pixels(&dir.path().join("shots/man_0000.exr"))
            != pixels(&dir.path().join("shots/man_0008.exr")),
        "the animation moved nothing"
    );
    let (_, meta) = read_exr(&dir.path().join("shots/man_0004.exr")).unwrap();
    assert_eq!(metadata_value(&meta, "animation_frame"), "4");
    assert!(metadata_value(&meta, "job").ends_with("frame 4"));
}

#[test]
fn a_rerun_skips_done_frames_and_redoes_a_damaged_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("box_###.png");
    let run = |extra: &[&str]| {
        let o = frames("1..3").out(&out).args(extra).run();
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    run(&[]);
    let second = dir.path().join("box_002.png");
    let original = std::fs::read(&second).unwrap();
    let decoded = |bytes: &[u8]| image::load_from_memory(bytes).unwrap().to_rgb8().into_raw();
    let lines = run(&[]);
    for f in 1..=3 {
        assert!(lines.contains(&format!("frame {f}: skipped")), "{lines}");
    }
    // Cut inside the pixels (past every metadata chunk): only reading to the end tells.
    std::fs::write(&second, &original[..original.len() - 16]).unwrap();
    let lines = run(&[]);
    assert!(lines.contains("frame 1: skipped"), "{lines}");
    assert!(lines.contains("frame 2: ok"), "{lines}");
    assert!(lines.contains("frame 3: skipped"), "{lines}");
    let redone = std::fs::read(&second).unwrap();
    assert!(decoded(&redone) == decoded(&original), "redone differently");
    // Other settings make other images: nothing is done.
    let lines = run(&["--seed", "3"]);
    assert_eq!(lines.matches(": ok").count(), 3, "{lines}");
    let lines = run(&["--seed", "3", "--overwrite"]);
    assert_eq!(lines.matches(": ok").count(), 3, "{lines}");
}

/// What the scene is loaded as is part of a job too: frames of one material variant are not
/// "done" for a rerun that asks for another (nor for another texture budget).
#[test]
fn a_rerun_with_another_variant_renders_its_frames_again() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("variants.glb");
    std::fs::write(&scene, platoon_scenegen::twins::variants()).unwrap();
    let out = dir.path().join("quad_#.exr");
    let run = |extra: &[&str]| {
        let o = frames("1..2").arg(&scene).out(&out).args(extra).run();
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    run(&["--variant", "red"]);
    let lines = run(&["--variant", "red"]);
    assert_eq!(lines.matches(": skipped").count(), 2, "{lines}");
    let lines = run(&["--variant", "blue"]);
    assert_eq!(lines.matches(": ok").count(), 2, "{lines}");
    let centre = pixels(&dir.path().join("quad_1.exr"))[12 * 24 + 12];
    assert_eq!(centre, [0.0, 0.0, 1.0]);
    let lines = run(&["--variant", "blue", "--texture-budget", "1"]);
    assert_eq!(lines.matches(": ok").count(), 2, "{lines}");
}

#[test]
fn log_json_says_each_frame_and_a_still_as_one_json_object_a_line() {
    // Issue 41: farm tools read one JSON object a line: each frame's fate, a skipped one on a
    // rerun, a JPEG sequence too; a still's line at its end.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("box_##.jpg");
    let run = || {
        let o = frames("1..2").arg("--log-json").out(&out).run();
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
            .lines()
            .map(|l| {
                serde_json::from_str::<serde_json::Value>(l).unwrap_or_else(|e| panic!("{l}: {e}"))
            })
            .collect::<Vec<_>>()
    };
    let first = run();
    assert_eq!(first.len(), 2, "{first:?}");
    for (line, f) in first.iter().zip(1..) {
        assert_eq!(line["frame"], f);
        assert_eq!(line["status"], "ok");
        let file = line["file"].as_str().unwrap();
        assert!(file.ends_with(&format!("box_0{f}.jpg")) && Path::new(file).is_file());
        assert!(line["seconds"].as_f64().is_some_and(|s| s > 0.0));
    }
    let again = run();
    assert!(again.iter().all(|l| l["status"] == "skipped"), "{again:?}");
    let still = dir.path().join("still.png");
    let o = Cli::new("render")
        .spp(2)
        .size(16, 8)
        .arg("--log-json")
        .out(&still)
        .run();
    assert!(o.status.success(), "{}", stderr(&o));
    let line: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(line["status"], "ok");
    assert_eq!(line["spp"], 2.0);
    assert_eq!(
        (line["width"].as_u64(), line["height"].as_u64()),
        (Some(16), Some(8))
    );
    assert!(line["file"].as_str().unwrap().ends_with("still.png"));
}

#[test]
fn a_rerun_redoes_frames_whose_environment_map_or_raw_image_changed() {
    // Issue 41, defect 3: the job named the environment map by its path alone, and a denoised
    // frame whose raw image (NAME.noisy.EXT) was deleted still counted as done.
    let dir = tempfile::tempdir().unwrap();
    let env = dir.path().join("sky.exr");
    let place_sky = |from: &str| {
        let _ = std::fs::remove_file(&env);
        std::fs::write(&env, std::fs::read(shared(from)).unwrap()).unwrap();
    };
    place_sky("envmaps/sunset.exr");
    let out = dir.path().join("f_#.png");
    let run = || {
        let o = frames("1..2")
            .flag("--env", &env)
            .flag("--denoise", "atrous")
            .out(&out)
            .run();
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    run();
    let lines = run();
    assert_eq!(lines.matches(": skipped").count(), 2, "{lines}");
    std::fs::remove_file(dir.path().join("f_2.noisy.png")).unwrap();
    let lines = run();
    assert!(lines.contains("frame 1: skipped"), "{lines}");
    assert!(lines.contains("frame 2: ok"), "{lines}");
    assert!(dir.path().join("f_2.noisy.png").is_file());
    // Another sky under the same name: every frame is another image.
    place_sky("envmaps/forest.exr");
    let lines = run();
    assert_eq!(lines.matches(": ok").count(), 2, "{lines}");
    // The job is said as a person reads it (issue 41, defect 7: it was Rust's debug output).
    let meta = platoon::core::output::read_metadata(&dir.path().join("f_1.png")).unwrap();
    let job = &meta.iter().find(|(k, _)| k == "platoon:job").unwrap().1;
    assert!(
        job.contains("environment /") && job.contains("sky.exr ("),
        "{job}"
    );
    for debug in ["Some(", "None", "File(", "\"", "["] {
        assert!(!job.contains(debug), "{debug} in {job}");
    }
    // The pixel filter, a crop, a transparent film and a method's setting make other images
    // too.
    for flags in [
        &["--filter", "gaussian"][..],
        &["--filter", "gaussian", "--crop", "0,0,8,8"],
        &[
            "--filter",
            "gaussian",
            "--crop",
            "0,0,8,8",
            "--film-transparent",
        ],
        // A method's setting too (the path tracer's resampled light).
        &[
            "--filter",
            "gaussian",
            "--crop",
            "0,0,8,8",
            "--film-transparent",
            "--resampled-light",
            "4",
        ],
    ] {
        let o = frames("1..2")
            .flag("--env", &env)
            .flag("--denoise", "atrous")
            .args(flags)
            .out(&out)
            .run();
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(stdout(&o).matches(": ok").count(), 2, "{flags:?}");
    }
}

#[test]
fn a_farm_task_renders_the_chunk_its_index_names() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("f_##.exr");
    let task = |index: Option<&str>| {
        frames("1..5")
            .flag("--chunk", "2")
            .flag("--task-index", "TEST_ARRAY_INDEX")
            .out(&out)
            .run_with_env(&[("TEST_ARRAY_INDEX", index)])
    };
    let o = task(Some("1"));
    assert!(o.status.success(), "{}", stderr(&o));
    let made: Vec<bool> = (1..=5)
        .map(|f| dir.path().join(format!("f_{f:02}.exr")).exists())
        .collect();
    assert_eq!(made, [false, false, true, true, false]);
    let o = task(Some("3"));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("task index 3"), "{}", stderr(&o));
    let o = task(None);
    assert!(!o.status.success());
    // Said once, without the standard library's own words after it (issue 41).
    let said = stderr(&o);
    assert!(
        said.contains("TEST_ARRAY_INDEX: the environment variable is not set")
            && !said.contains("environment variable not found"),
        "{said}"
    );
    let o = task(Some("two"));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("\"two\""), "{}", stderr(&o));
}

#[test]
fn a_failed_frame_is_reported_and_fails_the_command_while_the_others_are_written() {
    let dir = tempfile::tempdir().unwrap();
    // Frame 2's file cannot be written: a folder stands in its place.
    std::fs::create_dir(dir.path().join("g_2.exr")).unwrap();
    let o = frames("1..3").out(dir.path().join("g_#.exr")).run();
    assert!(!o.status.success());
    let lines = stdout(&o);
    assert!(lines.contains("frame 1: ok"), "{lines}");
    assert!(lines.contains("frame 2: failed"), "{lines}");
    assert!(lines.contains("frame 3: ok"), "{lines}");
    assert!(
        stderr(&o).contains("1 of 3 frame(s) failed"),
        "{}",
        stderr(&o)
    );
    assert!(dir.path().join("g_3.exr").is_file());
    let o = frames("3..1").out(dir.path().join("h.exr")).run();
    assert!(!o.status.success());
    assert!(stderr(&o).contains("3..1"), "{}", stderr(&o));
}

/// `--video`: every frame of the range (done ones too, read back from their files) encoded by
/// ffmpeg in order; without ffmpeg the run still succeeds and says there is no video. Skipped,
/// saying so, where ffmpeg is not installed.
#[test]
fn a_video_holds_every_frame_of_the_range_and_needs_ffmpeg() {
    let has = |tool: &str| {
        std::process::Command::new(tool)
            .arg("-version")
            .output()
            .is_ok()
    };
    if !has("ffmpeg") || !has("ffprobe") {
        eprintln!("skipped: ffmpeg is not installed (apt-get install ffmpeg)");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("box_#.exr");
    let video = dir.path().join("box.mp4");
    // Odd sizes (H.264 wants even ones: padded) and a step: frames 0, 2, 4.
    let run = |extra: &[&str], path: Option<&str>| {
        let cli = Cli::new("render")
            .flag("--frames", "0..4:2")
            .spp(1)
            .size(15, 11)
            .out(&out)
            .args(extra);
        match path {
            Some(p) => cli.run_with_env(&[("PATH", Some(p))]),
            None => cli.run(),
        }
    };
    let o = run(&[], None);
    assert!(o.status.success(), "{}", stderr(&o));
    // All three are done: the video is made from their files.
    let o = run(&["--video", video.to_str().unwrap()], None);
    assert!(o.status.success(), "{}", stderr(&o));
    let probe = std::process::Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=nb_read_frames,width,height",
            "-of",
            "csv=p=0",
        ])
        .arg(&video)
        .output()
        .unwrap();
    assert_eq!(String::from_utf8_lossy(&probe.stdout).trim(), "16,12,3");
    std::fs::remove_file(&video).unwrap();
    let empty = tempfile::tempdir().unwrap();
    let o = run(
        &["--video", video.to_str().unwrap()],
        Some(empty.path().to_str().unwrap()),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("ffmpeg is not installed") && !video.exists());
    let o = run(
        &["--video", video.to_str().unwrap(), "--task-index", "X"],
        None,
    );
    assert!(!o.status.success() && stderr(&o).contains("--task-index"));
}

#[test]
fn a_walking_figures_frames_carry_its_motion_and_a_still_box_none() {
    // Motion vectors through the CLI: CesiumMan's skinned walk moves between frames (measured
    // over 1/fps), the built-in box's still scene and camera do not move at all.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("man_#.exr");
    let o = frames("3..3")
        .arg(shared("scenes/CesiumMan.glb").to_str().unwrap())
        .flag("--aov", "motion")
        .flag("--fps", "12")
        .out(&out)
        .run();
    assert!(o.status.success(), "{}", stderr(&o));
    let channels = read_exr_channels(&dir.path().join("man_3.exr")).unwrap();
    let x = &channels.iter().find(|(c, _)| c == "motion.X").unwrap().1;
    let moving = x.iter().filter(|v| v.abs() > 0.05).count();
    assert!(moving > 10, "{moving} pixels moved");
    assert!(x.iter().all(|v| v.is_finite()));
    // A still of the walk (which keeps the frame's geometry on the host for them).
    let walk = dir.path().join("walk.exr");
    let o = Cli::new("render")
        .arg(shared("scenes/CesiumMan.glb").to_str().unwrap())
        .spp(1)
        .size(32, 32)
        .flag("--time", "0.25")
        .flag("--aov", "motion")
        .out(&walk)
        .run();
    assert!(o.status.success(), "{}", stderr(&o));
    let channels = read_exr_channels(&walk).unwrap();
    let x = &channels.iter().find(|(c, _)| c == "motion.X").unwrap().1;
    let moving = x.iter().filter(|v| v.abs() > 0.02).count();
    assert!(moving > 10, "the still: {moving} pixels moved");
    let still = dir.path().join("box.exr");
    let o = Cli::new("render")
        .spp(1)
        .size(16, 12)
        .flag("--aov", "motion")
        .out(&still)
        .run();
    assert!(o.status.success(), "{}", stderr(&o));
    let channels = read_exr_channels(&still).unwrap();
    for c in ["motion.X", "motion.Y"] {
        let plane = &channels.iter().find(|(n, _)| n == c).unwrap().1;
        assert!(plane.iter().all(|&v| v == 0.0), "{c}: {plane:?}");
    }
}

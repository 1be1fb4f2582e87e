//! `--video FILE` with `--frames`: the animation as a video, encoded by ffmpeg when it is
//! installed (H.264 in the container FILE's extension names, 8-bit sRGB as the PNG outputs are
//! tone-mapped). Every frame of the range is read back from its file, so frames skipped as done
//! count too; the video is written to a temporary folder and renamed into place. Without ffmpeg
//! the frames stay and a warning says there is no video.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, Context as _, Result};
use platoon::core::colour::View;
use platoon::core::output::{read_exr, write_image_as, ImageOptions};

/// Refuses a video the run could not make, before rendering.
pub fn check(video: &Path, farm_task: bool) -> Result<()> {
    if farm_task {
        bail!(
            "{}: --video with --task-index: a task renders only its chunk; encode the video \
             once every task is done",
            video.display()
        );
    }
    // The encoding is H.264 (`encode`), which these containers hold.
    let ext = video.extension().and_then(|e| e.to_str()).unwrap_or("");
    if !["mp4", "mkv", "mov"].contains(&ext.to_ascii_lowercase().as_str()) {
        bail!(
            "{}: --video writes H.264 in an .mp4, .mkv or .mov file",
            video.display()
        );
    }
    let parent = video.parent().filter(|p| !p.as_os_str().is_empty());
    if parent.is_some_and(|p| !p.is_dir()) {
        bail!("{}: its folder does not exist", video.display());
    }
    Ok(())
}

/// The frames' files (in order) encoded at `fps` to `video`, EXR frames shown under `view`
/// (PNG frames are already); a warning and no video when ffmpeg is not installed.
pub fn encode(video: &Path, frames: &[PathBuf], fps: f64, view: &View) -> Result<()> {
    if Command::new("ffmpeg").arg("-version").output().is_err() {
        eprintln!(
            "warning: ffmpeg is not installed (apt-get install ffmpeg): no video, the frames \
             are written"
        );
        return Ok(());
    }
    let folder = video.parent().filter(|p| !p.as_os_str().is_empty());
    let work = tempfile::tempdir_in(folder.unwrap_or(Path::new(".")))?;
    // Numbered 0, 1, 2 ... whatever the range's step: ffmpeg's image sequence wants no gaps.
    // EXR frames become PNGs under the view; the others go as they are (ffmpeg reads PNG,
    // JPEG and TIFF).
    let ext = match frames.first() {
        Some(f) if !is_exr(f) => f
            .extension()
            .map_or("png".into(), |e| e.to_string_lossy().to_ascii_lowercase()),
        _ => "png".to_string(),
    };
    for (i, frame) in frames.iter().enumerate() {
        let png = work.path().join(format!("{i:06}.{ext}"));
        if ext == "png" && is_exr(frame) {
            let (film, _) = read_exr(frame)?;
            let shown = ImageOptions {
                view: *view,
                ..Default::default()
            };
            write_image_as(&png, &film, &[], &[], &shown)?;
        } else {
            std::fs::copy(frame, &png).with_context(|| format!("{}", frame.display()))?;
        }
    }
    let container = video.extension().expect("checked").to_string_lossy();
    let encoded = work.path().join(format!("video.{container}"));
    let status = Command::new("ffmpeg")
        .args([
            "-loglevel",
            "error",
            "-y",
            "-framerate",
            &fps.to_string(),
            "-i",
        ])
        .arg(work.path().join(format!("%06d.{ext}")))
        // H.264's 4:2:0 needs even sizes.
        .args(["-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"])
        .args(["-c:v", "libx264", "-pix_fmt", "yuv420p"])
        .arg(&encoded)
        .status()
        .context("running ffmpeg")?;
    if !status.success() {
        bail!("{}: ffmpeg failed ({status})", video.display());
    }
    std::fs::rename(&encoded, video).with_context(|| format!("{}", video.display()))?;
    eprintln!("{}: {} frames at {fps} fps", video.display(), frames.len());
    Ok(())
}

fn is_exr(frame: &Path) -> bool {
    frame
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

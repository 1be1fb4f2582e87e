//! Playing the game headless for a number of frames: every finished frame's numbers, and on
//! request its image (a PNG sequence), an animated preview (MP4 through ffmpeg when installed,
//! else an animated GIF) and a CSV of the numbers.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use image::codecs::gif::{GifEncoder, Repeat};
use image::{Delay, Frame, RgbaImage};
use platoon::core::output::{write_image, Film};
use platoon::drive::plan::Join;
use platoon::drive::FinishedFrame;

use crate::game::{Game, GameOptions, Step};

/// One finished frame's numbers (the CSV's row).
#[derive(Clone, Debug, Default)]
pub struct FrameRecord {
    pub frame: u32,
    /// Time between the game's calls that started this frame and the next.
    pub interval_ms: f64,
    /// The render thread's time for the frame (commit, render, film): what spp scales.
    pub busy_ms: f64,
    pub render_ms: f64,
    pub commit_ms: f64,
    pub spp: u32,
    pub join: &'static str,
    pub f: f32,
    /// The balancer cut this frame anew.
    pub rebalance: bool,
    /// Russian-roulette survival scale and render resolution (1: not scaled).
    pub rr_survival: f32,
    pub resolution: f32,
    /// The updater's whole time for the generation this frame rendered.
    pub update_ms: f64,
    pub commit_bytes: u64,
    pub idle_percent: f64,
    /// The game's own work in the call that started the frame, and what it waited for.
    pub game_ms: f64,
    pub waited_render_ms: f64,
    pub waited_update_ms: f64,
    pub highlighted: Option<usize>,
    /// Seconds each line took (one tracer only; empty with several): a cost map's frame.
    pub line_seconds: Vec<f64>,
    /// Denoising the frame (its guides and the filter; part of busy), 0 when off.
    pub denoise_ms: f64,
}

pub struct PlayOptions {
    pub game: GameOptions,
    pub frames: u32,
    /// Where to write frames/, game.csv and the preview (None: nothing written).
    pub out: Option<PathBuf>,
    /// The last frames kept with their scenes and cameras ([`Played::kept`]), to be rendered
    /// still and measured against (0: none; the driver then keeps no scenes).
    pub keep_last: u32,
}

/// A frame as the player saw it, with what renders it again: its generation's flattened scene
/// and its camera (render space).
pub struct KeptFrame {
    pub frame: u32,
    pub shown: Film,
    pub scene: std::sync::Arc<platoon::core::flatten::GpuScene>,
    pub camera: platoon::core::scene::camera::Camera,
}

pub struct Played {
    pub records: Vec<FrameRecord>,
    pub last: Option<Film>,
    /// The preview written (MP4 or GIF), if any.
    pub preview: Option<PathBuf>,
    /// Every message of the devices' validation layers.
    pub device_messages: Vec<String>,
    /// The last `PlayOptions::keep_last` frames, oldest first.
    pub kept: Vec<KeptFrame>,
}

/// Plays `o.frames` frames, with a progress line per second on stderr when `progress`.
pub fn play(o: &PlayOptions, progress: bool) -> Result<Played> {
    let mut options = o.game.clone();
    options.driver.keep_frame_scenes |= o.keep_last > 0;
    let mut game = Game::start(&options)?;
    let frames_dir = o.out.as_ref().map(|d| d.join("frames"));
    if let Some(d) = &frames_dir {
        std::fs::create_dir_all(d).with_context(|| format!("creating {}", d.display()))?;
    }
    let mut records: Vec<FrameRecord> = Vec::new();
    let mut started: Vec<(Instant, Step)> = Vec::new();
    let mut films: Vec<Film> = Vec::new();
    let mut messages = Vec::new();
    let mut kept = std::collections::VecDeque::new();
    let mut keep = |done: FinishedFrame, records: &mut Vec<FrameRecord>| -> Result<()> {
        records.push(record(&done));
        messages = done.stats.device_messages.clone();
        // What a player sees: the denoised frame when the driver denoises.
        let shown = done.denoised.unwrap_or(done.film);
        if let Some(d) = &frames_dir {
            let path = d.join(format!("frame_{:04}.png", done.stats.frame));
            write_image(&path, &shown, &[])?;
        }
        if let (Some(scene), true) = (done.scene, o.keep_last > 0) {
            kept.push_back(KeptFrame {
                frame: done.stats.frame,
                shown: shown.clone(),
                scene,
                camera: done.camera,
            });
            if kept.len() > o.keep_last as usize {
                kept.pop_front();
            }
        }
        films.push(shown);
        Ok(())
    };
    let clock = Instant::now();
    let mut said = 0u64;
    for f in 0..o.frames {
        let at = Instant::now();
        let mut step = game.frame()?;
        if let Some(done) = step.finished.take() {
            keep(done, &mut records)?;
        }
        started.push((at, step));
        if progress && clock.elapsed().as_secs() > said {
            said = clock.elapsed().as_secs();
            eprint!("\rframe {}/{}", f + 1, o.frames);
        }
    }
    let end = Instant::now();
    if let Some(done) = game.finish()? {
        keep(done, &mut records)?;
    }
    if progress {
        eprintln!("\rframe {0}/{0}", o.frames);
    }
    // The per-call numbers belong to the frame each call started.
    for r in records.iter_mut() {
        let k = r.frame as usize;
        let (at, step) = &started[k];
        let next = started.get(k + 1).map_or(end, |(t, _)| *t);
        r.interval_ms = (next - *at).as_secs_f64() * 1e3;
        r.game_ms = step.game.as_secs_f64() * 1e3;
        r.waited_render_ms = step.waited_render.as_secs_f64() * 1e3;
        r.waited_update_ms = step.waited_update.as_secs_f64() * 1e3;
        r.highlighted = step.highlighted;
    }
    let mut preview = None;
    if let Some(dir) = &o.out {
        write_csv(&dir.join("game.csv"), &records)?;
        if let Some(d) = &frames_dir {
            preview = Some(write_preview(dir, d, &films)?);
        }
    }
    Ok(Played {
        records,
        last: films.pop(),
        preview,
        device_messages: messages,
        kept: kept.into(),
    })
}

fn record(done: &FinishedFrame) -> FrameRecord {
    let s = &done.stats;
    let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
    FrameRecord {
        frame: s.frame,
        busy_ms: ms(s.busy),
        render_ms: ms(s.render),
        commit_ms: ms(s.commit),
        spp: s.plan.spp,
        join: match s.plan.join {
            Join::Restart => "restart",
            Join::Sum => "sum",
            Join::Blend { .. } => "blend",
        },
        f: s.weight,
        rebalance: s.plan.rebalance,
        rr_survival: s.plan.rr_survival,
        resolution: s.plan.resolution,
        update_ms: ms(s.update.total),
        commit_bytes: s.commit_bytes,
        idle_percent: 100.0 * s.idle_fraction,
        line_seconds: s.line_seconds().unwrap_or_default(),
        denoise_ms: s
            .denoise
            .as_ref()
            .map_or(0.0, |d| ms(d.guides.unwrap_or_default() + d.filter)),
        ..Default::default()
    }
}

pub fn write_csv(path: &Path, records: &[FrameRecord]) -> Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "frame",
        "interval_ms",
        "busy_ms",
        "render_ms",
        "commit_ms",
        "spp",
        "join",
        "f",
        "rebalance",
        "rr_survival",
        "resolution",
        "update_ms",
        "commit_bytes",
        "idle_percent",
        "game_ms",
        "waited_render_ms",
        "waited_update_ms",
        "highlighted",
        "denoise_ms",
    ])?;
    for r in records {
        w.write_record([
            r.frame.to_string(),
            format!("{:.3}", r.interval_ms),
            format!("{:.3}", r.busy_ms),
            format!("{:.3}", r.render_ms),
            format!("{:.3}", r.commit_ms),
            r.spp.to_string(),
            r.join.to_string(),
            format!("{:.4}", r.f),
            u8::from(r.rebalance).to_string(),
            format!("{:.3}", r.rr_survival),
            format!("{:.3}", r.resolution),
            format!("{:.3}", r.update_ms),
            r.commit_bytes.to_string(),
            format!("{:.2}", r.idle_percent),
            format!("{:.3}", r.game_ms),
            format!("{:.3}", r.waited_render_ms),
            format!("{:.3}", r.waited_update_ms),
            r.highlighted.map_or(String::new(), |c| c.to_string()),
            format!("{:.3}", r.denoise_ms),
        ])?;
    }
    let text = String::from_utf8(w.into_inner()?)?;
    platoon::core::output::write_text(path, &text)?;
    Ok(())
}

/// An MP4 of the PNG sequence when ffmpeg is installed, else an animated GIF; returns its path.
fn write_preview(dir: &Path, frames: &Path, films: &[Film]) -> Result<PathBuf> {
    let mp4 = dir.join("game.mp4");
    let ffmpeg = std::process::Command::new("ffmpeg")
        .args(["-loglevel", "error", "-y", "-framerate", "30", "-i"])
        .arg(frames.join("frame_%04d.png"))
        .args([
            "-pix_fmt",
            "yuv420p",
            "-vf",
            "scale=trunc(iw/2)*2:trunc(ih/2)*2",
        ])
        .arg(&mp4)
        .status();
    if ffmpeg.is_ok_and(|s| s.success()) {
        return Ok(mp4);
    }
    let gif = dir.join("game.gif");
    write_gif(&gif, films)?;
    Ok(gif)
}

/// An animated GIF at 30 frames a second, written to a temporary file and renamed.
pub fn write_gif(path: &Path, films: &[Film]) -> Result<()> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
    let tmp = tempfile::NamedTempFile::new_in(parent.unwrap_or(Path::new(".")))?;
    {
        let mut encoder = GifEncoder::new_with_speed(tmp.as_file(), 10);
        encoder.set_repeat(Repeat::Infinite)?;
        for film in films {
            let rgba: Vec<u8> = film
                .srgb8()
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect();
            let image = RgbaImage::from_raw(film.width, film.height, rgba)
                .context("a film's pixels do not fill its size")?;
            encoder.encode_frame(Frame::from_parts(
                image,
                0,
                0,
                Delay::from_numer_denom_ms(100, 3),
            ))?;
        }
    }
    // Temporary files are created private; a preview is an ordinary file.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o644));
    }
    tmp.persist(path)
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

//! `platoon bench game`: the game (platoon-game) for a few hundred frames at a target frame
//! time: how closely the frame driver holds it, how long it takes to settle, the frame time's
//! median and p99, and how much of the CPU's update work is hidden behind rendering.

use std::time::Duration;

use anyhow::{bail, Result};
use platoon::core::denoise::Denoiser;
use platoon::core::measure::{median, percentile};
use platoon::core::method::settings::Value;
use platoon_game::{play, FrameRecord, GameOptions, PlayOptions};

/// `platoon bench game`'s settings.
#[derive(clap::Args)]
pub struct GameArgs {
    /// The game's frames.
    #[arg(long, default_value_t = 200)]
    pub frames: u32,
    /// The frame time to hold, in milliseconds.
    #[arg(long, default_value_t = 40.0)]
    pub target_ms: f64,
    /// The frame size, WIDTHxHEIGHT (small enough on lavapipe for about 13 samples a frame at
    /// 40 ms: a sample more or less is then a step of 8%, inside the +-10% band).
    #[arg(long, default_value = "64x48", value_parser = crate::size_arg::parse_size)]
    pub size: (u32, u32),
    /// Below one sample a frame, scale Russian-roulette survival down (unbiased).
    #[arg(long)]
    pub roulette_scaling: bool,
    /// Below one sample a frame, render fewer pixels, upscaled (biased).
    #[arg(long)]
    pub resolution_scaling: bool,
    /// The devices (see `platoon devices`; lavapipe:N,M makes software tracers).
    #[arg(long, default_value = "all")]
    pub devices: String,
    /// How each frame is split between the devices (and, with --mpi, the ranks): a balancer,
    /// with `+steal` for in-frame stealing of the bands' tails (cost-aware+steal).
    #[arg(long, default_value = "cost-aware", value_parser = crate::balancer_arg::parse_balancer)]
    pub balancer: String,
    /// The skinned, animated glTF the game's characters are.
    #[arg(long, default_value_os_t = platoon_lab::shared::path("scenes/CesiumMan.glb"))]
    pub character: std::path::PathBuf,
    /// Denoise every frame with its reprojected history (none, atrous, atrous-device on the
    /// first device, or oidn in a build with `--features oidn`): its cost joins the frame time the loop holds.
    #[arg(long, default_value = "none")]
    pub denoise: Denoiser,
    // The rendering method and its settings (`--method`, the path tracer's --resampled-light,
    // --kernel...), as `render` and `view` take them.
    #[command(flatten)]
    pub method: crate::method_args::MethodArgs,
    /// A game's real-time settings: resampled direct light over 8 candidates and the a-trous
    /// denoiser, unless --resampled-light or --denoise say otherwise (`platoon bench realtime`
    /// measures their error at equal time).
    #[arg(long)]
    pub realtime: bool,
    // What the path tracer learns over the frames (--world-cache, --light-reuse).
    #[command(flatten)]
    pub learning: crate::learning_args::LearningArgs,
    /// The last frames measured against still renders of the same frames (their scene, their
    /// camera): the error at the frame time the loop held.
    #[arg(long, default_value_t = 4)]
    pub measure: u32,
    /// Samples per pixel of those still renders (0: no error measured).
    #[arg(long, default_value_t = 256)]
    pub reference_spp: u32,
    /// Print one JSON object after the text.
    #[arg(long)]
    pub json: bool,
    /// Split every frame between the ranks of an MPI job (`mpirun -n N platoon bench game
    /// --mpi`, a build with `--features mpi`): rank 0 plays, each rank is one tracer of its
    /// frame driver rendering on its own --devices; the communication per frame is reported.
    #[arg(long)]
    pub mpi: bool,
    /// Instead of the bench, record the game's per-line cost maps (game.csv, and tune/game.csv
    /// for choosing constants) into this folder, for `platoon bench balance --costs`.
    #[arg(long)]
    pub record_costs: Option<std::path::PathBuf>,
    /// Folder for game.csv.
    #[arg(long, default_value = ".")]
    pub out: std::path::PathBuf,
}

/// A frame counts as held when it is within this share of the target.
const BAND: f64 = 0.10;
/// Frames in a row within the band that make the loop settled.
const SETTLED_RUN: usize = 3;

pub struct Summary {
    pub frames: usize,
    pub settle_frames: usize,
    pub frame_ms_median: f64,
    pub frame_ms_p99: f64,
    pub busy_ms_median: f64,
    pub held_fraction: f64,
    pub spp_median: f64,
    pub update_ms_median: f64,
    pub update_hidden_fraction: f64,
    pub idle_percent_median: f64,
    pub denoise_ms_median: f64,
}

pub fn run(o: &GameArgs) -> Result<()> {
    if let Some(dir) = &o.record_costs {
        return super::game_costs::record(&o.character, dir);
    }
    if !o.mpi {
        return bench(o, None);
    }
    let session = platoon::distributed::join()?;
    let ranks = platoon::distributed::Ranks(session.clone());
    let result = if session.rank() == 0 {
        bench(o, Some(ranks))
    } else {
        let devices = o.devices.parse().map_err(anyhow::Error::msg)?;
        platoon::distributed::game::serve(&ranks, &devices, &o.balancer, false)
    };
    match result {
        // The others would wait for this rank in their next exchange.
        Err(e) if session.size() > 1 => {
            eprintln!("error: rank {}: {e:#}", session.rank());
            session.abort(1)
        }
        r => r,
    }
}

/// The bench on this process's devices, or as rank 0 of `ranks`.
fn bench(o: &GameArgs, ranks: Option<platoon::distributed::Ranks>) -> Result<()> {
    let (width, height) = o.size;
    if !(o.target_ms > 0.0 && o.target_ms.is_finite()) {
        bail!("--target-ms must be a positive number of milliseconds");
    }
    if !o.out.is_dir() {
        bail!("{}: output folder does not exist", o.out.display());
    }
    if !o.character.exists() {
        bail!(
            "{}: the character to animate is missing (pass --character with a skinned glTF)",
            o.character.display()
        );
    }
    let mut game = GameOptions::new(o.character.clone());
    game.driver.width = width;
    game.driver.height = height;
    game.driver.target = Some(Duration::from_secs_f64(o.target_ms * 1e-3));
    game.driver.below_one = platoon::drive::scaling::BelowOneSample {
        roulette: o.roulette_scaling,
        resolution: o.resolution_scaling,
    };
    game.devices = o.devices.parse().map_err(anyhow::Error::msg)?;
    game.balancer = o.balancer.clone();
    game.driver.denoise = o.denoise;
    game.driver.method = o.method.method()?;
    if o.realtime {
        game.driver.realtime();
    }
    // After the real-time settings, whose resampled light light reuse needs.
    game.driver.method = o.learning.apply(game.driver.method.clone())?;
    game.ranks = ranks.clone();
    game.driver
        .denoise
        .available()
        .map_err(|e| anyhow::anyhow!("--denoise: {e}"))?;
    let method = &game.driver.method;
    let mut settings = method.settings().0;
    settings.extend(method.kind().learning_of(method).0);
    let techniques = Techniques {
        method: method.unit().describe(),
        denoise: game.driver.denoise,
        settings,
    };
    eprintln!(
        "playing {} frames of the game at {}x{} on {} ({}), holding {} ms a frame",
        o.frames, width, height, o.devices, o.balancer, o.target_ms
    );
    let played = play(
        &PlayOptions {
            game,
            frames: o.frames,
            out: None,
            keep_last: if o.reference_spp > 0 { o.measure } else { 0 },
        },
        true,
    )?;
    let s = summarize(&played.records, o.target_ms);
    let error = super::game_error::measure(&played.kept, &o.devices, o.reference_spp)?;
    let csv = o.out.join("game.csv");
    platoon_game::play::write_csv(&csv, &played.records)?;
    let comm = ranks.map(|r| communication(r.0.size(), s.frames));
    println!("{}", text(o, &techniques, &s));
    if let Some(e) = &error {
        println!(
            "error at this frame time: the last {} frames as shown against {} spp still \
             renders of them: relative MSE {:.4}, LDR-FLIP {:.4}",
            e.frames, e.reference_spp, e.relmse, e.flip
        );
    }
    if let Some(c) = &comm {
        println!(
            "over {} ranks: {:.0} bytes a frame to the other ranks, {:.0} back, {:.2} ms a frame \
             on the wire (round trips less the ranks' own work), {:.1} messages a frame",
            c.ranks,
            c.sent_per_frame,
            c.received_per_frame,
            c.wire_ms_per_frame,
            c.messages_per_frame
        );
    }
    println!("per-frame numbers in {}", csv.display());
    if o.json {
        let mut j = json(o, &techniques, &s);
        if let Some(e) = &error {
            j["error"] = serde_json::json!({
                "frames": e.frames,
                "reference_spp": e.reference_spp,
                "relmse": e.relmse,
                "flip": e.flip,
            });
        }
        if let Some(c) = &comm {
            j["mpi"] = serde_json::json!({
                "ranks": c.ranks,
                "sent_bytes_per_frame": c.sent_per_frame,
                "received_bytes_per_frame": c.received_per_frame,
                "wire_ms_per_frame": c.wire_ms_per_frame,
                "messages_per_frame": c.messages_per_frame,
            });
        }
        println!("{j}");
    }
    Ok(())
}

/// What rank 0 exchanged with the other ranks, per frame on average.
struct Communication {
    ranks: usize,
    sent_per_frame: f64,
    received_per_frame: f64,
    wire_ms_per_frame: f64,
    messages_per_frame: f64,
}

fn communication(ranks: usize, frames: usize) -> Communication {
    use std::sync::atomic::Ordering::Relaxed;
    let t = &platoon::distribute::remote::TRAFFIC;
    let per = |v: u64| v as f64 / frames.max(1) as f64;
    Communication {
        ranks,
        sent_per_frame: per(t.sent.load(Relaxed)),
        received_per_frame: per(t.received.load(Relaxed)),
        wire_ms_per_frame: per(t.wire_nanos.load(Relaxed)) * 1e-6,
        messages_per_frame: per(t.messages.load(Relaxed)),
    }
}

pub fn summarize(records: &[FrameRecord], target_ms: f64) -> Summary {
    let held = |r: &FrameRecord| (r.interval_ms / target_ms - 1.0).abs() <= BAND;
    let settle = (0..records.len())
        .find(|&k| {
            records[k..]
                .iter()
                .take(SETTLED_RUN)
                .filter(|r| held(r))
                .count()
                == SETTLED_RUN
        })
        .unwrap_or(records.len());
    // A loop that never settled is described over all its frames.
    let settled = if settle < records.len() {
        &records[settle..]
    } else {
        records
    };
    let of = |f: fn(&FrameRecord) -> f64| -> Vec<f64> { settled.iter().map(f).collect() };
    let update: f64 = records.iter().map(|r| r.update_ms).sum();
    let waited: f64 = records.iter().map(|r| r.waited_update_ms).sum();
    Summary {
        frames: records.len(),
        settle_frames: settle,
        frame_ms_median: median(of(|r| r.interval_ms)),
        frame_ms_p99: percentile(of(|r| r.interval_ms), 0.99),
        busy_ms_median: median(of(|r| r.busy_ms)),
        held_fraction: settled.iter().filter(|r| held(r)).count() as f64
            / settled.len().max(1) as f64,
        spp_median: median(of(|r| r.spp as f64)),
        update_ms_median: median(of(|r| r.update_ms)),
        update_hidden_fraction: if update > 0.0 {
            (1.0 - waited / update).clamp(0.0, 1.0)
        } else {
            1.0
        },
        idle_percent_median: median(of(|r| r.idle_percent)),
        denoise_ms_median: median(of(|r| r.denoise_ms)),
    }
}

/// What the game rendered with: the method, its settings and what it learns over frames
/// (the flags' names with `_`: `resampled_light`, `world_cache`...), and the denoiser.
struct Techniques {
    /// The method and its options (`RenderMethod::describe`).
    method: String,
    denoise: Denoiser,
    settings: Vec<(&'static str, Value)>,
}

impl Techniques {
    /// The settings as a line (`kernel megakernel, resampled_light 4, world_cache on`).
    fn settings_line(&self) -> String {
        let said: Vec<String> = self
            .settings
            .iter()
            .map(|(k, v)| format!("{k} {v}"))
            .collect();
        said.join(", ")
    }

    /// The settings as a JSON object, each value of its kind.
    fn settings_json(&self) -> serde_json::Value {
        let values = self.settings.iter().map(|(k, v)| {
            let json = match v {
                Value::Count(n) => serde_json::json!(n),
                Value::Number(x) => serde_json::json!(x),
                Value::Switch(on) => serde_json::json!(on),
                Value::Tile(t) => serde_json::json!(t),
                Value::Word(w) => serde_json::json!(w),
            };
            (k.to_string(), json)
        });
        serde_json::Value::Object(values.collect())
    }
}

fn text(o: &GameArgs, t: &Techniques, s: &Summary) -> String {
    format!(
        "game bench: {} frames at {}x{} by {} on {}, target {:.1} ms\n\
         settled after {} frames; then frame time median {:.2} ms, p99 {:.2} ms \
         (render thread {:.2} ms), {:.1}% of frames within +-10% of the target\n\
         samples per frame (median) {}, update {:.2} ms a frame of which {:.1}% hidden behind \
         rendering, tracers idle {:.2}% (median){}{}",
        s.frames,
        o.size.0,
        o.size.1,
        t.method,
        o.devices,
        o.target_ms,
        s.settle_frames,
        s.frame_ms_median,
        s.frame_ms_p99,
        s.busy_ms_median,
        100.0 * s.held_fraction,
        s.spp_median,
        s.update_ms_median,
        100.0 * s.update_hidden_fraction,
        s.idle_percent_median,
        match t.settings.is_empty() {
            true => String::new(),
            false => format!("\nthe method's settings: {}", t.settings_line()),
        },
        match t.denoise {
            Denoiser::None => String::new(),
            d => format!(
                "\ndenoised ({}) with reprojected history: {:.2} ms a frame (median, in the \
                 render thread's time)",
                d.name(),
                s.denoise_ms_median
            ),
        },
    )
}

fn json(o: &GameArgs, t: &Techniques, s: &Summary) -> serde_json::Value {
    serde_json::json!({
        "target_ms": o.target_ms,
        "frames": s.frames,
        "width": o.size.0,
        "height": o.size.1,
        "devices": o.devices,
        "balancer": o.balancer,
        "settle_frames": s.settle_frames,
        "frame_ms_median": s.frame_ms_median,
        "frame_ms_p99": s.frame_ms_p99,
        "busy_ms_median": s.busy_ms_median,
        "held_fraction": s.held_fraction,
        "spp_median": s.spp_median,
        "update_ms_median": s.update_ms_median,
        "update_hidden_fraction": s.update_hidden_fraction,
        "idle_percent_median": s.idle_percent_median,
        "method": t.method,
        "denoise": t.denoise.name(),
        "settings": t.settings_json(),
        "denoise_ms_median": s.denoise_ms_median,
    })
}

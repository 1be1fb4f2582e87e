//! `platoon bench balance`: Brigade's Table 16 for platoon. A camera orbits an outdoor scene
//! (a sky above a field of spheres on a ground plane, so line costs differ strongly) for N
//! frames, slow and fast, with 2 and 3 tracers, under every balancer; cells are mean idle %.
//! `--mode replay` replays recorded per-line cost maps against stated device speeds
//! (deterministic): the two orbits and the game's frames (platoon-game: bodies falling,
//! characters walking, a scripted camera), one column per map; `--mode real` renders the orbits
//! on lavapipe tracers of different thread counts.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context as _, Result};
use glam::Vec3;
use platoon_core::balance::replay::{replay, replay_stealing, CostMap, Overhead, StolenFrame};
use platoon_core::balance::steal::{ClaimBoard, Stealing};
use platoon_core::balance::{by_name, NAMES};
use platoon_core::frame::FrameParams;
use platoon_core::frame::Span;
use platoon_core::scene::camera::Camera;
use platoon_schedule::renderer::Renderer;
use platoon_tracer::Sampling;

use platoon::devices::{create_tracers, DeviceSpec};
use platoon::{prepare, EnvChoice, PrepareOptions, Prepared};

/// Recorded cost maps shipped with platoon (`--record-costs` makes new orbit ones,
/// `platoon bench game --record-costs` new game ones), in column order.
const SHIPPED: [(&str, &str); 3] = [
    ("slow", include_str!("../../../scenes/costs/slow.csv")),
    ("fast", include_str!("../../../scenes/costs/fast.csv")),
    ("game", include_str!("../../../scenes/costs/game.csv")),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Mode {
    /// Recorded line costs against stated device speeds (deterministic).
    Replay,
    /// Tracers on Vulkan devices.
    Real,
}

/// A camera orbiting the sphere field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraSpeed {
    /// 1 degree a frame.
    Slow,
    /// 8 degrees a frame.
    Fast,
    /// 4 degrees a frame from the far side: the orbit cost-aware's constants are chosen on,
    /// never a column of the table.
    Tune,
}

impl CameraSpeed {
    pub fn name(self) -> &'static str {
        match self {
            CameraSpeed::Slow => "slow",
            CameraSpeed::Fast => "fast",
            CameraSpeed::Tune => "orbit",
        }
    }
    /// Orbit step per frame and starting angle.
    fn degrees(self) -> (f32, f32) {
        match self {
            CameraSpeed::Slow => (1.0, 0.0),
            CameraSpeed::Fast => (8.0, 0.0),
            CameraSpeed::Tune => (4.0, 180.0),
        }
    }
}

/// The benchmark's settings; also the command line of `platoon bench balance`.
#[derive(Clone, Debug, clap::Args)]
pub struct Options {
    #[arg(long, value_enum, default_value = "replay")]
    pub mode: Mode,
    #[arg(long, default_value_t = 128)]
    pub frames: u32,
    #[arg(long, default_value_t = 96)]
    pub width: u32,
    #[arg(long, default_value_t = 96)]
    pub height: u32,
    #[arg(long, default_value_t = 2)]
    pub spp: u32,
    /// Replay: relative device speeds of the 2-device columns.
    #[arg(long, value_delimiter = ',', default_value = "1.0,0.6")]
    pub speeds2: Vec<f64>,
    /// Replay: relative device speeds of the 3-device columns.
    #[arg(long, value_delimiter = ',', default_value = "1.0,0.7,0.4")]
    pub speeds3: Vec<f64>,
    /// Real: the tracers of the 2-device columns.
    #[arg(long, default_value = "lavapipe:2,1")]
    pub devices2: DeviceSpec,
    /// Real: the tracers of the 3-device columns.
    #[arg(long, default_value = "lavapipe:2,1,1")]
    pub devices3: DeviceSpec,
    /// Replay every cost map (*.csv) of this folder, one column each, instead of the shipped
    /// ones (scenes/costs: slow, fast, game; scenes/costs/tune: the maps cost-aware's
    /// constants were chosen on).
    #[arg(long)]
    pub costs: Option<PathBuf>,
    /// Record the orbits' cost maps (slow.csv, fast.csv, and the tuning orbit.csv) of real
    /// renders into this folder first (and replay those).
    #[arg(long)]
    pub record_costs: Option<PathBuf>,
    /// Folder for balance.csv and balance.png.
    #[arg(long, default_value = ".")]
    pub out: PathBuf,
    /// Also run every balancer with in-frame stealing of the bands' tails (rows
    /// `<balancer>+steal`; their idle counts the pieces' overhead as lost).
    #[arg(long)]
    pub stealing: bool,
    /// Stealing: share of each band's predicted cost left in its tail.
    #[arg(long, default_value_t = Stealing::default().tail)]
    pub tail: f64,
    /// Stealing: a chunk's predicted cost as a share of its band's.
    #[arg(long, default_value_t = Stealing::default().chunk)]
    pub chunk: f64,
    /// Stealing: chunks an owner leaves for others while nobody has run out of work.
    #[arg(long, default_value_t = Stealing::default().reserve)]
    pub reserve: u32,
    /// Stealing: once some have run out, a claim takes the unclaimed chunks over this times
    /// the tracers sharing them.
    #[arg(long, default_value_t = Stealing::default().guide)]
    pub guide: f64,
    /// Stealing: a chunk's work is at least this many times a piece's overhead.
    #[arg(long, default_value_t = Stealing::default().work_per_overhead)]
    pub work_per_overhead: f64,
    /// Stealing: a frame is stolen only when a tracer's expected idle without it exceeds this
    /// many pieces' overhead.
    #[arg(long, default_value_t = Stealing::default().pieces_worth)]
    pub pieces_worth: f64,
    /// Replay with stealing: fixed cost of a piece's dispatch, microseconds (lavapipe's,
    /// measured by --measure-overhead at the maps' 96x96 and 2 spp; docs/BALANCING.md).
    #[arg(long, default_value_t = LAVAPIPE_OVERHEAD.dispatch * 1e6)]
    pub dispatch_us: f64,
    /// Replay with stealing: cost of a claim, microseconds (an atomic between the tracers of
    /// one process; a message's round trip to rank 0 between machines).
    #[arg(long, default_value_t = LAVAPIPE_OVERHEAD.claim * 1e6)]
    pub claim_us: f64,
    /// Measure the overhead model on the first tracer of --devices2 (the time of a band of
    /// one pixel; a claim on a board) and replay with it.
    #[arg(long)]
    pub measure_overhead: bool,
}

/// The overhead of a piece measured on lavapipe by `--measure-overhead` (one llvmpipe thread,
/// the orbit's frame at 96x96, 2 spp; docs/BALANCING.md).
pub const LAVAPIPE_OVERHEAD: Overhead = Overhead {
    dispatch: 380e-6,
    claim: 0.015e-6,
};

impl Default for Options {
    /// The command line's defaults.
    fn default() -> Self {
        #[derive(clap::Parser)]
        struct Wrapper {
            #[command(flatten)]
            options: Options,
        }
        <Wrapper as clap::Parser>::parse_from(["bench balance"]).options
    }
}

impl Options {
    pub fn validate(&self) -> Result<()> {
        if self.frames == 0 || self.width == 0 || self.height < 3 || self.spp == 0 {
            bail!("--frames, --width, --spp must be positive and --height at least 3");
        }
        for (name, s) in [("--speeds2", &self.speeds2), ("--speeds3", &self.speeds3)] {
            if s.is_empty() || s.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
                bail!("{name}: speeds must be positive");
            }
        }
        if !self.out.is_dir() {
            bail!("{}: output folder does not exist", self.out.display());
        }
        self.steal().validate().map_err(anyhow::Error::msg)?;
        if !(self.dispatch_us >= 0.0 && self.claim_us >= 0.0) {
            bail!("--dispatch-us and --claim-us must be non-negative");
        }
        Ok(())
    }

    /// The stealing the options describe.
    pub fn steal(&self) -> Stealing {
        Stealing {
            tail: self.tail,
            chunk: self.chunk,
            reserve: self.reserve,
            guide: self.guide,
            work_per_overhead: self.work_per_overhead,
            pieces_worth: self.pieces_worth,
        }
    }

    /// The replay's overhead model as the options state it.
    pub fn overhead(&self) -> Overhead {
        Overhead {
            dispatch: self.dispatch_us * 1e-6,
            claim: self.claim_us * 1e-6,
        }
    }
}

/// One cell of the table, with the per-frame idle fractions behind it.
#[derive(Clone, Debug)]
pub struct Cell {
    pub balancer: &'static str,
    /// The tracers stole the bands' tails in the frame (`balance::steal`).
    pub stealing: bool,
    pub devices: usize,
    /// The camera path: a cost map's name in replay, the orbit in real mode.
    pub camera: String,
    /// Mean idle % of the frames, the pieces' overhead counted in (replay: as lost; real: as
    /// the busy time it is).
    pub idle_pct: f64,
    /// Replay: the pieces' overhead % within `idle_pct`. Real: pieces x the dispatch overhead
    /// (`--dispatch-us`) over the tracers' time, an estimate the busy times already hold.
    pub overhead_pct: f64,
    /// Pieces claimed a frame, mean.
    pub pieces: f64,
    /// Mean frame time, ms (replay: of the slowest tracer, in the maps' seconds).
    pub frame_ms: f64,
    pub per_frame: Vec<f64>,
}

impl Cell {
    /// The table's row: the balancer, `+steal` with stealing.
    pub fn label(&self) -> String {
        if self.stealing {
            format!("{}+steal", self.balancer)
        } else {
            self.balancer.to_string()
        }
    }
}

/// The outdoor scene: the 103k-triangle sphere field under a constant sky.
pub fn outdoor_scene() -> Result<Prepared> {
    let scene = crate::generated::load(&platoon_scenegen::sphere_field(4, false), "field")?;
    prepare(
        scene,
        &PrepareOptions {
            env: EnvChoice::Color(Vec3::new(0.6, 0.75, 1.0)),
            ..Default::default()
        },
    )
}

/// The orbiting camera of frame `f`: around the field, bobbing up and down so that the horizon
/// (and with it the cost of every line) moves.
pub fn orbit_camera(frame: u32, speed: CameraSpeed) -> Camera {
    let (step, start) = speed.degrees();
    let a = (start + frame as f32 * step).to_radians();
    let eye = Vec3::new(13.0 * a.cos(), 3.0 + 2.0 * (2.0 * a).sin(), 13.0 * a.sin());
    Camera::look_at(eye, Vec3::new(0.0, 0.8, 0.0), 50f32.to_radians())
}

fn frame_params(o: &Options, frame: u32, speed: CameraSpeed) -> FrameParams {
    let mut p = FrameParams::new(o.width, o.height, o.spp, orbit_camera(frame, speed));
    p.frame = frame;
    p
}

/// Renders the camera path on one tracer and records seconds per line (the band's measured time
/// spread over its lines in proportion to the rays each traced).
pub fn record(
    o: &Options,
    scene: &Prepared,
    speed: CameraSpeed,
    spec: &DeviceSpec,
) -> Result<CostMap> {
    let mut tracers = create_tracers(spec, &scene.gpu, false, Sampling::Mis)?;
    let Some(tracer) = tracers.first_mut() else {
        bail!("no tracer to record with")
    };
    let mut frames = Vec::new();
    for f in 0..o.frames {
        let params = frame_params(o, f, speed);
        let band = tracer.render(&params, 0, o.height, &mut |_| {})?;
        let seconds = band.wall_time.as_secs_f64();
        let rays = band.rays.max(1) as f64;
        frames.push(
            band.line_rays
                .iter()
                .map(|&r| r as f64 / rays * seconds)
                .collect(),
        );
    }
    Ok(CostMap {
        width: o.width,
        frames,
    })
}

/// The replayed maps, named: the shipped ones, or every *.csv of `--costs` (or of
/// `--record-costs`; the shipped names first, in their order, then the others by name).
pub fn cost_maps(o: &Options) -> Result<Vec<(String, CostMap)>> {
    // Maps just recorded are the ones replayed.
    let Some(dir) = o.costs.as_ref().or(o.record_costs.as_ref()) else {
        return SHIPPED
            .iter()
            .map(|(name, text)| {
                let origin = format!("scenes/costs/{name}.csv (shipped)");
                Ok((name.to_string(), CostMap::parse(text, Path::new(&origin))?))
            })
            .collect();
    };
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .with_context(|| format!("{}: cannot read the cost-map folder", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "csv"))
        .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .collect();
    let rank = |n: &String| {
        SHIPPED
            .iter()
            .position(|(s, _)| s == n)
            .unwrap_or(SHIPPED.len())
    };
    names.sort_by(|a, b| rank(a).cmp(&rank(b)).then(a.cmp(b)));
    if names.is_empty() {
        bail!("{}: no cost maps (*.csv) in this folder", dir.display());
    }
    names
        .into_iter()
        .map(|n| {
            let map = CostMap::load(&dir.join(format!("{n}.csv")))?;
            Ok((n, map))
        })
        .collect()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

pub fn run(o: &Options) -> Result<Vec<Cell>> {
    if let Some(dir) = &o.record_costs {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create folder", dir.display()))?;
        let scene = outdoor_scene()?;
        for speed in [CameraSpeed::Slow, CameraSpeed::Fast, CameraSpeed::Tune] {
            let map = record(o, &scene, speed, &DeviceSpec::Lavapipe(vec![1]))?;
            let (step, start) = speed.degrees();
            let comment = format!(
                "{} camera ({step} degrees a frame from {start}), {} frames, {}x{} at {} spp, \
                 one lavapipe thread",
                speed.name(),
                o.frames,
                o.width,
                o.height,
                o.spp
            );
            // The tuning map goes apart, so that replaying the folder judges on the others.
            let folder = match speed {
                CameraSpeed::Tune => dir.join("tune"),
                _ => dir.clone(),
            };
            std::fs::create_dir_all(&folder)
                .with_context(|| format!("{}: cannot create folder", folder.display()))?;
            let path = folder.join(format!("{}.csv", speed.name()));
            platoon_core::output::write_text(&path, &map.to_text(&comment))?;
        }
    }
    let mut cells = Vec::new();
    match o.mode {
        Mode::Replay => {
            let maps = cost_maps(o)?;
            let overhead = if o.measure_overhead {
                let measured = measure_overhead(o, &o.devices2, 31)?;
                eprintln!(
                    "overhead measured on {}: a dispatch {:.1} us, a claim {:.3} us",
                    o.devices2,
                    measured.dispatch * 1e6,
                    measured.claim * 1e6
                );
                measured
            } else {
                o.overhead()
            };
            for speeds in [&o.speeds2, &o.speeds3] {
                for (camera, map) in &maps {
                    let map = map.take(o.frames as usize);
                    for stealing in steal_settings(o) {
                        for name in NAMES {
                            let played = (name, stealing.as_ref(), overhead);
                            cells.push(replayed_cell(&map, camera, speeds, played));
                        }
                    }
                }
            }
        }
        Mode::Real => {
            let scene = outdoor_scene()?;
            for spec in [&o.devices2, &o.devices3] {
                let mut tracers = create_tracers(spec, &scene.gpu, false, Sampling::Mis)?;
                for camera in [CameraSpeed::Slow, CameraSpeed::Fast] {
                    for stealing in steal_settings(o) {
                        for name in NAMES {
                            let cell;
                            (cell, tracers) = real_cell(o, tracers, camera, name, stealing)?;
                            cells.push(cell);
                        }
                    }
                }
            }
        }
    }
    Ok(cells)
}

/// The cell of `balancer` (with `stealing`, each piece costing `overhead`) replaying `map`
/// against devices of `speeds`.
fn replayed_cell(
    map: &CostMap,
    camera: &str,
    speeds: &[f64],
    (balancer, stealing, overhead): (&'static str, Option<&Stealing>, Overhead),
) -> Cell {
    let mut b = by_name(balancer).unwrap();
    let frames = replay_stealing(map, speeds, b.as_mut(), stealing, overhead);
    let of = |f: fn(&StolenFrame) -> f64| mean(&frames.iter().map(f).collect::<Vec<f64>>());
    Cell {
        balancer,
        stealing: stealing.is_some(),
        devices: speeds.len(),
        camera: camera.to_string(),
        idle_pct: 100.0 * of(|f| f.lost()),
        overhead_pct: 100.0 * of(|f| f.overhead),
        pieces: of(|f| f.pieces as f64),
        frame_ms: 1e3 * of(|f| f.frame_seconds),
        per_frame: frames.iter().map(|f| f.lost()).collect(),
    }
}

/// The cell of `balancer` (with `stealing`) rendering the `camera` path on `tracers`, which
/// come back for the next cell. Its overhead is the pieces at `--dispatch-us` each over the
/// tracers' time: an estimate (their busy times hold the true one).
fn real_cell(
    o: &Options,
    tracers: Vec<platoon_tracer::Tracer>,
    camera: CameraSpeed,
    balancer: &'static str,
    stealing: Option<Stealing>,
) -> Result<(Cell, Vec<platoon_tracer::Tracer>)> {
    let devices = tracers.len();
    let mut renderer = Renderer::new(tracers, by_name(balancer).unwrap());
    renderer.set_stealing(stealing);
    let (mut per_frame, mut pieces, mut ms, mut overhead) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for f in 0..o.frames {
        let frame = renderer.render_frame(&frame_params(o, f, camera))?;
        per_frame.push(frame.idle_fraction);
        let n: u32 = frame.tracers.iter().map(|t| t.pieces).sum();
        let busiest = frame
            .tracers
            .iter()
            .map(|t| (t.wall_time + t.idle).as_secs_f64())
            .fold(0.0, f64::max);
        pieces.push(n as f64);
        ms.push(1e3 * frame.wall_time.as_secs_f64());
        let spent = n as f64 * o.overhead().dispatch;
        overhead.push(spent / (devices as f64 * busiest).max(1e-9));
    }
    let cell = Cell {
        balancer,
        stealing: stealing.is_some(),
        devices,
        camera: camera.name().to_string(),
        idle_pct: 100.0 * mean(&per_frame),
        overhead_pct: 100.0 * mean(&overhead),
        pieces: mean(&pieces),
        frame_ms: mean(&ms),
        per_frame,
    };
    Ok((cell, renderer.into_tracers()))
}

/// The stealing settings a run compares: none, and the options' when `--stealing`.
fn steal_settings(o: &Options) -> Vec<Option<Stealing>> {
    let mut settings = vec![None];
    if o.stealing {
        settings.push(Some(o.steal()));
    }
    settings
}

/// The overhead of a piece on the first tracer of `spec`: the median time of a band of one
/// pixel of the orbit's frame (the fixed cost of a dispatch: recording, submitting, waiting,
/// reading back; the pixel's own work is a few microseconds) over `repeat` tries. A claim's
/// cost is timed on a board of many chunks, one thread claiming.
pub fn measure_overhead(o: &Options, spec: &DeviceSpec, repeat: u32) -> Result<Overhead> {
    let scene = outdoor_scene()?;
    let mut tracers = create_tracers(spec, &scene.gpu, false, Sampling::Mis)?;
    let Some(t) = tracers.first_mut() else {
        bail!("no tracer to measure the overhead on")
    };
    let params = frame_params(o, 20, CameraSpeed::Slow);
    let pixel = Span::new(o.width / 2, o.width / 2 + 1);
    t.render_span(&params, pixel, &mut |_| {})?;
    let mut times = Vec::new();
    for _ in 0..repeat.max(1) {
        let start = std::time::Instant::now();
        t.render_span(&params, pixel, &mut |_| {})?;
        times.push(start.elapsed().as_secs_f64());
    }
    let board_of = || {
        let planned = [Span::new(0, 1 << 20), Span::new(1 << 20, 1 << 21)];
        let fine = Stealing {
            tail: 1.0,
            chunk: 1e-4,
            reserve: 0,
            guide: 1e9,
            work_per_overhead: 0.0,
            pieces_worth: 0.0,
        };
        ClaimBoard::new(&planned, 1024, &[1.0; 2048], &fine, 0.0)
    };
    let board = board_of();
    let start = std::time::Instant::now();
    let mut claims = 0u32;
    while board.claim(0, 1.0).is_some() {
        claims += 1;
    }
    let claim = start.elapsed().as_secs_f64() / claims.max(1) as f64;
    Ok(Overhead {
        dispatch: platoon_core::measure::median(times),
        claim,
    })
}

/// Scaling efficiency T(1) / (n T(n)) of equal devices under `balancer`, replayed.
pub fn replay_efficiency(map: &CostMap, n: usize, balancer: &str) -> f64 {
    let mut b = by_name(balancer).unwrap();
    let per_frame = replay(map, &vec![1.0; n], b.as_mut());
    // With equal devices T(1) = sum of times = n * T_mean, so efficiency = T_mean / T_max = 1 - idle.
    1.0 - mean(&per_frame)
}

/// The cell of the row `label` (`Cell::label`) in a column.
pub fn cell<'a>(cells: &'a [Cell], label: &str, devices: usize, camera: &str) -> Option<&'a Cell> {
    cells
        .iter()
        .find(|c| c.label() == label && c.devices == devices && c.camera == camera)
}

/// The table's rows (`Cell::label`), in the order the cells came.
pub fn rows(cells: &[Cell]) -> Vec<String> {
    let mut rows: Vec<String> = Vec::new();
    for c in cells {
        if !rows.contains(&c.label()) {
            rows.push(c.label());
        }
    }
    rows
}

/// The table's columns, (devices, camera path), in the order the cells came.
pub fn columns(cells: &[Cell]) -> Vec<(usize, String)> {
    let mut columns: Vec<(usize, String)> = Vec::new();
    for c in cells {
        if !columns
            .iter()
            .any(|(d, n)| *d == c.devices && *n == c.camera)
        {
            columns.push((c.devices, c.camera.clone()));
        }
    }
    columns
}

/// The table in Brigade's Table 16 shape.
pub fn table(cells: &[Cell]) -> String {
    let columns = columns(cells);
    let mut s = format!("{:<20}", "idle %");
    for (d, c) in &columns {
        let _ = write!(s, " {:>9}", format!("{d}-{c}"));
    }
    s.push('\n');
    for name in rows(cells) {
        let _ = write!(s, "{name:<20}");
        for (d, c) in &columns {
            match cell(cells, &name, *d, c) {
                Some(x) => {
                    let _ = write!(s, " {:>9.2}", x.idle_pct);
                }
                None => {
                    let _ = write!(s, " {:>9}", "-");
                }
            }
        }
        s.push('\n');
    }
    if cells.iter().any(|c| c.stealing) {
        s.push_str(
            "+steal rows: overhead % within idle / pieces a frame / frame ms (plain row's ms)\n",
        );
        for c in cells.iter().filter(|c| c.stealing) {
            let plain = cell(cells, c.balancer, c.devices, &c.camera).map_or(0.0, |p| p.frame_ms);
            let _ = writeln!(
                s,
                "  {:<18} {}-{:<6} {:>6.3} / {:>6.1} / {:>8.2} ({:.2})",
                c.label(),
                c.devices,
                c.camera,
                c.overhead_pct,
                c.pieces,
                c.frame_ms,
                plain
            );
        }
    }
    s
}

pub fn json(cells: &[Cell]) -> String {
    let items: Vec<String> = cells
        .iter()
        .map(|c| {
            format!(
                r#"{{"balancer":"{}","stealing":{},"devices":{},"camera":"{}","idle_pct":{:.4},"overhead_pct":{:.4},"pieces":{:.2},"frame_ms":{:.3}}}"#,
                c.balancer, c.stealing, c.devices, c.camera, c.idle_pct, c.overhead_pct, c.pieces, c.frame_ms
            )
        })
        .collect();
    format!("[{}]", items.join(","))
}

pub fn csv(cells: &[Cell]) -> String {
    let mut s = String::from("balancer,devices,camera,frame,idle_pct\n");
    for c in cells {
        for (f, i) in c.per_frame.iter().enumerate() {
            let _ = writeln!(
                s,
                "{},{},{},{},{:.4}",
                c.label(),
                c.devices,
                c.camera,
                f,
                100.0 * i
            );
        }
    }
    s
}

/// Mean idle % when each of the devices renders every n-th line (interleaving: no balancer,
/// each device gets a similar mix of cheap and costly lines, but an equal count of them).
pub fn interleaved_idle(map: &CostMap, speeds: &[f64]) -> f64 {
    let n = speeds.len();
    let per_frame: Vec<f64> = map
        .frames
        .iter()
        .map(|costs| {
            let times: Vec<f64> = (0..n)
                .map(|i| costs.iter().skip(i).step_by(n).sum::<f64>() / speeds[i])
                .collect();
            platoon_core::balance::idle_fraction(&times)
        })
        .collect();
    100.0 * mean(&per_frame)
}

/// A row of the table that is not a balancer: `idle` of every replayed map and speeds, in the
/// table's columns.
fn reference_row(o: &Options, name: &str, idle: fn(&CostMap, &[f64]) -> f64) -> Result<String> {
    let maps = cost_maps(o)?;
    let mut s = format!("{name:<20}");
    for speeds in [&o.speeds2, &o.speeds3] {
        for (_, map) in &maps {
            let _ = write!(s, " {:>9.2}", idle(&map.take(o.frames as usize), speeds));
        }
    }
    Ok(s)
}

/// The replayed idle % of interleaved lines, in the table's columns.
pub fn interleaved_row(o: &Options) -> Result<String> {
    reference_row(o, "interleaved", interleaved_idle)
}

/// Mean idle % of a split that is told, for each frame, the mean of the costs of the frames
/// before and after it (and the true device speeds), cut to the pixel; the first frame is the
/// equal split every balancer starts from. Not a balancer (it sees the next frame): it shows
/// how much of the idle is the frame-to-frame noise of the line costs that nothing before the
/// frame can predict.
pub fn hindsight_idle(map: &CostMap, speeds: &[f64]) -> f64 {
    use platoon_core::balance::{fractional_cuts, idle_fraction, line_bands, proportional};
    use platoon_core::balance::{span_cost, spans_at};
    let (width, height, n) = (map.width, map.height() as u32, speeds.len());
    let frames = &map.frames;
    let per_frame: Vec<f64> = (0..frames.len())
        .map(|k| {
            let spans = if k == 0 || height < n as u32 {
                line_bands(width, &proportional(height, &vec![1.0; n]))
            } else {
                let after = frames.get(k + 1).unwrap_or(&frames[k - 1]);
                let guess: Vec<f64> = frames[k - 1]
                    .iter()
                    .zip(after)
                    .map(|(a, b)| 0.5 * (a + b))
                    .collect();
                spans_at(&fractional_cuts(&guess, speeds), width, height)
            };
            let times: Vec<f64> = spans
                .iter()
                .zip(speeds)
                .map(|(&s, v)| span_cost(&frames[k], width, s) / v)
                .collect();
            idle_fraction(&times)
        })
        .collect();
    100.0 * mean(&per_frame)
}

/// The hindsight split's idle % in the table's columns.
pub fn hindsight_row(o: &Options) -> Result<String> {
    reference_row(o, "hindsight", hindsight_idle)
}

/// Time to render the outdoor frame on one tracer as one contiguous band and as `stride`
/// interleaved passes (same pixels, same work): the cost of lost line coherence.
pub fn coherence(o: &Options, spec: &DeviceSpec, stride: u32, repeat: u32) -> Result<(f64, f64)> {
    let scene = outdoor_scene()?;
    let mut tracers = create_tracers(spec, &scene.gpu, false, Sampling::Mis)?;
    let Some(t) = tracers.first_mut() else {
        bail!("no tracer")
    };
    let params = frame_params(o, 20, CameraSpeed::Slow);
    t.render(&params, 0, o.height, &mut |_| {})?;
    let (mut contiguous, mut interleaved) = (Vec::new(), Vec::new());
    for _ in 0..repeat {
        contiguous.push(
            t.render(&params, 0, o.height, &mut |_| {})?
                .wall_time
                .as_secs_f64(),
        );
        let mut total = 0.0;
        for k in 0..stride {
            total += t
                .render_strided(&params, k, o.height, stride, &mut |_| {})?
                .wall_time
                .as_secs_f64();
        }
        interleaved.push(total);
    }
    Ok((
        platoon_core::measure::median(contiguous),
        platoon_core::measure::median(interleaved),
    ))
}

/// Scaling efficiency T(1) / (n T(n)) of n equal one-thread lavapipe tracers under cost-aware,
/// for each n in `counts`, from mean frame times over the slow camera path (first frames skipped
/// while the balancer settles). T(1) is measured once for all of them.
pub fn real_scaling_efficiency(o: &Options, counts: &[usize]) -> Result<Vec<f64>> {
    let scene = outdoor_scene()?;
    let frames = o.frames.max(4);
    let settle = (frames / 8).max(1);
    let mean_time = |tracers: usize| -> Result<f64> {
        let spec = DeviceSpec::Lavapipe(vec![1; tracers]);
        let mut r = Renderer::new(
            create_tracers(&spec, &scene.gpu, false, Sampling::Mis)?,
            by_name("cost-aware").unwrap(),
        );
        let mut t = Vec::new();
        for f in 0..frames {
            let frame = r.render_frame(&frame_params(o, f, CameraSpeed::Slow))?;
            if f >= settle {
                t.push(frame.wall_time.as_secs_f64());
            }
        }
        Ok(mean(&t))
    };
    let t1 = mean_time(1)?;
    counts
        .iter()
        .map(|&n| Ok(t1 / (n as f64 * mean_time(n)?)))
        .collect()
}

/// The same from the cost maps: equal speeds, so T(1) = n T_mean and efficiency = 1 - idle.
pub fn replay_scaling_row(o: &Options) -> Result<String> {
    let maps = cost_maps(o)?;
    let mut s = String::from("scaling efficiency, equal devices, cost-aware (replay):");
    for n in [2, 3] {
        for (camera, map) in &maps {
            let _ = write!(
                s,
                " {n}-{} {:.1}%",
                camera,
                100.0 * replay_efficiency(&map.take(o.frames as usize), n, "cost-aware")
            );
        }
    }
    Ok(s)
}

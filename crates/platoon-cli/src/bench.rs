//! `platoon bench`: samples/s, rays/s and BVH build times of the built-in scenes.

use std::time::Duration;

use anyhow::Result;
use platoon::core::flatten::GpuScene;
use platoon::core::frame::FrameParams;
use platoon::tracer::{Tracer, TracerOptions};

use platoon::core::measure::median;
use platoon::{prepare, PrepareOptions, Prepared};

struct Measure {
    samples_per_s: f64,
    rays_per_s: f64,
    seconds: f64,
}

impl Measure {
    fn print(&self, label: &str) {
        let (s, r) = (self.samples_per_s / 1e6, self.rays_per_s / 1e6);
        println!("{label:<40} {s:>12.3} {r:>12.3} {:>9.3}", self.seconds);
    }
}

fn measure(tracer: &mut Tracer, params: &FrameParams, repeat: u32) -> Result<Measure> {
    let mut warm = params.clone();
    warm.spp = 1;
    tracer.render(&warm, 0, warm.height, &mut |_| {})?;
    let mut times = Vec::new();
    let mut rays = Vec::new();
    for _ in 0..repeat {
        let band = tracer.render(params, 0, params.height, &mut |_| {})?;
        let t = band.wall_time.as_secs_f64();
        times.push(t);
        rays.push(band.rays as f64 / t);
    }
    let t = median(times);
    let samples = params.width as f64 * params.height as f64 * params.spp as f64;
    Ok(Measure {
        samples_per_s: samples / t,
        rays_per_s: median(rays),
        seconds: t,
    })
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

pub fn run(spp: u32, device: usize, repeat: u32) -> Result<()> {
    let options = TracerOptions {
        device,
        ..Default::default()
    };
    println!("platoon bench: {spp} spp per render, median of {repeat}, 256x256");
    let cornell = prepare(
        platoon::core::scene::cornell::scene(),
        &PrepareOptions::default(),
    )?;
    let mut tracer = Tracer::new(&options, &cornell.gpu)?;
    println!("device: {}", tracer.device_info().name);
    println!(
        "{:<40} {:>12} {:>12} {:>9}",
        "scene", "Msamples/s", "Mrays/s", "seconds"
    );
    // Camera rays only (max depth 1: the emitters seen directly) against full paths.
    for (label, depth) in [
        ("cornell box, camera rays only", Some(1)),
        ("cornell box, depth 8", Some(8)),
        ("cornell box, unbounded", None),
    ] {
        let mut params = FrameParams::new(256, 256, spp, cornell.camera);
        if let Some(d) = depth {
            params.max_depth = d;
        }
        let m = measure(&mut tracer, &params, repeat)?;
        m.print(label);
    }
    drop(tracer);

    // Contiguous bands against interleaved lines: what interleaving costs in coherence.
    let layout = platoon_lab::balance_bench::Options {
        width: 192,
        height: 144,
        spp,
        ..Default::default()
    };
    let one = platoon::devices::DeviceSpec::Indices(vec![device]);
    for stride in [2, 3] {
        let (c, i) = platoon_lab::balance_bench::coherence(&layout, &one, stride, repeat)?;
        println!("outdoor 192x144, {stride} interleaved passes vs one band: {:.3} s vs {:.3} s ({:+.1}%)", i, c, 100.0 * (i / c - 1.0));
    }

    let dir = tempfile::tempdir()?;
    for (label, unique) in [
        ("sphere field 100k, instanced", false),
        ("sphere field 100k, unique", true),
    ] {
        let path = dir.path().join(format!("field-{unique}.glb"));
        std::fs::write(
            &path,
            platoon_scenegen::to_glb(&platoon_scenegen::sphere_field(4, unique)),
        )?;
        let p = prepare(
            platoon::load_scene(Some(&path))?,
            &PrepareOptions::default(),
        )?;
        let mut tracer = Tracer::new(&options, &p.gpu)?;
        let mut params = FrameParams::new(256, 256, spp, p.camera);
        measure(&mut tracer, &params, repeat)?.print(label);
        params.max_depth = 1;
        measure(&mut tracer, &params, repeat)?.print(&format!("{label}, camera rays"));
        print_build_times(&p.gpu, label);
        if unique {
            compare_layouts(&p);
            refit_row(&p);
        }
    }
    Ok(())
}

/// Refitting against rebuilding the 16 distinct meshes of the 100k field, each deformed by a
/// wave (one thread: the refit of one mesh is one sweep).
fn refit_row(p: &Prepared) {
    use platoon::core::flatten::refit::MeshBvh;
    use std::time::Instant;
    let meshes: Vec<_> = p.posed.meshes.iter().map(|m| (**m).clone()).collect();
    let triangles: usize = meshes.iter().map(|m| m.indices.len()).sum();
    let mut bvhs: Vec<MeshBvh> = meshes.iter().map(MeshBvh::build).collect();
    let (mut refit, mut rebuild) = (Vec::new(), Vec::new());
    for frame in 0..5 {
        let moved: Vec<_> = meshes
            .iter()
            .map(|m| {
                let mut m = m.clone();
                for v in &mut m.positions {
                    v.y += 0.02 * (3.0 * v.x + 0.7 * frame as f32).sin();
                }
                m
            })
            .collect();
        let t = Instant::now();
        for (b, m) in bvhs.iter_mut().zip(&moved) {
            assert!(b.refit(m), "same triangles");
        }
        refit.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        for m in &moved {
            std::hint::black_box(platoon::core::flatten::bvh::build_mesh_bvh(m));
        }
        rebuild.push(t.elapsed().as_secs_f64());
    }
    let (refit, rebuild) = (median(refit), median(rebuild));
    println!(
        "BVH refit, {triangles} triangles in 16 meshes (leaf boxes included, 1 thread): {:.2} ms = {:.1} M triangles/s; rebuild {:.2} ms: {:.0}x",
        refit * 1e3,
        triangles as f64 / refit / 1e6,
        rebuild * 1e3,
        rebuild / refit
    );
}

/// BVH2 against CWBVH on the CPU (platoon_lab::layout_bench).
fn compare_layouts(p: &Prepared) {
    let (c, triangles, rays) = platoon_lab::layout_bench::on_prepared(p);
    println!(
        "BVH layouts on the CPU (1 thread, {} triangles, {} rays; same hits: {}):",
        triangles, rays, c.hits_agree
    );
    println!(
        "  BVH2:  {:>6.2} Mrays/s, nodes {:>6.2} MB, build {:>6.1} ms",
        c.bvh2_rays_per_s / 1e6,
        c.bvh2_node_bytes as f64 / 1e6,
        ms(c.bvh2_build)
    );
    println!(
        "  CWBVH: {:>6.2} Mrays/s, nodes {:>6.2} MB, build {:>6.1} ms",
        c.cwbvh_rays_per_s / 1e6,
        c.cwbvh_node_bytes as f64 / 1e6,
        ms(c.cwbvh_build)
    );
}

fn print_build_times(g: &GpuScene, label: &str) {
    println!(
        "  BVH build ({label}): {} triangles, bottom level {:.1} ms, top level {:.2} ms",
        g.triangle_count,
        ms(g.build_times.meshes),
        ms(g.build_times.instances)
    );
}

/// `platoon bench --dynamic` and its settings.
#[derive(clap::Args)]
pub struct DynamicArgs {
    /// Run the living-scene benchmark.
    #[arg(long, conflicts_with = "game")]
    pub dynamic: bool,
    /// Run the game benchmark: the game of platoon-game at a target frame time.
    #[arg(long)]
    pub game: bool,
    /// Frames of each run (--dynamic: animated, then still; --game: the game's frames).
    #[arg(long, default_value_t = 200)]
    pub frames: u32,
    /// --game: the frame time to hold, in milliseconds.
    #[arg(long, default_value_t = 40.0)]
    pub target_ms: f64,
    /// --game: the frame size, WIDTHxHEIGHT (small enough on lavapipe for about 13 samples a
    /// frame at 40 ms: a sample more or less is then a step of 8%, inside the +-10% band).
    #[arg(long, default_value = "64x48", value_parser = parse_size)]
    pub size: (u32, u32),
    /// --game: below one sample a frame, scale Russian-roulette survival down (unbiased).
    #[arg(long, requires = "game")]
    pub roulette_scaling: bool,
    /// --game: below one sample a frame, render fewer pixels, upscaled (biased).
    #[arg(long, requires = "game")]
    pub resolution_scaling: bool,
    /// --game: the devices (see `platoon devices`; lavapipe:N,M makes software tracers).
    #[arg(long, default_value = "all")]
    pub devices: String,
    /// Walking (skinned) characters.
    #[arg(long, default_value_t = 16)]
    characters: u32,
    /// Rigid objects moving every frame.
    #[arg(long, default_value_t = 64)]
    movers: u32,
    /// The skinned, animated glTF to place.
    #[arg(long, default_value = "../shared/scenes/CesiumMan.glb")]
    pub character: std::path::PathBuf,
    /// llvmpipe threads of the tracer (1 leaves the other core to the updater).
    #[arg(long, default_value_t = 1)]
    lavapipe_threads: u32,
    /// The game never waits for a generation: a frame whose next one is not built yet renders
    /// the previous one again (Pipeline::try_take).
    #[arg(long)]
    never_wait: bool,
    /// Let the system place the threads instead of keeping the updater on a core apart from
    /// the tracer's (it often puts both on one core).
    #[arg(long)]
    no_pin: bool,
    /// Print one JSON object after the text.
    #[arg(long)]
    pub json: bool,
    /// --game: instead of the bench, record the game's per-line cost maps (game.csv, and
    /// tune/game.csv for choosing constants) into this folder, for `balance-bench --costs`.
    #[arg(long, requires = "game")]
    pub record_costs: Option<std::path::PathBuf>,
    /// Folder for dynamic.csv and dynamic.png (--game: game.csv).
    #[arg(long, default_value = ".")]
    pub out: std::path::PathBuf,
}

pub fn parse_size(s: &str) -> std::result::Result<(u32, u32), String> {
    let (w, h) = s
        .split_once('x')
        .ok_or("expected WIDTHxHEIGHT, e.g. 64x48")?;
    let parse = |v: &str| v.parse::<u32>().ok().filter(|&n| n > 0);
    match (parse(w), parse(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!("{s:?} is not WIDTHxHEIGHT with positive sizes")),
    }
}

pub fn run_dynamic(a: &DynamicArgs, device: usize) -> Result<()> {
    use platoon_lab::dynamic_bench as db;
    if !a.out.is_dir() {
        anyhow::bail!("{}: output folder does not exist", a.out.display());
    }
    let options = db::Options {
        frames: a.frames,
        characters: a.characters,
        movers: a.movers,
        character: a.character.clone(),
        lavapipe_threads: a.lavapipe_threads,
        device,
        never_wait: a.never_wait,
        pin_threads: !a.no_pin,
        ..Default::default()
    };
    let report = db::run(&options)?;
    print!("{}", db::frames_text(&report));
    print!("{}", db::text(&options, &report.summary));
    let (csv, png) = (a.out.join("dynamic.csv"), a.out.join("dynamic.png"));
    platoon::core::output::write_text(&csv, &db::csv(&report)?)?;
    db::write_png(&png, &report)?;
    println!("wrote {} and {}", csv.display(), png.display());
    if a.json {
        println!("{}", db::json(&report.summary));
    }
    Ok(())
}

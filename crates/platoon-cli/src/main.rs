//! `platoon`: render, inspect and benchmark scenes from the command line.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{bail, Context as _, Result};
use clap::{Parser, Subcommand, ValueEnum};
use glam::Vec3;
use indicatif::{ProgressBar, ProgressStyle};
use platoon::core::balance;
use platoon::core::frame::FrameParams;
use platoon::devices::DeviceSpec;
use platoon::tracer::Sampling;
use platoon::{EnvChoice, PrepareOptions};

#[derive(Parser)]
#[command(
    name = "platoon",
    version,
    about = "Physically based path tracer on every Vulkan device"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum MemoryArg {
    Auto,
    TexelBuffers,
    StorageBuffers,
    DeviceAddress,
}

#[derive(Clone, Copy, ValueEnum)]
enum SamplingArg {
    Mis,
    Bsdf,
    Light,
}

#[derive(clap::Args)]
struct SceneArgs {
    /// glTF scene (.gltf or .glb); the built-in Cornell box when omitted.
    scene: Option<PathBuf>,
    /// Equirectangular environment map (.exr or .hdr).
    #[arg(long, conflicts_with = "env_color")]
    env: Option<PathBuf>,
    /// Constant environment radiance, as R,G,B.
    #[arg(long, value_parser = parse_rgb)]
    env_color: Option<Vec3>,
    /// Animation time in seconds.
    #[arg(long, default_value_t = 0.0)]
    time: f32,
    /// Read buffers and textures whose URI is absolute or leads out of the scene's folder
    /// (refused by default, as glTF viewers do).
    #[arg(long)]
    allow_external_files: bool,
}

impl SceneArgs {
    fn load(&self) -> Result<platoon::core::Scene> {
        let options = platoon::core::scene::gltf_load::LoadOptions {
            allow_external_files: self.allow_external_files,
        };
        platoon::load_scene_with(self.scene.as_deref(), &options)
    }
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an EXR (linear, with metadata) or PNG (tone-mapped sRGB).
    Render {
        #[command(flatten)]
        scene: SceneArgs,
        #[arg(long, default_value_t = 64)]
        spp: u32,
        /// Stop at the last complete pass within this many seconds (then --spp is an upper
        /// bound; the spp reached goes into the metadata). One device only.
        #[arg(long)]
        time_limit: Option<f64>,
        #[arg(long, default_value_t = 512)]
        width: u32,
        #[arg(long, default_value_t = 512)]
        height: u32,
        /// Longest path in segments (1: emitters only, 2: direct light). Default: effectively unbounded.
        #[arg(long)]
        max_depth: Option<u32>,
        #[arg(long, default_value_t = 0)]
        seed: u32,
        /// Index of the scene camera; the scene is framed from its bounds when it has none.
        #[arg(long)]
        camera: Option<usize>,
        /// Thin-lens aperture radius in scene units (0: pinhole).
        #[arg(long, default_value_t = 0.0)]
        aperture: f32,
        /// Distance to the plane in focus (default: the scene centre).
        #[arg(long)]
        focus_distance: Option<f32>,
        /// Devices: `all`, indices like `0,1` (see `platoon devices`), or `lavapipe:T1,T2,...`
        /// (one software tracer per entry, with Ti threads each).
        #[arg(long, default_value = "0")]
        devices: DeviceSpec,
        /// How lines are split between devices: none, robin-hood, perfect, perfect-smooth,
        /// cycles, cost-aware.
        #[arg(long, default_value = "cost-aware", value_parser = parse_balancer)]
        balancer: String,
        /// Estimator: MIS of light and BSDF sampling (default), or either alone.
        #[arg(long, value_enum, default_value = "mis")]
        sampling: SamplingArg,
        /// Enable the Khronos validation layer.
        #[arg(long)]
        validation: bool,
        /// How the kernel reads scene arrays: auto is texel buffers on CPU devices (lavapipe) and
        /// storage buffers on GPUs, each where the array fits the device's limits, else device
        /// addresses; the others force one path where it fits. Same image on every path.
        #[arg(long, value_enum, default_value = "auto")]
        memory: MemoryArg,
        #[arg(long, short, default_value = "render.png")]
        out: PathBuf,
    },
    /// Print a scene's contents and the feature set its kernel is compiled with.
    Info {
        #[command(flatten)]
        scene: SceneArgs,
    },
    /// List the Vulkan devices.
    Devices,
    /// Compare the line balancers over an orbiting camera (Brigade's Table 16 for platoon).
    BalanceBench {
        #[command(flatten)]
        options: platoon::balance_bench::Options,
        /// Print the cells as JSON on stdout (the table goes to stderr).
        #[arg(long)]
        json: bool,
    },
    /// Measure samples/s, rays/s and BVH build times.
    Bench {
        /// Samples per pixel of each measured render.
        #[arg(long, default_value_t = 16)]
        spp: u32,
        #[arg(long, default_value_t = 0)]
        device: usize,
        /// Repetitions of each measurement (the median is reported).
        #[arg(long, default_value_t = 3)]
        repeat: u32,
    },
}

fn parse_balancer(s: &str) -> Result<String, String> {
    match balance::by_name(s) {
        Some(_) => Ok(s.to_string()),
        None => Err(format!(
            "unknown balancer {s}: one of {}",
            balance::NAMES.join(", ")
        )),
    }
}

fn parse_rgb(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{s}: {e}"))?;
    match v.as_slice() {
        [r, g, b] => Ok(Vec3::new(*r, *g, *b)),
        [c] => Ok(Vec3::splat(*c)),
        _ => Err(format!("{s}: expected R,G,B")),
    }
}

fn env_choice(args: &SceneArgs) -> EnvChoice {
    match (&args.env, args.env_color) {
        (Some(p), _) => EnvChoice::File(p.clone()),
        (None, Some(c)) => EnvChoice::Color(c),
        _ => EnvChoice::Scene,
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render {
            scene,
            spp,
            time_limit,
            width,
            height,
            max_depth,
            seed,
            camera,
            aperture,
            focus_distance,
            devices,
            balancer,
            sampling,
            validation,
            memory,
            out,
        } => {
            platoon::core::output::check_image_path(&out)?;
            if width == 0 || height == 0 || spp == 0 {
                bail!("--width, --height and --spp must be positive");
            }
            let loaded = scene.load()?;
            let options = PrepareOptions {
                env: env_choice(&scene),
                time: scene.time,
                camera,
                aperture_radius: aperture,
                focus_distance,
            };
            let prepared = platoon::prepare(loaded, &options)?;
            for w in &prepared.scene.warnings {
                eprintln!("warning: {w}");
            }
            if let Some(note) = &prepared.note {
                eprintln!("note: {note}");
            }
            let mut params = FrameParams::new(width, height, spp, prepared.camera);
            params.seed = seed;
            if let Some(d) = max_depth {
                params.max_depth = d.max(1);
            }
            if let Some(t) = time_limit {
                if !(t.is_finite() && t > 0.0) {
                    bail!("--time-limit must be a positive number of seconds");
                }
                params.time_limit = Some(std::time::Duration::from_secs_f64(t));
            }
            let (sampling, sampling_name) = match sampling {
                SamplingArg::Mis => (Sampling::Mis, "mis"),
                SamplingArg::Bsdf => (Sampling::Bsdf, "bsdf"),
                SamplingArg::Light => (Sampling::Light, "light"),
            };
            let mut options = platoon::devices::tracer_options(&devices, validation, sampling)?;
            for o in &mut options {
                o.memory = match memory {
                    MemoryArg::Auto => platoon::tracer::MemoryPath::Auto,
                    MemoryArg::TexelBuffers => platoon::tracer::MemoryPath::TexelBuffers,
                    MemoryArg::StorageBuffers => platoon::tracer::MemoryPath::StorageBuffers,
                    MemoryArg::DeviceAddress => platoon::tracer::MemoryPath::DeviceAddress,
                };
            }
            if options.len() > 1 && time_limit.is_some() {
                bail!("--time-limit renders on one device: bands cut at different times would break the image's independence from the device split");
            }
            let rendered = if options.len() == 1 {
                let bar = ProgressBar::new(spp as u64);
                bar.set_style(
                    ProgressStyle::with_template(
                        "{elapsed_precise} [{bar:40}] {pos}/{len} spp {msg}",
                    )
                    .unwrap(),
                );
                let r = platoon::render(&prepared, &options[0], &params, &mut |done| {
                    bar.set_position(done as u64)
                })?;
                bar.finish_and_clear();
                r
            } else {
                let policy = balance::by_name(&balancer).expect("validated by clap");
                let tracers = platoon::devices::tracers_from_options(&options, &prepared.gpu)?;
                let mut renderer = platoon::core::frame::renderer::Renderer::new(tracers, policy);
                // Bands render on their own threads without per-sample progress: show that it runs.
                let spinner = ProgressBar::new_spinner();
                spinner.set_message(format!("rendering on {} tracers", options.len()));
                spinner.enable_steady_tick(std::time::Duration::from_millis(200));
                let r = platoon::render_frame(&mut renderer, &params);
                spinner.finish_and_clear();
                let r = r?;
                for t in &r.tracers {
                    eprintln!(
                        "  tracer {}: lines {}..{} ({} rendered), {:.3} s, idle {:.3} s",
                        t.tracer,
                        t.y0,
                        t.y1,
                        t.lines,
                        t.wall_time.as_secs_f64(),
                        t.idle.as_secs_f64()
                    );
                }
                r
            };
            for m in &rendered.validation_messages {
                eprintln!("validation: {m}");
            }
            let meta = platoon::metadata(&prepared, &params, &rendered, sampling_name);
            let spp = rendered.spp;
            platoon::core::output::write_image(&out, &rendered.film, &meta)?;
            let secs = rendered.wall_time.as_secs_f64();
            eprintln!(
                "{}: {}x{} at {} spp in {:.2} s on {} ({:.2} M samples/s, {:.2} M rays/s, {} rejected samples)",
                out.display(),
                width,
                height,
                spp,
                secs,
                rendered.device,
                (width as f64 * height as f64 * spp as f64) / secs / 1e6,
                rendered.rays() as f64 / secs / 1e6,
                rendered.rejected_samples()
            );
            Ok(())
        }
        Command::Info { scene } => {
            let loaded = scene.load()?;
            let prepared = platoon::prepare(
                loaded,
                &PrepareOptions {
                    env: env_choice(&scene),
                    time: scene.time,
                    ..Default::default()
                },
            )?;
            print!("{}", platoon::bench::describe(&prepared));
            Ok(())
        }
        Command::Devices => {
            let devices = platoon::tracer::list_devices()?;
            if devices.is_empty() {
                bail!("no Vulkan devices found (install mesa-vulkan-drivers for lavapipe)");
            }
            for d in devices {
                println!(
                    "{}: {} ({}), driver {}, Vulkan {}",
                    d.index, d.name, d.device_type, d.driver, d.api_version
                );
            }
            Ok(())
        }
        Command::BalanceBench { options, json } => {
            use platoon::balance_bench::{self as bb, Mode};
            options.validate()?;
            let out = options.out.clone();
            let frames = options.frames;
            let cells = bb::run(&options)?;
            let mode_name = if options.mode == Mode::Replay {
                "replay"
            } else {
                "real"
            };
            let title =
                format!("platoon balance-bench ({mode_name}, {frames} frames): idle % per frame");
            let mut table = bb::table(&cells);
            if options.mode == Mode::Replay {
                table.push_str(&bb::interleaved_row(&options)?);
                table.push('\n');
                table.push_str(&bb::replay_scaling_row(&options)?);
                table.push('\n');
            } else {
                table.push_str("scaling efficiency, equal lavapipe:1 tracers, cost-aware (real):");
                for (n, e) in [2, 3]
                    .iter()
                    .zip(bb::real_scaling_efficiency(&options, &[2, 3])?)
                {
                    table.push_str(&format!(" {n} tracers {:.1}%", 100.0 * e));
                }
                table.push('\n');
            }
            if json {
                eprint!("{table}");
                println!("{}", bb::json(&cells));
            } else {
                print!("{table}");
            }
            platoon::core::output::write_text(&out.join("balance.csv"), &bb::csv(&cells))?;
            platoon::plot::write_png(&out.join("balance.png"), &cells, &title)?;
            eprintln!(
                "wrote {} and {}",
                out.join("balance.csv").display(),
                out.join("balance.png").display()
            );
            Ok(())
        }
        Command::Bench {
            spp,
            device,
            repeat,
        } => platoon::bench::run(spp, device, repeat.max(1)).context("bench failed"),
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

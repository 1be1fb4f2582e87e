//! `platoon`: render, inspect and benchmark scenes from the command line. Each command is one
//! file; the work is done by the `platoon` library.

mod balance_bench;
mod bench;
mod devices;
mod game_bench;
mod game_costs;
mod info;
mod method_args;
mod render;
mod scene_args;
mod tradeoff;
mod view;

use std::process::ExitCode;

use anyhow::{Context as _, Result};
use clap::{Parser, Subcommand};

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

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an EXR (linear, with metadata) or PNG (tone-mapped sRGB).
    Render(render::RenderArgs),
    /// Print a scene's contents and the feature set its kernel is compiled with.
    Info {
        #[command(flatten)]
        scene: scene_args::SceneArgs,
    },
    /// List the Vulkan devices.
    Devices,
    /// Open a window on a scene: the image converges live; fly with the mouse and WASD.
    View(view::ViewArgs),
    /// What accuracy costs in time: techniques x sample counts against a converged reference.
    Tradeoff(tradeoff::TradeoffArgs),
    /// Compare the line balancers over an orbiting camera (Brigade's Table 16 for platoon).
    BalanceBench {
        #[command(flatten)]
        options: platoon_lab::balance_bench::Options,
        /// Print the cells as JSON on stdout (the table goes to stderr).
        #[arg(long)]
        json: bool,
    },
    /// Measure samples/s, rays/s and BVH build times (--dynamic: a living scene; --game: the
    /// game loop at a target frame time).
    Bench {
        /// Samples per pixel of each measured render.
        #[arg(long, default_value_t = 16)]
        spp: u32,
        #[arg(long, default_value_t = 0)]
        device: usize,
        /// Repetitions of each measurement (the median is reported).
        #[arg(long, default_value_t = 3)]
        repeat: u32,
        /// Measure a living scene instead: walking characters and moving objects over the
        /// sphere field, double-buffered updates and commits, against the scene standing still.
        #[command(flatten)]
        dynamic: bench::DynamicArgs,
    },
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(args),
        Command::Info { scene } => info::run(scene),
        Command::Devices => devices::run(),
        Command::View(args) => view::run(args),
        Command::Tradeoff(args) => tradeoff::run(args).context("tradeoff failed"),
        Command::BalanceBench { options, json } => balance_bench::run(options, json),
        Command::Bench {
            spp,
            device,
            repeat,
            dynamic,
        } => {
            if let Some(dir) = &dynamic.record_costs {
                game_costs::record(&dynamic.character, dir).context("recording game costs failed")
            } else if dynamic.game {
                game_bench::run(&game_bench::Options {
                    frames: dynamic.frames,
                    target_ms: dynamic.target_ms,
                    width: dynamic.size.0,
                    height: dynamic.size.1,
                    devices: dynamic.devices.clone(),
                    below_one: platoon::core::drive::scaling::BelowOneSample {
                        roulette: dynamic.roulette_scaling,
                        resolution: dynamic.resolution_scaling,
                    },
                    character: dynamic.character.clone(),
                    out: dynamic.out.clone(),
                    json: dynamic.json,
                })
                .context("bench --game failed")
            } else if dynamic.dynamic {
                bench::run_dynamic(&dynamic, device).context("bench --dynamic failed")
            } else {
                bench::run(spp, device, repeat.max(1)).context("bench failed")
            }
        }
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

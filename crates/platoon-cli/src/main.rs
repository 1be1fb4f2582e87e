//! `platoon`: render, inspect and benchmark scenes from the command line. Each command is one
//! file; the work is done by the `platoon` library.

#[cfg(feature = "lab")]
mod balancer_arg;
mod bench;
mod bytes_arg;
mod devices;
mod display_args;
mod info;
mod learning_args;
mod method_args;
mod render;
mod request_args;
mod request_flags;
mod scene_args;
#[cfg(any(feature = "lab", feature = "view"))]
mod size_arg;
#[cfg(feature = "lab")]
mod tradeoff;
mod value_arg;
#[cfg(feature = "view")]
mod view;
mod warnings;
mod work_folder;

use std::process::ExitCode;

#[cfg(feature = "lab")]
use anyhow::Context as _;
use anyhow::Result;
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

// Parsed once per run: the render's arguments being the largest variant costs nothing.
#[allow(clippy::large_enum_variant)]
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
    #[cfg(feature = "view")]
    View(view::ViewArgs),
    /// What accuracy costs in time: techniques x sample counts against a converged reference.
    #[cfg(feature = "lab")]
    Tradeoff(tradeoff::TradeoffArgs),
    /// Measure platoon: the kernel, a living scene, the game loop, the line balancers.
    #[cfg(feature = "lab")]
    Bench {
        #[command(subcommand)]
        mode: bench::BenchMode,
    },
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render(args) => render::run(args),
        Command::Info { scene } => info::run(scene),
        Command::Devices => devices::run(),
        #[cfg(feature = "view")]
        Command::View(args) => view::run(args),
        #[cfg(feature = "lab")]
        Command::Tradeoff(args) => tradeoff::run(args).context("tradeoff failed"),
        #[cfg(feature = "lab")]
        Command::Bench { mode } => bench::run(mode),
    }
}

fn main() -> ExitCode {
    warnings::to_stderr();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One write: under mpirun the ranks' pieces of a line would interleave.
            use std::io::Write as _;
            let _ = std::io::stderr().write_all(format!("error: {e:#}\n").as_bytes());
            ExitCode::FAILURE
        }
    }
}

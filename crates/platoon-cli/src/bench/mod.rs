//! `platoon bench <mode>`: what platoon's speed is, one mode a file; the measuring itself is
//! platoon-lab's.

mod balance;
mod dynamic;
mod game;
mod game_costs;
mod game_error;
mod kernel;
mod realtime;
mod scale;
mod scenes;

use anyhow::{Context as _, Result};

#[derive(clap::Subcommand)]
pub enum BenchMode {
    /// Samples/s, rays/s and BVH build times of the built-in scenes, interleaved lines against
    /// one band, and BVH2 against CWBVH on the CPU.
    Kernel(kernel::KernelArgs),
    /// The bench scenes (scenes as exporters write them) as whole renders against Mitsuba 3
    /// on the same scenes and cores, when it is installed: seconds, samples/s and the ratio.
    Scenes(scenes::ScenesArgs),
    /// Scenes of production size (millions of triangles and instances, hundreds of large
    /// textures) as whole renders: load, BVH build, first pixel, host and device memory.
    Scale(scale::ScaleArgs),
    /// A living scene: walking characters and moving objects over the sphere field,
    /// double-buffered updates and commits, against the scene standing still.
    Dynamic(dynamic::DynamicArgs),
    /// The game of platoon-game at a target frame time: how closely it is held (or, with
    /// --record-costs, its per-line cost maps for `bench balance`).
    Game(game::GameArgs),
    /// The line balancers compared over an orbiting camera (Brigade's Table 16 for platoon).
    Balance(balance::BalanceArgs),
    /// A game's image at its frame budget: each real-time technique (the denoiser, resampled
    /// direct light, both) against converged renders of the same frames.
    Realtime(realtime::RealtimeArgs),
    /// Each rendering method's own bench (platoon-lab's `method`).
    #[command(flatten)]
    Method(platoon_lab::method::MethodBench),
}

pub fn run(mode: BenchMode) -> Result<()> {
    match mode {
        BenchMode::Kernel(a) => kernel::run(&a).context("bench kernel failed"),
        BenchMode::Scenes(a) => scenes::run(&a).context("bench scenes failed"),
        BenchMode::Scale(a) => scale::run(&a).context("bench scale failed"),
        BenchMode::Dynamic(a) => dynamic::run(&a).context("bench dynamic failed"),
        BenchMode::Game(a) => game::run(&a).context("bench game failed"),
        BenchMode::Balance(a) => balance::run(a),
        BenchMode::Realtime(a) => realtime::run(&a).context("bench realtime failed"),
        BenchMode::Method(m) => m.run(),
    }
}

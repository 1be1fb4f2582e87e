//! The rendering methods' own measuring, a folder each (their benches, scenes and plots, and
//! the `platoon bench NAME` command that runs them), registered in one list (`MethodBench`),
//! which the CLI's `bench` takes whole: it names no method.

pub mod lhb;
pub mod links;
pub mod scenes;

use anyhow::{Context as _, Result};

/// `platoon bench NAME` for each method with a bench of its own.
#[derive(clap::Subcommand)]
pub enum MethodBench {
    /// Vertex links' update stage by stage, links raw and compressed, first frame and frame
    /// (Schmitz et al.'s table for platoon).
    Links(links::command::LinksArgs),
    /// Layered hit buffers: the build per direction, bytes, lookups against the path tracer's
    /// rays and the break-even queries per build, over triangles, directions and resolution.
    Lhb(lhb::command::LhbArgs),
}

impl MethodBench {
    pub fn run(&self) -> Result<()> {
        match self {
            MethodBench::Links(a) => links::command::run(a).context("bench links failed"),
            MethodBench::Lhb(a) => lhb::command::run(a).context("bench lhb failed"),
        }
    }
}

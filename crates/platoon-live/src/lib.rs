//! Driving a living scene from a game (Brigade's double-buffered updates): the game edits the
//! scene ([`edit::Edit`] values, checked once and applied by [`updater::Updater::apply`] or
//! queued by [`pipeline::Pipeline::push`]), and each update poses it,
//! keeps every mesh's BVH (static meshes built once, skinned ones refitted, rebuilt only when
//! degraded), rebuilds the top level, flattens, and says what changed since the previous
//! generation as a [`platoon_core::flatten::commit::Commit`] for the tracers to apply. [`plan`] decides
//! each game frame's samples and how they join the film; [`driver::FrameDriver`] carries the
//! plan out, one call per game frame, with the tracers on their threads and the
//! [`accumulation`] film, and [`denoising`] denoises its frames over time when asked.

pub mod accumulation;
pub mod denoising;
pub mod driver;
pub mod edit;
mod finished;
pub mod gi;
pub mod pipeline;
pub mod plan;
pub mod refinement;
mod render_thread;
pub mod scaling;
pub mod threads;
pub mod updater;
pub mod walk;

pub use denoising::DenoiseStats;
pub use driver::{realtime, DriverOptions, FrameDriver};
pub use edit::Edit;
pub use finished::{FinishedFrame, FrameOutput, FrameStats};
pub use gi::{GiStats, GiUpdate};
pub use pipeline::{Pipeline, UpdaterThreads};
/// The core's CPU ray queries over a flattened scene, which a game asks of a living one.
pub use platoon_core::flatten::queries::{self, QueryHit, QueryScene};
pub use platoon_core::method::path::REALTIME_CANDIDATES;
pub use refinement::{Refinement, StaticBuild};
pub use updater::{Generation, UpdateTimes, Updater, UpdaterOptions};

#[cfg(test)]
mod queries_follow_commits;

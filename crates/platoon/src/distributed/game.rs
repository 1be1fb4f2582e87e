//! The game loop over the ranks of a job: rank 0 runs the game and its frame driver, whose
//! tracers are the ranks (`platoon_distribute::remote`): its own devices as one, each
//! other rank as one reached by messages. The driver's balancer cuts each frame between the
//! ranks, each rank's renderer cuts its band between its devices; each generation's commit
//! (what changed) and each frame's parameters travel to the ranks as the driver hands them to
//! its tracers. The other ranks get rank 0's first generation whole, then [`serve`] until
//! rank 0's driver ends.

use std::sync::Arc;

use anyhow::{bail, Context as _, Result};
use glam::DVec3;
use platoon_core::flatten::commit::Commit;
use platoon_core::flatten::GpuScene;
use platoon_core::Scene;
use platoon_distribute::method_wire::travels;
use platoon_distribute::remote::{serve as serve_bands, LocalRank, RankTracer, RemoteRank};
use platoon_distribute::wire::{self, Reader, Writer};
use platoon_live::queries::QueryScene;
use platoon_live::{FrameDriver, Pipeline};
use platoon_schedule::renderer::Renderer;
use platoon_tracer::Sampling;

use super::Ranks;
use crate::devices::{create_tracers, DeviceSpec};
use crate::game::GameOptions;

/// Rank 0's frame driver over the ranks (every rank's tracers on its `options.devices`).
pub fn start(scene: Scene, options: &GameOptions, ranks: &Ranks) -> Result<FrameDriver> {
    let session = &ranks.0;
    if session.rank() != 0 {
        bail!("only rank 0 runs the game; the others serve it (platoon::distributed::game::serve)");
    }
    travels(&options.driver.method).map_err(anyhow::Error::msg)?;
    let link = session.link()?;
    let (pipeline, first) =
        Pipeline::with_updater_threads(scene, options.time, DVec3::ZERO, &options.updater)?;
    // The other ranks hold no scene yet: the first generation, whole.
    let mut w = Writer::default();
    wire::put_commit(&mut w, &Commit::between(&GpuScene::default(), &first));
    session.broadcast(w.0);
    let local = create_tracers(&options.devices, &first, options.validation, Sampling::Mis)?;
    let mut tracers = vec![RankTracer::Local(LocalRank(Renderer::new(
        local,
        crate::devices::balancer(&options.balancer)?,
    )))];
    for rank in 1..session.size() {
        tracers.push(RankTracer::Remote(RemoteRank::new(link.clone(), rank)));
    }
    Ok(FrameDriver::new(
        pipeline,
        &first,
        tracers,
        crate::devices::balancer(&options.balancer)?,
        options.driver.clone(),
    )?)
}

/// Another rank's part in rank 0's game: its devices (`devices`, split by `balancer`) hold
/// rank 0's first generation and render the bands rank 0 sends until its driver ends.
pub fn serve(ranks: &Ranks, devices: &DeviceSpec, balancer: &str, validation: bool) -> Result<()> {
    let session = &ranks.0;
    let rank = session.rank();
    let link: Arc<dyn platoon_distribute::remote::Link> = session.link()?;
    let bytes = session.broadcast(Vec::new());
    let mut r = Reader::new(&bytes);
    let commit =
        wire::get_commit(&mut r).with_context(|| format!("rank {rank}: the first scene"))?;
    r.finish()?;
    let mut scene = QueryScene::new(&GpuScene::default());
    scene.apply_commit(&commit);
    let scene = scene.scene();
    let tracers = create_tracers(devices, &scene, validation, Sampling::Mis)
        .with_context(|| format!("rank {rank}: creating its devices"))?;
    let mut renderer = Renderer::new(tracers, crate::devices::balancer(balancer)?);
    serve_bands(&mut renderer, link.as_ref()).with_context(|| format!("rank {rank}: serving"))?;
    Ok(())
}

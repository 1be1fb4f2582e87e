//! Rendering a prepared frame through the core's renderer, on one tracer or many (one renders
//! the frame as one band on its worker thread, the same path as many), and what it cost.
//! `render_bands` renders chosen bands on one tracer directly: the tests' and benches' tool.

use std::rc::Rc;
use std::sync::Arc;

use anyhow::{Context as _, Result};
use platoon_core::flatten::commit::Commit;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::{Band, FrameParams, Span};
use platoon_distribute::{Collective, RankFrame, RankRenderer};
use platoon_schedule::renderer::{frame_of, FrameResult, PartResult, Renderer};
use platoon_tracer::{Tracer, TracerOptions};

use crate::rendered::{pack, Devices, Measured};
pub use crate::rendered::{BatchedStats, Rendered};
use crate::Prepared;

/// Renders the frame on one tracer as the given bands (one band covering the frame is usual),
/// assembled as the renderer assembles its tracers' bands (`frame_of`).
pub fn render_bands(
    tracer: &mut Tracer,
    params: &FrameParams,
    bands: &[Span],
    progress: &mut dyn FnMut(u32),
) -> Result<Rendered> {
    let mut out: Vec<Band> = Vec::new();
    for &span in bands {
        out.push(
            tracer
                .render_span(params, span, progress)
                .context("render failed")?,
        );
    }
    let (wall_time, gpu_time, rays) = (
        out.iter().map(|b| b.wall_time).sum(),
        out.iter().map(|b| b.gpu_time).sum(),
        out.iter().map(|b| b.rays).sum(),
    );
    let part = PartResult {
        bands: out,
        ..Default::default()
    };
    let frame = frame_of(params, part, std::time::Instant::now());
    let measured = Measured {
        film: frame.film,
        sums: frame.sums,
        spp: frame.spp,
        wall_time,
        gpu_time,
        rays,
        rejected_samples: frame.rejected_samples,
        kernel_fallbacks: frame.kernel_fallbacks,
        method_report: frame.method_report,
        tracers: Vec::new(),
    };
    let devices = Devices {
        names: vec![tracer.device_info().name.clone()],
        kernel_defines: tracer.kernel_defines(params),
        traversals: vec![tracer.traversal().name()],
        balancer: None,
        validation_messages: tracer.validation_messages(),
    };
    Ok(pack(params, measured, devices))
}

/// Renders a prepared scene on one device (after the method's preparation, when it has one:
/// vertex links' update), through the renderer as `Tracers` renders.
pub fn render(
    prepared: &Prepared,
    options: &TracerOptions,
    params: &FrameParams,
    progress: &mut dyn FnMut(u32),
) -> Result<Rendered> {
    let mut tracers = Tracers::new(std::slice::from_ref(options), ONE_DEVICE, &prepared.gpu)?;
    tracers.render(&prepared.gpu, params, progress)
}

/// The balancer a single device is given: it cuts nothing (one band is the frame), but a
/// renderer has one.
const ONE_DEVICE: &str = "none";

/// The band covering the whole frame.
pub fn whole_frame(params: &FrameParams) -> Span {
    Span::lines(params.width, 0, params.height)
}

/// Renders one frame on a multi-device renderer.
pub fn render_frame(renderer: &mut Renderer<Tracer>, params: &FrameParams) -> Result<Rendered> {
    render_on(renderer, params, &mut |_| {})
}

/// Renders one frame on `renderer`; `progress` hears the samples done when it has one tracer.
/// A single device's frame reports no split (no per-tracer statistics, no balancer), as
/// nothing was split.
fn render_on(
    renderer: &mut Renderer<Tracer>,
    params: &FrameParams,
    progress: &mut dyn FnMut(u32),
) -> Result<Rendered> {
    let frame = renderer.render_frame_with_progress(params, progress)?;
    for f in &frame.failures {
        log::warn!("tracer {} failed in frame {} and was dropped; its lines were rendered by the others: {}", f.tracer, f.frame, f.message);
    }
    let mut rendered = rendered_of(renderer, params, frame);
    if rendered.tracers.len() == 1 {
        rendered.tracers.clear();
        rendered.balancer = None;
    }
    Ok(rendered)
}

/// A frame of `renderer` as the facade reports it: its devices, kernel, balancer and what
/// they measured.
fn rendered_of(renderer: &Renderer<Tracer>, params: &FrameParams, frame: FrameResult) -> Rendered {
    let defines = renderer
        .with_tracers(|t| t.kernel_defines(params))
        .into_iter()
        .next()
        .unwrap_or_default();
    let measured = Measured {
        wall_time: frame
            .tracers
            .iter()
            .map(|t| t.wall_time)
            .max()
            .unwrap_or_default(),
        gpu_time: frame.tracers.iter().map(|t| t.gpu_time).sum(),
        rays: frame.tracers.iter().map(|t| t.rays).sum(),
        rejected_samples: frame.rejected_samples,
        kernel_fallbacks: frame.kernel_fallbacks,
        spp: frame.spp,
        method_report: frame.method_report,
        tracers: frame.tracers,
        film: frame.film,
        sums: frame.sums,
    };
    let devices = Devices {
        names: renderer.with_tracers(|t| t.device_info().name.clone()),
        kernel_defines: defines,
        traversals: renderer.with_tracers(|t| t.traversal().name()),
        balancer: Some(renderer.balancer_name()),
        validation_messages: renderer.with_tracers(|t| t.validation_messages()).concat(),
    };
    pack(params, measured, devices)
}

/// A frame over the ranks as the facade reports it: rank 0's devices, kernel and balancer,
/// the ranks' parts and what crossed between them.
fn ranks_rendered(r: &RankRenderer<Tracer>, params: &FrameParams, frame: RankFrame) -> Rendered {
    let RankFrame {
        frame,
        ranks: parts,
        communication,
        ..
    } = frame;
    let wall_time = frame.wall_time;
    let rendered = rendered_of(r.local(), params, frame);
    Rendered {
        // Rank 0's frame, its exchanges included (the ranks' own times are in `tracers`).
        wall_time,
        device: format!("{} ranks; rank 0: {}", r.ranks(), rendered.device),
        ranks: Some(crate::distributed::RanksReport {
            ranks: r.ranks(),
            balancer: r.balancer_name(),
            parts,
            communication,
        }),
        ..rendered
    }
}

/// The devices a render runs on: this process's, one or several under the renderer's balancer
/// (one renders the frame as one band), or a rank's in a job of several processes. Created
/// once; an animation brings them from frame to frame with the updater's commits.
pub enum Tracers {
    Local(Renderer<Tracer>),
    /// This rank's devices in a job of several processes (`crate::distributed`): every call
    /// is a collective operation of the ranks.
    Ranks(Box<RankRenderer<Tracer>>),
}

impl Tracers {
    /// This rank's tracers for `options` holding `scene`, in the job `group`: `balancer` (a
    /// name `platoon_core::balance::by_name` knows) cuts frames between the ranks on rank 0
    /// and between each rank's devices. With `+steal` each rank's devices steal from each
    /// other; the ranks' shares, cut before the frame and sent in one scatter, are not stolen
    /// across ranks (the game loop's ranks are: `distribute::remote`).
    pub fn over_ranks(
        options: &[TracerOptions],
        balancer: &str,
        scene: &GpuScene,
        group: Rc<dyn Collective>,
    ) -> Result<Tracers> {
        let rank = group.rank();
        let tracers = crate::devices::tracers_from_options(options, scene)
            .with_context(|| format!("rank {rank}: creating its devices"))?;
        let local = Renderer::new(tracers, crate::devices::balancer(balancer)?);
        let ranks = RankRenderer::new(local, group, crate::devices::balancer(balancer)?);
        Ok(Tracers::Ranks(Box::new(ranks)))
    }
}

/// A device denoiser runs on the first tracer of this process (rank 0's, over ranks).
impl platoon_core::denoise::DeviceFilter for Tracers {
    fn atrous(
        &mut self,
        film: &platoon_core::output::Film,
        guides: &platoon_core::denoise::Guides,
    ) -> std::result::Result<platoon_core::output::Film, String> {
        match self {
            Tracers::Local(r) => r.filter_atrous(film, guides),
            Tracers::Ranks(r) => r.local().filter_atrous(film, guides),
        }
    }
}

impl Tracers {
    /// Tracers for `options` (one per entry) holding `scene`; `balancer` splits the lines
    /// when there are several (a name `platoon_core::balance::by_name` knows).
    pub fn new(options: &[TracerOptions], balancer: &str, scene: &GpuScene) -> Result<Tracers> {
        Tracers::of(
            crate::devices::tracers_from_options(options, scene)?,
            balancer,
        )
    }

    /// The tracers of a still of `method` with `aovs`, holding `scene`. A method that reads
    /// the scene on its devices only (`RenderMethod::reads_scene_on_host`: the path tracer's)
    /// lets `scene` give up its host copy of each large array once every tracer holds it
    /// (`Tracer::new_releasing`), so a big scene is not held twice; the others (links and LHB
    /// read it on the host) and motion vectors (the frame's geometry) keep it.
    pub fn for_still(
        options: &[TracerOptions],
        balancer: &str,
        scene: &mut GpuScene,
        method: &platoon_core::method::Method,
        aovs: &[platoon_core::frame::aov::Aov],
    ) -> Result<Tracers> {
        let host = method.unit().reads_scene_on_host();
        if host || aovs.contains(&platoon_core::frame::aov::Aov::Motion) {
            return Tracers::new(options, balancer, scene);
        }
        let tracers =
            Tracer::new_releasing(options, scene).context("creating the devices' tracers")?;
        Tracers::of(tracers, balancer)
    }

    /// The tracers under a renderer splitting lines by `balancer` (one alone renders the
    /// whole frame on its worker thread).
    fn of(tracers: Vec<Tracer>, balancer: &str) -> Result<Tracers> {
        let policy = crate::devices::balancer(balancer)?;
        Ok(Tracers::Local(Renderer::new(tracers, policy)))
    }

    /// The devices rendering in this process.
    pub fn count(&self) -> usize {
        match self {
            Tracers::Local(r) => r.alive().len(),
            Tracers::Ranks(r) => r.local().alive().len(),
        }
    }

    /// Device memory each tracer of this process holds, in bytes.
    pub fn device_bytes(&self) -> Vec<u64> {
        match self {
            Tracers::Local(r) => r.with_tracers(|t| t.device_bytes()),
            Tracers::Ranks(r) => r.local().with_tracers(|t| t.device_bytes()),
        }
    }

    /// The processes rendering each frame (1 unless over the ranks of a job).
    pub fn ranks(&self) -> usize {
        match self {
            Tracers::Ranks(r) => r.ranks(),
            _ => 1,
        }
    }

    /// This process's rank in its job (0 when alone): rank 0 gets the images.
    pub fn rank(&self) -> usize {
        match self {
            Tracers::Ranks(r) => r.rank(),
            _ => 0,
        }
    }

    /// Brings every tracer to the generation `commit` was made for.
    pub fn apply_commit(&mut self, commit: &Arc<Commit>, frame: u32) -> Result<()> {
        match self {
            Tracers::Local(r) => {
                r.apply_commit(commit, frame)
                    .context("uploading the frame's changes")?;
            }
            Tracers::Ranks(r) => {
                r.apply_commit(commit, frame)
                    .context("sending and uploading the frame's changes")?;
            }
        }
        Ok(())
    }

    /// Renders a frame of `scene` (the scene the tracers hold) after the method's preparation;
    /// `progress` hears the samples done (one tracer only: several render at once).
    pub fn render(
        &mut self,
        scene: &GpuScene,
        params: &FrameParams,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Rendered> {
        match self {
            Tracers::Local(r) => {
                params
                    .check_split(r.alive().len())
                    .map_err(anyhow::Error::msg)?;
                let params = crate::method_update::on_renderer(r, scene, params)?;
                render_on(r, &params, progress)
            }
            Tracers::Ranks(r) => {
                let (params, frame) = crate::distributed::render(r, scene, params)?;
                Ok(ranks_rendered(r, &params, frame))
            }
        }
    }
}

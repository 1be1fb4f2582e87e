//! A frame rendered in batches of samples, each continuing the sums of the ones before
//! (`platoon_core::frame::adaptive`): adaptive sampling and the variance AOV. Each batch is a
//! frame on the tracers like any other, so the bits are the same for any split; with neither
//! asked for, one frame.

use anyhow::{bail, Result};
use platoon_core::frame::adaptive::{Batched, Batching};
use platoon_core::frame::FrameParams;

use crate::render::BatchedStats;
use crate::{Rendered, Tracers};

impl Tracers {
    /// Renders the frame `params` of `scene` in the batches `batching` asks for; `progress`
    /// hears the samples done of the frame's `spp`.
    pub fn render_batched(
        &mut self,
        scene: &platoon_core::flatten::GpuScene,
        params: &FrameParams,
        batching: &Batching,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Rendered> {
        render(
            &mut |p, progress| self.render(scene, p, progress),
            params,
            batching,
            progress,
        )
    }
}

/// Renders a frame, telling `progress` the samples done.
pub type RenderFn<'a> = dyn FnMut(&FrameParams, &mut dyn FnMut(u32)) -> Result<Rendered> + 'a;

/// The same with each batch rendered by `render` (a bare tracer's, for the lab).
pub fn render(
    render: &mut RenderFn,
    params: &FrameParams,
    batching: &Batching,
    progress: &mut dyn FnMut(u32),
) -> Result<Rendered> {
    if !batching.is_some() {
        return render(params, progress);
    }
    check(params, batching)?;
    let mut state = Batched::new(params.width, params.height);
    let mut total: Option<Rendered> = None;
    for batch in batching.batches(params.spp, params.samples_per_pass) {
        let p = state.params(params, &batch);
        let mut r = render(&p, &mut |done| progress(batch.begin + done))?;
        // The frame's sums are the state's from here on (the result's are set at the end).
        state.join(&batch, std::mem::take(&mut r.sums));
        if batch.check {
            if let Some(a) = &batching.adaptive {
                state.check(a.threshold);
            }
        }
        total = Some(match total {
            None => r,
            Some(t) => Rendered {
                wall_time: t.wall_time + r.wall_time,
                gpu_time: t.gpu_time + r.gpu_time,
                rays: t.rays + r.rays,
                rejected_samples: t.rejected_samples + r.rejected_samples,
                kernel_fallbacks: t.kernel_fallbacks + r.kernel_fallbacks,
                ..r
            },
        });
    }
    let mut rendered = total.expect("a frame has at least one sample");
    rendered.film = state.film();
    rendered.sums = state.sums();
    rendered.spp = params.spp;
    rendered.batched = Some(BatchedStats {
        adaptive: batching.adaptive,
        samples: state.samples().to_vec(),
        variance: batching.variance.then(|| state.variance()),
    });
    Ok(rendered)
}

fn check(params: &FrameParams, batching: &Batching) -> Result<()> {
    if params.film.accumulated.is_some() {
        bail!("a frame rendered in batches starts its own sums: it cannot continue others");
    }
    if params.options.time_limit.is_some() {
        bail!("adaptive sampling and the variance AOV take every batch: no time limit with them");
    }
    if params.spp < 2 {
        bail!("adaptive sampling and the variance AOV need at least 2 samples per pixel");
    }
    if let Some(a) = &batching.adaptive {
        a.validate(params.spp, &params.method)
            .map_err(anyhow::Error::msg)?;
    }
    Ok(())
}

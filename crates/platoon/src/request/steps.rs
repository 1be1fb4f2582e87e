//! A render's steps, each a call of its request: the scene prepared ([`Request::prepare`],
//! [`Request::load_and_prepare`]),
//! the tracers holding it ([`Request::tracers`], [`Request::still_tracers`]), the frame
//! rendered in the batches its outputs need ([`Request::render_frame`]) and its outputs made
//! ([`Request::outputs`]). [`Request::render`] and [`crate::Progressive`] run them; so do the
//! CLI's still, its animations and its farm, which add what is theirs between them (a stage's
//! spinner, a checkpoint, an animation's updates, files), so no caller makes a frame's outputs
//! its own way.

use std::rc::Rc;

use anyhow::Result;
use platoon_core::flatten::GpuScene;
use platoon_core::frame::aov::Aov;
use platoon_core::frame::FrameParams;
use platoon_core::scene::Scene;

use super::form::Request;
use super::still::{FrameScene, Still};
use crate::animation::Animation;
use crate::distributed::Session;
use crate::{Prepared, Rendered, SceneFacts, Tracers};

/// The scene of a rendered frame as its outputs read it: flattened (`gpu`), what the metadata
/// says of it (`facts`), and the scene graph at `time`, which motion vectors pose again
/// `interval` seconds before.
pub struct FrameShown<'a> {
    pub gpu: &'a GpuScene,
    pub facts: SceneFacts<'a>,
    pub scene: &'a Scene,
    pub time: f32,
    pub interval: f32,
}

impl Prepared {
    /// This scene as a frame shows it, the frame before `interval` seconds earlier.
    pub fn shown(&self, interval: f32) -> FrameShown<'_> {
        FrameShown {
            gpu: &self.gpu,
            facts: self.facts(),
            scene: &self.scene,
            time: self.time,
            interval,
        }
    }
}

impl Animation {
    /// The scene at the current time as a frame shows it, the frame before `interval`
    /// seconds earlier.
    pub fn shown(&self, interval: f32) -> FrameShown<'_> {
        FrameShown {
            gpu: self.scene(),
            facts: self.facts(),
            scene: self.graph(),
            time: self.time(),
            interval,
        }
    }
}

impl Request {
    /// `scene` lit, posed at the request's time, flattened and its BVHs built, seen by the
    /// request's camera (a camera named that the scene lacks is refused, naming `camera`).
    pub fn prepare(&self, scene: Scene) -> Result<Prepared> {
        let options = self.prepare_options(&scene)?;
        crate::prepare(scene, &options)
    }

    /// The request's scene read and prepared for a render in this process, its warnings and
    /// its note logged: where a still and a progressive render start.
    pub fn load_and_prepare(&self) -> Result<Prepared> {
        let prepared = self.prepare(self.load_scene()?)?;
        for w in &prepared.scene.warnings {
            log::warn!("{w}");
        }
        if let Some(note) = &prepared.note {
            log::info!("{note}");
        }
        Ok(prepared)
    }

    /// The tracers holding `gpu` on the request's devices; with `ranks`, a frame's bands split
    /// between the devices of a job's ranks (`Tracers::over_ranks`).
    pub fn tracers(&self, gpu: &GpuScene, ranks: Option<Rc<dyn Session>>) -> Result<Tracers> {
        let options = self.tracer_options()?;
        match ranks {
            Some(ranks) => Tracers::over_ranks(&options, &self.balancer, gpu, ranks),
            None => Tracers::new(&options, &self.balancer, gpu),
        }
    }

    /// The tracers of a still: those of [`Request::tracers`], and without ranks ones that may
    /// take the scene's large arrays off the host where the method reads them on its devices
    /// only (`Tracers::for_still`; ranks keep them, as a job's exchanges may read them).
    pub fn still_tracers(
        &self,
        gpu: &mut GpuScene,
        ranks: Option<Rc<dyn Session>>,
    ) -> Result<Tracers> {
        if ranks.is_some() {
            return self.tracers(gpu, ranks);
        }
        let options = self.tracer_options()?;
        Tracers::for_still(&options, &self.balancer, gpu, &self.method, &self.aovs)
    }

    /// The frame `params` of `gpu` rendered on `tracers` in the batches the request's outputs
    /// need (adaptive sampling, the variance AOV); `progress` hears the samples done (one
    /// tracer; several render on their own threads).
    pub fn render_frame(
        &self,
        tracers: &mut Tracers,
        gpu: &GpuScene,
        params: &FrameParams,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Rendered> {
        tracers.render_batched(gpu, params, &self.batching(), progress)
    }

    /// The outputs of `rendered`, the frame `params` of `shown` on `tracers`: the AOVs asked
    /// for and the denoiser's guides rendered on the same tracers (motion measured against
    /// the frame `shown.interval` before), the image denoised, and the metadata (the
    /// render's, then `more`: what the caller adds, such as its files or an animation's frame).
    pub fn outputs(
        &self,
        tracers: &mut Tracers,
        shown: &FrameShown,
        params: &FrameParams,
        rendered: Rendered,
        more: Vec<(String, String)>,
    ) -> Result<Still> {
        let mut meta = crate::metadata_of(&shown.facts, params, &rendered, self.sampling.name());
        meta.extend(more);
        // The frame before, posed again only when motion vectors are asked for.
        let previous = match self.aovs.contains(&Aov::Motion) {
            true => Some(crate::motion::previous_frame(
                shown.scene,
                &self.prepare_options(shown.scene)?,
                &self.camera,
                shown.time - shown.interval,
                shown.facts.origin,
            )?),
            false => None,
        };
        let scene = FrameScene {
            gpu: shown.gpu,
            origin: shown.facts.origin,
            previous: previous.as_ref(),
        };
        let still = Still::of(tracers, &scene, params, rendered, &self.aovs, self.denoiser)?;
        Ok(still.with_metadata(meta))
    }
}

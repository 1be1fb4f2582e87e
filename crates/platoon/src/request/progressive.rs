//! A render that goes on: the request's scene prepared and its tracers made once, each call
//! adding samples to the film. The film continues its sums in sample order, so after any
//! number of calls it holds the same bits as one render of all their samples. A call stopped
//! early (`platoon_tracer::stop`, Ctrl-C) keeps none of its samples: its bands would hold
//! uneven counts, which a film continued in sample order cannot take.

use std::sync::Arc;
use std::time::Duration;

use anyhow::Result;
use platoon_core::frame::FrameParams;

use super::error::{Interrupted, RequestError};
use super::form::Request;
use super::still::Still;
use crate::{Prepared, Tracers};

pub struct Progressive {
    request: Request,
    prepared: Prepared,
    tracers: Tracers,
    /// The samples of every pixel so far, summed, and how many.
    sums: Option<Arc<[[f32; 3]]>>,
    spp: u32,
    /// The device time of every call so far.
    wall_time: Duration,
}

impl Progressive {
    /// The request's scene prepared on its devices, no sample taken yet. Its `spp` is not
    /// used (each `add` says how many); adaptive sampling, the variance AOV and a time limit
    /// are a single render's.
    pub fn new(request: Request) -> Result<Progressive> {
        let request = Request {
            spp: request.spp.max(1),
            ..request
        };
        request.validate()?;
        request.refuse_frame_to_frame()?;
        for (option, set) in [
            ("adaptive", request.adaptive.is_some()),
            ("aovs", request.batching().variance),
            ("time_limit", request.frame.time_limit.is_some()),
        ] {
            if set {
                return Err(RequestError {
                    option,
                    problem: "a single render's: a progressive render adds the samples it is \
                              asked for"
                        .into(),
                }
                .into());
            }
        }
        let prepared = request.load_and_prepare()?;
        let tracers = request.tracers(&prepared.gpu, None)?;
        Ok(Progressive {
            request,
            prepared,
            tracers,
            sums: None,
            spp: 0,
            wall_time: Duration::ZERO,
        })
    }

    /// Samples per pixel so far.
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// The frame of all the samples so far (its AOVs rendered at that count).
    fn params(&self) -> FrameParams {
        let mut p = self
            .request
            .frame_params(self.request.camera_in(&self.prepared));
        p.spp = self.spp;
        p
    }

    /// Adds `spp` samples to every pixel; the still of all of them so far. A stop asked for
    /// while it renders (`platoon_tracer::stop::request`) ends it with [`Interrupted`] and
    /// the film as it was.
    pub fn add(&mut self, spp: u32, progress: &mut dyn FnMut(u32)) -> Result<Still> {
        if spp == 0 {
            return Err(RequestError {
                option: "spp",
                problem: "must be positive".into(),
            }
            .into());
        }
        let mut more = self.params();
        more.spp = spp;
        more.first_sample = self.spp;
        more.film.accumulated = self.sums.clone();
        let mut rendered = self.tracers.render(&self.prepared.gpu, &more, progress)?;
        if platoon_tracer::stop::requested() {
            return Err(Interrupted.into());
        }
        self.spp += spp;
        self.wall_time += rendered.wall_time;
        rendered.average_over(self.spp);
        self.sums = Some(rendered.sums.clone().into());
        rendered.wall_time = self.wall_time;
        let params = self.params();
        let shown = self.prepared.shown(self.request.frame_interval);
        self.request
            .outputs(&mut self.tracers, &shown, &params, rendered, Vec::new())
    }
}

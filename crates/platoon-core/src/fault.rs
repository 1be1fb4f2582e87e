//! Fault injection: a tracer wrapper that fails from a given frame on, as a lost device would.

use crate::frame::{Band, BandTracer, FrameParams, TracerError};

pub struct FailingTracer<T> {
    pub inner: T,
    /// First frame (FrameParams::frame) on which every call fails.
    pub fail_from_frame: u32,
}

impl<T: BandTracer> BandTracer for FailingTracer<T> {
    fn render_band(
        &mut self,
        params: &FrameParams,
        y0: u32,
        y1: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        if params.frame >= self.fail_from_frame {
            return Err(format!("injected fault at frame {}", params.frame).into());
        }
        self.inner.render_band(params, y0, y1, progress)
    }
}

/// Lets a renderer hold tracers of which some are wrapped for fault injection.
pub enum MaybeFailing<T> {
    Plain(T),
    Failing(FailingTracer<T>),
}

impl<T: BandTracer> BandTracer for MaybeFailing<T> {
    fn render_band(
        &mut self,
        params: &FrameParams,
        y0: u32,
        y1: u32,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        match self {
            MaybeFailing::Plain(t) => t.render_band(params, y0, y1, progress),
            MaybeFailing::Failing(t) => t.render_band(params, y0, y1, progress),
        }
    }
}

//! Fault injection: a tracer wrapper that, when told to, fails from a given frame on, as a lost
//! device would. Healthy and failing tracers are the same type, so one renderer holds both.

use crate::frame::{Band, BandTracer, FrameParams, Span, TracerError};

pub struct FaultInjector<T> {
    pub inner: T,
    /// First frame (FrameParams::frame) on which every call fails; None: never fails.
    pub fail_from_frame: Option<u32>,
    /// Bands it renders before every later call fails (a device lost within a frame's work,
    /// e.g. midway through an update of several device frames); None: no such limit.
    pub fail_after_bands: Option<u32>,
    bands: u32,
}

impl<T> FaultInjector<T> {
    pub fn healthy(inner: T) -> Self {
        FaultInjector {
            inner,
            fail_from_frame: None,
            fail_after_bands: None,
            bands: 0,
        }
    }
    pub fn failing_from(inner: T, frame: u32) -> Self {
        FaultInjector {
            fail_from_frame: Some(frame),
            ..Self::healthy(inner)
        }
    }
    pub fn failing_after_bands(inner: T, bands: u32) -> Self {
        FaultInjector {
            fail_after_bands: Some(bands),
            ..Self::healthy(inner)
        }
    }
}

impl<T: BandTracer> BandTracer for FaultInjector<T> {
    fn render_band(
        &mut self,
        params: &FrameParams,
        span: Span,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        if self.fail_from_frame.is_some_and(|f| params.frame >= f) {
            return Err(format!("injected fault at frame {}", params.frame).into());
        }
        if self.fail_after_bands.is_some_and(|n| self.bands >= n) {
            return Err(format!("injected fault after {} bands", self.bands).into());
        }
        self.bands += 1;
        self.inner.render_band(params, span, progress)
    }

    fn apply_commit(
        &mut self,
        commit: &crate::flatten::commit::Commit,
    ) -> Result<u64, TracerError> {
        self.inner.apply_commit(commit)
    }
    fn messages(&self) -> Vec<String> {
        self.inner.messages()
    }
}

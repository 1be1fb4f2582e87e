//! Fault injection: a tracer wrapper that, when told to, fails from a given frame on, as a lost
//! device would. Healthy and failing tracers are the same type, so one renderer holds both.

use crate::frame::{Band, BandTracer, FrameParams, Span, TracerError};

pub struct FaultInjector<T> {
    pub inner: T,
    /// First frame (FrameParams::frame) on which every call fails; None: never fails.
    pub fail_from_frame: Option<u32>,
}

impl<T> FaultInjector<T> {
    pub fn healthy(inner: T) -> Self {
        FaultInjector {
            inner,
            fail_from_frame: None,
        }
    }
    pub fn failing_from(inner: T, frame: u32) -> Self {
        FaultInjector {
            inner,
            fail_from_frame: Some(frame),
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

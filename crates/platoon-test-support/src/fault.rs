//! Fault injection: a tracer wrapper that, when told to, fails from a given frame on, as a lost
//! device would. Healthy and failing tracers are the same type, so one renderer holds both.

use platoon_frame::frame::{Band, BandTracer, Span, TracerError, ValidatedFrame};

pub struct FaultInjector<T> {
    pub inner: T,
    /// First frame (FrameParams::frame) on which every call fails; None: never fails.
    pub fail_from_frame: Option<u32>,
    /// Bands it renders before every later call fails (a device lost within a frame's work,
    /// e.g. midway through an update of several device frames); None: no such limit.
    pub fail_after_bands: Option<u32>,
    /// The band within a frame (0: the first it renders of that frame) at which every later
    /// call fails: with stealing, 1 is the first piece a tracer claims after its head (a
    /// device lost while it holds a chunk); None: no such limit.
    pub fail_at_band_of_frame: Option<u32>,
    bands: u32,
    /// (frame, bands rendered of it).
    of_frame: (u32, u32),
}

impl<T> FaultInjector<T> {
    pub fn healthy(inner: T) -> Self {
        FaultInjector {
            inner,
            fail_from_frame: None,
            fail_after_bands: None,
            fail_at_band_of_frame: None,
            bands: 0,
            of_frame: (u32::MAX, 0),
        }
    }
    /// `tracers`, all healthy but the one at `slot`, which `fault` makes fail.
    pub fn one_failing(tracers: Vec<T>, slot: usize, fault: impl FnOnce(T) -> Self) -> Vec<Self> {
        let mut fault = Some(fault);
        tracers
            .into_iter()
            .enumerate()
            .map(|(i, t)| match fault.take_if(|_| i == slot) {
                Some(fault) => fault(t),
                None => Self::healthy(t),
            })
            .collect()
    }
    pub fn failing_at_band_of_frame(inner: T, band: u32) -> Self {
        FaultInjector {
            fail_at_band_of_frame: Some(band),
            ..Self::healthy(inner)
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
        params: &ValidatedFrame,
        span: Span,
        progress: &mut dyn FnMut(u32),
    ) -> Result<Band, TracerError> {
        if self.fail_from_frame.is_some_and(|f| params.frame >= f) {
            return Err(format!("injected fault at frame {}", params.frame).into());
        }
        if self.fail_after_bands.is_some_and(|n| self.bands >= n) {
            return Err(format!("injected fault after {} bands", self.bands).into());
        }
        if self.of_frame.0 != params.frame {
            self.of_frame = (params.frame, 0);
        }
        if let Some(k) = self.fail_at_band_of_frame {
            if self.of_frame.1 >= k {
                self.fail_from_frame = Some(params.frame);
                return Err(format!("injected fault at band {k} of frame {}", params.frame).into());
            }
        }
        self.of_frame.1 += 1;
        self.bands += 1;
        self.inner.render_band(params, span, progress)
    }

    fn apply_commit(
        &mut self,
        commit: &platoon_frame::flatten::commit::Commit,
    ) -> Result<u64, TracerError> {
        self.inner.apply_commit(commit)
    }
    fn messages(&self) -> Vec<String> {
        self.inner.messages()
    }
}

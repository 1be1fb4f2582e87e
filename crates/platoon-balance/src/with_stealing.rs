//! Any balancing policy with in-frame stealing (`balance::STEALING_NAMES`).

use super::{Balancer, FrameMeasure, Stealing};
use crate::Span;

/// A balancing policy whose renderer steals (`balance::STEALING_NAMES`): it plans and learns
/// as `inner` does.
pub struct WithStealing {
    pub inner: Box<dyn Balancer>,
    pub name: &'static str,
    pub stealing: Stealing,
}

impl Balancer for WithStealing {
    fn name(&self) -> &'static str {
        self.name
    }
    fn plan(&mut self, width: u32, height: u32, tracers: usize) -> Vec<Span> {
        self.inner.plan(width, height, tracers)
    }
    fn observe(&mut self, frame: &FrameMeasure) {
        self.inner.observe(frame)
    }
    fn remove_tracer(&mut self, index: usize) {
        self.inner.remove_tracer(index)
    }
    fn stealing(&self) -> Option<Stealing> {
        Some(self.stealing)
    }
}

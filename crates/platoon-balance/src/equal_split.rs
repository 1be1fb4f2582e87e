//! Brigade's "none": every tracer gets the same number of lines.

use super::{line_bands, proportional, Balancer, FrameMeasure};
use crate::Span;

pub struct EqualSplit;

impl Balancer for EqualSplit {
    fn name(&self) -> &'static str {
        "none"
    }
    fn plan(&mut self, width: u32, height: u32, tracers: usize) -> Vec<Span> {
        line_bands(width, &proportional(height, &vec![1.0; tracers]))
    }
    fn observe(&mut self, _: &FrameMeasure) {}
    fn remove_tracer(&mut self, _: usize) {}
}

//! Brigade's "none": every tracer gets the same number of lines.

use super::{proportional, Balancer, FrameMeasure};

pub struct EqualSplit;

impl Balancer for EqualSplit {
    fn name(&self) -> &'static str {
        "none"
    }
    fn plan(&mut self, height: u32, tracers: usize) -> Vec<u32> {
        proportional(height, &vec![1.0; tracers])
    }
    fn observe(&mut self, _: &FrameMeasure) {}
    fn remove_tracer(&mut self, _: usize) {}
}

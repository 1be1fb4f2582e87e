//! Brigade's "Perfect": each tracer's share from its speed (lines per second) in the previous
//! frame. Ignores that lines differ in cost, so it overshoots when a band's content changes.

use super::{line_bands, line_speeds, proportional, Balancer, FrameMeasure};
use crate::Span;

#[derive(Default)]
pub struct Perfect {
    speeds: Vec<f64>,
}

impl Balancer for Perfect {
    fn name(&self) -> &'static str {
        "perfect"
    }
    fn plan(&mut self, width: u32, height: u32, tracers: usize) -> Vec<Span> {
        if self.speeds.len() != tracers {
            self.speeds = vec![1.0; tracers];
        }
        line_bands(width, &proportional(height, &self.speeds))
    }
    fn observe(&mut self, frame: &FrameMeasure) {
        self.speeds = line_speeds(frame);
    }
    fn remove_tracer(&mut self, index: usize) {
        if index < self.speeds.len() {
            self.speeds.remove(index);
        }
    }
}

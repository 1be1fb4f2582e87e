//! Brigade's "Robin Hood": after each frame, the tracer that finished last gives one work unit
//! to the one that finished first. Stable, but slow to follow change.

use super::{line_bands, proportional, Balancer, FrameMeasure};
use crate::Span;

#[derive(Default)]
pub struct RobinHood {
    counts: Vec<u32>,
}

/// A work unit: about 1% of the frame's lines.
fn unit(height: u32) -> u32 {
    (height / 100).max(1)
}

impl Balancer for RobinHood {
    fn name(&self) -> &'static str {
        "robin-hood"
    }
    fn plan(&mut self, width: u32, height: u32, tracers: usize) -> Vec<Span> {
        if self.counts.len() != tracers || self.counts.iter().sum::<u32>() != height {
            self.counts = proportional(height, &vec![1.0; tracers]);
        }
        line_bands(width, &self.counts)
    }
    fn observe(&mut self, frame: &FrameMeasure) {
        let t = frame.tracers;
        if t.len() < 2 || self.counts.len() != t.len() {
            return;
        }
        let slowest = (0..t.len())
            .max_by(|&a, &b| t[a].seconds.total_cmp(&t[b].seconds))
            .unwrap();
        let fastest = (0..t.len())
            .min_by(|&a, &b| t[a].seconds.total_cmp(&t[b].seconds))
            .unwrap();
        let give = unit(frame.height).min(self.counts[slowest].saturating_sub(1));
        self.counts[slowest] -= give;
        self.counts[fastest] += give;
    }
    fn remove_tracer(&mut self, index: usize) {
        if index < self.counts.len() {
            self.counts.remove(index);
        }
    }
}

//! Brigade's "Perfect Smooth": Perfect, with each tracer's speed averaged over the last few
//! frames so that one unusual frame does not swing the split.

use std::collections::VecDeque;

use super::{line_bands, line_speeds, proportional, Balancer, FrameMeasure};
use crate::Span;

/// Frames averaged.
const WINDOW: usize = 4;

#[derive(Default)]
pub struct PerfectSmooth {
    history: VecDeque<Vec<f64>>,
    tracers: usize,
}

impl Balancer for PerfectSmooth {
    fn name(&self) -> &'static str {
        "perfect-smooth"
    }
    fn plan(&mut self, width: u32, height: u32, tracers: usize) -> Vec<Span> {
        if self.tracers != tracers {
            self.history.clear();
            self.tracers = tracers;
        }
        if self.history.is_empty() {
            return line_bands(width, &proportional(height, &vec![1.0; tracers]));
        }
        let mean: Vec<f64> = (0..tracers)
            .map(|i| self.history.iter().map(|s| s[i]).sum::<f64>() / self.history.len() as f64)
            .collect();
        line_bands(width, &proportional(height, &mean))
    }
    fn observe(&mut self, frame: &FrameMeasure) {
        self.history.push_back(line_speeds(frame));
        if self.history.len() > WINDOW {
            self.history.pop_front();
        }
    }
    fn remove_tracer(&mut self, index: usize) {
        for s in &mut self.history {
            if index < s.len() {
                s.remove(index);
            }
        }
        self.tracers = self.tracers.saturating_sub(1);
    }
}

//! Blender Cycles' approach (integrator/work_balancer.cpp, as BRIEF.md summarises it): weights
//! that equalise the tracers' times, moved only a 1/N step towards the equalising target each
//! frame (N tracers), and left alone while every time is within 2% of the mean (dead band).

use super::{line_bands, proportional, Balancer, FrameMeasure};
use crate::Span;

const DEAD_BAND: f64 = 0.02;

#[derive(Default)]
pub struct CyclesDamped {
    weights: Vec<f64>,
}

impl Balancer for CyclesDamped {
    fn name(&self) -> &'static str {
        "cycles"
    }
    fn plan(&mut self, width: u32, height: u32, tracers: usize) -> Vec<Span> {
        if self.weights.len() != tracers {
            self.weights = vec![1.0 / tracers.max(1) as f64; tracers];
        }
        line_bands(width, &proportional(height, &self.weights))
    }
    fn observe(&mut self, frame: &FrameMeasure) {
        let n = frame.tracers.len();
        if n < 2 || self.weights.len() != n {
            return;
        }
        let times: Vec<f64> = frame.tracers.iter().map(|t| t.seconds.max(1e-12)).collect();
        let mean = times.iter().sum::<f64>() / n as f64;
        if times.iter().all(|t| (t / mean - 1.0).abs() < DEAD_BAND) {
            return;
        }
        // Weight per unit time is the tracer's throughput; equal times need weights ∝ it.
        let target: Vec<f64> = self
            .weights
            .iter()
            .zip(&times)
            .map(|(w, t)| w / t)
            .collect();
        let total: f64 = target.iter().sum();
        for (w, t) in self.weights.iter_mut().zip(&target) {
            *w += (t / total - *w) / n as f64;
        }
    }
    fn remove_tracer(&mut self, index: usize) {
        if index < self.weights.len() {
            self.weights.remove(index);
            let total: f64 = self.weights.iter().sum();
            self.weights.iter_mut().for_each(|w| *w /= total.max(1e-12));
        }
    }
}

//! platoon's cost-aware balancer. It keeps a cost for every line (rays traced in it, smoothed
//! over frames) and a speed for every tracer (cost rendered per second of measured time,
//! smoothed), predicts each tracer's time for any band as band cost / speed, and cuts the next
//! frame on prefix sums of line cost so that every tracer's predicted time is equal.
//! Brigade's Perfect assumes all lines cost the same; a sky band and a geometry band do not.

use super::{line_bands, proportional, span_cost, Balancer, FrameMeasure};
use crate::frame::Span;

/// Weight of the newest frame in the per-line cost (the image moves between frames).
const COST_RATE: f64 = 0.7;
/// Weight of the newest frame in a tracer's speed (timings are noisy).
const SPEED_RATE: f64 = 0.3;

/// How far the cuts are extrapolated along their motion between the last two frames.
const TREND: f64 = 0.5;

#[derive(Default)]
pub struct CostAware {
    line_cost: Vec<f64>,
    /// `line_cost` as it was one frame earlier, to see where the cuts are moving.
    previous_cost: Vec<f64>,
    speed: Vec<f64>,
}

/// Fractional line positions of the n - 1 cuts that give tracer i a share of the total cost
/// proportional to its speed (linear within a line).
fn fractional_cuts(cost: &[f64], speed: &[f64]) -> Vec<f64> {
    let total: f64 = cost.iter().sum();
    let speed_total: f64 = speed.iter().sum();
    let mut cuts = Vec::with_capacity(speed.len().saturating_sub(1));
    let (mut y, mut prefix, mut target) = (0usize, 0.0f64, 0.0f64);
    for s in &speed[..speed.len().saturating_sub(1)] {
        target += total * s / speed_total;
        while y < cost.len() && prefix + cost[y] <= target {
            prefix += cost[y];
            y += 1;
        }
        let within = if y < cost.len() && cost[y] > 0.0 {
            (target - prefix) / cost[y]
        } else {
            0.0
        };
        cuts.push(y as f64 + within.clamp(0.0, 1.0));
    }
    cuts
}

impl CostAware {
    /// Bands from the predicted cuts: this frame's cuts moved on by their last motion, placed to
    /// the pixel.
    fn cut(&self, width: u32, tracers: usize) -> Vec<Span> {
        let height = self.line_cost.len();
        let pixels = (height as u32 * width) as i64;
        let now = fractional_cuts(&self.line_cost, &self.speed);
        let before = if self.previous_cost.len() == height {
            fractional_cuts(&self.previous_cost, &self.speed)
        } else {
            now.clone()
        };
        let mut spans = Vec::with_capacity(tracers);
        let mut start = 0i64;
        for (i, (n, b)) in now.iter().zip(&before).enumerate() {
            let predicted = ((n + TREND * (n - b)) * width as f64).round() as i64;
            // At least a line's worth of pixels for this tracer and each one still to come, so
            // that every tracer keeps being measured.
            let lo = start + width as i64;
            let hi = pixels - (tracers - 1 - i) as i64 * width as i64;
            let end = predicted.clamp(lo, hi);
            spans.push(Span::new(start as u32, end as u32));
            start = end;
        }
        spans.push(Span::new(start as u32, pixels as u32));
        spans
    }
}

impl Balancer for CostAware {
    fn name(&self) -> &'static str {
        "cost-aware"
    }

    fn plan(&mut self, width: u32, height: u32, tracers: usize) -> Vec<Span> {
        let ready = self.speed.len() == tracers
            && self.line_cost.len() == height as usize
            && self.speed.iter().all(|s| s.is_finite() && *s > 0.0)
            && self.line_cost.iter().sum::<f64>() > 0.0
            && height as usize >= tracers;
        if !ready {
            if self.speed.len() != tracers {
                self.speed.clear();
            }
            return line_bands(width, &proportional(height, &vec![1.0; tracers]));
        }
        self.cut(width, tracers)
    }

    fn observe(&mut self, frame: &FrameMeasure) {
        let h = frame.height as usize;
        if frame.line_costs.len() != h {
            return;
        }
        // A line that traced nothing still costs a dispatch slot: floor at a tiny cost.
        let floor = frame.line_costs.iter().sum::<f64>() / h.max(1) as f64 * 1e-3 + 1e-9;
        let measured: Vec<f64> = frame.line_costs.iter().map(|c| c.max(floor)).collect();
        if self.line_cost.len() != h {
            self.line_cost = measured.clone();
            self.previous_cost.clear();
        } else {
            self.previous_cost = self.line_cost.clone();
            for (c, m) in self.line_cost.iter_mut().zip(&measured) {
                *c += COST_RATE * (m - *c);
            }
        }
        let speeds: Vec<f64> = frame
            .tracers
            .iter()
            .map(|t| span_cost(&measured, frame.width, t.span) / t.seconds.max(1e-12))
            .collect();
        if self.speed.len() != speeds.len() {
            self.speed = speeds;
        } else {
            for (s, m) in self.speed.iter_mut().zip(speeds) {
                // A tracer given no lines measured nothing: keep its speed.
                if m > 0.0 && m.is_finite() {
                    *s += SPEED_RATE * (m - *s);
                }
            }
        }
    }

    fn remove_tracer(&mut self, index: usize) {
        if index < self.speed.len() {
            self.speed.remove(index);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::balance::replay::{replay, CostMap};

    #[test]
    fn cuts_equal_predicted_time_on_uneven_lines() {
        // Cheap sky on top, expensive geometry below; tracer 0 twice as fast as tracer 1.
        let costs: Vec<f64> = (0..100).map(|y| if y < 50 { 1.0 } else { 9.0 }).collect();
        let mut b = CostAware::default();
        replay(
            &CostMap {
                width: 10,
                frames: vec![costs.clone(); 10],
            },
            &[2.0, 1.0],
            &mut b,
        );
        let spans = b.plan(10, 100, 2);
        let t0 = span_cost(&costs, 10, spans[0]) / 2.0;
        let t1 = span_cost(&costs, 10, spans[1]);
        // The cut falls within line 81, exact to a pixel (0.9 units on the slower tracer).
        assert!((t0 - t1).abs() <= 0.9, "{spans:?}: {t0} vs {t1}");
        assert_eq!(spans, vec![Span::new(0, 815), Span::new(815, 1000)]);
    }
}

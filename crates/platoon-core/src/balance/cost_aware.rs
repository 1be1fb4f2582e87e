//! platoon's cost-aware balancer. It keeps a cost for every line (rays traced in it, smoothed
//! over frames) and a speed for every tracer (cost rendered per second of measured time,
//! smoothed), predicts each tracer's time for any band as band cost / speed, and cuts the next
//! frame on prefix sums of line cost so that every tracer's predicted time is equal.
//! Brigade's Perfect assumes all lines cost the same; a sky band and a geometry band do not.

use super::{proportional, Balancer, FrameMeasure};

/// Weight of the newest frame in the per-line cost (the image moves between frames).
const COST_RATE: f64 = 0.7;
/// Weight of the newest frame in a tracer's speed (timings are noisy).
const SPEED_RATE: f64 = 0.3;

#[derive(Default)]
pub struct CostAware {
    line_cost: Vec<f64>,
    speed: Vec<f64>,
}

impl CostAware {
    /// Boundaries that give tracer i a share of the total cost proportional to its speed.
    fn cut(&self, tracers: usize) -> Vec<u32> {
        let height = self.line_cost.len();
        let total: f64 = self.line_cost.iter().sum();
        let speed_total: f64 = self.speed.iter().sum();
        let mut counts = Vec::with_capacity(tracers);
        let (mut y, mut prefix, mut target) = (0usize, 0.0f64, 0.0f64);
        for i in 0..tracers {
            if i + 1 == tracers {
                counts.push((height - y) as u32);
                break;
            }
            target += total * self.speed[i] / speed_total;
            let start = y;
            // Leave at least one line for each tracer still to come.
            let limit = height - (tracers - 1 - i);
            while y < limit && (y == start || prefix + self.line_cost[y] * 0.5 <= target) {
                prefix += self.line_cost[y];
                y += 1;
            }
            counts.push((y - start) as u32);
        }
        counts
    }
}

impl Balancer for CostAware {
    fn name(&self) -> &'static str {
        "cost-aware"
    }

    fn plan(&mut self, height: u32, tracers: usize) -> Vec<u32> {
        let ready = self.speed.len() == tracers
            && self.line_cost.len() == height as usize
            && self.speed.iter().all(|s| s.is_finite() && *s > 0.0)
            && self.line_cost.iter().sum::<f64>() > 0.0
            && height as usize >= tracers;
        if !ready {
            if self.speed.len() != tracers {
                self.speed.clear();
            }
            return proportional(height, &vec![1.0; tracers]);
        }
        self.cut(tracers)
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
        } else {
            for (c, m) in self.line_cost.iter_mut().zip(&measured) {
                *c += COST_RATE * (m - *c);
            }
        }
        let speeds: Vec<f64> = frame
            .tracers
            .iter()
            .map(|t| {
                measured[t.y0 as usize..t.y1 as usize].iter().sum::<f64>() / t.seconds.max(1e-12)
            })
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
    use super::super::{bands, TracerFrame};
    use super::*;

    #[test]
    fn cuts_equal_predicted_time_on_uneven_lines() {
        // Cheap sky on top, expensive geometry below; tracer 0 twice as fast as tracer 1.
        let costs: Vec<f64> = (0..100).map(|y| if y < 50 { 1.0 } else { 9.0 }).collect();
        let mut b = CostAware::default();
        for _ in 0..10 {
            let counts = b.plan(100, 2);
            let frames: Vec<TracerFrame> = bands(&counts)
                .iter()
                .enumerate()
                .map(|(i, &(y0, y1))| TracerFrame {
                    y0,
                    y1,
                    seconds: costs[y0 as usize..y1 as usize].iter().sum::<f64>() / [2.0, 1.0][i],
                })
                .collect();
            b.observe(&FrameMeasure {
                height: 100,
                tracers: &frames,
                line_costs: &costs,
            });
        }
        let counts = b.plan(100, 2);
        let t0: f64 = costs[..counts[0] as usize].iter().sum::<f64>() / 2.0;
        let t1: f64 = costs[counts[0] as usize..].iter().sum::<f64>();
        // The best cut is exact to within one line: 9 units on the slower tracer.
        assert!((t0 - t1).abs() <= 9.0, "{counts:?}: {t0} vs {t1}");
        assert_eq!(counts, vec![81, 19]);
    }
}

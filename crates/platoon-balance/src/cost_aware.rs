//! platoon's cost-aware balancer. It keeps a cost for every line (rays traced in it, smoothed
//! over frames) and a speed for every tracer (cost rendered per second of measured time,
//! smoothed), predicts each tracer's time for any band as band cost / speed, and cuts the next
//! frame on prefix sums of line cost so that every tracer's predicted time is equal, to the
//! pixel. Brigade's Perfect assumes all lines cost the same; a sky band and a geometry band do
//! not. On top of the prediction, a damped closed loop: after each frame, the cut that would
//! have equalised the measured times is compared with the cut made, and a share of the
//! difference is carried into the next cuts, so a prediction that keeps missing the same way
//! (the costly lines moving with the camera, a model that misjudges a device) is corrected.
//!
//! The constants were chosen on the tuning maps (scenes/costs/tune: an orbit at 4 degrees a
//! frame and a later stretch of the game), never on the maps the balancers are judged on
//! (docs/BALANCING.md).

use super::{line_bands, proportional, span_cost, Balancer, FrameMeasure};
use crate::Span;

/// Weight of the newest frame in the per-line cost (the image moves between frames).
const COST_RATE: f64 = 0.7;
/// Weight of the newest frame in a tracer's speed (timings are noisy).
const SPEED_RATE: f64 = 0.3;
/// Share of the last frame's cut error carried into the correction, and the share of the
/// correction kept from frame to frame (below 1, so a correction fades once errors stop).
const LOOP_GAIN: f64 = 0.5;
const LOOP_DAMPING: f64 = 0.8;

pub struct CostAware {
    /// LOOP_GAIN, or 0 for the prediction alone (to measure what the loop adds).
    loop_gain: f64,
    line_cost: Vec<f64>,
    speed: Vec<f64>,
    /// Lines added to each predicted cut by the closed loop.
    correction: Vec<f64>,
    /// The last plan came from the model (not the equal split before it knows anything), so
    /// its error says something about the model.
    modelled: bool,
}

/// Fractional line positions of the n - 1 cuts that give tracer i a share of the total cost
/// proportional to its speed (linear within a line).
pub fn fractional_cuts(cost: &[f64], speed: &[f64]) -> Vec<f64> {
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

impl Default for CostAware {
    fn default() -> CostAware {
        CostAware {
            loop_gain: LOOP_GAIN,
            line_cost: Vec::new(),
            speed: Vec::new(),
            correction: Vec::new(),
            modelled: false,
        }
    }
}

/// Contiguous bands ending at the given fractional line positions (n - 1 cuts for n bands),
/// each placed to the nearest pixel, with at least a line's worth of pixels for every band so
/// that every tracer keeps being measured.
pub fn spans_at(cuts: &[f64], width: u32, height: u32) -> Vec<Span> {
    let tracers = cuts.len() + 1;
    let pixels = height as i64 * width as i64;
    let mut spans = Vec::with_capacity(tracers);
    let mut start = 0i64;
    for (i, cut) in cuts.iter().enumerate() {
        let lo = start + width as i64;
        let hi = pixels - (tracers - 1 - i) as i64 * width as i64;
        let end = ((cut * width as f64).round() as i64).clamp(lo, hi.max(lo));
        spans.push(Span::new(start as u32, end as u32));
        start = end;
    }
    spans.push(Span::new(start as u32, pixels as u32));
    spans
}

impl CostAware {
    /// The predicted cut alone, without the closed loop.
    pub fn open_loop() -> CostAware {
        CostAware {
            loop_gain: 0.0,
            ..CostAware::default()
        }
    }

    /// Bands from the predicted cuts plus the closed loop's correction, placed to the pixel.
    fn cut(&self, width: u32) -> Vec<Span> {
        let cuts: Vec<f64> = fractional_cuts(&self.line_cost, &self.speed)
            .iter()
            .enumerate()
            .map(|(i, p)| p + self.correction.get(i).copied().unwrap_or(0.0))
            .collect();
        spans_at(&cuts, width, self.line_cost.len() as u32)
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
        self.modelled = ready;
        if !ready {
            if self.speed.len() != tracers {
                self.speed.clear();
                self.correction.clear();
            }
            return line_bands(width, &proportional(height, &vec![1.0; tracers]));
        }
        self.cut(width)
    }

    fn observe(&mut self, frame: &FrameMeasure) {
        let h = frame.height as usize;
        if frame.line_costs.len() != h {
            return;
        }
        // A line that traced nothing still costs a dispatch slot: floor at a tiny cost.
        let floor = frame.line_costs.iter().sum::<f64>() / h.max(1) as f64 * 1e-3 + 1e-9;
        let measured: Vec<f64> = frame.line_costs.iter().map(|c| c.max(floor)).collect();
        let speeds: Vec<f64> = frame
            .tracers
            .iter()
            .map(|t| span_cost(&measured, frame.width, t.span) / t.seconds.max(1e-12))
            .collect();
        self.close_loop(frame, &measured, &speeds);
        if self.line_cost.len() != h {
            self.line_cost = measured;
        } else {
            for (c, m) in self.line_cost.iter_mut().zip(&measured) {
                *c += COST_RATE * (m - *c);
            }
        }
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
        // The cuts now divide other tracers: what was learnt about them no longer applies.
        self.correction.clear();
        self.modelled = false;
    }
}

impl CostAware {
    /// Compares the cuts made with those that would have equalised the measured times (this
    /// frame's costs and this frame's speeds) and carries a damped share of the difference into
    /// the next cuts.
    fn close_loop(&mut self, frame: &FrameMeasure, measured: &[f64], speeds: &[f64]) {
        let cuts = speeds.len().saturating_sub(1);
        let usable = self.modelled
            && cuts > 0
            && frame.tracers.len() == speeds.len()
            && speeds.iter().all(|s| s.is_finite() && *s > 0.0);
        if !usable {
            self.correction.clear();
            return;
        }
        self.correction.resize(cuts, 0.0);
        let ideal = fractional_cuts(measured, speeds);
        let width = frame.width.max(1) as f64;
        for (i, c) in self.correction.iter_mut().enumerate() {
            let made = frame.tracers[i].span.end as f64 / width;
            *c = LOOP_DAMPING * *c + self.loop_gain * (ideal[i] - made);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::replay::{replay, CostMap};

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

    /// A costly band of 30 lines whose top moves down `step` lines a frame (a camera tilting),
    /// on a cheap background; 100 lines of 100 pixels.
    fn moving_band(frames: usize, step: f64) -> CostMap {
        let frames = (0..frames)
            .map(|f| {
                let top = 10.0 + step * f as f64;
                (0..100)
                    .map(|y| {
                        let inside = ((y as f64 + 1.0).min(top + 30.0) - (y as f64).max(top))
                            .clamp(0.0, 1.0);
                        1.0 + 9.0 * inside
                    })
                    .collect()
            })
            .collect();
        CostMap { width: 100, frames }
    }

    fn mean_idle_after(idle: &[f64], settle: usize) -> f64 {
        idle[settle..].iter().sum::<f64>() / (idle.len() - settle) as f64
    }

    #[test]
    fn the_closed_loop_follows_moving_costs_the_prediction_lags_behind() {
        let map = moving_band(60, 0.5);
        let speeds = [1.0, 0.7, 0.4];
        let closed = replay(&map, &speeds, &mut CostAware::default());
        let open = replay(&map, &speeds, &mut CostAware::open_loop());
        let (closed, open) = (mean_idle_after(&closed, 10), mean_idle_after(&open, 10));
        // The prediction uses last frames' costs, so its cuts trail the band; the loop sees
        // the cuts miss the same way every frame and moves them on.
        assert!(closed < 0.6 * open, "closed loop {closed} vs open {open}");
    }

    #[test]
    fn on_still_costs_the_loop_settles_to_an_exact_cut() {
        let map = moving_band(40, 0.0);
        let idle = replay(&map, &[1.0, 0.7, 0.4], &mut CostAware::default());
        // Exact to a pixel's cost (0.1 of about 70 on the slowest tracer): no oscillation
        // left once the loop has settled.
        assert!(mean_idle_after(&idle, 20) < 0.002, "{:?}", &idle[20..]);
    }
}

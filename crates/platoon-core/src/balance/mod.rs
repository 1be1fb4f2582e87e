//! Workload balancing between tracers: before each frame a policy decides which pixels each
//! tracer renders (contiguous bands, in tracer order), from what earlier frames measured.
//! Brigade's policies move whole lines; cost-aware cuts within a line.
//! The policies follow Bikker's Brigade (none, Robin Hood, Perfect, Perfect Smooth), Blender
//! Cycles' damped time equalising, and platoon's own cost-aware cut. One policy per file.

mod cost_aware;
mod cycles;
mod equal_split;
mod perfect;
mod perfect_smooth;
pub mod replay;
mod robin_hood;

pub use cost_aware::{fractional_cuts, spans_at, CostAware};
pub use cycles::CyclesDamped;
pub use equal_split::EqualSplit;
pub use perfect::Perfect;
pub use perfect_smooth::PerfectSmooth;
pub use robin_hood::RobinHood;

use crate::frame::Span;

/// What one tracer did in a frame.
#[derive(Clone, Debug, PartialEq)]
pub struct TracerFrame {
    pub span: Span,
    /// Time the tracer took for its band (seconds; measured or simulated).
    pub seconds: f64,
}

/// What a frame measured, handed to the policy after the frame.
#[derive(Clone, Debug)]
pub struct FrameMeasure<'a> {
    pub width: u32,
    pub height: u32,
    pub tracers: &'a [TracerFrame],
    /// Relative cost of every line of the frame (rays traced in it), `height` entries.
    pub line_costs: &'a [f64],
}

pub trait Balancer: Send {
    fn name(&self) -> &'static str;
    /// The band of each of `tracers` tracers for the next frame of `width` x `height` pixels:
    /// contiguous, in tracer order, covering the frame.
    fn plan(&mut self, width: u32, height: u32, tracers: usize) -> Vec<Span>;
    /// Learns from the frame just rendered.
    fn observe(&mut self, frame: &FrameMeasure);
    /// Tracer `index` is gone (it failed); later plans have one tracer fewer.
    fn remove_tracer(&mut self, index: usize);
}

/// Names accepted by [`by_name`], in the order tables list them.
pub const NAMES: [&str; 6] = [
    "none",
    "robin-hood",
    "perfect",
    "perfect-smooth",
    "cycles",
    "cost-aware",
];

pub fn by_name(name: &str) -> Option<Box<dyn Balancer>> {
    Some(match name {
        "none" => Box::new(EqualSplit),
        "robin-hood" => Box::new(RobinHood::default()),
        "perfect" => Box::new(Perfect::default()),
        "perfect-smooth" => Box::new(PerfectSmooth::default()),
        "cycles" => Box::new(CyclesDamped::default()),
        "cost-aware" => Box::new(CostAware::default()),
        _ => return None,
    })
}

/// Contiguous bands of whole lines from line counts, in tracer order.
pub fn line_bands(width: u32, counts: &[u32]) -> Vec<Span> {
    let mut y = 0;
    counts
        .iter()
        .map(|&c| {
            let b = Span::lines(width, y, y + c);
            y += c;
            b
        })
        .collect()
}

/// Cost of the pixels of `span` from per-line costs, a cut line costing its share of pixels
/// (the cost within a line is taken as even: the kernel counts rays per line, not per pixel).
pub fn span_cost(line_costs: &[f64], width: u32, span: Span) -> f64 {
    (span.first_line(width)..span.end_line(width))
        .map(|y| {
            line_costs.get(y as usize).copied().unwrap_or(0.0)
                * span.pixels_in_line(width, y) as f64
                / width.max(1) as f64
        })
        .sum()
}

/// Fraction of the frame's tracer time spent idle: sum_i (T_max - T_i) / (n * T_max).
pub fn idle_fraction(times: &[f64]) -> f64 {
    let max = times.iter().copied().fold(0.0, f64::max);
    if times.len() < 2 || max <= 0.0 {
        return 0.0;
    }
    times.iter().map(|t| max - t).sum::<f64>() / (times.len() as f64 * max)
}

/// Splits `height` lines in proportion to `weights` (largest remainder), at least one line each
/// while there are lines enough, so every tracer keeps being measured.
pub fn proportional(height: u32, weights: &[f64]) -> Vec<u32> {
    let n = weights.len();
    if n == 0 {
        return vec![];
    }
    let floor = if height as usize >= n { 1 } else { 0 };
    let spare = height - floor * n as u32;
    let clean: Vec<f64> = weights
        .iter()
        .map(|w| if w.is_finite() && *w > 0.0 { *w } else { 0.0 })
        .collect();
    let total: f64 = clean.iter().sum();
    let shares: Vec<f64> = if total > 0.0 {
        clean.iter().map(|w| w / total * spare as f64).collect()
    } else {
        vec![spare as f64 / n as f64; n]
    };
    let mut counts: Vec<u32> = shares.iter().map(|s| s.floor() as u32).collect();
    let mut left = spare - counts.iter().sum::<u32>();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| {
        (shares[b] - shares[b].floor())
            .total_cmp(&(shares[a] - shares[a].floor()))
            .then(a.cmp(&b))
    });
    for &i in order.iter().cycle() {
        if left == 0 {
            break;
        }
        counts[i] += 1;
        left -= 1;
    }
    counts.iter().map(|c| c + floor).collect()
}

/// Lines per second of each tracer in a frame (the Brigade notion of speed: ignores how costly
/// the lines were).
pub(crate) fn line_speeds(frame: &FrameMeasure) -> Vec<f64> {
    frame
        .tracers
        .iter()
        .map(|t| t.span.len() as f64 / frame.width.max(1) as f64 / t.seconds.max(1e-12))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proportional_sums_and_keeps_everyone() {
        assert_eq!(proportional(10, &[1.0, 1.0]), vec![5, 5]);
        assert_eq!(proportional(10, &[3.0, 1.0]).iter().sum::<u32>(), 10);
        assert_eq!(proportional(10, &[1.0, 0.0]), vec![9, 1]);
        assert_eq!(proportional(2, &[1.0, 1.0, 1.0]).iter().sum::<u32>(), 2);
        assert_eq!(proportional(7, &[f64::NAN, 1.0]), vec![1, 6]);
    }

    /// Contiguous, in order, non-empty, covering [0, pixels).
    fn assert_covers(spans: &[Span], pixels: u32, name: &str) {
        assert_eq!(spans.first().map(|s| s.begin), Some(0), "{name}: {spans:?}");
        assert_eq!(
            spans.last().map(|s| s.end),
            Some(pixels),
            "{name}: {spans:?}"
        );
        assert!(
            spans.windows(2).all(|w| w[0].end == w[1].begin),
            "{name}: {spans:?}"
        );
        assert!(spans.iter().all(|s| !s.is_empty()), "{name}: {spans:?}");
    }

    #[test]
    fn span_cost_shares_a_cut_line_by_pixels() {
        let costs = [4.0, 8.0, 2.0];
        assert_eq!(span_cost(&costs, 4, Span::lines(4, 0, 3)), 14.0);
        // Half of line 0 and a quarter of line 1.
        assert_eq!(span_cost(&costs, 4, Span::new(2, 5)), 2.0 + 2.0);
        assert_eq!(span_cost(&costs, 4, Span::new(5, 5)), 0.0);
    }

    #[test]
    fn idle_fraction_matches_the_definition() {
        assert_eq!(idle_fraction(&[1.0, 1.0]), 0.0);
        assert_eq!(idle_fraction(&[1.0, 0.5]), 0.25);
        assert_eq!(idle_fraction(&[2.0]), 0.0);
    }

    #[test]
    fn every_policy_plans_the_whole_frame() {
        let costs: Vec<f64> = (0..50).map(|y| if y < 20 { 1.0 } else { 5.0 }).collect();
        let map = crate::balance::replay::CostMap {
            width: 7,
            frames: vec![costs; 5],
        };
        for name in NAMES {
            let mut b = by_name(name).unwrap();
            // replay() checks nothing itself: it plans, times and observes each frame.
            let idle = crate::balance::replay::replay(&map, &[1.0, 0.5, 1.0 / 3.0], b.as_mut());
            assert!(idle.iter().all(|i| (0.0..1.0).contains(i)), "{name}");
            assert_covers(&b.plan(map.width, 50, 3), map.width * 50, name);
            b.remove_tracer(1);
            assert_covers(&b.plan(map.width, 50, 2), map.width * 50, name);
        }
    }
}

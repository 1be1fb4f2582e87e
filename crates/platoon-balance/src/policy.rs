//! What every balancing policy implements (`Balancer`), what a frame tells it (`FrameMeasure`),
//! and the line arithmetic the policies share: bands from line counts, costs of spans, the split
//! proportional to weights.

use crate::Span;

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
    /// Whether the tracers take the unstarted tails of each other's bands within a frame, and
    /// how (`steal`): a renderer given this balancer steals so.
    fn stealing(&self) -> Option<super::Stealing> {
        None
    }
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

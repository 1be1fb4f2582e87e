//! A frame's rounds over the renderer's tracers: the first round (each planned band at once,
//! or with stealing the heads and the pieces claimed from a `ClaimBoard`), the rounds that
//! render what failed tracers lost, and what they gather: the bands, each tracer's stats,
//! what was lost, and the check that the bands tile the frame.

use std::sync::Arc;
use std::time::Duration;

use crate::outcome::{RenderError, TracerFailure, TracerStats};
use crate::workers::Worker;
use platoon_frame::balance::span_cost;
use platoon_frame::balance::steal::ClaimBoard;
use platoon_frame::frame::{Band, BandTracer, Span, TracerError, ValidatedFrame};

/// What a frame's rounds gather.
pub(crate) struct Gathered {
    /// One per tracer the frame started with, in their order.
    pub stats: Vec<TracerStats>,
    pub done: Vec<Band>,
    /// Pixels failed tracers did not hand in.
    pub lost: Vec<Span>,
    /// Slots of the tracers that failed in the last round.
    pub dead: Vec<usize>,
    pub failures: Vec<TracerFailure>,
    /// With stealing: what each tracer rendered of the first round.
    pub claimed: Vec<Claimed>,
}

/// What a tracer rendered of a stolen round: what the balancer learns its speed from and a
/// piece's overhead is measured by.
pub(crate) struct Claimed {
    pub tracer: usize,
    pub head: Span,
    /// Each band it rendered and its seconds, the head (when it rendered it) first.
    pub bands: Vec<(Span, f64)>,
}

impl Claimed {
    pub fn spans(&self) -> Vec<Span> {
        self.bands.iter().map(|&(span, _)| span).collect()
    }
}

impl Gathered {
    pub fn new<T>(tracers: &[(usize, Worker<T>)], planned: &[Span]) -> Gathered {
        Gathered {
            stats: tracers
                .iter()
                .zip(planned)
                .map(|((id, _), &span)| TracerStats {
                    tracer: *id,
                    span,
                    pixels: 0,
                    gpu_time: Duration::ZERO,
                    wall_time: Duration::ZERO,
                    idle: Duration::ZERO,
                    rays: 0,
                    pieces: 0,
                    stolen: 0,
                })
                .collect(),
            done: Vec::new(),
            lost: Vec::new(),
            dead: Vec::new(),
            failures: Vec::new(),
            claimed: Vec::new(),
        }
    }

    fn stats(&mut self, id: usize) -> &mut TracerStats {
        self.stats
            .iter_mut()
            .find(|s| s.tracer == id)
            .expect("stats of a live tracer")
    }

    fn add(&mut self, id: usize, band: Band) {
        let s = self.stats(id);
        s.pixels += band.span.len();
        s.gpu_time += band.gpu_time;
        s.wall_time += band.wall_time;
        s.rays += band.rays;
        self.done.push(band);
    }

    fn fail(&mut self, slot: usize, id: usize, frame: u32, error: TracerError, lost: Vec<Span>) {
        self.lost.extend(lost);
        self.dead.push(slot);
        self.failures.push(TracerFailure {
            tracer: id,
            frame,
            message: error.to_string(),
        });
    }
}

type Outcome = (usize, Span, Result<Band, TracerError>);

/// Renders `work[i]` on tracer i, all at once, each on its thread.
fn run_bands<T: BandTracer + Send + 'static>(
    tracers: &[(usize, Worker<T>)],
    work: &[Span],
    params: &Arc<ValidatedFrame>,
    progress: &mut dyn FnMut(u32),
) -> Vec<Outcome> {
    // Samples done mean something for the frame when one tracer renders it all.
    let report = tracers.len() == 1;
    for ((_, worker), &span) in tracers.iter().zip(work) {
        if !span.is_empty() {
            worker.start_band(params, span, report);
        }
    }
    tracers
        .iter()
        .zip(work)
        .enumerate()
        .map(|(slot, ((_, worker), &span))| {
            let result = if span.is_empty() {
                Ok(Band {
                    span,
                    ..Default::default()
                })
            } else {
                worker.band(progress)
            };
            (slot, span, result)
        })
        .collect()
}

/// Renders `work[i]` on tracer i, all at once; returns each tracer's band time. `progress`
/// hears the samples done when one tracer renders.
pub(crate) fn planned_round<T: BandTracer + Send + 'static>(
    tracers: &[(usize, Worker<T>)],
    work: &[Span],
    params: &Arc<ValidatedFrame>,
    g: &mut Gathered,
    progress: &mut dyn FnMut(u32),
) -> Vec<f64> {
    let mut times = vec![0.0; tracers.len()];
    for (slot, span, result) in run_bands(tracers, work, params, progress) {
        let id = tracers[slot].0;
        match result {
            Ok(band) => {
                times[slot] = band.wall_time.as_secs_f64();
                g.add(id, band);
            }
            Err(e) => g.fail(slot, id, params.frame, e, vec![span]),
        }
    }
    times
}

/// Every tracer renders its head of `board` and claims pieces until none is left; returns
/// each tracer's busy time. A failed tracer loses its head and every piece it claimed, but
/// for what it handed in.
pub(crate) fn stolen_round<T: BandTracer + Send + 'static>(
    tracers: &[(usize, Worker<T>)],
    board: ClaimBoard,
    params: &Arc<ValidatedFrame>,
    g: &mut Gathered,
) -> Vec<f64> {
    let board = Arc::new(board);
    for (slot, (_, worker)) in tracers.iter().enumerate() {
        worker.start_stealing(params, &board, slot);
    }
    let mut times = Vec::with_capacity(tracers.len());
    for (slot, (id, worker)) in tracers.iter().enumerate() {
        let stolen = worker.stolen();
        let s = g.stats(*id);
        (s.pieces, s.stolen) = (stolen.pieces, stolen.stolen);
        times.push(stolen.busy.as_secs_f64());
        let claimed = Claimed {
            tracer: *id,
            head: board.head(slot),
            bands: stolen
                .bands
                .iter()
                .map(|b| (b.span, b.wall_time.as_secs_f64()))
                .collect(),
        };
        for band in stolen.bands {
            g.add(*id, band);
        }
        if let Some(e) = stolen.error {
            let mut held = board.held_by(slot);
            held.push(claimed.head);
            g.fail(
                slot,
                *id,
                params.frame,
                e,
                subtract(&held, &claimed.spans()),
            );
        }
        g.claimed.push(claimed);
    }
    // Left only when every tracer failed (the others claim all there is).
    g.lost.extend(board.unclaimed_chunks());
    times
}

/// The median time of the frame's pieces beyond their work, each tracer's work timed by its
/// head (cost over time). None without a piece to tell.
pub(crate) fn piece_overhead(line_costs: &[f64], width: u32, claimed: &[Claimed]) -> Option<f64> {
    let mut excess = Vec::new();
    for c in claimed {
        let Some(&(first, head_seconds)) = c.bands.first() else {
            continue;
        };
        let head_cost = span_cost(line_costs, width, c.head);
        if first != c.head || c.head.is_empty() || head_cost <= 0.0 || head_seconds <= 0.0 {
            continue;
        }
        let per_cost = head_seconds / head_cost;
        for &(span, seconds) in &c.bands[1..] {
            excess.push((seconds - span_cost(line_costs, width, span) * per_cost).max(0.0));
        }
    }
    (!excess.is_empty()).then(|| platoon_frame::measure::median(excess))
}

/// `spans` less the pixels of `taken` (spans that lie within them or apart).
fn subtract(spans: &[Span], taken: &[Span]) -> Vec<Span> {
    let mut left: Vec<Span> = spans.iter().copied().filter(|s| !s.is_empty()).collect();
    for t in taken {
        left = left
            .into_iter()
            .flat_map(|s| {
                [
                    Span::new(s.begin, s.end.min(t.begin)),
                    Span::new(s.begin.max(t.end), s.end),
                ]
            })
            .filter(|s| !s.is_empty())
            .collect();
    }
    left
}

/// The bands rendered tile the planned pixels exactly (no pixel twice, none missing): what
/// keeps a claim handed out twice, or lost, from becoming a wrong frame.
pub(crate) fn check_cover(planned: &[Span], done: &[Band]) -> Result<(), RenderError> {
    let (Some(first), Some(last)) = (planned.first(), planned.last()) else {
        return Ok(());
    };
    let mut spans: Vec<Span> = done
        .iter()
        .map(|b| b.span)
        .filter(|s| !s.is_empty())
        .collect();
    spans.sort_by_key(|s| (s.begin, s.end));
    let mut at = first.begin;
    for s in &spans {
        if s.begin != at {
            let what = if s.begin < at {
                "rendered twice"
            } else {
                "never rendered"
            };
            return Err(RenderError::Incomplete(format!(
                "pixels {}..{} {what}",
                s.begin.min(at),
                s.begin.max(at)
            )));
        }
        at = s.end;
    }
    if at != last.end {
        return Err(RenderError::Incomplete(format!(
            "pixels {at}..{} never rendered",
            last.end
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_that_overlap_or_leave_a_gap_are_no_frame() {
        let band = |b, e| Band {
            span: Span::new(b, e),
            ..Default::default()
        };
        let planned = [Span::new(0, 10), Span::new(10, 20)];
        assert!(check_cover(&planned, &[band(10, 20), band(0, 10)]).is_ok());
        let twice = check_cover(&planned, &[band(0, 12), band(10, 20)]).unwrap_err();
        assert!(
            twice.to_string().contains("10..12 rendered twice"),
            "{twice}"
        );
        let lost = check_cover(&planned, &[band(0, 8), band(10, 20)]).unwrap_err();
        assert!(lost.to_string().contains("8..10 never rendered"), "{lost}");
        assert!(check_cover(&planned, &[band(0, 10), band(10, 19)]).is_err());
        assert_eq!(
            subtract(
                &[Span::new(0, 10), Span::new(20, 30)],
                &[Span::new(2, 4), Span::new(20, 30)]
            ),
            vec![Span::new(0, 2), Span::new(4, 10)]
        );
    }
}

//! What a renderer learns between frames to steal well (`steal`): the lines' costs, a
//! piece's overhead, the slowest tracer's time and the idle a split without stealing would
//! have had; from them each frame's claim board, or none where stealing would not pay.

use super::steal::{min_chunk, ClaimBoard, BLIND_TAIL};
use super::Stealing;
use crate::Span;

/// A tail holds at least this many times the idle expected without stealing (a share of the
/// frame's tracer time; a tracer's miss is about twice it with two tracers).
const TAIL_PER_IDLE: f64 = 2.0;

/// What a renderer learns between frames to steal well: the lines' costs (what tails are cut
/// by), a piece's overhead (what chunks may not be smaller than), the slowest tracer's time
/// and the idle a split without stealing would have had (whether stealing pays at all).
#[derive(Clone, Debug, Default)]
pub struct StealHistory {
    line_costs: Vec<f64>,
    piece_overhead: Option<f64>,
    last_seconds: f64,
    expected_idle: Option<f64>,
}

/// Weight of the newest frame in the estimates of a piece's overhead and the idle to expect.
const HISTORY_RATE: f64 = 0.3;

impl StealHistory {
    /// The board of the next frame's `planned` bands, or None where stealing would not pay:
    /// the idle expected without it is less than the pieces would cost. A frame of a size
    /// whose line costs are not known (the first) is always stolen: its split is blind.
    pub fn board(
        &self,
        stealing: &Stealing,
        planned: &[Span],
        width: u32,
        height: u32,
    ) -> Option<ClaimBoard> {
        let known = self.line_costs.len() == height as usize;
        let overhead = self.piece_overhead.unwrap_or(0.0);
        let expected = self.expected_idle.unwrap_or(1.0) * self.last_seconds;
        if known && expected <= stealing.pieces_worth * overhead {
            return None;
        }
        let costs: &[f64] = if known { &self.line_costs } else { &[] };
        let floor = min_chunk(stealing, overhead, self.last_seconds);
        // A split that keeps missing by much (a policy that cannot weigh the devices, a
        // change of speed) has its tails grown to hold the error, in chunks of the same size.
        let mut sizing = *stealing;
        let wanted = (TAIL_PER_IDLE * self.expected_idle.unwrap_or(0.0)).min(BLIND_TAIL);
        if sizing.tail > 0.0 && wanted > sizing.tail {
            sizing.tail = wanted;
        }
        Some(ClaimBoard::new(planned, width, costs, &sizing, floor))
    }

    /// Learns from a frame: its line costs, its slowest tracer's time, the idle its split
    /// would have had without stealing, and a piece's overhead if it measured one.
    pub fn learn(
        &mut self,
        line_costs: Vec<f64>,
        seconds: f64,
        idle_unstolen: f64,
        piece_overhead: Option<f64>,
    ) {
        let blend =
            |old: Option<f64>, new: f64| Some(old.map_or(new, |o| o + HISTORY_RATE * (new - o)));
        if let Some(o) = piece_overhead.filter(|o| o.is_finite()) {
            self.piece_overhead = blend(self.piece_overhead, o);
        }
        // A frame cut blind (its line costs unknown: the first) says nothing of how well the
        // policy predicts.
        let blind = self.line_costs.len() != line_costs.len();
        if idle_unstolen.is_finite() && !blind {
            self.expected_idle = blend(self.expected_idle, idle_unstolen);
        }
        self.line_costs = line_costs;
        self.last_seconds = seconds;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::steal::tests::fixed;

    #[test]
    fn stealing_is_skipped_where_it_cannot_pay_and_grows_where_the_split_misses_by_much() {
        let planned = [Span::lines(10, 0, 50), Span::lines(10, 50, 100)];
        let (s, costs) = (fixed(), vec![1.0; 100]);
        let mut h = StealHistory::default();
        // The first frame is blind: always stolen, most of each band shared.
        assert_eq!(
            h.board(&s, &planned, 10, 100).unwrap().head(0),
            Span::lines(10, 0, 10)
        );
        h.learn(costs.clone(), 0.1, 0.2, Some(1e-4));
        // Its idle teaches nothing; the next frame has the stated tail (6%: 3 of 50 lines, in
        // chunks of 0.4%, over the floor of four pieces' overhead, 0.4 ms of 100).
        assert_eq!(
            h.board(&s, &planned, 10, 100).unwrap().head(0),
            Span::lines(10, 0, 47)
        );
        // 0.1% idle of 0.1 s is 0.1 ms, under two pieces of 0.1 ms: not stolen...
        h.learn(costs.clone(), 0.1, 0.001, Some(1e-4));
        assert!(h.board(&s, &planned, 10, 100).is_none());
        // ...and after a split missing by a fifth (expected idle 0.001 + 0.3 x 0.199) the
        // tails hold twice the idle expected: 12.1% of a band, 30 chunks of 2 pixels.
        h.learn(costs.clone(), 0.1, 0.2, Some(1e-4));
        let head = h.board(&s, &planned, 10, 100).unwrap().head(0);
        assert_eq!(head.end, 500 - 60, "{head:?}");
    }
}

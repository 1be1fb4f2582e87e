//! In-frame stealing of the trailing pixels. A balancer's plan is a prediction, and the next
//! frame's costs differ from the last one's (docs/BALANCING.md: where the camera moves fast,
//! no split decided before the frame gets much below 1% idle). So each planned band keeps a
//! *head*, rendered by its tracer in one dispatch, and leaves a *tail* of small chunks at its
//! end. A tracer done with its head claims its own tail from the front; one done with all of
//! its own claims chunks from the back of the tail with the most work left. A claim is one
//! compare-and-swap on the tail's (front, back) pair, and a piece is a run of chunks next to
//! each other: one dispatch. A pixel's samples do not depend on who traces them, so the image
//! keeps its bits whoever renders which chunk.
//!
//! Every piece costs a dispatch (on lavapipe a third of a millisecond), so the claims keep the
//! pieces few. The first claim tells the board the tracer's speed in the frame; while no other
//! tracer has run out of chunks of its own, an owner takes what it can render before the first
//! of them is expected to (at most all of its tail but a reserve of a few chunks); once some
//! have, the unclaimed chunks of a tail are shared by speed between the owner and those (guided
//! self-scheduling, Polychronopoulos and Kuck), never less than a chunk, so the last pieces,
//! which decide who waits for whom, are single chunks. A chunk is never cut so small that its
//! dispatch would cost more than a share of its work (`min_chunk`), and where stealing would not
//! pay at all the frame is not stolen (`steal_history::StealHistory`).

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};

pub use super::stealing::Stealing;
use crate::span_cost;
use crate::Span;

/// The least share of a band a chunk may hold so that its work is `stealing`'s
/// `work_per_overhead` times a piece's `overhead` (seconds), the band taking `band_seconds`.
pub fn min_chunk(stealing: &Stealing, overhead: f64, band_seconds: f64) -> f64 {
    if band_seconds > 0.0 && overhead > 0.0 {
        (stealing.work_per_overhead * overhead / band_seconds).min(1.0)
    } else {
        0.0
    }
}

/// The tail's share of a band when no line cost is known yet.
pub(crate) const BLIND_TAIL: f64 = 0.8;

/// Nobody holds the chunk.
const UNCLAIMED: usize = usize::MAX;

/// One planned band: its head and the chunks of its tail, in pixel order.
struct Tail {
    head: Span,
    /// The head's predicted cost (the line costs' units; pixels over the width without them).
    head_cost: f64,
    /// The owner's speed in this frame (cost a second, the bits of an f64; 0 until it claims
    /// first): what the unclaimed chunks are shared by.
    speed: AtomicU64,
    /// When the owner is expected to be done with the piece it claimed last (seconds into the
    /// frame, the bits of an f64).
    busy_until: AtomicU64,
    /// A chunk's predicted cost (they are cut equal).
    chunk_cost: f64,
    chunks: Vec<Span>,
    /// (front, back) packed: chunks [front, back) are unclaimed.
    ends: AtomicU64,
    /// Who claimed each chunk (a tracer slot), for the frame's check and for what a tracer
    /// that failed held.
    holder: Vec<AtomicUsize>,
}

fn pack(front: u32, back: u32) -> u64 {
    (front as u64) << 32 | back as u64
}

fn unpack(ends: u64) -> (u32, u32) {
    ((ends >> 32) as u32, ends as u32)
}

/// A piece a tracer claimed: the pixels, and whose band they were planned in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Piece {
    pub span: Span,
    pub owner: usize,
    /// Whether it came from another tracer's band.
    pub stolen: bool,
}

/// The frame's tails, shared by the tracers while they render.
pub struct ClaimBoard {
    tails: Vec<Tail>,
    reserve: u32,
    guide: f64,
}

impl ClaimBoard {
    /// The board of a planned split: each band's tail cut from `line_costs` (the latest known
    /// cost of every line) so that it holds `stealing.tail` of the band's cost in chunks of
    /// `stealing.chunk` of it each (but `min_chunk` at least: the share of a band whose work
    /// makes a piece's overhead worth paying), to the pixel. With no costs known (a first
    /// frame, whose split no measurement has shaped: an equal one, 20-40% idle on unequal
    /// devices) the tail is most of each band (`BLIND_TAIL`), of chunks as many as a tail of
    /// the stated share has.
    pub fn new(
        planned: &[Span],
        width: u32,
        line_costs: &[f64],
        stealing: &Stealing,
        min_chunk: f64,
    ) -> ClaimBoard {
        let mut sizing = *stealing;
        // A tail keeps a chunk however costly a piece is, so that pieces keep being measured.
        sizing.chunk = sizing
            .chunk
            .max(min_chunk)
            .min(sizing.tail.max(f64::MIN_POSITIVE));
        if line_costs.is_empty() && sizing.tail > 0.0 {
            let scale = (BLIND_TAIL / sizing.tail).max(1.0);
            sizing.tail *= scale;
            sizing.chunk *= scale;
        }
        let tails = planned
            .iter()
            .map(|&band| {
                let chunks = tail_chunks(band, width, line_costs, &sizing);
                let head = Span::new(band.begin, chunks.first().map_or(band.end, |c| c.begin));
                let tail_cost = cost_of(line_costs, width, Span::new(head.end, band.end));
                Tail {
                    head,
                    head_cost: cost_of(line_costs, width, head),
                    speed: AtomicU64::new(0),
                    busy_until: AtomicU64::new(0),
                    chunk_cost: tail_cost / chunks.len().max(1) as f64,
                    ends: AtomicU64::new(pack(0, chunks.len() as u32)),
                    holder: chunks.iter().map(|_| AtomicUsize::new(UNCLAIMED)).collect(),
                    chunks,
                }
            })
            .collect();
        ClaimBoard {
            tails,
            reserve: stealing.reserve,
            guide: stealing.guide,
        }
    }

    /// The head of tracer `slot`'s band (its own, never claimed by others).
    pub fn head(&self, slot: usize) -> Span {
        self.tails.get(slot).map_or(Span::default(), |t| t.head)
    }

    /// Chunks in the frame's tails.
    pub fn chunks(&self) -> usize {
        self.tails.iter().map(|t| t.chunks.len()).sum()
    }

    /// Tracer `slot`'s next piece, `now` seconds after the frame's start: from the front of
    /// its own tail while it has one, else from the back of the tail with the most chunks left
    /// (the first such band on a tie). None when every chunk is claimed. Its first claim
    /// tells the board its speed (its head's cost over `now`).
    pub fn claim(&self, slot: usize, now: f64) -> Option<Piece> {
        if let Some(tail) = self.tails.get(slot) {
            if tail.speed.load(Ordering::Acquire) == 0 && now > 0.0 && tail.head_cost > 0.0 {
                let speed = tail.head_cost / now;
                tail.speed.store(speed.to_bits(), Ordering::Release);
            }
        }
        if let Some(span) = self.take(slot, slot, true, now) {
            return Some(Piece {
                span,
                owner: slot,
                stolen: false,
            });
        }
        loop {
            let victim = (0..self.tails.len())
                .map(|i| (i, self.unclaimed(i)))
                .filter(|&(_, left)| left > 0)
                .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))?
                .0;
            // Another tracer may empty the victim first: look again.
            if let Some(span) = self.take(victim, slot, false, now) {
                return Some(Piece {
                    span,
                    owner: victim,
                    stolen: victim != slot,
                });
            }
        }
    }

    fn unclaimed(&self, band: usize) -> u32 {
        let (front, back) = unpack(self.tails[band].ends.load(Ordering::Acquire));
        back.saturating_sub(front)
    }

    /// Chunks `by`'s claim on `band`'s tail, `now`, takes of `left` unclaimed. The tail is
    /// shared between its owner and every tracer with no unclaimed chunk left of its own (at
    /// the end of their work, or stealing already): a claim then takes its share by speed
    /// (equal shares where a speed is not known), over the guide. While nobody else shares
    /// it, the owner takes what it can render before the first other tracer is expected to run
    /// out of its own work, and at most all but the reserve (all of a reserve).
    fn piece_size(&self, band: usize, by: usize, left: u32, now: f64) -> u32 {
        let sharers: Vec<usize> = (0..self.tails.len())
            .filter(|&i| i == band || i == by || self.unclaimed(i) == 0)
            .collect();
        if sharers.len() > 1 {
            let speeds: Vec<f64> = sharers.iter().map(|&i| self.speed(i)).collect();
            let share = if speeds.iter().all(|&s| s > 0.0) {
                self.speed(by) / speeds.iter().sum::<f64>()
            } else {
                1.0 / sharers.len() as f64
            };
            return ((left as f64 * share / self.guide) as u32).clamp(1, left);
        }
        let most = if left > self.reserve {
            left - self.reserve
        } else {
            left
        };
        let (mine, cost) = (self.speed(by), self.tails[band].chunk_cost);
        let first_out = (0..self.tails.len())
            .filter(|&i| i != by && self.speed(i) > 0.0)
            .map(|i| {
                let t = &self.tails[i];
                f64::from_bits(t.busy_until.load(Ordering::Acquire))
                    + self.unclaimed(i) as f64 * t.chunk_cost / self.speed(i)
            })
            .fold(f64::INFINITY, f64::min);
        if mine > 0.0 && cost > 0.0 && first_out.is_finite() {
            let fits = ((first_out - now) * mine / cost).max(0.0);
            (fits.min(most as f64) as u32).max(1)
        } else {
            most
        }
    }

    fn speed(&self, band: usize) -> f64 {
        self.tails
            .get(band)
            .map_or(0.0, |t| f64::from_bits(t.speed.load(Ordering::Acquire)))
    }

    /// Claims a piece of `band`'s tail for `by` at `now`, from the front or the back: one
    /// compare-and-swap.
    fn take(&self, band: usize, by: usize, front: bool, now: f64) -> Option<Span> {
        let tail = self.tails.get(band)?;
        let mut seen = tail.ends.load(Ordering::Acquire);
        loop {
            let (f, b) = unpack(seen);
            if f >= b {
                return None;
            }
            let n = self.piece_size(band, by, b - f, now);
            let (lo, hi, next) = if front {
                (f, f + n, pack(f + n, b))
            } else {
                (b - n, b, pack(f, b - n))
            };
            match tail
                .ends
                .compare_exchange_weak(seen, next, Ordering::AcqRel, Ordering::Acquire)
            {
                Ok(_) => {
                    for h in &tail.holder[lo as usize..hi as usize] {
                        h.store(by, Ordering::Release);
                    }
                    let speed = self.speed(by);
                    if speed > 0.0 {
                        let done = now + n as f64 * tail.chunk_cost / speed;
                        self.tails[by]
                            .busy_until
                            .store(done.to_bits(), Ordering::Release);
                    }
                    let (lo, hi) = (lo as usize, hi as usize);
                    return Some(Span::new(tail.chunks[lo].begin, tail.chunks[hi - 1].end));
                }
                Err(current) => seen = current,
            }
        }
    }

    /// The chunks tracer `slot` claimed, joined where they touch: what is lost with it when
    /// it fails before handing them in.
    pub fn held_by(&self, slot: usize) -> Vec<Span> {
        let mut held: Vec<Span> = Vec::new();
        for tail in &self.tails {
            for (chunk, holder) in tail.chunks.iter().zip(&tail.holder) {
                if holder.load(Ordering::Acquire) != slot {
                    continue;
                }
                match held.last_mut() {
                    Some(last) if last.end == chunk.begin => last.end = chunk.end,
                    _ => held.push(*chunk),
                }
            }
        }
        held
    }

    /// Chunks nobody claimed (none once the tracers are done, unless every one of them failed).
    pub fn unclaimed_chunks(&self) -> Vec<Span> {
        self.tails
            .iter()
            .flat_map(|t| {
                let (f, b) = unpack(t.ends.load(Ordering::Acquire));
                t.chunks[f as usize..b.max(f) as usize].to_vec()
            })
            .collect()
    }
}

/// What a tracer's `planned` band would have taken at the speed it rendered at, from its
/// `seconds` for what it `rendered` (its band less what others took, plus what it took from
/// them), by the frame's line costs: what the balancer learns, so that it learns the speed of
/// the tracer, not the luck of the claims.
pub fn unstolen_seconds(
    line_costs: &[f64],
    width: u32,
    planned: Span,
    rendered: &[Span],
    seconds: f64,
) -> f64 {
    let done: f64 = rendered
        .iter()
        .map(|&s| span_cost(line_costs, width, s))
        .sum();
    let band = span_cost(line_costs, width, planned);
    if done > 0.0 && band > 0.0 {
        seconds * band / done
    } else {
        seconds
    }
}

/// The predicted cost of `span`: by the line costs, or its pixels over the width without them.
fn cost_of(line_costs: &[f64], width: u32, span: Span) -> f64 {
    if line_costs.is_empty() {
        span.len() as f64 / width.max(1) as f64
    } else {
        span_cost(line_costs, width, span)
    }
}

/// The chunks of `band`'s tail: from its end backwards, each `stealing.chunk` of the band's
/// cost, until they hold `stealing.tail` of it; the head keeps at least a pixel.
fn tail_chunks(band: Span, width: u32, line_costs: &[f64], stealing: &Stealing) -> Vec<Span> {
    let width = width.max(1);
    // Cost of the band's pixels in order, a pixel its line's cost over the width.
    let pixel_cost = |p: u32| {
        let y = (p / width) as usize;
        let line = if line_costs.is_empty() {
            1.0
        } else {
            line_costs.get(y).copied().unwrap_or(0.0).max(0.0)
        };
        line / width as f64
    };
    let total = cost_of(line_costs, width, band);
    let chunk = stealing.chunk * total;
    // Chunks whole: the tail is as many as fit its share.
    let count = (stealing.tail / stealing.chunk + 1e-9).floor() as u32;
    if band.len() < 2 || chunk.is_nan() || chunk <= 0.0 || count == 0 {
        return Vec::new();
    }
    let mut chunks = Vec::new();
    // Walk back from the band's end, a line at a time where the next cut lies beyond it, else
    // a pixel at a time; chunk k ends where the cost walked reaches k chunks.
    let (mut end, mut p, mut walked) = (band.end, band.end, 0.0);
    while p > band.begin + 1 && (chunks.len() as u32) < count {
        let target = chunk * (chunks.len() + 1) as f64;
        let c = pixel_cost(p - 1);
        let line_start = ((p - 1) / width * width).max(band.begin + 1);
        let run = (p - line_start) as f64 * c;
        if walked + run < target * (1.0 - 1e-9) {
            walked += run;
            p = line_start;
            continue;
        }
        walked += c;
        p -= 1;
        if walked >= target * (1.0 - 1e-9) {
            chunks.push(Span::new(p, end));
            end = p;
        }
    }
    chunks.reverse();
    chunks
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::sync::Arc;

    /// Settings the tests' numbers are worked out for (the defaults may be tuned).
    pub(crate) fn fixed() -> Stealing {
        Stealing {
            tail: 0.06,
            chunk: 0.004,
            reserve: 3,
            guide: 1.0,
            work_per_overhead: 4.0,
            pieces_worth: 2.0,
        }
    }

    fn board(planned: &[Span], width: u32, costs: &[f64]) -> ClaimBoard {
        ClaimBoard::new(planned, width, costs, &fixed(), 0.0)
    }

    #[test]
    fn a_tail_holds_its_share_of_the_band_in_chunks_of_equal_cost() {
        let costs: Vec<f64> = (0..100).map(|y| if y < 60 { 1.0 } else { 9.0 }).collect();
        let band = Span::lines(50, 40, 100);
        let s = Stealing {
            tail: 0.1,
            chunk: 0.02,
            ..fixed()
        };
        let chunks = tail_chunks(band, 50, &costs, &s);
        let total = span_cost(&costs, 50, band);
        assert_eq!(chunks.len(), 5, "{chunks:?}");
        for c in &chunks {
            let share = span_cost(&costs, 50, *c) / total;
            assert!((share - 0.02).abs() < 0.001, "{c:?}: {share}");
        }
        assert_eq!(chunks.last().unwrap().end, band.end);
        assert!(chunks.windows(2).all(|w| w[0].end == w[1].begin));
        // A floor on the chunk (a dispatch's overhead) makes them fewer and larger.
        let b = ClaimBoard::new(&[band], 50, &costs, &s, 0.05);
        assert_eq!(b.chunks(), 2);
    }

    #[test]
    fn while_nobody_is_hungry_the_owner_leaves_only_its_reserve() {
        let planned = [Span::lines(10, 0, 50), Span::lines(10, 50, 100)];
        let b = board(&planned, 10, &[1.0; 100]);
        let chunks = b.tails[0].chunks.clone();
        assert_eq!(chunks.len(), 15, "{chunks:?}");
        let own = b.claim(0, 1.0).unwrap();
        assert_eq!((own.owner, own.stolen), (0, false));
        assert_eq!(own.span, Span::new(chunks[0].begin, chunks[11].end));
        // Tracer 1 takes its own tail but the reserve, then the reserve itself...
        assert_eq!(b.claim(1, 1.0).unwrap().span.end, b.tails[1].chunks[11].end);
        assert_eq!(b.claim(1, 1.0).unwrap().span.end, planned[1].end);
        // ...and now hungry, takes tracer 0's reserve from the back, shared with the owner
        // (guide 1: half of 3, a chunk).
        let stolen = b.claim(1, 1.0).unwrap();
        assert_eq!((stolen.owner, stolen.stolen), (0, true));
        assert_eq!(stolen.span, chunks[14]);
        assert!(b.held_by(1).contains(&stolen.span));
        // The owner, with someone hungry, shares what is left too.
        assert_eq!(b.claim(0, 1.0).unwrap().span, chunks[12]);
        assert_eq!(b.claim(1, 1.0).unwrap().span, chunks[13]);
        assert!(b.claim(0, 1.0).is_none() && b.claim(1, 1.0).is_none());
    }

    /// Every pixel of the frame in exactly one head or claimed piece, with any number of
    /// tracers claiming at once.
    #[test]
    fn concurrent_claims_hand_out_every_chunk_exactly_once() {
        let width = 33;
        let planned = [
            Span::new(0, 700),
            Span::new(700, 2000),
            Span::new(2000, 2900),
            Span::new(2900, 3300),
        ];
        let costs: Vec<f64> = (0..100).map(|y| 1.0 + (y % 7) as f64).collect();
        for reserve in [0, 3, 1000] {
            let s = Stealing {
                tail: 0.5,
                chunk: 0.01,
                reserve,
                guide: 1.0,
                work_per_overhead: 0.0,
                pieces_worth: 0.0,
            };
            let b = Arc::new(ClaimBoard::new(&planned, width, &costs, &s, 0.0));
            assert!(b.chunks() > 100);
            let threads: Vec<_> = (0..planned.len())
                .map(|slot| {
                    let b = Arc::clone(&b);
                    std::thread::spawn(move || {
                        let mut got = vec![b.head(slot)];
                        while let Some(p) = b.claim(slot, 1.0) {
                            got.push(p.span);
                        }
                        got
                    })
                })
                .collect();
            let mut covered = vec![0u8; 3300];
            for t in threads {
                for span in t.join().unwrap() {
                    for p in span.begin..span.end {
                        covered[p as usize] += 1;
                    }
                }
            }
            assert!(covered.iter().all(|&c| c == 1), "reserve {reserve}");
            assert!(b.unclaimed_chunks().is_empty());
        }
    }

    #[test]
    fn small_bands_and_no_tail_keep_the_band_whole() {
        let none = Stealing {
            tail: 0.0,
            ..Stealing::default()
        };
        let b = ClaimBoard::new(&[Span::new(0, 1), Span::new(1, 90)], 10, &[], &none, 0.0);
        assert_eq!(
            (b.head(0), b.head(1), b.chunks()),
            (Span::new(0, 1), Span::new(1, 90), 0)
        );
        assert!(b.claim(0, 1.0).is_none());
        assert!(Stealing {
            chunk: 0.0,
            ..Stealing::default()
        }
        .validate()
        .is_err());
    }

    #[test]
    fn a_first_frame_shares_most_of_each_band() {
        let planned = [Span::lines(10, 0, 50), Span::lines(10, 50, 100)];
        let b = board(&planned, 10, &[]);
        assert_eq!(b.head(0), Span::lines(10, 0, 10));
        assert_eq!(b.chunks(), 30);
    }

    #[test]
    fn shared_chunks_go_by_the_sharers_speeds() {
        let planned = [Span::lines(10, 0, 50), Span::lines(10, 50, 100)];
        let stealing = Stealing {
            tail: 0.5,
            chunk: 0.01,
            reserve: 0,
            ..fixed()
        };
        let b = ClaimBoard::new(&planned, 10, &[1.0; 100], &stealing, 0.0);
        // Tracer 0 done with its head (25 lines) after 1 s, its tail too...
        assert_eq!(b.claim(0, 1.0).unwrap().span, Span::lines(10, 25, 50));
        // ...and tracer 1, 3 times as slow, takes a quarter of its own tail (12 of 50 chunks
        // of 5 pixels), tracer 0 three quarters of what is left.
        assert_eq!(b.claim(1, 3.0).unwrap().span.len(), 60);
        let stolen = b.claim(0, 2.0).unwrap();
        assert_eq!((stolen.stolen, stolen.span.len()), (true, 140));
    }
}

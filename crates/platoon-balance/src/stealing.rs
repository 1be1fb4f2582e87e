//! How a renderer steals within a frame (`steal`): the options, plain data a balancer may
//! carry (`Balancer::stealing`).

/// How a band's end is cut into chunks others may claim.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stealing {
    /// Share of each band's predicted cost left in its tail.
    pub tail: f64,
    /// A chunk's predicted cost as a share of its band's (at least; see `ClaimBoard::new`).
    pub chunk: f64,
    /// Chunks an owner leaves at the back of its tail for others while every other tracer
    /// still has chunks of its own.
    pub reserve: u32,
    /// Once others share a tail (they have none of their own left), a claim takes its share
    /// of the unclaimed chunks by speed, divided by this (at least one chunk).
    pub guide: f64,
    /// A chunk's predicted work is at least this many times a piece's overhead (`min_chunk`).
    pub work_per_overhead: f64,
    /// A frame is stolen only when the idle a tracer is expected to have without stealing
    /// exceeds this many pieces' overhead (`StealHistory::board`).
    pub pieces_worth: f64,
}

impl Default for Stealing {
    /// Chosen on the tuning maps (scenes/costs/tune), the mean of their four columns at three
    /// overheads of a piece (none, 20 us, lavapipe's 380 us), never on the judged maps
    /// (docs/BALANCING.md, "Stealing the trailing lines").
    fn default() -> Stealing {
        Stealing {
            tail: 0.03,
            chunk: 0.001,
            reserve: 2,
            guide: 2.0,
            work_per_overhead: 4.0,
            pieces_worth: 8.0,
        }
    }
}

impl Stealing {
    pub fn validate(&self) -> Result<(), String> {
        let share = |v: f64| v.is_finite() && (0.0..=1.0).contains(&v);
        if !share(self.tail) || !share(self.chunk) || self.chunk <= 0.0 {
            return Err(format!(
                "stealing: the tail ({}) and the chunk ({}) are shares of a band in [0, 1], \
                 the chunk above 0",
                self.tail, self.chunk
            ));
        }
        if !(self.work_per_overhead.is_finite() && self.work_per_overhead >= 0.0) {
            return Err(format!(
                "stealing: the work per overhead ({}) must be non-negative",
                self.work_per_overhead
            ));
        }
        if !(self.guide.is_finite() && self.guide >= 1.0) {
            return Err(format!(
                "stealing: the guide ({}) must be at least 1",
                self.guide
            ));
        }
        Ok(())
    }
}

//! Dynamic workload scaling (Bikker 7.3.7): how much work each frame does so that frames take
//! a target time. Frame time is nearly linear in the samples per frame, so the next rate is the
//! measured frame's rate scaled by target / measured, kept while the measured time is within
//! the hysteresis band and changed at most by a factor per frame.
//!
//! Below one sample a frame the rate can go on falling only through the options asked for:
//! - **Russian-roulette survival scaling** (unbiased): paths survive with a scaled-down
//!   probability from the first bounce on and survivors are weighted up; shorter paths, more
//!   noise.
//! - **Render-resolution scaling** (biased, reported): fewer pixels per axis (in sixteenths),
//!   upscaled into the film, which blends the frames in (a change of resolution is not a move
//!   of the view: the film goes on converging, as a mean).
//!
//! A frame's [`Workload::rate`] is what it really rendered (the quantised resolution's share
//! of the pixels), so the measured time is held against the work done, not the work wished.
//!
//! With both, roulette takes the rates from 1 down to 1/2 and resolution the rest.

use std::time::Duration;

/// How much work a frame does: what the workload scaler sets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Workload {
    pub spp: u32,
    /// Russian-roulette survival scale (`PathLoop::rr_survival`; 1: not scaled).
    pub rr_survival: f32,
    /// Render resolution per axis relative to the film (1: full; below 1 the frame is upscaled,
    /// a biased approximation).
    pub resolution: f32,
    /// The scaler's fractional rate behind this workload (samples a frame; below 1 the share
    /// of a one-sample frame's time it aims at): what a frame's measured time is held against.
    pub rate: f64,
}

impl Workload {
    /// `spp` samples a frame, nothing else scaled.
    pub fn samples(spp: u32) -> Workload {
        Workload {
            spp,
            rr_survival: 1.0,
            resolution: 1.0,
            rate: spp as f64,
        }
    }
}

/// The ways below one sample a frame, each off unless asked for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BelowOneSample {
    pub roulette: bool,
    pub resolution: bool,
}

/// Lowest rate the options go to: 1/16 of a one-sample frame.
const MIN_RATE: f64 = 1.0 / 16.0;
/// Lowest survival scale and resolution the options use.
const MIN_SURVIVAL: f64 = 0.1;
const MIN_RESOLUTION: f64 = 0.25;
/// The resolution moves in steps of this much.
const RESOLUTION_STEP: f64 = 1.0 / 16.0;

/// Adapts the samples per frame to hold a frame time. It keeps a fractional rate and renders
/// its nearest whole count: each frame then misses the target by at most half a sample (within
/// 10% from 5 samples a frame up), where handing out 8 and 9 for a rate of 8.5 would be right
/// on average but each frame a whole sample off.
#[derive(Clone, Debug)]
pub struct WorkloadScaler {
    pub target: Duration,
    /// Relative band around the target within which the rate is kept (e.g. 0.05).
    pub hysteresis: f64,
    /// Largest factor by which one frame may change the rate.
    pub max_step: f64,
    /// Share of the way to the rate a measure asks for that one frame goes (1: all of it).
    pub gain: f64,
    pub max_spp: u32,
    pub below_one: BelowOneSample,
    rate: f64,
}

impl WorkloadScaler {
    pub fn new(target: Duration, start_spp: u32) -> WorkloadScaler {
        WorkloadScaler {
            target,
            hysteresis: 0.05,
            max_step: 2.0,
            gain: 0.5,
            max_spp: 1 << 16,
            below_one: BelowOneSample::default(),
            rate: start_spp.max(1) as f64,
        }
    }

    /// The fractional samples per frame the scaler aims at.
    pub fn rate(&self) -> f64 {
        self.rate
    }

    fn min_rate(&self) -> f64 {
        if self.below_one.roulette || self.below_one.resolution {
            MIN_RATE
        } else {
            1.0
        }
    }

    /// The next frame's work.
    pub fn workload(&self) -> Workload {
        let rate = self.rate.clamp(self.min_rate(), self.max_spp.max(1) as f64);
        if rate >= 1.0 {
            let spp = (rate.round() as u32).clamp(1, self.max_spp.max(1));
            return Workload {
                rate: spp as f64,
                ..Workload::samples(spp)
            };
        }
        let (survival, area) = match (self.below_one.roulette, self.below_one.resolution) {
            (true, false) => (rate.max(MIN_SURVIVAL), 1.0),
            (false, true) => (1.0, rate),
            _ if rate >= 0.5 => (rate, 1.0),
            _ => (0.5, rate / 0.5),
        };
        let resolution =
            ((area.sqrt() / RESOLUTION_STEP).round() * RESOLUTION_STEP).clamp(MIN_RESOLUTION, 1.0);
        Workload {
            spp: 1,
            rr_survival: survival as f32,
            resolution: resolution as f32,
            // The work done: the survival's share (as the scaler counts it) of the pixels kept.
            rate: survival * resolution * resolution,
        }
    }

    /// Takes the measured time of a frame rendered at `rate` (its [`Workload::rate`]) and
    /// returns the next frame's work.
    pub fn observe(&mut self, frame_time: Duration, rate: f64) -> Workload {
        let (measured, target) = (frame_time.as_secs_f64(), self.target.as_secs_f64());
        if measured > 0.0 && target > 0.0 && (measured / target - 1.0).abs() > self.hysteresis {
            // Frame time is nearly linear in the rate: the rate that frame would have needed.
            let wanted = rate.max(f64::MIN_POSITIVE) * target / measured;
            let (lo, hi) = (self.rate / self.max_step, self.rate * self.max_step);
            // Half way there: one noisy frame moves the rate half as far.
            let wanted = (self.rate + self.gain * (wanted - self.rate)).max(f64::MIN_POSITIVE);
            self.rate = wanted
                .clamp(lo, hi)
                .clamp(self.min_rate(), self.max_spp.max(1) as f64);
        }
        self.workload()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tracer of known cost: 2 ms plus 0.7 ms a sample, with deterministic noise.
    fn synthetic_frame(spp: u32, frame: u32, noise: f64) -> Duration {
        let wobble = ((frame.wrapping_mul(2654435761) >> 8) % 1000) as f64 / 1000.0 - 0.5;
        Duration::from_secs_f64((2.0 + 0.7 * spp as f64) * (1.0 + noise * wobble) * 1e-3)
    }

    #[test]
    fn workload_scaling_settles_within_ten_percent_of_the_target() {
        for (start, noise) in [(1, 0.0), (200, 0.0), (1, 0.08), (64, 0.08)] {
            let target = Duration::from_millis(16);
            let mut s = WorkloadScaler::new(target, start);
            let mut work = s.workload();
            let times: Vec<f64> = (0..60)
                .map(|f| {
                    let t = synthetic_frame(work.spp, f, noise);
                    work = s.observe(t, work.rate);
                    t.as_secs_f64() / target.as_secs_f64()
                })
                .collect();
            let settled = &times[15..];
            assert!(
                settled.iter().all(|r| (r - 1.0).abs() <= 0.1),
                "start {start}, noise {noise}: {times:?}"
            );
        }
    }

    /// One sample costs 40 ms at full resolution and survival; the work scales with the pixels
    /// and (for the part after the first bounce, 3/4 of it) with the survival scale.
    fn costly_frame(w: Workload) -> Duration {
        let pixels = (w.resolution as f64).powi(2);
        let per_sample = 10.0 + 30.0 * w.rr_survival as f64;
        Duration::from_secs_f64(pixels * per_sample * w.spp as f64 * 1e-3)
    }

    #[test]
    fn below_one_sample_only_the_options_asked_for_scale_and_they_hold_the_target() {
        let target = Duration::from_millis(10);
        for (roulette, resolution) in [(false, false), (true, false), (false, true), (true, true)] {
            let mut s = WorkloadScaler::new(target, 4);
            s.below_one = BelowOneSample {
                roulette,
                resolution,
            };
            let mut work = s.workload();
            let mut last = Vec::new();
            for f in 0..80 {
                let t = costly_frame(work);
                if f >= 60 {
                    last.push((t.as_secs_f64() / target.as_secs_f64(), work));
                }
                work = s.observe(t, work.rate);
            }
            let (ratio, w) = last[last.len() - 1];
            assert_eq!(w.spp, 1);
            assert_eq!(w.rr_survival < 1.0, roulette, "{w:?}");
            assert_eq!(w.resolution < 1.0, resolution, "{w:?}");
            if !roulette && !resolution {
                // One sample a frame is as low as it goes: the target is missed, 4x over.
                assert!(ratio > 3.5, "{ratio}");
            } else if resolution {
                // Resolution steps of a sixteenth: about 10% of the area at half resolution.
                assert!(
                    last.iter().all(|(r, _)| (r - 1.0).abs() <= 0.15),
                    "{last:?}"
                );
            } else {
                // Roulette alone bottoms out at survival 0.1: 13 ms of the 10 wanted.
                assert!((ratio - 1.3).abs() < 0.05, "{ratio} {w:?}");
            }
        }
    }
}

//! The plan of each game frame, decided in one place (issue 9, after Cycles' session and
//! Bikker's chapter 7): how many samples, where their indices start, how the new samples join
//! the film, and whether the balancer cuts the frame anew. The frame driver carries the plan
//! out; nothing else decides these.
//!
//! Rebalancing (as Cycles' scheduler rebalances only when the devices' times drift apart): after
//! anything moved the lines' costs have changed, so the balancer cuts anew; while nothing moves
//! the last cut stays as long as the devices idled at most `REBALANCE_IDLE` in the last frame,
//! and at most `REBALANCE_EVERY` frames, so that a converging view does not chase the noise of
//! its timings (the balancer still learns from every frame).
//!
//! Joining (Bikker 7.3.5) is `C = C_prev (1 - f) + C_new f`:
//! - camera moved: the film restarts (f = 1), the sample indices from 0;
//! - camera and scene still: f = 1/k over the k frames since the restart, which is a plain sum
//!   of samples, so the plan asks for a sum and continues the sample indices: k still frames of
//!   s samples are the offline render of k s samples;
//! - only objects moved: f = max(1/k, floor), so that moving objects leave no ghost. Once a
//!   film has been blended it holds a weighted mean, not sums: later still frames go on blending
//!   with f = 1/k (still converging) until the camera moves.
//!
//! Dynamic workload scaling (Bikker 7.3.7): frame time is nearly linear in the samples per
//! frame, so the next rate is the measured frame's count scaled by target / measured, kept when
//! the measured time is within the hysteresis band and changed at most by a factor per frame.
//! Below one sample a frame two options go on, each off unless asked for: Russian-roulette
//! survival scaling (paths end sooner, survivors weighted up: unbiased, noisier) and render
//! resolution scaling (fewer pixels, upscaled into the film: biased, reported). A frame at a
//! reduced resolution holds a mean, not exact sums, so the film blends (f = 1/k while still, and
//! with the floor when the resolution changes).

use super::scaling::Workload;

/// What moved since the previous frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Motion {
    pub camera: bool,
    /// Any object, light, material or the environment.
    pub scene: bool,
}

/// How a frame's samples join the film.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Join {
    /// The film is this frame's samples alone.
    Restart,
    /// Added to the sums of the previous frames (the exact f = 1/k of a still view).
    Sum,
    /// Blended in with weight `f` (objects moved under a still camera).
    Blend { f: f32 },
}

impl Join {
    /// The weight of the new samples in the film: what the frame reports.
    pub fn weight(&self, frames_joined: u32) -> f32 {
        match *self {
            Join::Restart => 1.0,
            Join::Sum => 1.0 / frames_joined.max(1) as f32,
            Join::Blend { f } => f,
        }
    }
}

/// One frame's plan.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FramePlan {
    pub spp: u32,
    /// Russian-roulette survival scale and render resolution of the frame (see [`Workload`]).
    pub rr_survival: f32,
    pub resolution: f32,
    /// The workload's rate, for the scaler.
    pub rate: f64,
    /// Index of the frame's first sample: after a restart 0, then continuing, so that the
    /// random numbers of a converging view never repeat (wrapping at 2^32).
    pub first_sample: u32,
    pub join: Join,
    /// Frames in the film including this one (k of f = 1/k).
    pub frames_joined: u32,
    /// The balancer cuts this frame anew (false: the previous frame's bands again).
    pub rebalance: bool,
}

/// Idle share of the last frame above which a still view is cut anew.
pub const REBALANCE_IDLE: f64 = 0.02;
/// A still view is cut anew at least every this many frames (devices drift: clocks, load).
pub const REBALANCE_EVERY: u32 = 16;

/// Decides each frame's join from what moved.
#[derive(Clone, Debug)]
pub struct Planner {
    /// Smallest weight of new samples while objects move (Bikker uses about 0.2).
    pub floor: f32,
    frames_joined: u32,
    next_sample: u32,
    /// The film holds a blended mean since the last restart.
    blended: bool,
    /// Frames since the balancer last cut anew.
    since_rebalance: u32,
    /// Render resolution of the last frame.
    resolution: f32,
}

impl Planner {
    /// `floor` is clamped into (0, 1].
    pub fn new(floor: f32) -> Planner {
        let floor = if floor.is_finite() {
            floor.clamp(f32::MIN_POSITIVE, 1.0)
        } else {
            1.0
        };
        Planner {
            floor,
            frames_joined: 0,
            next_sample: 0,
            blended: false,
            since_rebalance: 0,
            resolution: 1.0,
        }
    }

    /// The plan of the next frame doing `work` after `motion`; `last_idle` is the idle share
    /// of the frame before (None when there was none).
    pub fn plan(&mut self, motion: Motion, work: Workload, last_idle: Option<f64>) -> FramePlan {
        let spp = work.spp;
        let resized = work.resolution != self.resolution;
        self.resolution = work.resolution;
        // A changed resolution changes every line's cost and the film's detail, not the view:
        // blended in like moving objects (restarting would lose the film at every step).
        let motion = Motion {
            camera: motion.camera,
            scene: motion.scene || resized,
        };
        let rebalance = motion.camera
            || motion.scene
            || self.frames_joined == 0
            || self.since_rebalance + 1 >= REBALANCE_EVERY
            || last_idle.is_none_or(|i| i.is_nan() || i > REBALANCE_IDLE);
        self.since_rebalance = if rebalance {
            0
        } else {
            self.since_rebalance + 1
        };
        let join = if motion.camera || self.frames_joined == 0 {
            self.frames_joined = 0;
            self.next_sample = 0;
            self.blended = false;
            Join::Restart
        } else if motion.scene {
            self.blended = true;
            let f = (1.0 / (self.frames_joined + 1) as f32).max(self.floor);
            Join::Blend { f }
        } else if self.blended || work.resolution < 1.0 {
            // An upscaled frame is a mean, not sums: the film converges as a mean.
            Join::Blend {
                f: 1.0 / (self.frames_joined + 1) as f32,
            }
        } else {
            Join::Sum
        };
        self.frames_joined += 1;
        let plan = FramePlan {
            spp,
            rr_survival: work.rr_survival,
            resolution: work.resolution,
            rate: work.rate,
            first_sample: self.next_sample,
            join,
            frames_joined: self.frames_joined,
            rebalance,
        };
        self.next_sample = self.next_sample.wrapping_add(spp);
        plan
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STILL: Motion = Motion {
        camera: false,
        scene: false,
    };

    #[test]
    fn a_still_view_sums_and_continues_the_sample_indices() {
        let mut p = Planner::new(0.2);
        let plans: Vec<FramePlan> = (0..4)
            .map(|_| p.plan(STILL, Workload::samples(8), None))
            .collect();
        assert_eq!(plans[0].join, Join::Restart);
        for (k, plan) in plans.iter().enumerate().skip(1) {
            assert_eq!(plan.join, Join::Sum);
            assert_eq!(plan.first_sample, 8 * k as u32);
            assert_eq!(plan.join.weight(plan.frames_joined), 1.0 / (k + 1) as f32);
        }
    }

    #[test]
    fn a_still_balanced_view_keeps_its_cut_and_motion_or_imbalance_cuts_anew() {
        let mut p = Planner::new(0.2);
        let balanced = Some(0.005);
        assert!(
            p.plan(STILL, Workload::samples(4), None).rebalance,
            "the first frame"
        );
        let still: Vec<bool> = (0..20)
            .map(|_| p.plan(STILL, Workload::samples(4), balanced).rebalance)
            .collect();
        // Kept, but cut anew every REBALANCE_EVERY frames.
        let anew: Vec<usize> = (0..20).filter(|&k| still[k]).collect();
        assert_eq!(anew, vec![REBALANCE_EVERY as usize - 1]);
        assert!(
            p.plan(STILL, Workload::samples(4), Some(0.05)).rebalance,
            "idle above the threshold"
        );
        assert!(!p.plan(STILL, Workload::samples(4), balanced).rebalance);
        assert!(
            p.plan(STILL, Workload::samples(4), Some(f64::NAN))
                .rebalance,
            "an unknown idle"
        );
        let objects = Motion {
            camera: false,
            scene: true,
        };
        assert!(
            p.plan(objects, Workload::samples(4), balanced).rebalance,
            "objects moved"
        );
        let camera = Motion {
            camera: true,
            scene: false,
        };
        assert!(
            p.plan(camera, Workload::samples(4), balanced).rebalance,
            "the camera moved"
        );
    }

    #[test]
    fn a_moving_camera_restarts_and_moving_objects_keep_the_floor() {
        let mut p = Planner::new(0.2);
        for _ in 0..10 {
            p.plan(STILL, Workload::samples(4), None);
        }
        let moved = p.plan(
            Motion {
                camera: true,
                scene: false,
            },
            Workload::samples(4),
            None,
        );
        assert_eq!((moved.join, moved.first_sample), (Join::Restart, 0));
        let objects = Motion {
            camera: false,
            scene: true,
        };
        let weights: Vec<f32> = (0..12)
            .map(|_| {
                let plan = p.plan(objects, Workload::samples(4), None);
                plan.join.weight(plan.frames_joined)
            })
            .collect();
        assert_eq!(weights[0], 0.5);
        assert!(weights.iter().all(|&f| f >= 0.2), "{weights:?}");
        assert_eq!(*weights.last().unwrap(), 0.2);
        // Objects stop: the blended film goes on converging as 1/k, never back to sums.
        let still = p.plan(STILL, Workload::samples(4), None);
        assert_eq!(still.join, Join::Blend { f: 1.0 / 14.0 });
        assert_eq!(still.first_sample, 4 * 13);
    }

    /// A tracer whose frame costs 2 ms plus 0.7 ms per sample, with deterministic noise.

    #[test]
    fn the_floor_is_kept_sane() {
        assert_eq!(Planner::new(f32::NAN).floor, 1.0);
        assert_eq!(Planner::new(7.0).floor, 1.0);
        assert!(Planner::new(-1.0).floor > 0.0);
    }
}

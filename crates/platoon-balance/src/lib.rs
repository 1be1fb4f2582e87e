//! platoon-balance: workload balancing between tracers. Before each frame a policy decides
//! which pixels each tracer renders (contiguous bands, in tracer order), from what earlier frames measured.
//! Brigade's policies move whole lines; cost-aware cuts within a line.
//! The policies follow Bikker's Brigade (none, Robin Hood, Perfect, Perfect Smooth), Blender
//! Cycles' damped time equalising, and platoon's own cost-aware cut. One policy per file.
//!
//! It knows no frame, method or device: only [`Span`]s and what each tracer measured of them
//! (the scene crate lends [`replay`] its error type for a user's recorded costs), and the
//! summaries of measurements the benches share ([`measure`]). The core re-exports it as
//! `platoon_core::balance`, its `Span` as `platoon_core::frame::Span`.

mod cost_aware;
mod cycles;
mod equal_split;
pub mod measure;
mod perfect;
mod perfect_smooth;
mod policy;
pub mod replay;
mod robin_hood;
mod span;
pub mod steal;
pub mod steal_history;
mod stealing;
mod with_stealing;

pub use cost_aware::{fractional_cuts, spans_at, CostAware};
pub use cycles::CyclesDamped;
pub use equal_split::EqualSplit;
pub use perfect::Perfect;
pub use perfect_smooth::PerfectSmooth;
pub use robin_hood::RobinHood;
pub use span::Span;
pub use stealing::Stealing;
pub use with_stealing::WithStealing;

pub(crate) use policy::line_speeds;
pub use policy::{
    idle_fraction, line_bands, proportional, span_cost, Balancer, FrameMeasure, TracerFrame,
};

/// Names accepted by [`by_name`], in the order tables list them.
pub const NAMES: [&str; 6] = [
    "none",
    "robin-hood",
    "perfect",
    "perfect-smooth",
    "cycles",
    "cost-aware",
];

/// Every balancer with in-frame stealing of the bands' tails (`steal`): `<name>+steal`.
pub const STEALING_NAMES: [&str; 6] = [
    "none+steal",
    "robin-hood+steal",
    "perfect+steal",
    "perfect-smooth+steal",
    "cycles+steal",
    "cost-aware+steal",
];

/// What the names accepted by [`by_name`] are, for messages.
pub fn names_help() -> String {
    format!("one of {}, each with +steal", NAMES.join(", "))
}

/// The balancer of a name of [`NAMES`], or of [`STEALING_NAMES`]: the same policy, its bands'
/// tails taken by the tracers that run out first (`steal::Stealing::default()`).
pub fn by_name(name: &str) -> Option<Box<dyn Balancer>> {
    if let Some(i) = STEALING_NAMES.iter().position(|n| *n == name) {
        let inner = by_name(NAMES[i])?;
        return Some(Box::new(WithStealing {
            inner,
            name: STEALING_NAMES[i],
            stealing: Stealing::default(),
        }));
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Span;

    #[test]
    fn every_name_with_steal_plans_as_its_policy_and_steals() {
        for (plain, stolen) in NAMES.iter().zip(STEALING_NAMES) {
            let (mut a, mut b) = (by_name(plain).unwrap(), by_name(stolen).unwrap());
            assert_eq!((a.name(), b.name()), (*plain, stolen));
            assert_eq!(
                (a.stealing(), b.stealing()),
                (None, Some(steal::Stealing::default()))
            );
            assert_eq!(a.plan(7, 50, 3), b.plan(7, 50, 3));
        }
        assert!(by_name("cost-aware+steal+steal").is_none());
        assert!(names_help().contains("cost-aware"));
    }

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
        let map = crate::replay::CostMap {
            width: 7,
            frames: vec![costs; 5],
        };
        for name in NAMES {
            let mut b = by_name(name).unwrap();
            // replay() checks nothing itself: it plans, times and observes each frame.
            let idle = crate::replay::replay(&map, &[1.0, 0.5, 1.0 / 3.0], b.as_mut());
            assert!(idle.iter().all(|i| (0.0..1.0).contains(i)), "{name}");
            assert_covers(&b.plan(map.width, 50, 3), map.width * 50, name);
            b.remove_tracer(1);
            assert_covers(&b.plan(map.width, 50, 2), map.width * 50, name);
        }
    }
}

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
mod policy;
pub mod replay;
mod robin_hood;
pub mod steal;

pub use cost_aware::{fractional_cuts, spans_at, CostAware};
pub use cycles::CyclesDamped;
pub use equal_split::EqualSplit;
pub use perfect::Perfect;
pub use perfect_smooth::PerfectSmooth;
pub use robin_hood::RobinHood;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Span;

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

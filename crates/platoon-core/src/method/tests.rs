//! A frame's `Method` across the methods: the reference's (platoon-frame's) beside this
//! crate's.

use crate::method::igi::IgiOptions;
use crate::method::path::light_reuse::LightReuse;
use crate::method::path::world_cache::WorldCacheOptions;
use crate::method::path::{LearningOptions, PathTracing, ResampledLight};
use crate::method::Method;

#[test]
fn methods_are_equal_when_their_units_and_states_are() {
    let igi = |vpls| Method::new(IgiOptions::with_vpls(vpls));
    assert_eq!(igi(30), igi(30));
    assert_ne!(igi(30), igi(31));
    assert_ne!(igi(30), Method::path_tracing());
    assert_ne!(Method::path_tracing(), igi(30));
    assert_eq!(Method::default(), Method::path_tracing());
    assert!(Method::default().is_path_tracing() && !igi(30).is_path_tracing());
    assert_eq!(
        igi(30).state::<IgiOptions>(),
        Some(&IgiOptions::with_vpls(30))
    );
    assert!(igi(30).state::<PathTracing>().is_none());
    assert_eq!(igi(30).unit().name(), "igi");
    assert_eq!(igi(30).kind().name(), "igi");
}

#[test]
fn the_path_tracers_learner_gives_a_frame_of_another_method_nothing() {
    let both = PathTracing {
        resampled_light: Some(ResampledLight::new(8)),
        learning: LearningOptions {
            world_cache: Some(WorldCacheOptions::default()),
            light_reuse: Some(LightReuse::default()),
        },
        ..Default::default()
    };
    let mut learner = Method::new(both).unit().learning(1.0);
    let learner = learner.as_mut().unwrap().as_mut().unwrap();
    let igi = Method::new(IgiOptions::default());
    let mut m = igi.clone();
    learner.give(&mut m, None);
    assert_eq!(m, igi);
}

//! `platoon bench realtime` (issue 43): at equal frame time, each real-time technique lowers the
//! error of what the game shows against converged renders of the same frames, and their
//! combination lowers it most, in the many-light hall.

#[path = "../common/mod.rs"]
mod common;

use platoon_lab::realtime_bench::{self as rb, Options, Technique};

#[test]
fn each_technique_lowers_the_error_at_equal_time_and_both_together_most() {
    common::init();
    let o = Options {
        character: None,
        width: 48,
        height: 27,
        frames: 6,
        measured: 2,
        reference_spp: 128,
        devices: "lavapipe:1".into(),
        repeat: 2,
        techniques: vec![
            Technique::PLAIN,
            Technique::ATROUS,
            Technique::RESAMPLED,
            Technique::RESAMPLED_ATROUS,
        ],
        ..Default::default()
    };
    let rows = rb::run(&o, &mut |s| eprintln!("{s}")).unwrap();
    eprint!("{}", rb::text(&o, &rows));
    let of = |t: Technique| {
        rows.iter()
            .find(|r| r.technique == t)
            .unwrap_or_else(|| panic!("no row for {}", t.name()))
    };
    let plain = of(Technique::PLAIN).relmse;
    let (denoised, resampled, combined) = (
        of(Technique::ATROUS).relmse,
        of(Technique::RESAMPLED).relmse,
        of(Technique::RESAMPLED_ATROUS).relmse,
    );
    for r in &rows {
        assert!(r.relmse.is_finite() && r.flip.is_finite(), "{r:?}");
        assert!(r.spp_median >= 1.0, "{r:?}");
    }
    assert!(
        denoised < 0.7 * plain,
        "a-trous {denoised} vs plain {plain}"
    );
    assert!(
        resampled < 0.7 * plain,
        "resampled {resampled} vs plain {plain}"
    );
    assert!(
        combined < 0.25 * plain && combined < denoised && combined < resampled,
        "combined {combined}: plain {plain}, a-trous {denoised}, resampled {resampled}"
    );
    let json: serde_json::Value = serde_json::from_str(&rb::json(&rows)).unwrap();
    assert_eq!(json["rows"].as_array().unwrap().len(), 4);
}

//! Many tracers, one frame: identical bits for any number of tracers under every balancer, no
//! lost lines when a tracer dies, and the balance benchmark's published ordering.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::balance::steal::Stealing;
use platoon::core::balance::{by_name, NAMES};
use platoon::core::frame::FrameParams;
use platoon::core::method::path::PathKernel;
use platoon::devices::{create_tracers, DeviceSpec};
use platoon::schedule::renderer::{Renderer, TracerFailure};
use platoon::tracer::{Sampling, Tracer};
use platoon_lab::balance_bench as bb;
use platoon_test_support::fault::FaultInjector;

fn scene() -> platoon::Prepared {
    let scene = platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap();
    prepare(
        scene,
        platoon::EnvChoice::File(shared("envmaps/sunset.exr")),
    )
}

#[test]
fn images_are_bit_identical_for_one_two_and_three_tracers_under_every_balancer() {
    init();
    let prepared = scene();
    let params = FrameParams::new(16, 24, 3, prepared.camera);
    let reference = render(&prepared, &params, Sampling::Mis);
    for spec in ["lavapipe:1,1", "lavapipe:2,1,1"] {
        let spec: DeviceSpec = spec.parse().unwrap();
        let mut tracers = create_tracers(&spec, &prepared.gpu, true, Sampling::Mis).unwrap();
        // Both kernels of the path tracer: the streaming one's sums too are taken in sample
        // order per pixel, whatever the split.
        for kernel in [PathKernel::Mega, PathKernel::Streaming] {
            let params = FrameParams {
                method: common::in_kernel(&params.method, kernel),
                ..params.clone()
            };
            for (name, stealing) in NAMES.iter().flat_map(|n| [(n, None), (n, Some(greedy()))]) {
                let mut renderer = Renderer::new(tracers, by_name(name).unwrap());
                renderer.set_stealing(stealing);
                let mut pieces = 0;
                // Several frames, so that the balancers move the cuts between them.
                for _ in 0..4 {
                    let frame = renderer.render_frame(&params).unwrap();
                    assert!(
                        frame.film == reference,
                        "{spec} under {name} (stealing: {}) in the {} kernel: image differs",
                        stealing.is_some(),
                        kernel.name()
                    );
                    assert_eq!(frame.tracers.iter().map(|t| t.pixels).sum::<u32>(), 16 * 24);
                    assert_eq!(frame.rejected_samples, 0);
                    pieces += frame.tracers.iter().map(|t| t.pieces).sum::<u32>();
                }
                assert_eq!(pieces > 0, stealing.is_some(), "{spec} under {name}");
                tracers = renderer.into_tracers();
            }
        }
        for t in &tracers {
            assert_no_validation_messages(t);
        }
    }
}

/// Stealing on every frame, of long tails in small chunks, so that a few frames of a small
/// image are mostly claimed.
fn greedy() -> Stealing {
    Stealing {
        tail: 0.5,
        chunk: 0.05,
        reserve: 1,
        guide: 2.0,
        work_per_overhead: 0.0,
        pieces_worth: 0.0,
    }
}

/// `frames` frames of CesiumMan on three one-thread tracers under cost-aware (stealing as
/// `stealing` says), tracer 1 failing as `fault` makes it: each frame the one-tracer render's
/// bits. Returns the failures reported and the tracers left.
fn play_with_tracer_1_failing(
    fault: impl FnOnce(Tracer) -> FaultInjector<Tracer>,
    stealing: Option<Stealing>,
    frames: u32,
) -> (Vec<TracerFailure>, Vec<usize>) {
    init();
    let prepared = scene();
    let spec: DeviceSpec = "lavapipe:1,1,1".parse().unwrap();
    let tracers = create_tracers(&spec, &prepared.gpu, true, Sampling::Mis).unwrap();
    let mut renderer = Renderer::new(
        FaultInjector::one_failing(tracers, 1, fault),
        by_name("cost-aware").unwrap(),
    );
    renderer.set_stealing(stealing);
    let mut reference_tracer = tracer(&prepared, Sampling::Mis);
    let mut reports = Vec::new();
    for f in 0..frames {
        let mut params = FrameParams::new(16, 24, 2, prepared.camera);
        params.frame = f;
        let frame = renderer.render_frame(&params).expect("frame completes");
        assert!(
            frame.film == render_with(&mut reference_tracer, &params),
            "frame {f} is not complete"
        );
        reports.extend(frame.failures);
    }
    (reports, renderer.alive())
}

#[test]
fn a_tracer_dying_with_a_claimed_chunk_loses_no_pixel() {
    // Tracer 1 renders its head and fails on the first piece it claims (its second band of
    // a frame), whichever frame that is.
    let (reports, alive) = play_with_tracer_1_failing(
        |t| FaultInjector::failing_at_band_of_frame(t, 1),
        Some(greedy()),
        6,
    );
    assert_eq!(reports.len(), 1, "the failure is reported exactly once");
    assert_eq!(reports[0].tracer, 1);
    assert!(reports[0].message.contains("injected fault at band 1"));
    assert_eq!(alive, vec![0, 2]);
}

#[test]
fn a_tracer_killed_mid_run_loses_no_line_of_any_frame() {
    // Tracer 1 fails from frame 2 on, as a lost device would.
    let (reports, alive) =
        play_with_tracer_1_failing(|t| FaultInjector::failing_from(t, 2), None, 5);
    assert_eq!(reports.len(), 1, "the failure is reported exactly once");
    assert_eq!((reports[0].tracer, reports[0].frame), (1, 2));
    assert!(reports[0].message.contains("injected fault"));
    assert_eq!(alive, vec![0, 2]);
}

#[test]
fn replay_shows_the_published_ordering_and_cost_aware_beats_perfect_smooth() {
    let cells = bb::run(&bb::Options::default()).unwrap();
    // Two device counts, three camera paths: the orbits and the game.
    assert_eq!(cells.len(), 2 * 3 * NAMES.len());
    for devices in [2, 3] {
        for camera in ["slow", "fast", "game"] {
            let idle = |name| bb::cell(&cells, name, devices, camera).unwrap().idle_pct;
            assert!(
                idle("cost-aware") < idle("perfect-smooth"),
                "{devices}-{camera}: cost-aware {} vs perfect-smooth {}",
                idle("cost-aware"),
                idle("perfect-smooth")
            );
            for name in NAMES.iter().filter(|n| **n != "none") {
                assert!(
                    idle("none") > 3.0 * idle(name),
                    "none is not far worst in {devices}-{camera}"
                );
            }
        }
    }
    // Robin Hood is the weakest balancer on the fast camera with 3 devices.
    let worst = NAMES.iter().filter(|n| **n != "none").max_by(|a, b| {
        let i = |n: &str| bb::cell(&cells, n, 3, "fast").unwrap().idle_pct;
        i(a).total_cmp(&i(b))
    });
    assert_eq!(worst, Some(&"robin-hood"));
    let json = bb::json(&cells);
    assert!(
        json.starts_with(
            "[{\"balancer\":\"none\",\"stealing\":false,\"devices\":2,\"camera\":\"slow\",\"idle_pct\":"
        ),
        "{json}"
    );
}

#[test]
fn replayed_stealing_takes_up_what_cost_aware_leaves_even_at_lavapipes_overhead() {
    let options = bb::Options {
        stealing: true,
        ..bb::Options::default()
    };
    let cells = bb::run(&options).unwrap();
    for devices in [2, 3] {
        for camera in ["slow", "fast", "game"] {
            let idle = |row: &str| bb::cell(&cells, row, devices, camera).unwrap().idle_pct;
            // The stealing rows count the pieces' overhead (lavapipe's, as measured) as lost.
            for name in NAMES {
                let stolen = format!("{name}+steal");
                assert!(
                    idle(&stolen) < idle(name),
                    "{devices}-{camera}: {name} {} with stealing vs {} without",
                    idle(&stolen),
                    idle(name)
                );
            }
        }
    }
    // Free pieces: the tails take up all but a few hundredths of a percent.
    let free = bb::Options {
        dispatch_us: 0.0,
        claim_us: 0.0,
        ..options
    };
    let cells = bb::run(&free).unwrap();
    for c in cells.iter().filter(|c| c.label() == "cost-aware+steal") {
        assert!(
            c.idle_pct < 0.3,
            "{}-{}: {}",
            c.devices,
            c.camera,
            c.idle_pct
        );
    }
}

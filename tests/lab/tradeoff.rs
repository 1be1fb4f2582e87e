//! `platoon tradeoff` (issue 10): errors against a converged reference behave as theory says,
//! biased techniques show their floor, the figures are reproducible, bad references are refused
//! before any sweep.

#[path = "../common/mod.rs"]
mod common;

use common::*;
use platoon::core::frame::FrameParams;
use platoon::tracer::Sampling;
use platoon_lab::tradeoff::{self, metrics, Options, Row, Technique};

fn options(out: &std::path::Path, spp_list: &[u32], techniques: &[Technique]) -> Options {
    Options {
        width: 64,
        height: 64,
        spp_list: spp_list.to_vec(),
        techniques: techniques.to_vec(),
        seed: 7,
        repeat: 1,
        reference_spp: 2048,
        reference: None,
        out: out.to_path_buf(),
        scene_label: "test".into(),
    }
}

/// Width and height from a PNG's header.
fn png_size(path: &std::path::Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&bytes[1..4], b"PNG", "{}", path.display());
    let at = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (at(16), at(20))
}

fn md_has_flip_table(dir: &std::path::Path) -> bool {
    std::fs::read_to_string(dir.join("report.md"))
        .is_ok_and(|md| md.contains("Mean LDR-FLIP error"))
}

fn cornell() -> platoon::Prepared {
    prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Scene,
    )
}

fn rows_of<'a>(rows: &'a [Row], technique: &str) -> Vec<&'a Row> {
    rows.iter().filter(|r| r.technique == technique).collect()
}

/// A grey Lambertian sphere under a uniform sky: noise without fireflies, so one realisation's
/// RMSE follows its expectation closely.
fn sphere_under_sky() -> platoon::Prepared {
    let grey = platoon::core::scene::cornell::lambertian("grey", glam::Vec3::splat(0.5));
    prepare(sphere_scene(grey), constant_env(1.0))
}

#[test]
fn unbiased_error_falls_as_the_inverse_square_root() {
    init();
    let dir = tempfile::tempdir().unwrap();
    let spps = [4, 8, 16, 32, 64];
    for technique in [Technique::Mis, Technique::Bsdf] {
        // The reference's own noise must stay well below the 64-spp error: it would flatten
        // the curve (BSDF sampling is the better estimator under a uniform sky).
        let o = Options {
            reference_spp: 16384,
            ..options(dir.path(), &spps, std::slice::from_ref(&technique))
        };
        let report = tradeoff::run(&sphere_under_sky(), &o, &mut |_| {}).unwrap();
        let points: Vec<(f64, f64)> = report.rows.iter().map(|r| (r.spp as f64, r.rmse)).collect();
        let slope = metrics::log_log_slope(&points);
        eprintln!("{technique}: RMSE slope {slope}: {points:?}");
        assert!(
            (slope + 0.5).abs() <= 0.1,
            "{technique}: RMSE slope {slope}: {points:?}"
        );
    }
}

#[test]
fn a_depth_cap_and_a_clamp_leave_an_error_floor_that_samples_do_not_lower() {
    init();
    let dir = tempfile::tempdir().unwrap();
    let spps = [4, 8, 16, 32, 64];
    let clamp = Technique::parse("clamp=0.02").unwrap();
    let o = options(
        dir.path(),
        &spps,
        &[
            Technique::Mis,
            Technique::parse("max-depth=2").unwrap(),
            clamp,
            Technique::parse("single-bounce").unwrap(),
            Technique::parse("dpt").unwrap(),
        ],
    );
    let report = tradeoff::run(&cornell(), &o, &mut |_| {}).unwrap();
    assert_eq!(report.rows.len(), 25);
    let mis = rows_of(&report.rows, "mis");
    // Light after two segments is lost: more samples do not bring the capped paths to the
    // reference. At 64 spp the cap's error stands well above the unbiased one, and its
    // relative MSE has nearly stopped falling (a floor) while MIS's keeps falling.
    let capped = rows_of(&report.rows, "max-depth=2");
    let (m16, m64) = (mis[2], mis[4]);
    let (c16, c64) = (capped[2], capped[4]);
    assert!(capped.iter().all(|r| r.biased) && mis.iter().all(|r| !r.biased));
    assert!(c64.relmse > 5.0 * m64.relmse, "{c64:?} vs {m64:?}");
    assert!(
        c64.relmse > 0.7 * c16.relmse,
        "no floor: {c16:?} -> {c64:?}"
    );
    assert!(m64.relmse < 0.4 * m16.relmse, "{m16:?} -> {m64:?}");
    // The perceptual error falls with samples too, and stays higher with the depth cap.
    assert!(
        m64.flip < m16.flip && c64.flip > m64.flip,
        "{m64:?} {c64:?}"
    );
    assert!(md_has_flip_table(dir.path()));
    // Clamping the light after the first bounce loses energy the same way.
    let clamped = rows_of(&report.rows, "clamp=0.02");
    let (k16, k64) = (clamped[2], clamped[4]);
    assert!(
        k64.biased && k64.relmse > 3.0 * m64.relmse,
        "{k64:?} vs {m64:?}"
    );
    assert!(
        k64.relmse > 0.6 * k16.relmse,
        "no floor: {k16:?} -> {k64:?}"
    );
    // One diffuse bounce of indirect light: the Cornell box's interreflections are lost.
    let single = rows_of(&report.rows, "single-bounce");
    let (s16, s64) = (single[2], single[4]);
    assert!(
        s64.biased && s64.relmse > 3.0 * m64.relmse,
        "{s64:?} vs {m64:?}"
    );
    assert!(
        s64.relmse > 0.6 * s16.relmse,
        "no floor: {s16:?} -> {s64:?}"
    );
    // Deterministic termination truncates paths only past log2(spp) tests: at 64 spp its
    // bias is below the noise and its error falls like MIS's.
    let dpt = rows_of(&report.rows, "dpt");
    assert!(
        dpt[4].biased && dpt[4].relmse < 0.4 * dpt[2].relmse,
        "{dpt:?}"
    );
    // The CSV holds every row (it is rewritten after each); the plots, the report and its
    // images are written beside it.
    let csv = std::fs::read_to_string(dir.path().join("tradeoff.csv")).unwrap();
    assert_eq!(csv.lines().count(), 26);
    for png in ["tradeoff-error.png", "tradeoff-efficiency.png"] {
        let (w, h) = png_size(&dir.path().join(png));
        assert!(w >= 800 && h >= 400, "{png}: {w}x{h}");
    }
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(
        md.contains("| max-depth=2 (biased) |") && md.contains("| 64 spp |"),
        "{md}"
    );
    for image in [
        "reference",
        "mis",
        "mis-error",
        "max-depth-2",
        "clamp-0-02-error",
        "reference-crop",
        "mis-crop",
        "mis-error-crop",
    ] {
        assert!(
            md.contains(&format!("images/{image}.png")),
            "{image} not in the report"
        );
        let size = png_size(&dir.path().join("images").join(format!("{image}.png")));
        assert_eq!(size, (4 * 64, 4 * 64), "{image}");
    }
}

#[test]
fn unbiased_knobs_converge_to_the_reference_with_no_floor() {
    // The Cornell box open to a dim sky: two kinds of light of very different power, so
    // picking lights uniformly instead of by power changes where NEE samples go.
    init();
    let dir = tempfile::tempdir().unwrap();
    let lit = prepare(
        platoon::core::scene::cornell::scene(),
        platoon::EnvChoice::Color(glam::Vec3::splat(0.3)),
    );
    let knobs = [
        Technique::parse("uniform-lights").unwrap(),
        Technique::parse("rr-fixed=50").unwrap(),
        Technique::parse("rr-survival=40").unwrap(),
        Technique::Ris(4),
        Technique::MisRis(4),
    ];
    let o = options(
        dir.path(),
        &[16, 64],
        &[&[Technique::Mis, Technique::Light][..], &knobs].concat(),
    );
    let report = tradeoff::run(&lit, &o, &mut |_| {}).unwrap();
    for knob in knobs {
        let rows = rows_of(&report.rows, &knob.to_string());
        let (at16, at64) = (rows[0], rows[1]);
        // Four times the samples, about a quarter of the relative MSE: nothing left over.
        assert!(
            at64.relmse < 0.45 * at16.relmse,
            "{knob}: {at16:?} -> {at64:?}"
        );
        // And in the estimator's own league: RIS has no MIS (its M = 1 case is light
        // sampling), the others are MIS with another roulette or light pick.
        let league = if matches!(knob, Technique::Ris(_)) {
            "light"
        } else {
            "mis"
        };
        let peer = rows_of(&report.rows, league)[1];
        assert!(
            at64.relmse < 4.0 * peer.relmse,
            "{knob}: {at64:?} vs {peer:?}"
        );
        assert!(!at64.biased);
    }
    // RIS over 4 candidates beats picking one light by power, without MIS either way.
    let (ris, light) = (
        rows_of(&report.rows, "ris=4")[1],
        rows_of(&report.rows, "light")[1],
    );
    assert!(ris.relmse < light.relmse, "{ris:?} vs {light:?}");
    // And combining it with BSDF sampling by MIS (Bikker's MIS+RIS) beats RIS alone.
    let mis_ris = rows_of(&report.rows, "mis-ris=4")[1];
    assert!(mis_ris.relmse < ris.relmse, "{mis_ris:?} vs {ris:?}");
}

#[test]
fn the_errors_are_the_same_for_the_same_seed_and_the_reference_is_cached() {
    init();
    let (dir, second) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
    let prepared = cornell();
    let o = options(
        dir.path(),
        &[2, 4],
        &[Technique::Bsdf, Technique::parse("rr-depth=1").unwrap()],
    );
    let a = tradeoff::run(&prepared, &o, &mut |_| {}).unwrap();
    let b = tradeoff::run(
        &prepared,
        &Options {
            out: second.path().to_path_buf(),
            ..o.clone()
        },
        &mut |_| {},
    )
    .unwrap();
    // The report's images (renders and error maps) are the same bytes.
    for image in [
        "reference",
        "bsdf",
        "bsdf-error",
        "rr-depth-1",
        "rr-depth-1-error",
    ] {
        let read =
            |d: &std::path::Path| std::fs::read(d.join("images").join(format!("{image}.png")));
        assert_eq!(
            read(dir.path()).unwrap(),
            read(second.path()).unwrap(),
            "{image}"
        );
    }
    assert!(
        b.reference_loaded,
        "the second run reads the cached reference"
    );
    assert_eq!(a.reference, b.reference);
    let errors = |r: &[Row]| -> Vec<(String, u32, u64, u64)> {
        r.iter()
            .map(|r| {
                (
                    r.technique.clone(),
                    r.spp,
                    r.rmse.to_bits(),
                    r.relmse.to_bits(),
                )
            })
            .collect()
    };
    assert_eq!(errors(&a.rows), errors(&b.rows));
    // Another seed, other errors.
    let other = tradeoff::run(&prepared, &Options { seed: 8, ..o }, &mut |_| {}).unwrap();
    assert_ne!(errors(&a.rows), errors(&other.rows));
}

#[test]
fn a_reference_that_does_not_fit_is_refused_before_any_sweep() {
    init();
    let dir = tempfile::tempdir().unwrap();
    let prepared = cornell();
    let small = dir.path().join("small.exr");
    let film = platoon::core::output::Film {
        width: 8,
        height: 8,
        pixels: vec![[0.5; 3]; 64],
    };
    platoon::core::output::write_image(&small, &film, &[]).unwrap();
    let mut nan = film.clone();
    nan.width = 64;
    nan.height = 64;
    nan.pixels = vec![[0.5; 3]; 64 * 64];
    nan.pixels[5] = [f32::NAN, 0.0, 0.0];
    let bad = dir.path().join("nan.exr");
    platoon::core::output::write_image(&bad, &nan, &[]).unwrap();
    for (path, says) in [
        (small.clone(), "is 8x8"),
        (bad, "non-finite"),
        (dir.path().join("missing.exr"), "does not exist"),
    ] {
        let o = Options {
            reference: Some(path.clone()),
            ..options(dir.path(), &[1], &[Technique::Mis])
        };
        let e = tradeoff::run(&prepared, &o, &mut |_| {})
            .err()
            .expect("refused");
        let e = format!("{e:#}");
        assert!(
            e.contains(says) && e.contains(path.to_str().unwrap()),
            "{e}"
        );
        assert!(!dir.path().join("tradeoff.csv").exists(), "a sweep started");
    }
}

#[test]
fn each_technique_changes_the_kernel_only_through_its_own_defines() {
    init();
    let prepared = cornell();
    let base = FrameParams::new(16, 16, 1, prepared.camera);
    let defines = |t: &Technique| {
        let tracer = tracer(&prepared, t.sampling());
        let mut p = base.clone();
        t.apply(&mut p);
        tracer.kernel_defines(&p)
    };
    let plain = defines(&Technique::Mis);
    for t in [
        Technique::parse("max-depth=2").unwrap(),
        Technique::parse("rr-depth=1").unwrap(),
        Technique::parse("rr-survival=50").unwrap(),
        Technique::NoRegeneration,
    ] {
        assert_eq!(defines(&t), plain, "{t} changed the kernel");
    }
    let with = |d: &'static str| {
        let mut v = plain.clone();
        v.push(d);
        v
    };
    let sorted = |mut v: Vec<&'static str>| {
        v.sort_unstable();
        v
    };
    assert_eq!(
        sorted(defines(&Technique::Bsdf)),
        sorted(with("SAMPLING_BSDF"))
    );
    assert_eq!(
        sorted(defines(&Technique::Light)),
        sorted(with("SAMPLING_LIGHT"))
    );
    assert_eq!(Technique::Light.sampling(), Sampling::Light);
    let clamp = Technique::parse("clamp=4").unwrap();
    assert_eq!(sorted(defines(&clamp)), sorted(with("CLAMP_INDIRECT")));
    assert_eq!(
        sorted(defines(&Technique::parse("uniform-lights").unwrap())),
        sorted(with("LIGHT_SELECT_UNIFORM"))
    );
    assert_eq!(
        sorted(defines(&Technique::parse("dpt").unwrap())),
        sorted(with("RR_DETERMINISTIC"))
    );
    assert_eq!(
        sorted(defines(&Technique::parse("single-bounce").unwrap())),
        sorted(with("SINGLE_DIFFUSE_BOUNCE"))
    );
    assert_eq!(
        sorted(defines(&Technique::Ris(4))),
        sorted(with("LIGHT_SELECT_RIS"))
    );
    let mut both = with("LIGHT_SELECT_RIS");
    both.push("RIS_MIS");
    assert_eq!(sorted(defines(&Technique::MisRis(4))), sorted(both));
    let generic = defines(&Technique::parse("generic-kernel").unwrap());
    for effect in [
        "HAS_TEXTURES",
        "HAS_TRANSMISSION",
        "HAS_ENVIRONMENT_MAP",
        "HAS_ALPHA_MASK",
    ] {
        assert!(
            generic.contains(&effect) && !plain.contains(&effect),
            "{effect}"
        );
    }
    let fixed = Technique::parse("rr-fixed=50").unwrap();
    assert_eq!(sorted(defines(&fixed)), sorted(with("RR_FIXED")));
}

#[test]
fn the_generated_glossy_glass_scene_loads_and_sweeps() {
    init();
    let dir = tempfile::tempdir().unwrap();
    let scene = load_generated(&platoon_scenegen::glossy_glass());
    let prepared = prepare(scene, platoon::EnvChoice::Scene);
    assert!(prepared.gpu.features.transmission && prepared.gpu.features.emissive_triangles);
    let o = Options {
        width: 16,
        height: 16,
        reference_spp: 64,
        ..options(dir.path(), &[1, 2], &[Technique::Mis, Technique::Bsdf])
    };
    let report = tradeoff::run(&prepared, &o, &mut |_| {}).unwrap();
    assert_eq!(report.rows.len(), 4);
    assert!(report
        .rows
        .iter()
        .all(|r| r.rmse.is_finite() && r.rmse > 0.0));
}

#[test]
fn a_generic_kernel_renders_the_specialised_kernels_image() {
    // Every effect compiled in (what a renderer that does not specialise runs) must change the
    // time only: the same estimator, the same random numbers, so the same image.
    init();
    let scenes = [
        cornell(),
        prepare(
            platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap(),
            constant_env(0.8),
        ),
        prepare(
            load_generated(&platoon_scenegen::glossy_glass()),
            platoon::EnvChoice::Scene,
        ),
    ];
    for prepared in &scenes {
        let mut t = tracer(prepared, Sampling::Mis);
        let params = FrameParams::new(24, 24, 4, prepared.camera);
        let mut generic = params.clone();
        generic.path_loop.generic_kernel = true;
        assert_ne!(t.kernel_defines(&params), t.kernel_defines(&generic));
        let a = render_with(&mut t, &params);
        let b = render_with(&mut t, &generic);
        assert!(
            a == b,
            "the generic kernel's image differs ({})",
            prepared.env_label
        );
    }
}

#[test]
fn each_effect_the_scene_uses_has_a_time_and_an_error_and_the_others_are_skipped() {
    // CesiumMan is textured and lit by an environment map; it has no normal maps and no
    // transmission.
    init();
    let dir = tempfile::tempdir().unwrap();
    let man = prepare(
        platoon::load_scene(Some(&shared("scenes/CesiumMan.glb"))).unwrap(),
        platoon::EnvChoice::File(shared("envmaps/courtyard.exr")),
    );
    let effects: Vec<Technique> = ["no-textures", "env-mean", "no-normal-maps", "opaque"]
        .iter()
        .map(|t| Technique::parse(t).unwrap())
        .collect();
    let o = Options {
        reference_spp: 512,
        ..options(
            dir.path(),
            &[32],
            &[&[Technique::Mis][..], &effects].concat(),
        )
    };
    let report = tradeoff::run(&man, &o, &mut |_| {}).unwrap();
    let names: Vec<&str> = report.rows.iter().map(|r| r.technique.as_str()).collect();
    assert_eq!(names, vec!["mis", "no-textures", "env-mean"]);
    assert_eq!(report.skipped.len(), 2, "{:?}", report.skipped);
    assert!(report.skipped[0].starts_with("no-normal-maps"));
    let mis = &report.rows[0];
    for r in &report.rows[1..] {
        // An approximation: biased, and further from the reference than the noise of MIS.
        assert!(
            r.biased && r.relmse > mis.relmse && r.flip > mis.flip,
            "{r:?} vs {mis:?}"
        );
    }
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(md.contains("Not run: no-normal-maps"), "{md}");
}

/// Vertex links sweep like any technique: biased, timed with their update, and on the built-in
/// box (its walls two triangles each) left with a floor of error the path tracer goes under;
/// the same box subdivided (`+sub3`: the same surfaces, 64 times the triangles) lowers it.
#[test]
fn vertex_links_sweep_against_the_path_tracer_with_their_update_timed() {
    init();
    let dir = tempfile::tempdir().unwrap();
    let links = Technique::parse("links=16+b2").unwrap();
    let subdivided = Technique::parse("links=16+b2+sub3").unwrap();
    let o = options(dir.path(), &[4, 64], &[Technique::Mis, links, subdivided]);
    let report = tradeoff::run(&cornell(), &o, &mut |_| {}).unwrap();
    let (mis, l, sub) = (
        rows_of(&report.rows, "mis"),
        rows_of(&report.rows, "links=16+b2"),
        rows_of(&report.rows, "links=16+b2+sub3"),
    );
    assert_eq!((l.len(), sub.len()), (2, 2));
    assert!(l.iter().all(|r| r.biased && r.ms > 0.0) && !mis[0].biased);
    assert!(
        l[1].relmse > 3.0 * mis[1].relmse,
        "{:?} vs {:?}",
        l[1],
        mis[1]
    );
    println!(
        "relative MSE at 64 spp: mis {:.5}, links {:.5}, subdivided {:.5}",
        mis[1].relmse, l[1].relmse, sub[1].relmse
    );
    assert!(
        sub[1].relmse - mis[1].relmse < 0.5 * (l[1].relmse - mis[1].relmse),
        "subdividing did not lower the floor: {:?} vs {:?}",
        sub[1],
        l[1]
    );
}

/// A technique whose resampled light weighs lights by emitted luminance is skipped on a scene
/// with a point light, for the reason the tracer would refuse it (`ResampledLight::check_lights`),
/// while the others run.
#[test]
fn resampled_light_by_luminance_is_skipped_where_punctual_lights_are() {
    init();
    let dir = tempfile::tempdir().unwrap();
    let mut scene = platoon::core::scene::cornell::scene();
    let point = platoon::core::scene::LightKind::Point;
    add_light(&mut scene, point, 1.0, glam::Vec3::new(0.0, 1.0, 0.0));
    let lit = prepare(scene, platoon::EnvChoice::Scene);
    assert!(lit.gpu.features.punctual_lights);
    let o = Options {
        width: 16,
        height: 16,
        reference_spp: 32,
        ..options(dir.path(), &[4], &[Technique::Mis, Technique::Ris(4)])
    };
    let report = tradeoff::run(&lit, &o, &mut |_| {}).unwrap();
    let names: Vec<&str> = report.rows.iter().map(|r| r.technique.as_str()).collect();
    assert_eq!(names, vec!["mis"]);
    assert_eq!(report.skipped.len(), 1, "{:?}", report.skipped);
    let why = &report.skipped[0];
    assert!(
        why.starts_with("ris=4: ") && why.contains("punctual"),
        "{why}"
    );
}

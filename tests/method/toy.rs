//! A method from outside platoon's crates (`toy/grey.rs`), registered at run time: found by
//! name, rendered through the front door with its pass after assembly, written as a technique
//! and read back, and refused when it would take a name or flag already there. (Over the ranks
//! of a game loop: tests/drive/game.rs.)

#[path = "../common/mod.rs"]
mod common;
#[path = "toy/grey.rs"]
mod toy;

use common::*;
use platoon::core::method::kind::MethodKind;
use platoon::core::method::registry;
use platoon::core::method::settings::Setting;
use platoon::core::method::technique;
use platoon::devices::DeviceSpec;
use platoon::Request;

#[test]
fn a_method_from_outside_is_registered_once_by_name() {
    toy::register();
    let kind = registry::kind("grey").expect("found by name");
    assert_eq!(kind.summary(), toy::GREY.summary());
    assert!(registry::names().ends_with("grey"), "{}", registry::names());
    let e = registry::register(&toy::GREY).unwrap_err();
    assert!(e.contains("a method named grey"), "{e}");
    // A method whose flag another has.
    struct Thief;
    const TAKEN: &[Setting] = &[Setting {
        key: "vpls",
        flag: "vpls",
        token: None,
        kind: platoon::core::method::settings::ValueKind::Count,
        help: "",
    }];
    impl MethodKind for Thief {
        fn name(&self) -> &'static str {
            "thief"
        }
        fn title(&self) -> &'static str {
            "thief"
        }
        fn summary(&self) -> &'static str {
            ""
        }
        fn settings(&self) -> &'static [Setting] {
            TAKEN
        }
        fn build(
            &self,
            _: &platoon::core::method::settings::Settings,
        ) -> Result<platoon::core::Method, String> {
            Err("never".into())
        }
        fn settings_of(
            &self,
            _: &platoon::core::Method,
        ) -> platoon::core::method::settings::Settings {
            Default::default()
        }
        fn sweep(&self) -> &'static [&'static str] {
            &[]
        }
        fn unit<'a>(
            &self,
            _: &'a platoon::core::Method,
        ) -> Option<&'a dyn platoon::core::method::render_method::RenderMethod> {
            None
        }
    }
    let e = registry::register(&Thief).unwrap_err();
    assert!(e.contains("--vpls of method igi"), "{e}");
}

#[test]
fn it_renders_through_the_front_door_with_its_own_pass() {
    let small = |method| Request {
        width: 24,
        height: 16,
        spp: 4,
        devices: DeviceSpec::Lavapipe(vec![1]),
        method,
        ..Default::default()
    };
    let colour = small(platoon::core::Method::path_tracing())
        .render(&mut |_| {})
        .unwrap();
    let grey = small(toy::grey(1.0, false)).render(&mut |_| {}).unwrap();
    let mut coloured = 0;
    for (g, c) in grey.image.pixels.iter().zip(&colour.image.pixels) {
        assert!(g[0] == g[1] && g[1] == g[2], "{g:?} is not grey");
        let y = toy::luminance(*c);
        assert!((g[0] - y).abs() <= 1e-5 * y.max(1.0), "{g:?} against {y}");
        coloured += (c[0] != c[1]) as u32;
    }
    assert!(coloured > 0, "the box has colour to take out");
    let meta = |k: &str| {
        grey.metadata
            .iter()
            .find(|(key, _)| key == k)
            .unwrap()
            .1
            .clone()
    };
    assert!(
        meta("method").contains("grey: the path tracer's image"),
        "{}",
        meta("method")
    );
    assert!(meta("approximations").contains("colour taken out at strength 1"));
    // Three tracers: the same bits.
    let three = Request {
        devices: DeviceSpec::Lavapipe(vec![1, 1, 1]),
        ..small(toy::grey(0.5, false))
    }
    .render(&mut |_| {})
    .unwrap();
    let one = small(toy::grey(0.5, false)).render(&mut |_| {}).unwrap();
    assert_eq!(three.image.pixels, one.image.pixels);
    assert_ne!(one.image.pixels, grey.image.pixels);
    // Its kernel option reaches the path kernel as a define.
    let short = small(toy::grey(1.0, true)).render(&mut |_| {}).unwrap();
    assert!(meta_of(&short, "kernel_defines").contains("SINGLE_DIFFUSE_BOUNCE"));
    assert!(
        mean(&short.image) < mean(&grey.image),
        "one bounce carries less light"
    );
}

fn meta_of(still: &platoon::Still, key: &str) -> String {
    still
        .metadata
        .iter()
        .find(|(k, _)| k == key)
        .unwrap()
        .1
        .clone()
}

#[test]
fn its_techniques_and_settings_come_from_its_description() {
    toy::register();
    let kind = registry::kind("grey").unwrap();
    let given = technique::parse(kind, "grey=0.5+onebounce", "0.5+onebounce").unwrap();
    assert_eq!(technique::format(kind, &given), "grey=0.5+onebounce");
    assert!(technique::parse(kind, "grey=2", "2")
        .unwrap_err()
        .contains("0..=1"));
    let method = kind.build(&given).unwrap();
    assert_eq!(kind.build(&method.settings()).unwrap(), method);
    init();
}

//! A method from outside platoon's crates (`toy/grey.rs`, its kernel `toy/grey.comp`),
//! registered at run time with both halves: found by name, rendered through the front door by
//! its own kernel, written as a technique and read back, and refused when it would take a
//! name, a flag or a kernel source's name already there. (Over the ranks
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
use platoon::tracer::device::DeviceMethodKind;
use platoon::Request;

#[test]
fn a_method_from_outside_is_registered_once_by_name() {
    toy::register();
    let kind = registry::kind("grey").expect("found by name");
    assert_eq!(kind.summary(), toy::GREY.summary());
    assert!(registry::names().ends_with("grey"), "{}", registry::names());
    let e = registry::register(&toy::GREY).unwrap_err();
    assert!(e.contains("a method named grey"), "{e}");
    // A method whose flag another has, and one whose name and flags are free.
    struct Stranger(&'static str, &'static [Setting]);
    const TAKEN: &[Setting] = &[Setting {
        key: "vpls",
        flag: "vpls",
        token: None,
        kind: platoon::core::method::settings::ValueKind::Count,
        help: "",
    }];
    impl MethodKind for Stranger {
        fn name(&self) -> &'static str {
            self.0
        }
        fn title(&self) -> &'static str {
            self.0
        }
        fn summary(&self) -> &'static str {
            ""
        }
        fn settings(&self) -> &'static [Setting] {
            self.1
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
    }
    static THIEF: Stranger = Stranger("thief", TAKEN);
    static FREE_KIND: Stranger = Stranger("free", &[]);
    let e = registry::register(&THIEF).unwrap_err();
    assert!(e.contains("--vpls of method igi"), "{e}");
    // Both halves, refused for the kind's flag; a device half whose shader would take a file
    // of shaders/, or named for another method: refused, and nothing of the method registered.
    static SHADOW: DeviceMethodKind = DeviceMethodKind {
        name: "thief",
        shaders: &[("thief/thief.comp", "")],
        passes: platoon::tracer::device::path_passes,
    };
    let e = platoon::register_method(&THIEF, Some(&SHADOW)).unwrap_err();
    assert!(e.contains("--vpls of method igi"), "{e}");
    static FREE: DeviceMethodKind = DeviceMethodKind {
        name: "free",
        shaders: &[("common/scene.glsl", "")],
        passes: platoon::tracer::device::path_passes,
    };
    let e = platoon::register_method(&FREE_KIND, Some(&FREE)).unwrap_err();
    assert!(
        e.contains("a kernel source is named common/scene.glsl"),
        "{e}"
    );
    let e = platoon::register_method(&FREE_KIND, Some(&SHADOW)).unwrap_err();
    assert!(e.contains("its device half is named thief"), "{e}");
    assert!(registry::kind("free").is_none());
    // A device half for a built-in method, which has its own.
    static IGI_AGAIN: DeviceMethodKind = DeviceMethodKind {
        name: "igi",
        shaders: &[],
        passes: platoon::tracer::device::path_passes,
    };
    let e = platoon::tracer::device::register(&IGI_AGAIN).unwrap_err();
    assert!(e.contains("device half of igi: it has one"), "{e}");
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
        let y = luminance(*c);
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

/// A pixel's grey: its luminance (Rec. 709), as grey.comp takes it.
fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
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

//! A toy rendering method from outside platoon's crates, the whole of it in this file: "grey",
//! the path tracer's image with its colour taken out, at a strength, by a pass of its own after
//! assembly. It is one registration (`register`) away from the front door, the technique
//! strings and the wire between ranks: its kind (`GreyKind`: its one setting, how it builds the
//! frame's method, its sweep) and its unit (`Grey`: what the core asks of a method). Its device
//! side is the path kernel's, which a method registered at run time gets.

use std::sync::Once;

use platoon::core::flatten::features::KernelOption;
use platoon::core::frame::{Band, FrameParams};
use platoon::core::method::kind::MethodKind;
use platoon::core::method::registry;
use platoon::core::method::render_method::RenderMethod;
use platoon::core::method::settings::{Setting, Settings, Value, ValueKind};
use platoon::core::Method;

/// The frame's state of the method.
#[derive(Debug, PartialEq)]
pub struct Grey {
    pub strength: f32,
    /// Paths end at their second diffuse vertex: a kernel option of the method, a define of
    /// the path kernel it renders with.
    pub one_bounce: bool,
}

/// A pixel's grey: its luminance (Rec. 709).
pub fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

impl RenderMethod for Grey {
    fn name(&self) -> &'static str {
        "grey"
    }
    fn describe(&self) -> String {
        format!(
            "grey: the path tracer's image, its colour taken out at strength {}",
            self.strength
        )
    }
    fn validate(&self, _params: &FrameParams) -> Result<(), String> {
        Ok(())
    }
    fn kernel_options(&self) -> Vec<KernelOption> {
        vec![("grey-one-bounce", "SINGLE_DIFFUSE_BOUNCE", self.one_bounce)]
    }
    fn approximations(&self) -> Vec<String> {
        vec![format!("colour taken out at strength {}", self.strength)]
    }
    /// Every pixel's sums moved towards their luminance (linear, so the same on sums as on
    /// means, and on any split).
    fn finish(&self, _params: &FrameParams, bands: &mut [Band]) {
        for s in bands.iter_mut().flat_map(|b| b.sums.iter_mut()) {
            let y = luminance(*s);
            for c in s.iter_mut() {
                *c = (1.0 - self.strength) * *c + self.strength * y;
            }
        }
    }
}

pub struct GreyKind;

const SETTINGS: &[Setting] = &[
    Setting {
        key: "strength",
        flag: "grey-strength",
        token: None,
        kind: ValueKind::Number,
        help: "how much of the colour is taken out, 0..=1.",
    },
    Setting {
        key: "one_bounce",
        flag: "grey-one-bounce",
        token: Some("onebounce"),
        kind: ValueKind::Switch,
        help: "paths end at their second diffuse vertex.",
    },
];

impl MethodKind for GreyKind {
    fn unit<'a>(&self, method: &'a Method) -> Option<&'a dyn RenderMethod> {
        method.state::<Grey>().map(|s| s as &dyn RenderMethod)
    }
    fn name(&self) -> &'static str {
        "grey"
    }
    fn title(&self) -> &'static str {
        "grey"
    }
    fn summary(&self) -> &'static str {
        "The path tracer's image without its colour (a toy)."
    }
    fn settings(&self) -> &'static [Setting] {
        SETTINGS
    }
    fn build(&self, given: &Settings) -> Result<Method, String> {
        let strength = given.number("strength").unwrap_or(1.0);
        if !(0.0..=1.0).contains(&strength) {
            return Err(format!("grey strength must be in 0..=1, not {strength}"));
        }
        let one_bounce = given.switch("one_bounce").unwrap_or(false);
        Ok(Method::new(Grey {
            strength,
            one_bounce,
        }))
    }
    fn settings_of(&self, method: &Method) -> Settings {
        let g = method.state::<Grey>().expect("a grey method");
        Settings(vec![
            ("strength", Value::Number(g.strength)),
            ("one_bounce", Value::Switch(g.one_bounce)),
        ])
    }
    fn primary(&self) -> Option<&'static str> {
        Some("strength")
    }
    fn sweep(&self) -> &'static [&'static str] {
        &["mis", "grey=1", "grey=0.5", "grey=1+onebounce"]
    }
}

pub static GREY: GreyKind = GreyKind;

/// The registration: one line, once per process.
pub fn register() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| registry::register(&GREY).expect("grey registers"));
}

/// The method at `strength`, its paths ending at their second diffuse vertex with
/// `one_bounce`.
pub fn grey(strength: f32, one_bounce: bool) -> Method {
    register();
    registry::kind("grey")
        .expect("registered")
        .build(&Settings(vec![
            ("strength", Value::Number(strength)),
            ("one_bounce", Value::Switch(one_bounce)),
        ]))
        .expect("a valid strength")
}

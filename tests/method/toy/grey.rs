//! A toy rendering method from outside platoon's crates, the whole of it in this file and its
//! kernel (grey.comp): "grey", the path tracer's image with its colour taken out, at a
//! strength, by a kernel of its own at the end of each band. It is one registration
//! (`register`) away from the front door, the technique strings and the wire between ranks:
//! its kind (`GreyKind`: its one setting, how it builds the frame's method, its sweep), its
//! unit (`Grey`: what the core asks of a method) and its device half (`GreyPasses`: the path
//! tracer's passes, then its kernel on the band's sums).

use std::sync::Once;
use std::time::Duration;

use platoon::core::flatten::features::KernelOption;
use platoon::core::frame::{FrameParams, MethodReport, PixelData, Span};
use platoon::core::method::kind::MethodKind;
use platoon::core::method::registry;
use platoon::core::method::render_method::RenderMethod;
use platoon::core::method::settings::{Setting, Settings, Value, ValueKind};
use platoon::core::Method;
use platoon::tracer::device::{
    path_passes, vk, DeviceMethodKind, Gpu, MethodPasses, Push, Recorder, METHOD_WORDS,
};
use platoon::tracer::Result as DeviceResult;

/// The frame's state of the method.
#[derive(Debug, PartialEq)]
pub struct Grey {
    pub strength: f32,
    /// Paths end at their second diffuse vertex: a kernel option of the method, a define of
    /// the path kernel it renders with.
    pub one_bounce: bool,
}

impl RenderMethod for Grey {
    fn kind(&self) -> &'static dyn MethodKind {
        &GreyKind
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
    fn kernel_options(&self, _params: &FrameParams) -> Vec<KernelOption> {
        vec![("grey-one-bounce", "SINGLE_DIFFUSE_BOUNCE", self.one_bounce)]
    }
    fn approximations(&self) -> Vec<String> {
        vec![format!("colour taken out at strength {}", self.strength)]
    }
}

/// Its kernel, by the name it registers it under.
const GREY_KERNEL: &str = "toy/grey.comp";

/// The device half: the path tracer's passes, then at the end of the band its kernel moves the
/// sums towards their luminance (push word 0: the strength).
pub struct GreyPasses {
    path: Box<dyn MethodPasses>,
}

impl MethodPasses for GreyPasses {
    fn kernels(&self, params: &FrameParams, cpu: bool) -> Vec<&'static str> {
        let mut kernels = self.path.kernels(params, cpu);
        kernels.push(GREY_KERNEL);
        kernels
    }
    fn prepare(&mut self, gpu: &mut Gpu, params: &FrameParams) -> DeviceResult<[u64; 4]> {
        self.path.prepare(gpu, params)
    }
    fn push_words(&self, params: &FrameParams) -> [u32; METHOD_WORDS] {
        self.path.push_words(params)
    }
    fn clears(&self, params: &FrameParams, span: Span) -> Vec<(vk::Buffer, u64, u64)> {
        self.path.clears(params, span)
    }
    fn samples_per_pass(&self, params: &FrameParams) -> u32 {
        self.path.samples_per_pass(params)
    }
    fn begin_band(&mut self, rec: &mut Recorder, push: &Push) -> DeviceResult<Duration> {
        self.path.begin_band(rec, push)
    }
    fn pass(
        &mut self,
        rec: &mut Recorder,
        push: &Push,
        groups: (u32, u32),
    ) -> DeviceResult<Duration> {
        self.path.pass(rec, push, groups)
    }
    fn end_band(&mut self, rec: &mut Recorder, push: &Push) -> DeviceResult<Duration> {
        let strength = rec
            .params
            .method
            .state::<Grey>()
            .expect("grey's frames")
            .strength;
        let mut method = [0; METHOD_WORDS];
        method[0] = strength.to_bits();
        let push = Push { method, ..*push };
        let groups = rec.band_groups(&push);
        rec.dispatch(GREY_KERNEL, &push, groups)
    }
    fn report(&mut self, counters: &[u32]) -> MethodReport {
        self.path.report(counters)
    }
    fn per_pixel(&mut self, params: &FrameParams, span: Span) -> PixelData {
        self.path.per_pixel(params, span)
    }
    fn destroy(&mut self, gpu: &mut Gpu) {
        self.path.destroy(gpu);
    }
}

static GREY_DEVICE: DeviceMethodKind = DeviceMethodKind {
    name: "grey",
    shaders: &[(GREY_KERNEL, include_str!("grey.comp"))],
    passes: || {
        Box::new(GreyPasses {
            path: path_passes(),
        })
    },
};

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

/// The registration of both halves: one line, once per process.
pub fn register() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| platoon::register_method(&GREY, Some(&GREY_DEVICE)).expect("grey registers"));
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

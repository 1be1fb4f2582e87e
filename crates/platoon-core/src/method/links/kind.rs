//! Vertex links as a user chooses them: their settings (`--links-*`; `links=256+b2` in the
//! lab), how they make the method, and the sweep they are compared in.

use super::{Links, LinksOptions};
use crate::method::kind::MethodKind;
use crate::method::settings::{Setting, Settings, Value, ValueKind};
use crate::method::Method;

pub struct LinksKind;

const SETTINGS: &[Setting] = &[
    Setting {
        key: "directions",
        flag: "links-directions",
        token: None,
        kind: ValueKind::Count,
        help: "directions every vertex shoots (a square: 16, 64, 256, 1024).",
    },
    Setting {
        key: "bounces",
        flag: "links-bounces",
        token: Some("b"),
        kind: ValueKind::Count,
        help: "bounces of indirect light the gather carries.",
    },
    Setting {
        key: "feature_angle",
        flag: "links-feature-angle",
        token: None,
        kind: ValueKind::Number,
        help: "vertices within this angle (degrees) are one element; smoothing stops at it.",
    },
    Setting {
        key: "no_smoothing",
        flag: "links-no-smoothing",
        token: Some("nosmooth"),
        kind: ValueKind::Switch,
        help: "no smoothing of the gathered light over vertex neighbourhoods.",
    },
    Setting {
        key: "light_samples",
        flag: "links-light-samples",
        token: None,
        kind: ValueKind::Count,
        help: "next-event samples of the direct light at each vertex.",
    },
    Setting {
        key: "vertex_light",
        flag: "links-vertex-light",
        token: Some("vertex"),
        kind: ValueKind::Switch,
        help: "direct light taken at each vertex alone, not averaged over its triangles (the \
               paper without its light-link oversampling).",
    },
];

impl MethodKind for LinksKind {
    fn name(&self) -> &'static str {
        "links"
    }
    fn title(&self) -> &'static str {
        "vertex links"
    }
    fn summary(&self) -> &'static str {
        "Vertex links: indirect diffuse light solved per mesh vertex over fixed-direction links."
    }
    fn settings(&self) -> &'static [Setting] {
        SETTINGS
    }
    fn build(&self, given: &Settings) -> Result<Method, String> {
        let mut o = LinksOptions::default();
        if let Some(n) = given.count("directions") {
            o.directions = n;
        }
        if let Some(b) = given.count("bounces") {
            o.bounces = b;
        }
        if let Some(a) = given.number("feature_angle") {
            o.feature_angle = a;
        }
        if let Some(off) = given.switch("no_smoothing") {
            o.smooth = !off;
        }
        if let Some(k) = given.count("light_samples") {
            o.light_samples = k;
        }
        if let Some(at_vertex) = given.switch("vertex_light") {
            o.fan_light = !at_vertex;
        }
        o.validate()?;
        Ok(Method::new(Links::new(o)))
    }
    fn settings_of(&self, method: &Method) -> Settings {
        let o = &method
            .state::<Links>()
            .expect("a vertex links method")
            .options;
        Settings(vec![
            ("directions", Value::Count(o.directions)),
            ("bounces", Value::Count(o.bounces)),
            ("feature_angle", Value::Number(o.feature_angle)),
            ("no_smoothing", Value::Switch(!o.smooth)),
            ("light_samples", Value::Count(o.light_samples)),
            ("vertex_light", Value::Switch(!o.fan_light)),
        ])
    }
    fn primary(&self) -> Option<&'static str> {
        Some("directions")
    }
    /// The path tracer and IGI at 180 VPLs against vertex links at the paper's 256
    /// directions and fewer, with one bounce, without smoothing, with the direct light at
    /// vertices alone, and on the scene subdivided (the lab's `+subK`).
    fn sweep(&self) -> &'static [&'static str] {
        &[
            "mis",
            "igi=180",
            "links=16",
            "links=64",
            "links=256",
            "links=256+b1",
            "links=256+nosmooth",
            "links=256+vertex",
            "links=256+sub2",
            "links=256+sub3",
        ]
    }
    fn travels(&self) -> Result<(), String> {
        Err("its solution, made before the frames, does not travel".into())
    }
}

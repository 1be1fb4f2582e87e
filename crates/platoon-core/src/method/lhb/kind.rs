//! Layered hit buffers as a user chooses them: their settings (`--lhb-*`; `lhb=ico320+r64` in
//! the lab), how they make the method, and the sweep they are compared in.

use super::directions::DirectionSet;
use super::{Lhb, LhbOptions, RasterVariant};
use crate::method::kind::MethodKind;
use crate::method::settings::{Setting, Settings, Value, ValueKind};
use crate::method::Method;

pub struct LhbKind;

const SETTINGS: &[Setting] = &[
    Setting {
        key: "directions",
        flag: "lhb-directions",
        token: None,
        kind: ValueKind::Word(&[]),
        help: "the buffers' directions (ico20|80|320|1280, oct8|32|128, haltonN).",
    },
    Setting {
        key: "resolution",
        flag: "lhb-resolution",
        token: Some("r"),
        kind: ValueKind::Count,
        help: "texels on a side of every buffer.",
    },
    Setting {
        key: "cone",
        flag: "lhb-cone",
        token: Some("c"),
        kind: ValueKind::Number,
        help: "radius of the cone jitter in texels.",
    },
    Setting {
        key: "bounces",
        flag: "lhb-bounces",
        token: Some("b"),
        kind: ValueKind::Count,
        help: "indirect bounces answered by lookups.",
    },
    Setting {
        key: "layers",
        flag: "lhb-layers",
        token: Some("l"),
        kind: ValueKind::Count,
        help: "layers a texel keeps (the capacity rasterizer).",
    },
    Setting {
        key: "variant",
        flag: "lhb-variant",
        token: None,
        kind: ValueKind::Word(&["capacity", "exact"]),
        help: "rasterizer, capacity (fixed lists, overflow lost) or exact (count, prefix sum, \
               fill).",
    },
    Setting {
        key: "rebuild",
        flag: "lhb-rebuild",
        token: Some("rebuild"),
        kind: ValueKind::Switch,
        help: "rebuild every buffer every frame, instead of keeping the layers of what did not \
               move.",
    },
];

impl MethodKind for LhbKind {
    fn name(&self) -> &'static str {
        "lhb"
    }
    fn title(&self) -> &'static str {
        "layered hit buffers"
    }
    fn summary(&self) -> &'static str {
        "Layered hit buffers: indirect rays answered by lookups in buffers of fixed directions."
    }
    fn settings(&self) -> &'static [Setting] {
        SETTINGS
    }
    fn build(&self, given: &Settings) -> Result<Method, String> {
        let mut o = LhbOptions::default();
        if let Some(d) = given.word("directions") {
            o.directions = DirectionSet::parse(d).map_err(|e| e.to_string())?;
        }
        if let Some(r) = given.count("resolution") {
            o.resolution = r;
        }
        if let Some(c) = given.number("cone") {
            o.cone = c;
        }
        if let Some(b) = given.count("bounces") {
            o.bounces = b;
        }
        if let Some(l) = given.count("layers") {
            o.layers = l;
        }
        if let Some(v) = given.word("variant") {
            o.variant = RasterVariant::parse(v)?;
        }
        if let Some(on) = given.switch("rebuild") {
            o.rebuild = on;
        }
        o.validate()?;
        Ok(Method::new(Lhb::new(o)))
    }
    fn settings_of(&self, method: &Method) -> Settings {
        let o = &method
            .state::<Lhb>()
            .expect("a layered hit buffers method")
            .options;
        Settings(vec![
            ("directions", Value::Word(o.directions.to_string())),
            ("resolution", Value::Count(o.resolution)),
            ("cone", Value::Number(o.cone)),
            ("bounces", Value::Count(o.bounces)),
            ("layers", Value::Count(o.layers)),
            ("variant", Value::Word(o.variant.name().into())),
            ("rebuild", Value::Switch(o.rebuild)),
        ])
    }
    fn primary(&self) -> Option<&'static str> {
        Some("directions")
    }
    /// The path tracer, IGI at 180 VPLs and vertex links at 256 directions against layered
    /// hit buffers along the thesis' directions and resolutions, cone radii and bounces.
    fn sweep(&self) -> &'static [&'static str] {
        &[
            "mis",
            "igi=180",
            "links=256",
            "lhb=ico20+r32",
            "lhb=ico80+r64",
            "lhb=ico320+r64",
            "lhb=ico320",
            "lhb=ico320+c0",
            "lhb=ico320+c3",
            "lhb=ico320+b1",
            "lhb=ico320+b3",
            "lhb=oct128",
            "lhb=halton320",
        ]
    }
    fn travels(&self) -> Result<(), String> {
        Err("its tables, made from the scene before the frames, do not travel".into())
    }
}

//! IGI as a user chooses it: its settings (`--vpls`, `--igi-*`; `igi=180+boxes` in the lab),
//! how they make its options, and the sweep it is compared in.

use super::IgiOptions;
use crate::method::kind::{MethodKind, Preset};
use crate::method::settings::{Setting, Settings, Value, ValueKind};
use crate::method::Method;

pub struct IgiKind;

const SETTINGS: &[Setting] = &[
    Setting {
        key: "vpls",
        flag: "vpls",
        token: None,
        kind: ValueKind::Count,
        help: "VPLs per frame (light paths x --vpl-bounces).",
    },
    Setting {
        key: "bounces",
        flag: "vpl-bounces",
        token: Some("b"),
        kind: ValueKind::Count,
        help: "VPLs a light path leaves at most (light bounced more often is lost).",
    },
    Setting {
        key: "imperfect_visibility",
        flag: "igi-imperfect-visibility",
        token: Some("boxes"),
        kind: ValueKind::Switch,
        help: "VPL shadow rays against BVH leaf boxes instead of triangles.",
    },
    Setting {
        key: "downsample",
        flag: "igi-downsample",
        token: Some("down"),
        kind: ValueKind::Count,
        help: "gather indirect light at one pixel in K x K and upsample it.",
    },
    Setting {
        key: "interleave",
        flag: "igi-interleave",
        token: Some("inter"),
        kind: ValueKind::Tile,
        help: "interleave M x N subsets of the VPLs (e.g. 3x3), recombined by a \
               discontinuity buffer.",
    },
    Setting {
        key: "min_distance",
        flag: "vpl-min-distance",
        token: Some("min"),
        kind: ValueKind::Number,
        help: "bound the geometry term below this distance (0: unbounded).",
    },
];

impl MethodKind for IgiKind {
    fn name(&self) -> &'static str {
        "igi"
    }
    fn title(&self) -> &'static str {
        "IGI"
    }
    fn summary(&self) -> &'static str {
        "Instant global illumination: indirect diffuse light from virtual point lights."
    }
    fn settings(&self) -> &'static [Setting] {
        SETTINGS
    }
    fn build(&self, given: &Settings) -> Result<Method, String> {
        let mut o = IgiOptions::default();
        if let Some(b) = given.count("bounces") {
            o.bounces = b;
        }
        // The paper counts VPL slots; the kernel shoots paths that leave `bounces` each.
        if let Some(n) = given.count("vpls") {
            if n == 0 {
                return Err("IGI needs at least one VPL".into());
            }
            o.paths = n.div_ceil(o.bounces.max(1)).max(1);
        }
        if let Some(on) = given.switch("imperfect_visibility") {
            o.imperfect_visibility = on;
        }
        if let Some(k) = given.count("downsample") {
            o.downsample = k;
        }
        if let Some(t) = given.tile("interleave") {
            o.interleave = t;
        }
        if let Some(d) = given.number("min_distance") {
            o.min_distance = d;
        }
        o.validate()?;
        Ok(Method::new(o))
    }
    fn settings_of(&self, method: &Method) -> Settings {
        let o = method.state::<IgiOptions>().expect("an IGI method");
        Settings(vec![
            ("vpls", Value::Count(o.slots())),
            ("bounces", Value::Count(o.bounces)),
            (
                "imperfect_visibility",
                Value::Switch(o.imperfect_visibility),
            ),
            ("downsample", Value::Count(o.downsample)),
            ("interleave", Value::Tile(o.interleave)),
            ("min_distance", Value::Number(o.min_distance)),
        ])
    }
    fn primary(&self) -> Option<&'static str> {
        Some("vpls")
    }
    fn presets(&self) -> &'static [Preset] {
        // The paper's combination of its three accelerations.
        &[(
            "all",
            &[
                ("imperfect_visibility", "on"),
                ("downsample", "4"),
                ("interleave", "3x3"),
            ],
        )]
    }
    /// The path tracer, IGI at the paper's VPL counts, then at 180 VPLs each acceleration
    /// alone and the three together.
    fn sweep(&self) -> &'static [&'static str] {
        &[
            "mis",
            "igi=30",
            "igi=90",
            "igi=180",
            "igi=720",
            "igi=180+boxes",
            "igi=180+down4",
            "igi=180+inter3x3",
            "igi=180+all",
        ]
    }
}

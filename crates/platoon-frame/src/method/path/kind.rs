//! The path tracer as a user chooses it: its settings (`--kernel`, `--resampled-light`; the
//! keywords `kernel`, `resampled_light`), made into its state and read back for the wire.

use super::kernel::PathKernel;
use super::learning::check;
use super::state::{PathTracing, ResampledLight};
use crate::method::kind::MethodKind;
use crate::method::settings::{Setting, Settings, Value, ValueKind};
use crate::method::Method;

static SETTINGS: &[Setting] = &[
    Setting {
        key: "kernel",
        flag: "kernel",
        token: None,
        // Any word, read by `PathKernel::by_name` (which also takes "streaming").
        kind: ValueKind::Word(&[]),
        help: "the megakernel (mega), streaming path tracing (spt), or the one measured \
               faster on each kind of device (auto, the default). The same image either way.",
    },
    Setting {
        key: "resampled_light",
        flag: "resampled-light",
        token: None,
        kind: ValueKind::Count,
        help: "next-event estimation resamples this many candidate lights toward their \
               unshadowed contribution (ReSTIR DI's candidates, without reuse; unbiased): for \
               scenes of many lights (8-32). Default: one light drawn by power.",
    },
];

/// What it learns over a game loop's frames (`LearningOptions`).
static LEARNING: &[Setting] = &[
    Setting {
        key: "world_cache",
        flag: "world-cache",
        token: None,
        kind: ValueKind::Switch,
        help: "the bounces after the first read a world cache trained as the frames go (hashed \
               cells in world space; biased, reported as such).",
    },
    Setting {
        key: "light_reuse",
        flag: "light-reuse",
        token: None,
        kind: ValueKind::Mode(&["unbiased", "biased"]),
        help: "resampled light reuses the previous frame's reservoirs where each pixel's \
               surface was and around it (ReSTIR DI's temporal and spatial reuse): unbiased \
               (the default), or biased (a little cheaper, darker where a neighbour cannot see \
               the light). Needs --resampled-light or --realtime.",
    },
];

pub struct PathKind;

impl MethodKind for PathKind {
    fn name(&self) -> &'static str {
        "path"
    }
    fn title(&self) -> &'static str {
        "path tracing"
    }
    fn summary(&self) -> &'static str {
        "Path tracing with NEE and MIS: unbiased, the reference."
    }
    fn settings(&self) -> &'static [Setting] {
        SETTINGS
    }
    /// Its whole state as serde derives it (CBOR; the world cache's table and the reservoirs
    /// as byte strings).
    fn state_bytes(&self, method: &Method) -> Result<Option<Vec<u8>>, String> {
        let mut bytes = Vec::new();
        ciborium::into_writer(method.path(), &mut bytes)
            .map_err(|e| format!("encoding the path tracer's state: {e}"))?;
        Ok(Some(bytes))
    }
    fn with_state(&self, _method: Method, bytes: &[u8]) -> Result<Method, String> {
        let state: PathTracing =
            ciborium::from_reader(bytes).map_err(|e| format!("the path tracer's state: {e}"))?;
        if let Some(c) = &state.world_cache {
            if !c.slots.len().is_power_of_two() {
                return Err("the world cache's table is not a power of two long".into());
            }
        }
        Ok(Method::new(state))
    }
    fn build(&self, given: &Settings) -> Result<Method, String> {
        let kernel = match given.word("kernel") {
            None => PathKernel::Auto,
            Some(name) => PathKernel::by_name(name).ok_or_else(|| {
                format!(
                    "kernel: unknown kernel {name}: one of {}",
                    PathKernel::NAMES.join(", ")
                )
            })?,
        };
        let resampled_light = given.count("resampled_light").map(ResampledLight::new);
        if let Some(Err(problem)) = resampled_light.map(|r| r.check()) {
            return Err(format!("resampled_light: {problem}"));
        }
        Ok(Method::new(PathTracing {
            kernel,
            resampled_light,
            ..Default::default()
        }))
    }
    /// Its settings; the rest of its state (the last paths cut, resampled light by luminance,
    /// what its frames carry) travels beside them (`state_bytes`).
    fn settings_of(&self, method: &Method) -> Settings {
        let path = method.path();
        let mut s = Settings::default();
        s.set("kernel", Value::Word(path.kernel.name().into()));
        if let Some(r) = path.resampled_light {
            s.set("resampled_light", Value::Count(r.candidates));
        }
        s
    }
    fn learning_settings(&self) -> &'static [Setting] {
        LEARNING
    }
    fn with_learning(&self, mut method: Method, given: &Settings) -> Result<Method, String> {
        let Some(path) = method.path_mut() else {
            return Err("the path tracer's learning for another method".into());
        };
        if given.switch("world_cache") == Some(true) {
            path.learning.world_cache = Some(Default::default());
        }
        if let Some(mode) = given.word("light_reuse") {
            path.learning.light_reuse =
                Some(mode.parse().map_err(|e| format!("light_reuse: {e}"))?);
        }
        check(path).map_err(|(key, problem)| format!("{key}: {problem}"))?;
        Ok(method)
    }
    fn learning_of(&self, method: &Method) -> Settings {
        let learning = method.path().learning;
        let mut s = Settings::default();
        if learning.world_cache.is_some() {
            s.set("world_cache", Value::Switch(true));
        }
        if let Some(r) = learning.light_reuse {
            s.set("light_reuse", Value::Word(r.mode().into()));
        }
        s
    }
    /// Its estimators against each other, a short path and no regeneration.
    fn sweep(&self) -> &'static [&'static str] {
        &["mis", "bsdf", "light", "max-depth=2", "no-regeneration"]
    }
}

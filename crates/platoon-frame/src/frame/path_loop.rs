//! The path loop every method's kernels run (shaders/path/path.glsl; IGI, vertex links and
//! layered hit buffers continue the path tracer's paths through it): how long a path may be,
//! how Russian roulette ends it, what its contributions are clamped to, how it picks lights,
//! and whether its kernel is specialised. The path tracer's own options (its kernels, resampled
//! and reused light, the world cache) are its method's state (`method::path`).

use super::kernel_word::KernelWord;
use crate::flatten::features::KernelOption;

/// Default path-length limit: high enough to be unbounded in practice (Russian roulette ends
/// paths long before), low enough to stop a pathological scene. Reported in the output metadata.
pub const DEFAULT_MAX_DEPTH: u32 = 1024;
/// The path depth Russian roulette starts at.
pub const DEFAULT_RR_DEPTH: u32 = 3;

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PathLoop {
    /// Longest path in segments (Mitsuba's convention: 1 = emitters seen directly, 2 = direct light).
    pub max_depth: u32,
    /// Depth from which Russian roulette may end a path.
    pub rr_depth: u32,
    /// Russian-roulette survival scale in (0, 1]: a path survives with probability
    /// min(max throughput component x this, 0.95) and survivors are weighted up by its inverse,
    /// so any value is unbiased; below 1 paths are shorter (faster) and the image noisier. What
    /// the frame driver's roulette scaling lowers when one sample a frame is already too slow.
    pub rr_survival: f32,
    /// Russian roulette with this fixed survival probability in (0, 1] instead of one from the
    /// path's throughput (unbiased; Bikker's comparison). Compiled in only when set.
    pub rr_fixed: Option<f32>,
    /// Clamp every contribution after the first bounce to this maximum component (a firefly
    /// suppressor games use; biased, listed as an approximation). Compiled in only when set.
    pub clamp_indirect: Option<f32>,
    /// Next-event estimation picks every light with the same probability instead of by power
    /// (unbiased, usually noisier). Compiled in only when set.
    pub uniform_light_selection: bool,
    /// Compile every effect a scene may call for into the kernel, not only this scene's: what
    /// a renderer without specialisation pays (the image is the same; the time is not).
    pub generic_kernel: bool,
    /// Bikker's deterministic path termination instead of Russian roulette: of a pixel's N
    /// samples N/2 end at the first test, N/4 at the second... (biased: no path outlives log2 N
    /// tests). Compiled in only when set.
    pub deterministic_termination: bool,
    /// Paths end at their second non-delta vertex: direct light and one diffuse bounce of
    /// indirect (Bikker's games; biased). Compiled in only when set.
    pub single_diffuse_bounce: bool,
}

impl Default for PathLoop {
    fn default() -> PathLoop {
        PathLoop {
            max_depth: DEFAULT_MAX_DEPTH,
            rr_depth: DEFAULT_RR_DEPTH,
            rr_survival: 1.0,
            rr_fixed: None,
            clamp_indirect: None,
            uniform_light_selection: false,
            generic_kernel: false,
            deterministic_termination: false,
            single_diffuse_bounce: false,
        }
    }
}

impl PathLoop {
    /// The kernel defines of the knobs that select code (each compiled in only when set),
    /// with whether each is on: part of the kernel variant (`method::variant`).
    pub fn kernel_options(&self) -> Vec<KernelOption> {
        vec![
            // Max depth 1: the kernel has no bounce code.
            ("camera-rays-only", "CAMERA_RAYS_ONLY", self.max_depth <= 1),
            (
                "clamp-indirect",
                "CLAMP_INDIRECT",
                self.clamp_indirect.is_some(),
            ),
            ("fixed-roulette", "RR_FIXED", self.rr_fixed.is_some()),
            (
                "uniform-lights",
                "LIGHT_SELECT_UNIFORM",
                self.uniform_light_selection,
            ),
            (
                "deterministic-termination",
                "RR_DETERMINISTIC",
                self.deterministic_termination,
            ),
            (
                "single-diffuse-bounce",
                "SINGLE_DIFFUSE_BOUNCE",
                self.single_diffuse_bounce,
            ),
        ]
    }

    /// What an image's metadata says of the path loop, label and text, in order. How lights
    /// are picked is `method_lights` where the method picks them its own way (the path
    /// tracer's resampled light), else by power or uniformly.
    pub fn metadata(&self, method_lights: Option<String>) -> Vec<(String, String)> {
        let survival = match (self.deterministic_termination, self.rr_fixed) {
            (true, _) => "deterministic (DPT)".to_string(),
            (false, Some(p)) => format!("fixed {p}"),
            (false, None) => format!("throughput x {}", self.rr_survival),
        };
        let lights = method_lights.unwrap_or_else(|| match self.uniform_light_selection {
            true => "uniform".into(),
            false => "power".into(),
        });
        let clamp = self
            .clamp_indirect
            .map_or_else(|| "none".into(), |c| c.to_string());
        [
            ("max_depth", self.max_depth.to_string()),
            ("russian_roulette_depth", self.rr_depth.to_string()),
            ("russian_roulette_survival", survival),
            ("light_selection", lights),
            ("clamp_indirect", clamp),
        ]
        .into_iter()
        .map(|(label, text)| (label.to_string(), text))
        .collect()
    }

    /// What these knobs approximate, each as the output's metadata lists it: the biased knobs
    /// (`Knob::biased`), each when set (a test holds every biased knob of `KNOBS` to a line
    /// here and every unbiased one to none).
    pub fn approximations(&self) -> Vec<String> {
        let mut a = Vec::new();
        if self.max_depth < DEFAULT_MAX_DEPTH {
            a.push(format!("path depth capped at {}", self.max_depth));
        }
        if let Some(c) = self.clamp_indirect {
            a.push(format!("light after the first bounce clamped at {c}"));
        }
        if self.deterministic_termination {
            a.push("deterministic path termination: no path outlives log2(spp) tests".into());
        }
        if self.single_diffuse_bounce {
            a.push("a single diffuse bounce of indirect light".into());
        }
        a
    }

    /// What is wrong with these values, if anything (the tracer's band refuses them too: a
    /// frame may come from an embedder without the request's validation).
    pub fn check(&self) -> Result<(), String> {
        if !(self.rr_survival > 0.0 && self.rr_survival <= 1.0) {
            return Err(format!(
                "the Russian-roulette survival scale must be in (0, 1], not {}",
                self.rr_survival
            ));
        }
        if self.rr_fixed.is_some_and(|p| !(p > 0.0 && p <= 1.0)) {
            return Err("a fixed Russian-roulette survival probability must be in (0, 1]".into());
        }
        if self.clamp_indirect.is_some_and(|c| c.is_nan() || c <= 0.0) {
            return Err("the indirect clamp must be a positive radiance".into());
        }
        Ok(())
    }
}

/// What the kernel reads of the path loop, in order (`KernelWord`): a knob the kernel reads
/// is its field, its entry in `KNOBS`, a word here and its shader.
pub const LOOP_WORDS: &[KernelWord<PathLoop>] = &[
    // At least one segment: a depth of 0 renders as 1.
    KernelWord {
        name: "max_depth",
        float: false,
        of: |l| l.max_depth.max(1),
    },
    KernelWord {
        name: "rr_depth",
        float: false,
        of: |l| l.rr_depth,
    },
    // With RR_FIXED the fixed survival probability, else the survival scale.
    KernelWord {
        name: "rr_survival",
        float: true,
        of: |l| l.rr_fixed.unwrap_or(l.rr_survival).to_bits(),
    },
    // Read with CLAMP_INDIRECT only.
    KernelWord {
        name: "clamp_indirect",
        float: true,
        of: |l| l.clamp_indirect.unwrap_or(f32::INFINITY).to_bits(),
    },
];

/// How a knob's value is written (`max-depth=2`, `rr-survival=30`, `clamp=10`, `dpt`) and held
/// (one word: the count, the percentage, the f32's bits, 0 for a switch).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KnobValue {
    /// A whole number of at least `min`.
    Count { min: u32 },
    /// A percentage in 1..=100, set as its fraction.
    Percent,
    /// A positive finite number.
    Positive,
    /// On when named.
    Switch,
}

/// One knob of the path loop, declared once: its token (the lab's techniques: `TOKEN=VALUE`,
/// or `TOKEN` for a switch), how its value is written, whether it changes what the estimate
/// converges to, and what it sets. A new knob is a field, an entry here and its shader.
pub struct Knob {
    pub token: &'static str,
    pub value: KnobValue,
    pub biased: bool,
    /// Sets the knob to `v` (the count, the fraction, the number; 1 for a switch).
    set: fn(&mut PathLoop, f32),
}

/// Every knob of the path loop the lab sweeps.
pub const KNOBS: &[Knob] = &[
    // Paths of at most N segments.
    Knob {
        token: "max-depth",
        value: KnobValue::Count { min: 1 },
        biased: true,
        set: |l, v| l.max_depth = v as u32,
    },
    // Russian roulette from depth N on.
    Knob {
        token: "rr-depth",
        value: KnobValue::Count { min: 0 },
        biased: false,
        set: |l, v| l.rr_depth = v as u32,
    },
    // Russian roulette's survival scaled to P percent.
    Knob {
        token: "rr-survival",
        value: KnobValue::Percent,
        biased: false,
        set: |l, v| l.rr_survival = v,
    },
    // Russian roulette with a fixed survival of P percent.
    Knob {
        token: "rr-fixed",
        value: KnobValue::Percent,
        biased: false,
        set: |l, v| l.rr_fixed = Some(v),
    },
    // Contributions after the first bounce clamped at C.
    Knob {
        token: "clamp",
        value: KnobValue::Positive,
        biased: true,
        set: |l, v| l.clamp_indirect = Some(v),
    },
    // Next-event estimation picks every light alike.
    Knob {
        token: "uniform-lights",
        value: KnobValue::Switch,
        biased: false,
        set: |l, _| l.uniform_light_selection = true,
    },
    // Every effect compiled into the kernel, not only the scene's.
    Knob {
        token: "generic-kernel",
        value: KnobValue::Switch,
        biased: false,
        set: |l, _| l.generic_kernel = true,
    },
    // Deterministic path termination instead of Russian roulette.
    Knob {
        token: "dpt",
        value: KnobValue::Switch,
        biased: true,
        set: |l, _| l.deterministic_termination = true,
    },
    // Paths end at their second non-delta vertex.
    Knob {
        token: "single-bounce",
        value: KnobValue::Switch,
        biased: true,
        set: |l, _| l.single_diffuse_bounce = true,
    },
];

impl Knob {
    /// How it is written with a placeholder for its value (`max-depth=N`, `dpt`): what a list
    /// of the techniques shows.
    pub fn written(&self) -> String {
        let t = self.token;
        match self.value {
            KnobValue::Switch => t.to_string(),
            KnobValue::Count { .. } => format!("{t}=N"),
            KnobValue::Percent => format!("{t}=PERCENT"),
            KnobValue::Positive => format!("{t}=C"),
        }
    }

    /// The word `value` (the text after `=`, None for a bare token) holds, or what is wrong.
    pub fn parse(&self, value: Option<&str>) -> Result<u32, String> {
        let t = self.token;
        match (self.value, value) {
            (KnobValue::Switch, None) => Ok(0),
            (KnobValue::Switch, Some(_)) => Err(format!("{t} takes no value")),
            (KnobValue::Count { min }, v) => match v.map(str::parse::<u32>) {
                Some(Ok(n)) if n >= min => Ok(n),
                _ => Err(format!(
                    "{t} needs a whole number of at least {min}, e.g. {t}=2"
                )),
            },
            (KnobValue::Percent, v) => match v.map(str::parse::<u32>) {
                Some(Ok(p @ 1..=100)) => Ok(p),
                _ => Err(format!("{t} needs a percentage in 1..=100, e.g. {t}=50")),
            },
            (KnobValue::Positive, v) => match v.map(str::parse::<f32>) {
                Some(Ok(c)) if c > 0.0 && c.is_finite() => Ok(c.to_bits()),
                _ => Err(format!("{t} needs a positive number, e.g. {t}=10")),
            },
        }
    }

    /// `word` written as `parse` reads it back (`TOKEN=VALUE`, or `TOKEN` for a switch).
    pub fn format(&self, word: u32) -> String {
        let t = self.token;
        match self.value {
            KnobValue::Switch => t.to_string(),
            KnobValue::Count { .. } | KnobValue::Percent => format!("{t}={word}"),
            KnobValue::Positive => format!("{t}={}", f32::from_bits(word)),
        }
    }

    /// Sets the knob of `l` to `word`.
    pub fn apply(&self, l: &mut PathLoop, word: u32) {
        let v = match self.value {
            KnobValue::Count { .. } => word as f32,
            KnobValue::Percent => word as f32 / 100.0,
            KnobValue::Positive => f32::from_bits(word),
            KnobValue::Switch => 1.0,
        };
        (self.set)(l, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value of `knob`'s kind as written: `whole` for a count or a percentage, 2.5 for a
    /// positive number, none for a switch.
    fn a_value(knob: &Knob, whole: &'static str) -> Option<&'static str> {
        match knob.value {
            KnobValue::Switch => None,
            KnobValue::Positive => Some("2.5"),
            _ => Some(whole),
        }
    }

    impl Knob {
        fn named(token: &str) -> Option<&'static Knob> {
            KNOBS.iter().find(|k| k.token == token)
        }
    }

    /// Each knob sets its own field and only it: the loop differs from the default in one
    /// field, and a knob's text reads back as its word.
    #[test]
    fn every_knob_sets_its_field_and_reads_back() {
        let fields = |l: &PathLoop| {
            [
                format!("{}", l.max_depth),
                format!("{}", l.rr_depth),
                format!("{}", l.rr_survival),
                format!("{:?}", l.rr_fixed),
                format!("{:?}", l.clamp_indirect),
                format!("{}", l.uniform_light_selection),
                format!("{}", l.generic_kernel),
                format!("{}", l.deterministic_termination),
                format!("{}", l.single_diffuse_bounce),
            ]
        };
        let defaults = fields(&PathLoop::default());
        for (i, knob) in KNOBS.iter().enumerate() {
            let text = a_value(knob, "7");
            let word = knob.parse(text).unwrap();
            assert_eq!(knob.format(word), knob.format(knob.parse(text).unwrap()));
            let mut l = PathLoop::default();
            knob.apply(&mut l, word);
            let changed: Vec<usize> = (0..defaults.len())
                .filter(|&f| fields(&l)[f] != defaults[f])
                .collect();
            assert_eq!(changed, [i], "{} changed {changed:?}", knob.token);
        }
        assert_eq!(
            Knob::named("rr-survival").unwrap().format(30),
            "rr-survival=30"
        );
        let mut l = PathLoop::default();
        Knob::named("rr-fixed").unwrap().apply(&mut l, 80);
        assert_eq!(l.rr_fixed, Some(0.8));
        assert!(Knob::named("max-depth").unwrap().parse(Some("0")).is_err());
        assert!(Knob::named("dpt").unwrap().parse(Some("1")).is_err());
        assert!(Knob::named("clamp").unwrap().parse(Some("-1")).is_err());
    }

    /// Each knob, set, changes the metadata's line that says it (and only it); the switches
    /// the metadata says elsewhere (the kernel's features, the approximations) change none. A
    /// method's own light picking takes the place of the loop's.
    #[test]
    fn every_knob_is_said_by_its_own_metadata_line() {
        let says = |token: &str| -> &[&str] {
            match token {
                "max-depth" => &["max_depth"],
                "rr-depth" => &["russian_roulette_depth"],
                "rr-survival" | "rr-fixed" | "dpt" => &["russian_roulette_survival"],
                "clamp" => &["clamp_indirect"],
                "uniform-lights" => &["light_selection"],
                "generic-kernel" | "single-bounce" => &[],
                other => panic!("{other}: which metadata line says it?"),
            }
        };
        let base = PathLoop::default().metadata(None);
        for knob in KNOBS {
            let text = a_value(knob, "7");
            let mut l = PathLoop::default();
            knob.apply(&mut l, knob.parse(text).unwrap());
            let said = l.metadata(None);
            let changed: Vec<&str> = said
                .iter()
                .zip(&base)
                .filter(|(a, b)| a != b)
                .map(|(a, _)| a.0.as_str())
                .collect();
            assert_eq!(changed, says(knob.token), "{}: {said:?}", knob.token);
        }
        let resampled = PathLoop::default().metadata(Some("RIS over 8 candidates".into()));
        let lights = resampled
            .iter()
            .find(|(label, _)| label == "light_selection");
        assert_eq!(lights.unwrap().1, "RIS over 8 candidates");
    }

    /// A biased knob, set, is listed among the approximations; an unbiased one is not.
    #[test]
    fn every_biased_knob_and_only_those_is_an_approximation() {
        assert!(PathLoop::default().approximations().is_empty());
        for knob in KNOBS {
            let text = a_value(knob, "2");
            let mut l = PathLoop::default();
            knob.apply(&mut l, knob.parse(text).unwrap());
            let listed = l.approximations();
            assert_eq!(
                listed.len(),
                knob.biased as usize,
                "{}: {listed:?}",
                knob.token
            );
        }
    }
}

//! The request's frame options declared once (`OPTIONS`): each one's keyword (the request's
//! field, Python's keyword, the name its errors give), its command-line flag, its help, the
//! kind of value it takes, how a value is set on a request and read back, its own rule and what
//! an image's metadata says of it. `platoon render`'s flags, `platoon.render`'s keywords, the
//! request's rules of one option (`Request::validate`), the flag its errors name (the CLI) and
//! the frame's part of the metadata are made from this table, so an option of the frame is one
//! entry here, its field (in `FrameOptions` where the frame takes it as given: the request
//! holds those, the frame carries them; else the request's own), and its use below.

use platoon_core::frame::adaptive::Adaptive;
use platoon_core::frame::{FrameParams, PixelFilter, Region, DEFAULT_MAX_DEPTH};
use platoon_core::method::settings::{Value, ValueKind};
use platoon_tracer::{Sampling, Traversal};

use super::form::Request;

/// One option of a render request.
pub struct RequestOption {
    /// Its name: Python's keyword, the request's field, what its errors name.
    pub key: &'static str,
    /// Its command-line flag, without the dashes.
    pub flag: &'static str,
    pub help: &'static str,
    pub kind: ValueKind,
    /// Sets `value` (of its kind) on a request; an error says what is wrong with it.
    pub set: fn(&mut Request, &Value) -> Result<(), String>,
    /// Its value in a request; None where it is unset (what help shows as the default is the
    /// default request's).
    pub get: fn(&Request) -> Option<Value>,
    /// Whether it changes the image. Where and how a frame is rendered (the devices, the
    /// balancer, validation) does not: the image is the same bits on any split. What changes
    /// it is part of a render job (`image_settings`: a farm's rerun takes a frame made with
    /// another value as not done).
    pub image: bool,
    /// What is wrong with its value in `request` (checked by `Request::validate`, whose
    /// error names the option's key, before the rules between options).
    pub rule: fn(&Request) -> Result<(), String>,
    /// What an image's metadata says of it: its label and its text, read from the frame the
    /// image was rendered as (None: the frame does not hold it, or a report says it, as the
    /// samples reached say `spp`).
    pub metadata: Option<(&'static str, MetadataText)>,
}

/// An option's text in an image's metadata, read from the frame rendered.
pub type MetadataText = fn(&FrameParams) -> String;

/// The rule of an option any value of whose kind is right.
fn any_value(_: &Request) -> Result<(), String> {
    Ok(())
}

/// The most pixels a frame may have: a frame's sample and line counts are 32-bit.
pub const MAX_PIXELS: u64 = 1 << 28;

/// `n` refused when zero.
fn positive(n: u32) -> Result<(), String> {
    match n {
        0 => Err("must be positive".into()),
        _ => Ok(()),
    }
}

impl std::fmt::Debug for RequestOption {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.key)
    }
}

/// Every frame option of a request, in the order help lists them.
pub static OPTIONS: &[RequestOption] = &[
    RequestOption {
        key: "spp",
        flag: "spp",
        help: "Samples per pixel (with --time-limit, the most).",
        kind: ValueKind::Count,
        set: |r, v| {
            r.spp = v.count()?;
            Ok(())
        },
        get: |r| Some(Value::Count(r.spp)),
        image: true,
        rule: |r| positive(r.spp),
        metadata: None,
    },
    RequestOption {
        key: "time_limit",
        flag: "time-limit",
        help: "Stop within this many seconds: the passes start at one sample and grow as the \
               time left allows (then --spp is an upper bound; the spp reached goes into the \
               metadata). One device only.",
        kind: ValueKind::Number,
        set: |r, v| {
            let seconds = Some(v.number()? as f64);
            r.frame.time_limit = Request::time_limit_secs(seconds).map_err(|e| e.problem)?;
            Ok(())
        },
        get: |r| r.frame.time_limit.map(|t| Value::Number(t.as_secs_f32())),
        image: true,
        rule: |r| match r.frame.time_limit {
            Some(t) if t.is_zero() => Err("must be a positive number of seconds".into()),
            _ => Ok(()),
        },
        metadata: Some(("time_limit_s", |p| {
            p.options
                .time_limit
                .map(|t| format!("{:.3}", t.as_secs_f64()))
                .unwrap_or_else(|| "none".into())
        })),
    },
    RequestOption {
        key: "width",
        flag: "width",
        help: "The image's width in pixels.",
        kind: ValueKind::Count,
        set: |r, v| {
            r.width = v.count()?;
            Ok(())
        },
        get: |r| Some(Value::Count(r.width)),
        image: true,
        rule: |r| {
            positive(r.width)?;
            let pixels = r.width as u64 * r.height as u64;
            if pixels > MAX_PIXELS {
                return Err(format!(
                    "{} x {} is {pixels} pixels, more than the {MAX_PIXELS} a frame may have",
                    r.width, r.height
                ));
            }
            Ok(())
        },
        metadata: Some(("width", |p| p.width.to_string())),
    },
    RequestOption {
        key: "height",
        flag: "height",
        help: "The image's height in pixels.",
        kind: ValueKind::Count,
        set: |r, v| {
            r.height = v.count()?;
            Ok(())
        },
        get: |r| Some(Value::Count(r.height)),
        image: true,
        rule: |r| positive(r.height),
        metadata: Some(("height", |p| p.height.to_string())),
    },
    RequestOption {
        key: "crop",
        flag: "crop",
        help: "A border render: only the window X,Y,W,H of the image (its top-left pixel and \
               size, in pixels of --width x --height after --resolution-percent); the output is W x H, its pixels the same \
               bits as the whole render's there (path tracing).",
        kind: ValueKind::Word(&[]),
        set: |r, v| {
            r.crop = Some(Region::parse(v.word()?)?);
            Ok(())
        },
        get: |r| r.crop.map(|c| Value::Word(c.to_string())),
        image: true,
        rule: |r| match &r.crop {
            Some(c) => c.check(r.width, r.height),
            None => Ok(()),
        },
        metadata: Some(("crop", |p| match p.crop {
            Some(c) => format!(
                "{},{},{},{} of {} x {}",
                c.x, c.y, p.width, p.height, c.image_width, c.image_height
            ),
            None => "none".into(),
        })),
    },
    RequestOption {
        key: "ao_distance",
        flag: "ao-distance",
        help: "How far the ao AOV (ambient occlusion) looks for occluders, in scene units \
               (Cycles' world AO distance).",
        kind: ValueKind::Number,
        set: |r, v| {
            r.frame.ao_distance = v.number()?;
            Ok(())
        },
        get: |r| Some(Value::Number(r.frame.ao_distance)),
        image: true,
        rule: |r| match r.frame.ao_distance {
            d if d.is_finite() && d > 0.0 => Ok(()),
            d => Err(format!("must be a positive distance, not {d}")),
        },
        metadata: Some(("ao_distance", |p| p.options.ao_distance.to_string())),
    },
    RequestOption {
        key: "transparent_film",
        flag: "film-transparent",
        help: "A transparent film (Cycles' Film > Transparent): the environment the camera sees \
               is left out of the image, which gets an alpha channel (EXR: premultiplied; PNG \
               and TIFF: straight); it still lights the scene. Not for JPEG.",
        kind: ValueKind::Switch,
        set: |r, v| {
            r.frame.transparent_film = v.switch()?;
            Ok(())
        },
        get: |r| Some(Value::Switch(r.frame.transparent_film)),
        image: true,
        rule: any_value,
        metadata: Some(("film", |p| match p.options.transparent_film {
            true => "transparent (alpha: the share of camera rays finding a surface)".into(),
            false => "opaque".into(),
        })),
    },
    RequestOption {
        key: "max_depth",
        flag: "max-depth",
        help: "Longest path in segments (1: emitters only, 2: direct light). Default: \
               effectively unbounded.",
        kind: ValueKind::Count,
        set: |r, v| {
            r.path_loop.max_depth = v.count()?;
            Ok(())
        },
        // None at its default, which help says in words.
        get: |r| match r.path_loop.max_depth {
            DEFAULT_MAX_DEPTH => None,
            d => Some(Value::Count(d)),
        },
        image: true,
        rule: |r| match r.path_loop.max_depth {
            0 => Err("a path has at least one segment (1: emitters seen directly)".into()),
            _ => Ok(()),
        },
        // (The metadata says it with the rest of the path loop's: `PathLoop::metadata`.)
        metadata: None,
    },
    RequestOption {
        key: "seed",
        flag: "seed",
        help: "The random numbers' seed.",
        kind: ValueKind::Count,
        set: |r, v| {
            r.frame.seed = v.count()?;
            Ok(())
        },
        get: |r| Some(Value::Count(r.frame.seed)),
        image: true,
        rule: any_value,
        metadata: Some(("seed", |p| p.options.seed.to_string())),
    },
    RequestOption {
        key: "filter",
        flag: "filter",
        help: "The pixel filter: box (1 px), gaussian (sigma 0.5 px, cut at 1.5) or \
               blackman-harris (1.5 px, Cycles' default). Camera rays are drawn from it, so any \
               split of the frame gives the same image.",
        kind: ValueKind::Word(&[]),
        set: |r, v| {
            r.frame.filter = PixelFilter::parse(v.word()?)?;
            Ok(())
        },
        get: |r| Some(Value::Word(r.frame.filter.name().into())),
        image: true,
        rule: any_value,
        metadata: Some(("filter", |p| p.options.filter.describe())),
    },
    RequestOption {
        key: "aperture",
        flag: "aperture",
        help: "Thin-lens aperture radius in scene units (0: pinhole).",
        kind: ValueKind::Number,
        set: |r, v| {
            r.aperture = v.number()?;
            Ok(())
        },
        get: |r| Some(Value::Number(r.aperture)),
        image: true,
        rule: |r| match r.aperture {
            a if a.is_finite() && a >= 0.0 => Ok(()),
            a => Err(format!("must be a radius >= 0 (0: a pinhole), not {a}")),
        },
        metadata: None,
    },
    RequestOption {
        key: "focus_distance",
        flag: "focus-distance",
        help: "Distance to the plane in focus (default: the scene centre).",
        kind: ValueKind::Number,
        set: |r, v| {
            r.focus_distance = Some(v.number()?);
            Ok(())
        },
        get: |r| r.focus_distance.map(Value::Number),
        image: true,
        rule: |r| match r.focus_distance {
            Some(f) if !(f.is_finite() && f > 0.0) => Err(format!("must be positive, not {f}")),
            _ => Ok(()),
        },
        metadata: None,
    },
    RequestOption {
        key: "sampling",
        flag: "sampling",
        help: "Estimator: MIS of light and BSDF sampling (mis), or either alone (bsdf, light).",
        kind: ValueKind::Word(&["mis", "bsdf", "light"]),
        set: |r, v| {
            let name = v.word()?;
            r.sampling = Sampling::by_name(name)
                .ok_or_else(|| format!("unknown estimator {name}: one of mis, bsdf, light"))?;
            Ok(())
        },
        get: |r| Some(Value::Word(r.sampling.name().into())),
        image: true,
        rule: any_value,
        metadata: None,
    },
    RequestOption {
        key: "traversal",
        flag: "traversal",
        help: "How each device finds what a ray hits: platoon's own BVH traversal (own), the \
               device's ray queries over acceleration structures built on it (ray-query: a GPU \
               with ray tracing, lavapipe from Mesa 24.1; `platoon devices` says which), or \
               auto (own on CPU devices, where it measured faster, and on devices without ray \
               queries; ray-query on GPUs that offer them). The image agrees within noise; the \
               metadata says which each device took.",
        kind: ValueKind::Word(&Traversal::NAMES),
        set: |r, v| {
            let name = v.word()?;
            r.traversal = Traversal::by_name(name).ok_or_else(|| {
                format!("unknown traversal {name}: one of {}", Traversal::NAMES.join(", "))
            })?;
            Ok(())
        },
        get: |r| Some(Value::Word(r.traversal.name().into())),
        image: true,
        rule: any_value,
        metadata: None,
    },
    RequestOption {
        key: "devices",
        flag: "devices",
        help: "Devices: `auto` (every GPU, or lavapipe where there is none), `all`, indices like \
               `0,1` (see `platoon devices`), or `lavapipe:T1,T2,...` (one software tracer per \
               entry, with Ti threads each).",
        kind: ValueKind::Word(&[]),
        set: |r, v| {
            r.devices = v.word()?.parse()?;
            Ok(())
        },
        get: |r| Some(Value::Word(r.devices.to_string())),
        image: false,
        rule: any_value,
        metadata: None,
    },
    RequestOption {
        key: "balancer",
        flag: "balancer",
        help: "How lines are split between devices: none, robin-hood, perfect, perfect-smooth, \
               cycles, cost-aware; each with `+steal` (cost-aware+steal): the devices that \
               finish first take the unstarted ends of the others' bands in the same frame \
               (same image).",
        kind: ValueKind::Word(&[]),
        set: |r, v| {
            // (Its name is checked by the request's rule: `validate`.)
            r.balancer = v.word()?.to_string();
            Ok(())
        },
        get: |r| Some(Value::Word(r.balancer.clone())),
        image: false,
        rule: |r| match platoon_core::balance::by_name(&r.balancer) {
            Some(_) => Ok(()),
            None => Err(format!(
                "unknown balancer {}: {}",
                r.balancer,
                platoon_core::balance::names_help()
            )),
        },
        metadata: None,
    },
    RequestOption {
        key: "validation",
        flag: "validation",
        help: "Enable the Khronos validation layer.",
        kind: ValueKind::Switch,
        set: |r, v| {
            r.validation = v.switch()?;
            Ok(())
        },
        get: |r| Some(Value::Switch(r.validation)),
        image: false,
        rule: any_value,
        metadata: None,
    },
    RequestOption {
        key: "denoise",
        flag: "denoise",
        help: "Denoise the image after assembly, guided by its albedo, normal and depth: none, \
               atrous (the edge-avoiding a-trous filter), atrous-device (the same on the first \
               device) or oidn (Intel Open Image Denoise, in a build with `--features oidn`); \
               biased. The raw image is written beside it as NAME.noisy.EXT.",
        kind: ValueKind::Word(&[]),
        set: |r, v| {
            r.denoiser = v.word()?.parse()?;
            Ok(())
        },
        get: |r| Some(Value::Word(r.denoiser.name().into())),
        image: true,
        rule: |r| r.denoiser.available(),
        metadata: None,
    },
    RequestOption {
        key: "adaptive_threshold",
        flag: "adaptive-threshold",
        help: "Adaptive sampling (Cycles' scheme): a pixel stops taking samples once its noise \
               estimate is below this threshold (0.01 clean, 0.1 a preview); --spp is then the \
               most a pixel takes. An EXR output gets the sample-count layer. Path tracing \
               only.",
        kind: ValueKind::Number,
        set: |r, v| {
            let min_spp = r.adaptive.and_then(|a| a.min_spp);
            let threshold = v.number()?;
            r.adaptive = Some(Adaptive { threshold, min_spp });
            Ok(())
        },
        get: |r| r.adaptive.map(|a| Value::Number(a.threshold)),
        image: true,
        rule: any_value,
        metadata: None,
    },
];

/// The options that change the image as `key value` (`key default` where unset), in the table's
/// order: with the scene, the camera, the method and the outputs, what a render job is.
pub fn image_settings(request: &Request) -> Vec<String> {
    OPTIONS
        .iter()
        .filter(|o| o.image)
        .map(|o| match (o.get)(request) {
            Some(v) => format!("{} {v}", o.key),
            None => format!("{} default", o.key),
        })
        .collect()
}

/// What the metadata of an image says of the frame options its frame holds, in the table's
/// order.
pub fn frame_metadata(params: &FrameParams) -> Vec<(String, String)> {
    OPTIONS
        .iter()
        .filter_map(|o| o.metadata)
        .map(|(label, text)| (label.to_string(), text(params)))
        .collect()
}

/// The option named `key`.
pub fn option(key: &str) -> Option<&'static RequestOption> {
    OPTIONS.iter().find(|o| o.key == key)
}

/// What help shows as `option`'s default: its value in `base` (the request a front end starts
/// from), if it has one.
pub fn default_text(option: &RequestOption, base: &Request) -> Option<String> {
    (option.get)(base).map(|v| v.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value of each option its own rule refuses: the request's validation names the
    /// option, and the value its default has passes.
    #[test]
    fn each_options_rule_refuses_its_wrong_values_under_its_key() {
        let wrong = |key: &str| -> Option<Request> {
            let mut r = Request::default();
            match key {
                "spp" => r.spp = 0,
                "width" => r.width = 0,
                "height" => r.height = 0,
                "time_limit" => r.frame.time_limit = Some(std::time::Duration::ZERO),
                "crop" => r.crop = Some(Region::parse("500,0,20,20").unwrap()),
                "ao_distance" => r.frame.ao_distance = -1.0,
                "max_depth" => r.path_loop.max_depth = 0,
                "aperture" => r.aperture = f32::NAN,
                "focus_distance" => r.focus_distance = Some(0.0),
                "balancer" => r.balancer = "fastest".into(),
                _ => return None,
            }
            Some(r)
        };
        Request::default().validate().unwrap();
        let mut ruled = Vec::new();
        for o in OPTIONS {
            let Some(r) = wrong(o.key) else { continue };
            let e = r.validate().expect_err(o.key);
            assert_eq!(e.option, o.key, "{e}");
            assert!((o.rule)(&r).is_err(), "{}: its own rule passes {e}", o.key);
            ruled.push(o.key);
        }
        assert_eq!(ruled.len(), 10, "{ruled:?}");
        let mut huge = Request::default();
        (huge.width, huge.height) = (1 << 15, 1 << 14);
        assert!(huge.validate().unwrap_err().problem.contains("pixels"));
    }

    /// Each option the metadata says reads its own value from the frame: a request of another
    /// value gives another text for its label alone.
    #[test]
    fn the_metadata_says_each_options_value_from_the_frame() {
        let camera =
            platoon_core::scene::camera::Camera::look_at(glam::Vec3::Z, glam::Vec3::ZERO, 1.0);
        let base = frame_metadata(&Request::default().frame_params(camera));
        let labels: Vec<&str> = OPTIONS
            .iter()
            .filter_map(|o| o.metadata.map(|m| m.0))
            .collect();
        assert_eq!(
            base.iter().map(|(l, _)| l.as_str()).collect::<Vec<_>>(),
            labels
        );
        for o in OPTIONS.iter().filter(|o| o.metadata.is_some()) {
            let mut r = Request::default();
            let value = match (o.key, o.kind) {
                ("crop", _) => Value::Word("1,2,3,4".into()),
                ("filter", _) => Value::Word("gaussian".into()),
                (_, ValueKind::Count) => Value::Count(7),
                (_, ValueKind::Number) => Value::Number(0.5),
                (_, ValueKind::Switch) => Value::Switch(true),
                (key, kind) => panic!("{key}: no test value of {kind:?}"),
            };
            (o.set)(&mut r, &value).unwrap();
            let said = frame_metadata(&r.frame_params(camera));
            let changed: Vec<&str> = said
                .iter()
                .zip(&base)
                .filter(|(a, b)| a != b)
                .map(|(a, _)| a.0.as_str())
                .collect();
            let label = o.metadata.unwrap().0;
            // A crop's window is the frame's size too.
            let expected: &[&str] = match o.key {
                "crop" => &["width", "height", "crop"],
                _ => &[label],
            };
            assert_eq!(changed, expected, "{}: {said:?}", o.key);
        }
    }

    /// Every option that changes the image is part of a job's text with its value, and only
    /// where and how the frame renders is left out.
    #[test]
    fn every_option_that_changes_the_image_is_in_a_jobs_settings() {
        let left_out: Vec<&str> = OPTIONS.iter().filter(|o| !o.image).map(|o| o.key).collect();
        assert_eq!(left_out, ["devices", "balancer", "validation"]);
        let base = Request::default();
        let before = image_settings(&base);
        for o in OPTIONS.iter().filter(|o| o.image) {
            let value = match (o.key, o.kind) {
                ("crop", _) => Value::Word("0,0,2,2".into()),
                ("filter", _) => Value::Word("gaussian".into()),
                ("sampling", _) => Value::Word("bsdf".into()),
                ("traversal", _) => Value::Word("ray-query".into()),
                ("denoise", _) => Value::Word("atrous".into()),
                (_, ValueKind::Count) => Value::Count(3),
                (_, ValueKind::Number) => Value::Number(0.5),
                (_, ValueKind::Switch) => Value::Switch(true),
                (key, kind) => panic!("{key}: no test value of {kind:?}"),
            };
            let mut r = Request::default();
            (o.set)(&mut r, &value).unwrap_or_else(|e| panic!("{}: {e}", o.key));
            let after = image_settings(&r);
            assert_ne!(after, before, "{} does not change the settings", o.key);
            assert!(
                after
                    .iter()
                    .any(|s| s.starts_with(o.key) && s.contains(&value.to_string())),
                "{}: {after:?}",
                o.key
            );
        }
    }
}

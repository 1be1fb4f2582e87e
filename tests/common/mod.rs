//! Shared helpers of the integration tests: lavapipe forced, validation on, small images.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::Once;

use glam::Vec3;
use platoon::core::frame::FrameParams;
use platoon::core::output::Film;
use platoon::tracer::{Sampling, Tracer, TracerOptions};
use platoon::{PrepareOptions, Prepared};

static INIT: Once = Once::new();

pub const LAVAPIPE_ICD: &str = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";

/// Forces Mesa lavapipe so results do not depend on other installed drivers, and keeps the
/// kernel caches in the target folder shared by all test runs.
pub fn init() {
    INIT.call_once(|| {
        assert!(
            Path::new(LAVAPIPE_ICD).exists(),
            "lavapipe is not installed: run tools/install-deps.sh"
        );
        // SAFETY: runs once, before any test thread touches the environment or Vulkan.
        unsafe {
            std::env::set_var("VK_DRIVER_FILES", LAVAPIPE_ICD);
            std::env::set_var("VK_ICD_FILENAMES", LAVAPIPE_ICD);
            if std::env::var_os("PLATOON_CACHE_DIR").is_none() {
                let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("platoon-cache");
                std::env::set_var("PLATOON_CACHE_DIR", dir);
            }
        }
    });
}

pub fn shared(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared")
        .join(rel)
}

pub fn tracer(prepared: &Prepared, sampling: Sampling) -> Tracer {
    init();
    Tracer::new(
        &TracerOptions {
            device: 0,
            validation: true,
            sampling,
        },
        &prepared.gpu,
    )
    .expect("tracer")
}

/// Renders the whole frame with validation on and asserts the layer said nothing.
pub fn render_with(tracer: &mut Tracer, params: &FrameParams) -> Film {
    let r =
        platoon::render_bands(tracer, params, &[(0, params.height)], &mut |_| {}).expect("render");
    assert_eq!(r.rejected_samples(), 0, "NaN/Inf samples were produced");
    assert_no_validation_messages(tracer);
    r.film
}

pub fn assert_no_validation_messages(tracer: &Tracer) {
    let msgs = tracer.validation_messages();
    assert!(msgs.is_empty(), "validation messages:\n{}", msgs.join("\n"));
}

pub fn render(prepared: &Prepared, params: &FrameParams, sampling: Sampling) -> Film {
    let mut t = tracer(prepared, sampling);
    render_with(&mut t, params)
}

pub fn prepare(scene: platoon::core::Scene, env: platoon::EnvChoice) -> Prepared {
    platoon::prepare(
        scene,
        &PrepareOptions {
            env,
            ..Default::default()
        },
    )
    .expect("prepare")
}

pub fn constant_env(c: f32) -> platoon::EnvChoice {
    platoon::EnvChoice::Color(Vec3::splat(c))
}

/// Mean and standard error of the per-pixel values of one channel-averaged film region.
pub fn mean_and_stderr(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let v: Vec<f64> = values.collect();
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

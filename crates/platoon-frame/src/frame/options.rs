//! The options of a frame that a request sets as they are (the seed, the pixel filter, a
//! transparent film, the AO pass's distance, a time limit), declared once with their defaults:
//! what a request holds (`platoon::Request::frame`), what the frame's parameters carry to every
//! tracer and rank (`FrameParams::options`), and what the request's table sets, checks and
//! writes into an image's metadata (`platoon::request::options`). A new option of this kind is
//! its field here (and a word of `OPTION_WORDS` when the kernel reads its value), its entry in
//! that table, its use (a shader) and its test.

use std::time::Duration;

use super::kernel_word::KernelWord;
use super::pixel_filter::PixelFilter;
use crate::flatten::features::KernelOption;

/// The ambient-occlusion pass's distance by default: Cycles' (10 m).
pub const DEFAULT_AO_DISTANCE: f32 = 10.0;

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrameOptions {
    /// The random numbers' seed: with the pixel, the sample index and the frame, what every
    /// random number of the frame is a pure function of.
    pub seed: u32,
    /// What a sample counts for its pixel by its offset (the camera rays' distribution).
    pub filter: PixelFilter,
    /// A transparent film (Cycles' Film > Transparent): the environment the camera sees is
    /// left out of the image (alpha 0 there, the `AovPass::Alpha` pass); it still lights the
    /// scene. Compiled in only when set.
    pub transparent_film: bool,
    /// How far the ambient-occlusion pass (`AovPass::Ao`) looks for what occludes a point,
    /// in scene units (Cycles' world AO distance).
    pub ao_distance: f32,
    /// Stop adding passes once this much wall time has gone (at least one sample is
    /// rendered): `spp` is then an upper bound and each band reports the samples it holds. For
    /// one device (`FrameParams::check_split`): bands cut at different times would break the
    /// bit-identity of device splits.
    pub time_limit: Option<Duration>,
}

/// What the kernel reads of the frame's options, in order (`KernelWord`); the options that
/// select code say their defines instead (`FrameOptions::kernel_options`).
pub const OPTION_WORDS: &[KernelWord<FrameOptions>] = &[
    // What every random number of the frame is a pure function of, with the pixel, the
    // sample index and the frame.
    KernelWord {
        name: "render_seed",
        float: false,
        of: |o| o.seed,
    },
    // The ambient-occlusion pass's reach (path/aov.glsl).
    KernelWord {
        name: "ao_distance",
        float: true,
        of: |o| o.ao_distance.to_bits(),
    },
];

impl Default for FrameOptions {
    fn default() -> Self {
        FrameOptions {
            seed: 0,
            filter: PixelFilter::Box,
            transparent_film: false,
            ao_distance: DEFAULT_AO_DISTANCE,
            time_limit: None,
        }
    }
}

impl FrameOptions {
    /// The kernel defines of the options that select code, with whether each is on: part of
    /// the kernel variant (`method::variant`).
    pub fn kernel_options(&self) -> Vec<KernelOption> {
        vec![
            (
                "transparent-film",
                "FILM_TRANSPARENT",
                self.transparent_film,
            ),
            (
                "gaussian-filter",
                "PIXEL_FILTER_GAUSSIAN",
                self.filter == PixelFilter::Gaussian,
            ),
            (
                "blackman-harris-filter",
                "PIXEL_FILTER_BLACKMAN_HARRIS",
                self.filter == PixelFilter::BlackmanHarris,
            ),
        ]
    }
}

//! The frame that renders one AOV pass of a frame: what a still's layers (the facade's
//! `aov`) and the game loop's denoising guides (`drive::denoising`) both render.

use super::aov::AovPass;
use super::{FilmState, FrameParams, Output};
use crate::method::Method;

/// `params`' frame rendering `pass` at `spp`: the path tracer's kernel whatever method renders
/// the beauty, from no earlier sums, without a time limit or scaled roulette.
pub fn aov_pass_params(params: &FrameParams, pass: AovPass, spp: u32) -> FrameParams {
    let mut p = params.clone();
    p.output = Output::Aov(pass);
    // A method whose image is the sum of the light passes keeps its state (a light pass's paths
    // must be the beauty's); another's passes are the reference's, the path tracer's.
    if !p.method.unit().splits_into_light_passes() {
        p.method = Method::path_tracing();
    }
    p.spp = spp;
    // A light pass keeps the beauty's roulette: its paths must be the beauty's.
    if !matches!(pass, AovPass::Light(_)) {
        p.path_loop.rr_survival = 1.0;
    }
    p.film = FilmState::default();
    p.options.time_limit = None;
    if let AovPass::SampleIds(sample) = pass {
        p.first_sample = params.first_sample.wrapping_add(sample);
    }
    p
}

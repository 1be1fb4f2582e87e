//! What a sweep measured: a row per technique and sample count, and the report that holds them.

use std::path::PathBuf;

/// One technique at one sample count.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub technique: String,
    pub spp: u32,
    /// Device time of the render (GPU timestamps; wall time where the device has none).
    pub ms: f64,
    pub rmse: f64,
    pub relmse: f64,
    /// Mean LDR-FLIP error (perceptual, 0 to 1).
    pub flip: f64,
    pub mrays: f64,
    pub efficiency: f64,
    pub biased: bool,
}

pub struct Report {
    pub rows: Vec<Row>,
    pub reference: PathBuf,
    /// Samples of the reference (None for a user's file).
    pub reference_spp: Option<u32>,
    pub reference_loaded: bool,
    /// Techniques not run, and why (an effect the scene does not use).
    pub skipped: Vec<String>,
}

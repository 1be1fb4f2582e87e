//! `platoon tradeoff`: what accuracy costs in time (issue 10). Every technique is rendered at
//! every sample count of a sweep and measured against a converged unbiased reference: time,
//! rays per second, RMSE (Bikker's appendix D), relative MSE, and efficiency 1 / (MSE x time).
//! Against an unbiased reference bias shows up as an error floor that more samples do not
//! lower, which a reference rendered by the same technique (Bikker's) would hide.

pub mod metrics;
pub mod reference;
pub mod report;
pub mod technique;

use std::collections::HashMap;
use std::path::PathBuf;

use anyhow::{bail, Context as _, Result};
use platoon_core::frame::{assemble, FrameParams};
use platoon_tracer::{Sampling, Tracer, TracerOptions};

pub use technique::Technique;

use crate::Prepared;

#[derive(Clone, Debug)]
pub struct Options {
    pub width: u32,
    pub height: u32,
    pub spp_list: Vec<u32>,
    pub techniques: Vec<Technique>,
    pub seed: u32,
    /// Samples of platoon's own reference.
    pub reference_spp: u32,
    /// A reference image to use instead (EXR, the sweep's size).
    pub reference: Option<PathBuf>,
    /// Folder for tradeoff.csv (rewritten after every row, so an interrupted sweep keeps the
    /// rows it finished).
    pub out: PathBuf,
}

impl Options {
    pub fn validate(&self) -> Result<()> {
        if self.width == 0 || self.height == 0 {
            bail!("--width and --height must be positive");
        }
        if self.spp_list.is_empty() || self.spp_list.contains(&0) {
            bail!("--spp-list needs one or more positive sample counts");
        }
        if self.techniques.is_empty() {
            bail!("--techniques needs one or more techniques");
        }
        if self.reference_spp == 0 {
            bail!("--reference-spp must be positive");
        }
        if !self.out.is_dir() {
            bail!("{}: output folder does not exist", self.out.display());
        }
        Ok(())
    }
}

/// One technique at one sample count.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub technique: String,
    pub spp: u32,
    /// Device time of the render (GPU timestamps; wall time where the device has none).
    pub ms: f64,
    pub rmse: f64,
    pub relmse: f64,
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
}

/// What the sweep is doing, for a progress display.
pub enum Progress<'a> {
    /// Samples of the reference rendered so far, of `total`.
    Reference { done: u32, total: u32 },
    /// A row is starting: `index` of `total`.
    Row {
        index: usize,
        total: usize,
        label: &'a str,
    },
}

/// Renders the reference (or loads it), then every technique at every sample count.
pub fn run(prepared: &Prepared, o: &Options, progress: &mut dyn FnMut(Progress)) -> Result<Report> {
    o.validate()?;
    let mut base = FrameParams::new(o.width, o.height, 1, prepared.camera);
    base.seed = o.seed;
    // Bad references are refused before any sweep starts.
    let reference = match &o.reference {
        Some(path) => reference::user_reference(path, o.width, o.height)?,
        None => {
            let total = o.reference_spp;
            reference::platoon_reference(prepared, &base, total, &mut |done| {
                progress(Progress::Reference { done, total })
            })?
        }
    };
    let mut tracers: HashMap<Sampling, Tracer> = HashMap::new();
    let mut rows = Vec::new();
    let total = o.techniques.len() * o.spp_list.len();
    let csv_path = o.out.join("tradeoff.csv");
    for technique in &o.techniques {
        let label = technique.to_string();
        let tracer = match tracers.entry(technique.sampling()) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => e.insert(Tracer::new(
                &TracerOptions {
                    sampling: technique.sampling(),
                    ..Default::default()
                },
                &prepared.gpu,
            )?),
        };
        let mut params = base.clone();
        technique.apply(&mut params);
        // The first dispatch of a kernel variant pays for its compilation: not a cost of the
        // technique.
        params.spp = 1;
        tracer
            .render(&params, 0, o.height, &mut |_| {})
            .with_context(|| format!("warming up {label}"))?;
        for &spp in &o.spp_list {
            progress(Progress::Row {
                index: rows.len(),
                total,
                label: &label,
            });
            params.spp = spp;
            let band = tracer
                .render(&params, 0, o.height, &mut |_| {})
                .with_context(|| format!("rendering {label} at {spp} spp"))?;
            let seconds = if band.gpu_time.is_zero() {
                band.wall_time.as_secs_f64()
            } else {
                band.gpu_time.as_secs_f64()
            };
            let rays = band.rays;
            let film = assemble(&params, &[band]);
            let e = metrics::errors(&film, &reference.film);
            rows.push(Row {
                technique: label.clone(),
                spp,
                ms: seconds * 1e3,
                rmse: e.rmse,
                relmse: e.relmse,
                mrays: rays as f64 / seconds.max(1e-12) / 1e6,
                efficiency: metrics::efficiency(e.rmse, seconds),
                biased: technique.biased(),
            });
            platoon_core::output::write_text(&csv_path, &report::csv(&rows))?;
        }
    }
    Ok(Report {
        rows,
        reference: reference.path,
        reference_spp: reference.spp,
        reference_loaded: reference.loaded,
    })
}

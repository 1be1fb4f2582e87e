//! `platoon tradeoff`: what accuracy costs in time (issue 10). Every technique is rendered at
//! every sample count of a sweep and measured against a converged unbiased reference: time,
//! rays per second, RMSE (Bikker's appendix D), relative MSE, and efficiency 1 / (MSE x time).
//! Against an unbiased reference bias shows up as an error floor that more samples do not
//! lower, which a reference rendered by the same technique (Bikker's) would hide.

pub mod adaptive;
pub mod denoise;
pub mod effects;
pub mod markdown;
pub mod method_technique;
pub mod metrics;
pub mod plots;
pub mod reference;
pub mod report;
mod results;
pub mod technique;
pub mod variant;

use std::collections::hash_map::Entry;
use std::collections::HashMap;
use std::path::PathBuf;

use anyhow::{bail, Context as _, Result};
use platoon_core::frame::{assemble, FrameParams};
use platoon_tracer::{Sampling, Tracer, TracerOptions};

pub use results::{Report, Row};
pub use technique::Technique;

use platoon::Prepared;

#[derive(Clone, Debug)]
pub struct Options {
    pub width: u32,
    pub height: u32,
    pub spp_list: Vec<u32>,
    pub techniques: Vec<Technique>,
    pub seed: u32,
    /// Renders timed per cell; the median time is reported (the errors are the same each time:
    /// the random numbers are a function of the seed).
    pub repeat: u32,
    /// Samples of platoon's own reference.
    pub reference_spp: u32,
    /// A reference image to use instead (EXR, the sweep's size).
    pub reference: Option<PathBuf>,
    /// Folder for tradeoff.csv (rewritten after every row, so an interrupted sweep keeps the
    /// rows it finished), the plots, report.md and its images.
    pub out: PathBuf,
    /// What report.md calls the scene.
    pub scene_label: String,
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
    base.options.seed = o.seed;
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
    // One tracer per estimator and scene variant (with the variant, which a method's
    // preparation reads); each technique's parameters; every kernel variant warmed up (its
    // first dispatch pays for compiling it: not a cost of the technique).
    type Key = (Sampling, Option<variant::Variant>);
    let mut tracers: HashMap<Key, (Tracer, Option<Prepared>)> = HashMap::new();
    let mut setups = Vec::with_capacity(o.techniques.len());
    let mut skipped = Vec::new();
    for technique in &o.techniques {
        let mut params = base.clone();
        technique.apply(&mut params);
        // What the tracer would refuse of the scene's lights (`ResampledLight::check_lights`).
        let lights = prepared.gpu.features.punctual_lights;
        if let Some(Err(why)) = params
            .method
            .path()
            .resampled_light
            .map(|r| r.check_lights(lights))
        {
            skipped.push(format!("{technique}: {why}"));
            continue;
        }
        let key = (technique.sampling(), technique.variant());
        let (tracer, scene) = match tracers.entry(key) {
            Entry::Occupied(e) => e.into_mut(),
            Entry::Vacant(e) => {
                let options = TracerOptions {
                    sampling: technique.sampling(),
                    ..Default::default()
                };
                let entry = match technique.variant() {
                    None => (Tracer::new(&options, &prepared.gpu)?, None),
                    Some(v) => match variant::prepare(prepared, v)? {
                        Some(p) => (Tracer::new(&options, &p.gpu)?, Some(p)),
                        None => {
                            skipped.push(format!("{technique}: the scene has no such effect"));
                            continue;
                        }
                    },
                };
                e.insert(entry)
            }
        };
        let gpu = &scene.as_ref().unwrap_or(prepared).gpu;
        params.spp = 1;
        // A method's preparation (vertex links' update) runs on the technique's tracer, once to
        // compile its kernels and once timed; that time is added to every render of the
        // technique (a still frame pays for it once).
        let mut update = 0.0;
        let warm = platoon::method_update::on_tracer(tracer, gpu, &params)
            .with_context(|| format!("preparing {technique}"))?;
        if warm.method != params.method {
            let clock = std::time::Instant::now();
            params = platoon::method_update::on_tracer(tracer, gpu, &params)?;
            update = clock.elapsed().as_secs_f64();
        }
        tracer
            .render(&params, 0, o.height, &mut |_| {})
            .with_context(|| format!("warming up {technique}"))?;
        setups.push((technique.clone(), params, update));
    }
    let cells: Vec<(usize, u32)> = (0..setups.len())
        .flat_map(|t| o.spp_list.iter().map(move |&spp| (t, spp)))
        .collect();
    let top_spp = o.spp_list.iter().copied().max().unwrap_or(1);
    let csv_path = o.out.join("tradeoff.csv");
    let mut rows: Vec<Row> = Vec::with_capacity(cells.len());
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); cells.len()];
    let mut rays = vec![0u64; cells.len()];
    // Each technique's render at the highest sample count, for the report's images.
    let mut finals: Vec<(String, platoon_core::output::Film)> = Vec::new();
    // Repeats go round every cell in turn, so that a slow spell of the machine spreads over
    // all techniques instead of falling on one; each cell reports its median time.
    let repeat = o.repeat.max(1) as usize;
    for round in 0..repeat {
        for (c, &(t, spp)) in cells.iter().enumerate() {
            let (technique, params, update) = &setups[t];
            let label = technique.to_string();
            progress(Progress::Row {
                index: round * cells.len() + c,
                total: repeat * cells.len(),
                label: &label,
            });
            let mut params = params.clone();
            params.spp = spp;
            let (tracer, _) = tracers
                .get_mut(&(technique.sampling(), technique.variant()))
                .expect("a tracer per estimator and scene variant");
            let (mut film, frame_rays, mut seconds_spent) = match technique {
                Technique::Adaptive(bits) => {
                    adaptive::render(tracer, &params, f32::from_bits(*bits))
                        .with_context(|| format!("rendering {label} at {spp} spp"))?
                }
                _ => {
                    let band = tracer
                        .render(&params, 0, o.height, &mut |_| {})
                        .with_context(|| format!("rendering {label} at {spp} spp"))?;
                    let device = platoon_core::measure::device_time(band.gpu_time, band.wall_time);
                    // A method's pass after assembly runs on the CPU (IGI's filters): its time
                    // is the technique's too.
                    let filters = std::time::Instant::now();
                    let mut bands = [band];
                    params.method.unit().finish(&params, &mut bands);
                    let [band] = bands;
                    let film = assemble(&params, std::slice::from_ref(&band));
                    (film, band.rays, (device + filters.elapsed()).as_secs_f64())
                }
            };
            seconds_spent += update;
            if let Technique::Denoise(d) = technique {
                let (denoised, spent) = denoise::apply(*d, tracer, &params, &film)?;
                film = denoised;
                seconds_spent += spent;
            }
            times[c].push(seconds_spent);
            let seconds = platoon_core::measure::median(times[c].clone());
            if round == 0 {
                // The errors are the same every round (the same random numbers).
                rays[c] = frame_rays;
                let e = metrics::errors(&film, &reference.film);
                if spp == top_spp {
                    finals.push((label.clone(), film));
                }
                rows.push(Row {
                    technique: label,
                    spp,
                    ms: 0.0,
                    rmse: e.rmse,
                    relmse: e.relmse,
                    flip: e.flip,
                    mrays: 0.0,
                    efficiency: 0.0,
                    biased: technique.biased(),
                });
            }
            let row = &mut rows[c];
            row.ms = seconds * 1e3;
            row.mrays = rays[c] as f64 / seconds.max(1e-12) / 1e6;
            row.efficiency = metrics::efficiency(row.rmse, seconds);
            // Rewritten after every render: an interrupted sweep keeps what it measured.
            platoon_core::output::write_text(&csv_path, &report::csv(&rows))?;
        }
    }
    let report = Report {
        rows,
        reference: reference.path,
        reference_spp: reference.spp,
        reference_loaded: reference.loaded,
        skipped,
    };
    let title = format!("{} at {}x{}", o.scene_label, o.width, o.height);
    plots::write_error_png(&o.out.join("tradeoff-error.png"), &report.rows, &title)?;
    plots::write_efficiency_png(
        &o.out.join("tradeoff-efficiency.png"),
        &report.rows,
        &format!("efficiency at {top_spp} spp, {title}"),
    )?;
    markdown::write(&o.out, &report, &reference.film, &finals, &o.scene_label)?;
    Ok(report)
}

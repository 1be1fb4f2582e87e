//! `platoon tradeoff [SCENE]`: every technique at every sample count, measured against a
//! converged reference: the table (Bikker's appendix D shape), tradeoff.csv, and with --json one
//! JSON object on stdout after the text.

use std::path::PathBuf;

use anyhow::{anyhow, Result};
use indicatif::{ProgressBar, ProgressStyle};
use platoon_lab::tradeoff::{self, report, Progress, Technique};

use crate::scene_args::SceneArgs;
use platoon::core::method::kind::MethodKind;
use platoon::core::method::registry;

#[derive(clap::Args)]
pub struct TradeoffArgs {
    #[command(flatten)]
    scene: SceneArgs,
    #[arg(long, default_value_t = 64)]
    width: u32,
    #[arg(long, default_value_t = 64)]
    height: u32,
    /// Sample counts of the sweep.
    #[arg(long, value_delimiter = ',', default_value = "4,8,16,32,64")]
    spp_list: Vec<u32>,
    /// Techniques: mis, bsdf, light, max-depth=N, rr-depth=N, rr-survival=PERCENT,
    /// rr-fixed=PERCENT, clamp=C, uniform-lights, no-regeneration, generic-kernel, ris=M,
    /// mis-ris=M, resampled-light=M, dpt, spt (the streaming kernels: Bikker's RR/SPT), nop (the last path of a
    /// pass cut where its SIMD group stopped: biased), single-bounce, no-textures,
    /// no-normal-maps, opaque, env-mean, denoise=atrous (the filter after assembly, guides and
    /// filter timed), adaptive=T (adaptive sampling at noise threshold T; the spp is each
    /// pixel's most), and a method with its options, NAME=VALUE[+OPTION]... (its flags'
    /// settings, `+subK`: every mesh subdivided K times; its preparation's time counts; an
    /// unknown option lists them). Default: the sweep of --method.
    #[arg(long, value_delimiter = ',')]
    techniques: Option<Vec<String>>,
    /// The method whose comparison is swept when no --techniques are given (path: mis, bsdf,
    /// light, max-depth=2, no-regeneration; another: that method at its settings against the
    /// path tracer and the methods before it).
    #[arg(long, default_value = "path", value_parser = parse_method)]
    method: &'static dyn MethodKind,
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Renders timed per cell (the median is reported).
    #[arg(long, default_value_t = 3)]
    repeat: u32,
    /// Samples per pixel of platoon's own reference (cached between runs).
    #[arg(long, default_value_t = 4096)]
    reference_spp: u32,
    /// Measure against this EXR instead (e.g. another renderer's; the sweep's size).
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Folder for tradeoff.csv.
    #[arg(long, default_value = ".")]
    out: PathBuf,
    /// Print one JSON object after the text.
    #[arg(long)]
    json: bool,
}

pub fn run(args: TradeoffArgs) -> Result<()> {
    let techniques = match &args.techniques {
        Some(list) => list
            .iter()
            .map(|t| Technique::parse(t))
            .collect::<Result<Vec<_>>>()?,
        None => Technique::sweep_of(args.method),
    };
    let options = tradeoff::Options {
        width: args.width,
        height: args.height,
        spp_list: args.spp_list.clone(),
        techniques,
        seed: args.seed,
        repeat: args.repeat,
        reference_spp: args.reference_spp,
        reference: args.reference.clone(),
        out: args.out.clone(),
        scene_label: args
            .scene
            .scene
            .as_ref()
            .map_or("the built-in Cornell box".into(), |p| {
                p.display().to_string()
            }),
    };
    options.validate()?;
    let prepared = args.scene.prepare()?;
    if let Some(note) = &prepared.note {
        eprintln!("note: {note}");
    }
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} {msg}")
            .map_err(|e| anyhow!("{e}"))?,
    );
    let report = tradeoff::run(&prepared, &options, &mut |p| match p {
        Progress::Reference { done, total } => {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
            bar.set_message("spp of the reference");
        }
        Progress::Row {
            index,
            total,
            label,
        } => {
            bar.set_length(total as u64);
            bar.set_position(index as u64);
            bar.set_message(label.to_string());
        }
    });
    bar.finish_and_clear();
    let report = report?;
    let origin = match (report.reference_spp, report.reference_loaded) {
        (Some(spp), true) => format!("platoon, {spp} spp, from the cache"),
        (Some(spp), false) => format!("platoon, {spp} spp, rendered now"),
        (None, _) => "given".into(),
    };
    for s in &report.skipped {
        eprintln!("skipped {s}");
    }
    let text = format!(
        "reference: {} ({origin})\n{}wrote {} (the rows), tradeoff-error.png, \
         tradeoff-efficiency.png and report.md",
        report.reference.display(),
        report::table(&report.rows),
        args.out.join("tradeoff.csv").display()
    );
    if args.json {
        eprintln!("{text}");
        println!("{}", report::json(&report));
    } else {
        println!("{text}");
    }
    Ok(())
}

fn parse_method(name: &str) -> Result<&'static dyn MethodKind, String> {
    registry::kind(name)
        .ok_or_else(|| format!("unknown method {name}: one of {}", registry::names()))
}

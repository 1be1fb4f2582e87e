//! `platoon bench scenes`: the bench scenes (the built-in box, the box a node per object, the
//! spheres scene, the sphere field, CesiumMan under an environment) as whole `platoon render`
//! processes against Mitsuba 3 on the same scenes, alternated, medians; platoon's numbers alone
//! when Mitsuba is not installed (and it says so).

use std::path::PathBuf;

use anyhow::{bail, Result};
use platoon::core::measure::median;
use platoon_lab::scene_bench::{self, Mitsuba, Options, Row};

/// `platoon bench scenes`'s settings.
#[derive(clap::Args)]
pub struct ScenesArgs {
    /// Scenes, comma-separated: cornell, cornell-nodes, cornell-16, cornell-48, spheres, field,
    /// cesium, room, atrium; `all` for every generated one and the built-in box.
    #[arg(
        long,
        default_value = "cornell,cornell-nodes,spheres,field,cesium",
        value_delimiter = ','
    )]
    scenes: Vec<String>,
    /// Path lengths, comma-separated (max depth in segments; 0 for unbounded).
    #[arg(long, default_value = "1,8,0", value_delimiter = ',')]
    depths: Vec<u32>,
    #[arg(long, default_value_t = 256)]
    spp: u32,
    /// Image width and height.
    #[arg(long, default_value_t = 256)]
    size: u32,
    /// Measured runs of each renderer (after one warm-up run each).
    #[arg(long, default_value_t = 3)]
    repeat: u32,
    /// The Python with Mitsuba 3 (default: $PLATOON_MITSUBA_PYTHON, else python3).
    #[arg(long)]
    mitsuba: Option<PathBuf>,
    /// The folder of the shared test data (scenes/, envmaps/).
    #[arg(long, default_value_os_t = platoon_lab::shared::dir())]
    shared: PathBuf,
    /// Keep the generated scenes, their Mitsuba exports and the renders in this folder
    /// (default: a temporary folder, removed at the end).
    #[arg(long)]
    keep: Option<PathBuf>,
    /// Further `platoon render` arguments, after `--` (e.g. `-- --kernel spt`).
    #[arg(last = true)]
    render_args: Vec<String>,
}

fn print(row: &Row) {
    let depth = row.depth.map_or("unbounded".into(), |d| d.to_string());
    let p = median(row.platoon.clone());
    let rate = row.samples / p / 1e6;
    match row.ratio() {
        Some(r) => println!(
            "{:<14} {depth:>9} {p:>10.2} {rate:>10.2} {:>10.2} {r:>7.2}x",
            row.scene,
            median(row.mitsuba.clone())
        ),
        None => println!("{:<14} {depth:>9} {p:>10.2} {rate:>10.2}", row.scene),
    }
}

pub fn run(a: &ScenesArgs) -> Result<()> {
    if a.spp == 0 || a.size == 0 {
        bail!("--spp and --size must be positive");
    }
    let folder = crate::work_folder::WorkFolder::new(a.keep.as_deref())?;
    let dir = folder.path();
    let scenes = scene_bench::scenes(dir, &a.shared, &a.scenes)?;
    let mitsuba = Mitsuba::find_or_say(a.mitsuba.as_deref(), dir);
    let options = Options {
        width: a.size,
        height: a.size,
        spp: a.spp,
        depths: a.depths.iter().map(|&d| (d > 0).then_some(d)).collect(),
        repeat: a.repeat.max(1),
        platoon: std::env::current_exe()?,
        platoon_args: a.render_args.clone(),
    };
    println!(
        "platoon bench scenes: {0}x{0}, {1} spp, whole processes, median of {2}{3}",
        a.size,
        a.spp,
        options.repeat,
        if mitsuba.is_some() {
            ", platoon and Mitsuba 3 (llvm_ad_rgb) alternated"
        } else {
            ""
        }
    );
    for s in &scenes {
        println!("  {:<14} {}", s.name, s.what);
    }
    println!(
        "{:<14} {:>9} {:>10} {:>10} {:>10} {:>8}",
        "scene", "depth", "platoon s", "Msamples/s", "mitsuba s", "ratio"
    );
    for s in &scenes {
        scene_bench::measure(s, &options, mitsuba.as_ref(), dir, &mut print)?;
    }
    Ok(())
}

//! `platoon bench lhb`: layered hit buffers' build and lookups against the path tracer's rays,
//! the thesis' scaling over triangles, directions and resolution (the measuring is
//! platoon-lab's `lhb_bench`).

use std::path::PathBuf;

use super::{bench as lhb_bench, plot as lhb_plot, scenes as lhb_scenes};
use anyhow::{bail, Result};
use platoon::core::method::lhb::directions::DirectionSet;
use platoon::core::method::lhb::{LhbOptions, RasterVariant};

/// `platoon bench lhb`'s settings.
#[derive(clap::Args)]
pub struct LhbArgs {
    /// Scenes, comma-separated: cubesN (the Cornell box with N rotated cubes floating in its
    /// middle, 12 N triangles), icosphereL (with a bumpy icosphere, 20 * 4^L triangles), boxN
    /// (the Cornell box, each face N x N quads: about 30 N^2 triangles, box183 over a million),
    /// conference, cesium, tearoomN.
    #[arg(
        long,
        default_value = "box1,box16,box64,tearoom16",
        value_delimiter = ','
    )]
    scenes: Vec<String>,
    /// Direction sets, comma-separated (ico20|80|320|1280, oct8|32|128, haltonN).
    #[arg(long, default_value = "ico20,ico80,ico320", value_delimiter = ',')]
    directions: Vec<String>,
    /// Buffer resolutions, comma-separated.
    #[arg(long, default_value = "64,128", value_delimiter = ',')]
    resolutions: Vec<u32>,
    /// The rasterizer (capacity or exact).
    #[arg(long, default_value = "exact")]
    variant: String,
    /// Lookup bounces.
    #[arg(long, default_value_t = 2)]
    bounces: u32,
    /// Frame width and height, and samples per pixel of a frame.
    #[arg(long, default_value_t = 128)]
    size: u32,
    #[arg(long, default_value_t = 4)]
    spp: u32,
    /// The folder of the shared test data (scenes/).
    #[arg(long, default_value_os_t = crate::shared::dir())]
    shared: PathBuf,
    /// Instead of the scenes: CesiumMan walking this many steps across the Cornell box, each
    /// step's buffers built keeping what did not move and rebuilt whole, against the path
    /// tracer after the updater's refit (the first direction set and resolution, capacity
    /// rasterizer).
    #[arg(long)]
    walk: Option<usize>,
    /// The walk's box: every face N x N quads.
    #[arg(long, default_value_t = 16)]
    walk_cells: u32,
    /// Also draw build and image-pass time against triangles, a line per setting, into this
    /// PNG (the thesis' scaling curves).
    #[arg(long)]
    plot: Option<PathBuf>,
}

pub fn run(a: &LhbArgs) -> Result<()> {
    if a.size == 0 || a.spp == 0 {
        bail!("--size and --spp must be positive");
    }
    let variant = RasterVariant::parse(&a.variant).map_err(|e| anyhow::anyhow!("{e}"))?;
    let mut settings = Vec::new();
    for d in &a.directions {
        let directions = DirectionSet::parse(d).map_err(|e| anyhow::anyhow!("{e}"))?;
        for &resolution in &a.resolutions {
            let o = LhbOptions {
                directions,
                resolution,
                variant,
                bounces: a.bounces,
                ..Default::default()
            };
            if let Err(e) = o.validate() {
                bail!("{e}");
            }
            settings.push(o);
        }
    }
    if let Some(steps) = a.walk {
        return walk(a, settings[0], steps);
    }
    let scenes = lhb_scenes::scenes(&a.scenes, &a.shared)?;
    println!(
        "platoon bench lhb: {} rasterizer, {} bounces; frames {2}x{2} at {3} spp on device 0 \
         (device times; direct: the image pass cut after the first diffuse vertex's direct \
         light, the rest of the image pass is the lookups' and their vertices' light; a query \
         is a traced ray or a lookup)",
        variant.name(),
        a.bounces,
        a.size,
        a.spp
    );
    println!(
        "{:<11} {:>9} {:<13} {:>9} {:>8} {:>9} {:>6} {:>9} {:>9} {:>10} {:>10} {:>10} {:>11}",
        "scene",
        "triangles",
        "setting",
        "build ms",
        "ms/dir",
        "MB",
        "lost",
        "image ms",
        "direct ms",
        "Mq/s lhb",
        "Mrays/s pt",
        "lookups %",
        "break-even"
    );
    let mut all = Vec::new();
    for s in &scenes {
        let rows = lhb_bench::measure(s, &settings, a.size, a.spp)?;
        for (row, o) in rows.iter().zip(&settings) {
            let rate = |n: u64, t: f64| n as f64 / t.max(1e-9) / 1e6;
            println!(
                "{:<11} {:>9} {:<13} {:>9.1} {:>8.3} {:>9.1} {:>6} {:>9.1} {:>9.1} {:>10.2} {:>10.2} {:>10.1} {:>11}",
                row.scene,
                row.triangles,
                row.setting,
                row.build_s * 1e3,
                row.ms_per_direction(o.directions.count()),
                row.bytes as f64 / 1e6,
                row.lost,
                row.image_s * 1e3,
                row.direct_s * 1e3,
                rate(row.queries, row.image_s),
                rate(row.path_rays, row.path_s),
                100.0 * row.lookups as f64 / row.queries.max(1) as f64,
                row.break_even()
                    .map_or("never".to_string(), |q| format!("{:.2e}", q))
            );
        }
        all.extend(rows);
    }
    if let Some(path) = &a.plot {
        lhb_plot::write_png(
            path,
            &all,
            "platoon bench lhb: build (thick) and image pass (thin) against triangles",
        )?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn walk(a: &LhbArgs, options: LhbOptions, steps: usize) -> Result<()> {
    let man = crate::method::scenes::shared_scene(&a.shared, "CesiumMan.glb")?;
    let options = LhbOptions {
        variant: RasterVariant::Capacity,
        ..options
    };
    println!(
        "platoon bench lhb --walk {steps}: CesiumMan across the Cornell box ({0}x{0} quads a \
         face), {1}@{2}, {3} layers; frames {4}x{4} at {5} spp (device times, ms)",
        a.walk_cells, options.directions, options.resolution, options.layers, a.size, a.spp
    );
    println!(
        "{:>4} {:>10} {:>10} {:>10} {:>10} {:>10} {:>5}  kept part",
        "step", "kept ms", "rebuild ms", "lhb frame", "refit", "pt frame", "same"
    );
    for r in lhb_bench::walk(&man, a.walk_cells, steps, options, a.size, a.spp)? {
        println!(
            "{:>4} {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>10.1} {:>5}  {}",
            r.step,
            r.kept_build_s * 1e3,
            r.rebuild_s * 1e3,
            r.lhb_frame_s * 1e3,
            r.refit_s * 1e3,
            r.path_frame_s * 1e3,
            r.same,
            r.kept_what
        );
    }
    Ok(())
}

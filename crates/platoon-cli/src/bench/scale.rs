//! `platoon bench scale`: scenes of production size (1, 4 and 16 million unique triangles, a
//! million instances, 200 textures of 2048 x 2048) as whole `platoon render` processes: load,
//! BVH build, upload, first pixel, render, peak host memory, device memory and bytes a
//! triangle; against Mitsuba 3 on the cut boxes when it is installed. A scene a device refuses
//! (too large) is reported as such and the bench goes on.

use std::path::PathBuf;

use anyhow::{bail, Result};
use platoon::tracer::memory_budget::size;
use platoon_lab::scale_bench::{self, Options};
use platoon_lab::scene_bench::Mitsuba;

/// `platoon bench scale`'s settings.
#[derive(clap::Args)]
pub struct ScaleArgs {
    /// Scenes, comma-separated: box-1m, box-4m, box-16m, instances-1m, textures-200; `all`.
    #[arg(long, default_value = "all", value_delimiter = ',')]
    scenes: Vec<String>,
    /// Image width and height.
    #[arg(long, default_value_t = 64)]
    size: u32,
    #[arg(long, default_value_t = 1)]
    spp: u32,
    /// Path length in segments.
    #[arg(long, default_value_t = 2)]
    max_depth: u32,
    /// The Python with Mitsuba 3 (default: $PLATOON_MITSUBA_PYTHON, else python3).
    #[arg(long)]
    mitsuba: Option<PathBuf>,
    /// Keep the generated scenes (reused by the next run), the exports and the images in this
    /// folder (default: a temporary folder, removed at the end).
    #[arg(long)]
    keep: Option<PathBuf>,
    /// Also measure a living scene's refinement of the cut boxes' BVHs (in this process, on
    /// the first device): its time, the SAH cost before and after, and the frame time with
    /// each tree (medians of this many alternated frames).
    #[arg(long, value_name = "FRAMES")]
    refine: Option<usize>,
    /// Further `platoon render` arguments, after `--` (e.g. `-- --devices lavapipe:1,1`).
    #[arg(last = true)]
    render_args: Vec<String>,
}

pub fn run(a: &ScaleArgs) -> Result<()> {
    if a.spp == 0 || a.size == 0 || a.max_depth == 0 {
        bail!("--spp, --size and --max-depth must be positive");
    }
    let folder = crate::work_folder::WorkFolder::new(a.keep.as_deref())?;
    let dir = folder.path();
    let names = scale_bench::expand(&a.scenes);
    for n in &names {
        if !scale_bench::ALL.contains(&n.as_str()) {
            bail!(
                "unknown scale scene {n}: one of {}",
                scale_bench::NAMES.join(", ")
            );
        }
    }
    let mitsuba = Mitsuba::find_or_say(a.mitsuba.as_deref(), dir);
    let options = Options {
        width: a.size,
        height: a.size,
        spp: a.spp,
        max_depth: a.max_depth,
        platoon: std::env::current_exe()?,
        platoon_args: a.render_args.clone(),
    };
    println!(
        "platoon bench scale: {0}x{0}, {1} spp, depth {2}, whole processes (one run each)",
        a.size, a.spp, a.max_depth
    );
    for name in &names {
        eprintln!("generating {name} (kept for the next run with --keep)...");
        let scene = scale_bench::scene(dir, name)?;
        println!("\n{}: {}", scene.name, scene.what);
        match scale_bench::render_platoon(&scene, &options, dir) {
            Ok(m) => {
                println!(
                    "  platoon: {:.2} s in all; load {:.2} s, prepare {:.2} s (BVH {:.2} s), \
                     upload {:.2} s, first pixel at {:.2} s, render {:.2} s",
                    m.process.seconds, m.load, m.prepare, m.bvh, m.upload, m.first_pixel, m.render
                );
                let devices: Vec<String> = m.device_bytes.iter().map(|&b| size(b)).collect();
                println!(
                    "           host peak {}, device {} for {} triangles ({} bytes a triangle) \
                     and {} instances",
                    size(m.process.peak_bytes),
                    devices.join(" + "),
                    m.triangles,
                    m.bytes_per_triangle()
                        .map_or("-".into(), |b| format!("{b:.0}")),
                    m.instances
                );
                if let (Some(mi), true) = (&mitsuba, scene.mitsuba) {
                    let xml = scale_bench::export_mitsuba(&scene, &options, dir)?;
                    let p = scale_bench::render_mitsuba(mi, &xml)?;
                    println!(
                        "  Mitsuba: {:.2} s in all, host peak {}; platoon's first pixel {:.2}x \
                         its time, host peak {:.2}x",
                        p.seconds,
                        size(p.peak_bytes),
                        m.first_pixel / p.seconds,
                        m.process.peak_bytes as f64 / p.peak_bytes as f64
                    );
                }
            }
            Err(e) => println!("  platoon: refused or failed: {e:#}"),
        }
        if let (Some(frames), true) = (a.refine, scene.mitsuba) {
            match scale_bench::refinement(&scene, &options, frames) {
                Ok(r) => println!(
                    "  refinement: first generation {:.2} s, refined in {:.2} s more; SAH {:.2} \
                     -> {:.2}; frame {:.3} s -> {:.3} s ({:.3}x)",
                    r.first_generation,
                    r.refine,
                    r.sah.0,
                    r.sah.1,
                    r.render.0,
                    r.render.1,
                    r.render.1 / r.render.0
                ),
                Err(e) => println!("  refinement: failed: {e:#}"),
            }
        }
    }
    Ok(())
}

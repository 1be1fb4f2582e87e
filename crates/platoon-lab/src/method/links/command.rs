//! `platoon bench links`: vertex links' update on generated and shared scenes, Schmitz et al.'s
//! table for platoon (the measuring is platoon-lab's `links_bench`).

use std::path::PathBuf;

use super::{bench as links_bench, walk as links_walk};
use anyhow::{bail, Result};
use platoon::core::method::links::LinksOptions;
use platoon::drive::GiUpdate;

/// `platoon bench links`'s settings.
#[derive(clap::Args)]
pub struct LinksArgs {
    /// Scenes, comma-separated: boxN (the Cornell box, each face N x N quads), conference,
    /// cesium, tearoomN (a furnished room, walls N x N quads, teapots).
    #[arg(
        long,
        default_value = "box16,box32,cesium,tearoom16,conference",
        value_delimiter = ','
    )]
    scenes: Vec<String>,
    /// Directions per element.
    #[arg(long, default_value_t = 256)]
    directions: u32,
    /// Bounces of the gather.
    #[arg(long, default_value_t = 3)]
    bounces: u32,
    /// Frame width and height, and samples per pixel of a frame.
    #[arg(long, default_value_t = 256)]
    size: u32,
    #[arg(long, default_value_t = 1)]
    spp: u32,
    /// The folder of the shared test data (scenes/).
    #[arg(long, default_value_os_t = crate::shared::dir())]
    shared: PathBuf,
    /// Instead of the scenes: CesiumMan walking this many steps across the Cornell box, each
    /// step's links regenerated (the paper) and revalidated (platoon), and the error of the
    /// previous step's.
    #[arg(long)]
    walk: Option<usize>,
    /// The walk's box: every face N x N quads.
    #[arg(long, default_value_t = 16)]
    walk_cells: u32,
    /// Then the walk played in the game loop for this many frames (each a tenth of a step),
    /// the links updated synchronously and asynchronously; frames of --size at 1 spp.
    #[arg(long, default_value_t = 0)]
    walk_frames: usize,
}

pub fn run(a: &LinksArgs) -> Result<()> {
    let options = LinksOptions {
        directions: a.directions,
        bounces: a.bounces,
        ..Default::default()
    };
    if let Err(e) = options.validate() {
        bail!("{e}");
    }
    if a.size == 0 || a.spp == 0 {
        bail!("--size and --spp must be positive");
    }
    if let Some(steps) = a.walk {
        return walk(a, options, steps);
    }
    let scenes = crate::method::scenes::scenes(&a.scenes, &a.shared)?;
    println!(
        "platoon bench links: {} directions, {} bounces; frames {2}x{2} at {3} spp on device 0",
        a.directions, a.bounces, a.size, a.spp
    );
    for s in &scenes {
        println!("  {:<11} {}", s.name, s.what);
    }
    println!(
        "{:<11} {:>8} {:>16} {:>6} {:>8} {:>14} {:>8} {:>8} {:>9} {:>9} {:>8}",
        "scene",
        "elements",
        "links raw->comp",
        "/elem",
        "MB",
        "shoot s (Mr/s)",
        "reduce s",
        "light s",
        "gather ms",
        "1st frame",
        "frame ms"
    );
    for s in &scenes {
        let r = links_bench::measure(s, options, a.size, a.spp)?;
        let u = &r.stats;
        println!(
            "{:<11} {:>8} {:>16} {:>6.0} {:>8.1} {:>14} {:>8.2} {:>8.2} {:>9.1} {:>9.2} {:>8.1}",
            r.scene,
            u.elements,
            format!(
                "{:.2}M->{:.2}M",
                u.raw_links as f64 / 1e6,
                u.links as f64 / 1e6
            ),
            u.links as f64 / u.elements.max(1) as f64,
            u.link_bytes as f64 / 1e6,
            format!(
                "{:.2} ({:.2})",
                u.shoot_s,
                u.rays as f64 / u.shoot_s.max(1e-9) / 1e6
            ),
            u.reduce_s,
            u.light_s,
            (u.gather_s + u.smooth_s) * 1e3,
            r.first_frame.as_secs_f64(),
            r.frame.as_secs_f64() * 1e3
        );
    }
    Ok(())
}

fn walk(a: &LinksArgs, options: LinksOptions, steps: usize) -> Result<()> {
    let man = crate::method::scenes::shared_scene(&a.shared, "CesiumMan.glb")?;
    println!(
        "platoon bench links --walk: CesiumMan walking {steps} steps across the Cornell box \
         (faces {0}x{0} quads), {1} directions, {2} bounces, device 0",
        a.walk_cells, a.directions, a.bounces
    );
    println!(
        "{:>4} {:>8} {:>6} {:>16} {:>10} {:>12} {:>12} {:>22} {:>7} {:>9} {:>11}",
        "step",
        "elements",
        "moved",
        "rays shot",
        "regrouped",
        "regenerate s",
        "revalidate s",
        "(find/shoot/reduce s)",
        "speedup",
        "same bits",
        "stale error"
    );
    for (k, r) in links_walk::walk(&man, a.walk_cells, options, steps)?
        .iter()
        .enumerate()
    {
        let v = &r.revalidated;
        println!(
            "{:>4} {:>8} {:>6} {:>16} {:>10} {:>12.2} {:>12.2} {:>22} {:>7.2} {:>9} {:>10.1}%",
            k + 1,
            v.elements,
            v.moved_instances,
            format!(
                "{} ({:.1}%)",
                v.rays,
                100.0 * v.rays as f64 / r.all_rays.max(1) as f64
            ),
            v.regrouped,
            r.regenerate_s,
            r.revalidate_s,
            format!("{:.2}/{:.2}/{:.2}", v.revalidate_s, v.shoot_s, v.reduce_s),
            r.regenerate_s / r.revalidate_s.max(1e-9),
            if r.same_bits { "yes" } else { "NO" },
            100.0 * r.stale_error
        );
    }
    if a.walk_frames < 2 {
        return Ok(());
    }
    println!(
        "in the game loop: {} frames of {1}x{1} at 1 spp, every device",
        a.walk_frames, a.size
    );
    println!(
        "{:<6} {:>6} {:>14} {:>8} {:>10} {:>11} {:>9}",
        "update", "fps", "render ms/frm", "updates", "update ms", "mean age", "max age"
    );
    for (name, mode) in [
        ("sync", GiUpdate::Synchronous),
        ("async", GiUpdate::Asynchronous),
    ] {
        let p = links_walk::play(&man, a.walk_cells, options, mode, a.walk_frames, a.size)?;
        println!(
            "{:<6} {:>6.2} {:>14.1} {:>8} {:>10.1} {:>11.2} {:>9}",
            name,
            p.fps,
            p.busy_ms,
            p.updates,
            p.update_ms,
            p.ages.iter().sum::<u64>() as f64 / p.ages.len().max(1) as f64,
            p.ages.iter().max().unwrap_or(&0)
        );
    }
    Ok(())
}

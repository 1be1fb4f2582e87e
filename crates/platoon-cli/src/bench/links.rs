//! `platoon bench links`: vertex links' update on generated and shared scenes, Schmitz et al.'s
//! table for platoon (the measuring is platoon-lab's `links_bench`).

use std::path::PathBuf;

use anyhow::{bail, Result};
use platoon::core::method::links::LinksOptions;
use platoon_lab::links_bench;

/// `platoon bench links`'s settings.
#[derive(clap::Args)]
pub struct LinksArgs {
    /// Scenes, comma-separated: boxN (the Cornell box, each face N x N quads), conference,
    /// cesium.
    #[arg(
        long,
        default_value = "box16,box32,cesium,conference",
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
    #[arg(long, default_value = "../shared")]
    shared: PathBuf,
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
    let scenes = links_bench::scenes(&a.scenes, &a.shared)?;
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

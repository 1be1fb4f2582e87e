//! `platoon bench dynamic`: a living scene, walking characters and moving objects over the
//! sphere field, with double-buffered updates and commits, against the scene standing still.

use anyhow::Result;

/// `platoon bench dynamic`'s settings.
#[derive(clap::Args)]
pub struct DynamicArgs {
    /// Frames of each run (animated, then still).
    #[arg(long, default_value_t = 200)]
    frames: u32,
    /// Walking (skinned) characters.
    #[arg(long, default_value_t = 16)]
    characters: u32,
    /// Rigid objects moving every frame.
    #[arg(long, default_value_t = 64)]
    movers: u32,
    /// The skinned, animated glTF to place.
    #[arg(long, default_value_os_t = platoon_lab::shared::path("scenes/CesiumMan.glb"))]
    character: std::path::PathBuf,
    #[arg(long, default_value_t = 0)]
    device: usize,
    /// llvmpipe threads of the tracer (1 leaves the other core to the updater).
    #[arg(long, default_value_t = 1)]
    lavapipe_threads: u32,
    /// The game never waits for a generation: a frame whose next one is not built yet renders
    /// the previous one again (Pipeline::try_take).
    #[arg(long)]
    never_wait: bool,
    /// Let the system place the threads instead of keeping the updater on a core apart from
    /// the tracer's (it often puts both on one core).
    #[arg(long)]
    no_pin: bool,
    /// How the tracer finds what a ray hits (own, ray-query, auto): with ray queries each
    /// commit refits the skins' bottom levels and builds the top level on the device.
    #[arg(long, default_value = "own", value_parser = parse_traversal)]
    traversal: platoon::tracer::Traversal,
    /// Print one JSON object after the text.
    #[arg(long)]
    json: bool,
    /// Folder for dynamic.csv and dynamic.png.
    #[arg(long, default_value = ".")]
    out: std::path::PathBuf,
}

pub fn run(a: &DynamicArgs) -> Result<()> {
    use platoon_lab::dynamic_bench as db;
    if !a.out.is_dir() {
        anyhow::bail!("{}: output folder does not exist", a.out.display());
    }
    let options = db::Options {
        frames: a.frames,
        characters: a.characters,
        movers: a.movers,
        character: a.character.clone(),
        lavapipe_threads: a.lavapipe_threads,
        device: a.device,
        never_wait: a.never_wait,
        pin_threads: !a.no_pin,
        traversal: a.traversal,
        ..Default::default()
    };
    let report = db::run(&options)?;
    print!("{}", db::frames_text(&report));
    print!("{}", db::text(&options, &report.summary));
    let (csv, png) = (a.out.join("dynamic.csv"), a.out.join("dynamic.png"));
    platoon::core::output::write_text(&csv, &db::csv(&report)?)?;
    db::write_png(&png, &report)?;
    println!("wrote {} and {}", csv.display(), png.display());
    if a.json {
        println!("{}", db::json(&report.summary));
    }
    Ok(())
}

fn parse_traversal(name: &str) -> Result<platoon::tracer::Traversal, String> {
    platoon::tracer::Traversal::by_name(name).ok_or_else(|| {
        let names = platoon::tracer::Traversal::NAMES.join(", ");
        format!("unknown traversal {name}: one of {names}")
    })
}

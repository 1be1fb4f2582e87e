//! `platoon-scenegen OUT.glb [--grid N] [--unique]`: writes the benchmark sphere field.
//! `platoon-scenegen OUT.glb --glossy-glass`: the trade-off tool's glossy-and-glass scene.
//! `platoon-scenegen OUT.glb --conference-room`: the IGI scene (a room lit by point lights).
//! `platoon-scenegen OUT.glb --many-lights`: a hall lit by 128 emissive panels and 48 sconces.
//! `platoon-scenegen OUT.glb --cornell-nodes | --cornell-cut N | --spheres | --atrium`: the bench
//! scenes as exporters write them (the Cornell box a node per object, with every face cut into
//! N x N quads; five spheres of glTF materials, textured ground; a Sponza-sized courtyard).
//! `platoon-scenegen OUT.glb --clearcoat | --diffuse-transmission | --sheen | --volume |
//! --iridescence | --anisotropy | --dispersion`: spheres of a material extension (`materials::SCENES`; render them under an
//! environment: `platoon render OUT.glb --env MAP.exr`).
//! `platoon-scenegen --adversarial DIR [--shared SCENES] [--mutants N] [--seed S]`: writes the
//! adversarial suite (valid hard scenes, malformed and hostile files, mutations of SCENES).

use std::path::PathBuf;
use std::process::ExitCode;

/// What the command takes (`--help`; printed after a mistake too).
const USAGE: &str = "usage: platoon-scenegen OUT.glb [--grid N] [--unique] [--glossy-glass | --conference-room | --many-lights | --cornell-nodes | --cornell-cut N | --spheres | --atrium | --clearcoat | --diffuse-transmission | --sheen | --volume | --iridescence | --anisotropy | --dispersion]\n       platoon-scenegen --adversarial DIR [--shared SCENES] [--mutants N] [--seed S]";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut out = None;
    let mut grid = 4u32;
    let mut unique = false;
    let mut glossy_glass = false;
    let mut conference_room = false;
    let mut many_lights = false;
    let mut cornell_nodes = false;
    let mut cornell_cut = None;
    let mut atrium = false;
    let mut spheres = false;
    let mut material_scene = None;
    let mut adversarial = None;
    let mut shared = PathBuf::from("../shared/scenes");
    let mut mutants = 8usize;
    let mut seed = 1u64;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut number = |what: &str| -> Option<u64> {
            let v = it.next().and_then(|v| v.parse().ok());
            if v.is_none() {
                eprintln!("error: {what} needs a non-negative integer");
            }
            v
        };
        match a.as_str() {
            "--grid" => match number("--grid") {
                Some(g) if g > 0 => grid = g as u32,
                _ => return ExitCode::FAILURE,
            },
            "--cornell-cut" => match number("--cornell-cut") {
                Some(n) if n > 0 && n <= 1024 => cornell_cut = Some(n as u32),
                _ => {
                    eprintln!("error: --cornell-cut takes 1 to 1024 cells a side");
                    return ExitCode::FAILURE;
                }
            },
            "--mutants" => match number("--mutants") {
                Some(m) => mutants = m as usize,
                None => return ExitCode::FAILURE,
            },
            "--seed" => match number("--seed") {
                Some(s) => seed = s,
                None => return ExitCode::FAILURE,
            },
            "--unique" => unique = true,
            "--glossy-glass" => glossy_glass = true,
            "--conference-room" => conference_room = true,
            "--many-lights" => many_lights = true,
            "--cornell-nodes" => cornell_nodes = true,
            "--spheres" => spheres = true,
            "--atrium" => atrium = true,
            "--adversarial" => adversarial = it.next().map(PathBuf::from),
            "--shared" => shared = it.next().map(PathBuf::from).unwrap_or(shared),
            other => match platoon_scenegen::materials::SCENES
                .iter()
                .find(|(flag, _)| *flag == other)
            {
                Some(&(_, make)) => material_scene = Some(make),
                None if other == "--help" || other == "-h" => {
                    println!("{USAGE}");
                    return ExitCode::SUCCESS;
                }
                // A mistyped option would otherwise become the output's name.
                None if other.starts_with('-') => {
                    eprintln!("error: unknown option {other}\n{USAGE}");
                    return ExitCode::FAILURE;
                }
                None if out.is_some() => {
                    eprintln!(
                        "error: one output file, not {} and {other}\n{USAGE}",
                        out.unwrap_or_default()
                    );
                    return ExitCode::FAILURE;
                }
                None => out = Some(other.to_string()),
            },
        }
    }
    if let Some(dir) = adversarial {
        let cases = platoon_scenegen::adversarial::suite(&shared, mutants, seed);
        if let Err(e) = platoon_scenegen::adversarial::write(&dir, &cases) {
            eprintln!("error: {}: {e}", dir.display());
            return ExitCode::FAILURE;
        }
        for c in &cases {
            println!("{}\t{:?}", dir.join(c.scene_path()).display(), c.expect);
        }
        return ExitCode::SUCCESS;
    }
    let Some(out) = out else {
        eprintln!("{USAGE}");
        return ExitCode::FAILURE;
    };
    let scene = if glossy_glass {
        platoon_scenegen::glossy_glass()
    } else if conference_room {
        platoon_scenegen::conference_room()
    } else if many_lights {
        platoon_scenegen::many_lights::many_lights()
    } else if cornell_nodes {
        platoon_scenegen::bench::cornell_nodes()
    } else if let Some(cells) = cornell_cut {
        platoon_scenegen::bench::cornell_cut(cells)
    } else if spheres {
        platoon_scenegen::bench::spheres()
    } else if atrium {
        platoon_scenegen::atrium::atrium()
    } else if let Some(make) = material_scene {
        make()
    } else {
        platoon_scenegen::sphere_field(grid, unique)
    };
    let glb = platoon_scenegen::to_glb(&scene);
    let tmp = format!("{out}.part");
    if let Err(e) = std::fs::write(&tmp, &glb).and_then(|_| std::fs::rename(&tmp, &out)) {
        eprintln!("error: {out}: {e}");
        return ExitCode::FAILURE;
    }
    println!("{out}: {} bytes", glb.len());
    ExitCode::SUCCESS
}

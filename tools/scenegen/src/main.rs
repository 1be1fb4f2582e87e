//! `platoon-scenegen OUT.glb [--grid N] [--unique]`: writes the benchmark sphere field.

use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut out = None;
    let mut grid = 4u32;
    let mut unique = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--grid" => match it.next().and_then(|v| v.parse().ok()) {
                Some(g) if g > 0 => grid = g,
                _ => {
                    eprintln!("error: --grid needs a positive integer");
                    return ExitCode::FAILURE;
                }
            },
            "--unique" => unique = true,
            other => out = Some(other.to_string()),
        }
    }
    let Some(out) = out else {
        eprintln!("usage: platoon-scenegen OUT.glb [--grid N] [--unique]");
        return ExitCode::FAILURE;
    };
    let glb = platoon_scenegen::to_glb(&platoon_scenegen::sphere_field(grid, unique));
    let tmp = format!("{out}.part");
    if let Err(e) = std::fs::write(&tmp, &glb).and_then(|_| std::fs::rename(&tmp, &out)) {
        eprintln!("error: {out}: {e}");
        return ExitCode::FAILURE;
    }
    println!("{out}: {} bytes", glb.len());
    ExitCode::SUCCESS
}

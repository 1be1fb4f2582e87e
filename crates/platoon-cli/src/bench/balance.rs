//! `platoon bench balance`: the line balancers compared over an orbiting camera, as a table,
//! CSV, JSON and a plot.

use anyhow::Result;

/// `platoon bench balance`'s settings.
#[derive(clap::Args)]
pub struct BalanceArgs {
    #[command(flatten)]
    options: platoon_lab::balance_bench::Options,
    /// Print the cells as JSON on stdout (the table goes to stderr).
    #[arg(long)]
    json: bool,
}

pub fn run(a: BalanceArgs) -> Result<()> {
    use platoon_lab::balance_bench::{self as bb, Mode};
    let (options, json) = (a.options, a.json);
    options.validate()?;
    let out = options.out.clone();
    let frames = options.frames;
    let cells = bb::run(&options)?;
    let mode_name = if options.mode == Mode::Replay {
        "replay"
    } else {
        "real"
    };
    let title = format!("platoon bench balance ({mode_name}, {frames} frames): idle % per frame");
    let mut table = bb::table(&cells);
    if options.mode == Mode::Replay {
        table.push_str(&bb::interleaved_row(&options)?);
        table.push('\n');
        table.push_str(&bb::hindsight_row(&options)?);
        table.push_str("   (not a balancer: told the next frame's costs)\n");
        table.push_str(&bb::replay_scaling_row(&options)?);
        table.push('\n');
    } else {
        table.push_str("scaling efficiency, equal lavapipe:1 tracers, cost-aware (real):");
        for (n, e) in [2, 3]
            .iter()
            .zip(bb::real_scaling_efficiency(&options, &[2, 3])?)
        {
            table.push_str(&format!(" {n} tracers {:.1}%", 100.0 * e));
        }
        table.push('\n');
    }
    if json {
        eprint!("{table}");
        println!("{}", bb::json(&cells));
    } else {
        print!("{table}");
    }
    platoon::core::output::write_text(&out.join("balance.csv"), &bb::csv(&cells))?;
    platoon_lab::plot::write_png(&out.join("balance.png"), &cells, &title)?;
    eprintln!(
        "wrote {} and {}",
        out.join("balance.csv").display(),
        out.join("balance.png").display()
    );
    Ok(())
}

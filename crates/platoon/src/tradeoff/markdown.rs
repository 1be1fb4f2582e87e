//! The sweep's short Markdown report (`report.md`): the table, the two plots, and side by side
//! the reference, each technique's render at the highest sample count and its error map, all
//! written next to it. Deterministic for a fixed seed but for the times.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use platoon_core::output::{write_image, Film};

use super::{Report, Row};

/// Images are written this many times larger (nearest pixel): sweeps run on small frames.
const ZOOM: u32 = 4;

/// A film enlarged `ZOOM` times, pixel by pixel.
fn zoomed(film: &Film) -> Film {
    let (w, h) = (film.width * ZOOM, film.height * ZOOM);
    let pixels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x / ZOOM, y / ZOOM)))
        .map(|(x, y)| film.pixels[(y * film.width + x) as usize])
        .collect();
    Film {
        width: w,
        height: h,
        pixels,
    }
}

/// |film - reference| per pixel (luminance), as a black-red-yellow-white ramp where white is
/// `scale` or more: one scale for every map, so they compare.
fn error_map(film: &Film, reference: &Film, scale: f32) -> Film {
    let pixels = film
        .pixels
        .iter()
        .zip(&reference.pixels)
        .map(|(p, r)| {
            let d: f32 = (0..3).map(|k| (p[k] - r[k]).abs()).sum::<f32>() / 3.0;
            let t = (d / scale.max(1e-12)).clamp(0.0, 1.0) * 3.0;
            // Linear radiance that the PNG writer's tone curve maps near these colours.
            [
                t.min(1.0),
                (t - 1.0).clamp(0.0, 1.0),
                (t - 2.0).clamp(0.0, 1.0),
            ]
        })
        .collect();
    Film {
        width: film.width,
        height: film.height,
        pixels,
    }
}

/// The mean absolute error of the worst render: the error maps' white point.
fn error_scale(finals: &[(String, Film)], reference: &Film) -> f32 {
    let mut values: Vec<f32> = finals
        .iter()
        .flat_map(|(_, f)| {
            f.pixels
                .iter()
                .zip(&reference.pixels)
                .map(|(p, r)| (0..3).map(|k| (p[k] - r[k]).abs()).sum::<f32>() / 3.0)
        })
        .filter(|v| v.is_finite())
        .collect();
    values.sort_by(f32::total_cmp);
    // The 99th percentile: one firefly does not wash the maps out.
    values
        .get(values.len().saturating_sub(1) * 99 / 100)
        .copied()
        .unwrap_or(1.0)
}

/// One row per technique, one column per sample count, each cell `cell(row)`.
fn table(rows: &[Row], cell: fn(&Row) -> String) -> String {
    let mut spps: Vec<u32> = rows.iter().map(|r| r.spp).collect();
    spps.sort_unstable();
    spps.dedup();
    let mut techniques: Vec<&str> = Vec::new();
    for r in rows {
        if !techniques.contains(&r.technique.as_str()) {
            techniques.push(&r.technique);
        }
    }
    let mut s = String::from("| technique |");
    for spp in &spps {
        let _ = write!(s, " {spp} spp |");
    }
    s.push_str("\n|---|");
    s.push_str(&"---|".repeat(spps.len()));
    s.push('\n');
    for t in techniques {
        let biased = rows.iter().any(|r| r.technique == t && r.biased);
        let _ = write!(s, "| {t}{} |", if biased { " (biased)" } else { "" });
        for spp in &spps {
            match rows.iter().find(|r| r.technique == t && r.spp == *spp) {
                Some(r) => {
                    let _ = write!(s, " {} |", cell(r));
                }
                None => s.push_str(" - |"),
            }
        }
        s.push('\n');
    }
    s
}

/// Writes `report.md` and its images into `dir`.
pub fn write(
    dir: &Path,
    report: &Report,
    reference: &Film,
    finals: &[(String, Film)],
    scene: &str,
) -> Result<()> {
    let images = dir.join("images");
    std::fs::create_dir_all(&images)?;
    write_image(&images.join("reference.png"), &zoomed(reference), &[])?;
    let scale = error_scale(finals, reference);
    let file = |t: &str| t.replace(['=', '.'], "-");
    for (t, film) in finals {
        write_image(&images.join(format!("{}.png", file(t))), &zoomed(film), &[])?;
        let map = error_map(film, reference, scale);
        write_image(
            &images.join(format!("{}-error.png", file(t))),
            &zoomed(&map),
            &[],
        )?;
    }
    let spp = report.rows.iter().map(|r| r.spp).max().unwrap_or(0);
    let origin = match report.reference_spp {
        Some(n) => format!("platoon's own MIS render at {n} spp"),
        None => "given".into(),
    };
    let mut md = format!(
        "# platoon tradeoff: {scene}\n\nReference: `{}` ({origin}).\n\nEach cell is ms / RMSE / \
         Mrays/s (Bikker's appendix D); a biased technique converges to something else than the \
         reference.\n\n{}\nMean LDR-FLIP error (perceptual, 0 = identical, 1 = opposite; the images \
         as platoon's PNGs show them, at 67 pixels per degree):\n\n{}\n## Error against time\n\n![error against time](tradeoff-error.png)\n\n\
         ## Efficiency at {spp} spp\n\n![efficiency](tradeoff-efficiency.png)\n\n## Images at \
         {spp} spp\n\nError maps: mean absolute error per pixel, black = 0, white = {scale:.3} \
         (the 99th percentile over all maps).\n\n| reference |",
        report.reference.display(),
        table(&report.rows, |r| format!("{:.1} / {:.4} / {:.1}", r.ms, r.rmse, r.mrays)),
        table(&report.rows, |r| format!("{:.4}", r.flip)),
    );
    for (t, _) in finals {
        let _ = write!(md, " {t} |");
    }
    md.push_str("\n|---|");
    md.push_str(&"---|".repeat(finals.len()));
    md.push_str("\n| ![reference](images/reference.png) |");
    for (t, _) in finals {
        let _ = write!(md, " ![{t}](images/{}.png) |", file(t));
    }
    md.push_str("\n| error |");
    for (t, _) in finals {
        let _ = write!(md, " ![{t} error](images/{}-error.png) |", file(t));
    }
    md.push('\n');
    if !report.skipped.is_empty() {
        md.push_str("\nNot run: ");
        md.push_str(&report.skipped.join("; "));
        md.push_str(".\n");
    }
    platoon_core::output::write_text(&dir.join("report.md"), &md)?;
    Ok(())
}

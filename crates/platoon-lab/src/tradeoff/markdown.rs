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
    enlarged(film, ZOOM)
}

/// A film enlarged `k` times, pixel by pixel.
fn enlarged(film: &Film, k: u32) -> Film {
    let (w, h) = (film.width * k, film.height * k);
    let pixels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x / k, y / k)))
        .map(|(x, y)| film.pixels[(y * film.width + x) as usize])
        .collect();
    Film {
        width: w,
        height: h,
        pixels,
    }
}

/// A square region of a film: (x, y, side).
type Region = (u32, u32, u32);

fn crop(film: &Film, (x0, y0, side): Region) -> Film {
    let pixels = (y0..y0 + side)
        .flat_map(|y| (x0..x0 + side).map(move |x| (x, y)))
        .map(|(x, y)| film.pixels[(y * film.width + x) as usize])
        .collect();
    Film {
        width: side,
        height: side,
        pixels,
    }
}

/// The quarter-size square (on a grid of eighths) where the renders differ most from the
/// reference, summed over every technique: where a reader should look.
fn worst_region(finals: &[(String, Film)], reference: &Film) -> Region {
    let side = (reference.width.min(reference.height) / 4).max(1);
    let step = (side / 2).max(1);
    let error = |x: u32, y: u32| -> f64 {
        finals
            .iter()
            .map(|(_, f)| {
                let i = (y * f.width + x) as usize;
                (0..3)
                    .map(|k| (f.pixels[i][k] - reference.pixels[i][k]).abs() as f64)
                    .filter(|v| v.is_finite())
                    .sum::<f64>()
            })
            .sum()
    };
    let mut best = ((0, 0, side), -1.0);
    for y0 in (0..=reference.height - side).step_by(step as usize) {
        for x0 in (0..=reference.width - side).step_by(step as usize) {
            let e: f64 = (y0..y0 + side)
                .flat_map(|y| (x0..x0 + side).map(move |x| (x, y)))
                .map(|(x, y)| error(x, y))
                .sum();
            if e > best.1 {
                best = ((x0, y0, side), e);
            }
        }
    }
    best.0
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

/// A file name for a technique's images.
fn file(technique: &str) -> String {
    technique.replace(['=', '.'], "-")
}

/// The table of images with `suffix` (`""` or `"-crop"`): the reference and each technique's
/// render in a row, their error maps in the next.
fn image_grid(md: &mut String, finals: &[(String, Film)], suffix: &str) {
    let what = if suffix.is_empty() { "" } else { " crop" };
    md.push_str("| reference |");
    for (t, _) in finals {
        let _ = write!(md, " {t} |");
    }
    md.push_str("\n|---|");
    md.push_str(&"---|".repeat(finals.len()));
    let _ = write!(md, "\n| ![reference{what}](images/reference{suffix}.png) |");
    for (t, _) in finals {
        let _ = write!(md, " ![{t}{what}](images/{}{suffix}.png) |", file(t));
    }
    md.push_str("\n| error |");
    for (t, _) in finals {
        let _ = write!(
            md,
            " ![{t} error{what}](images/{}-error{suffix}.png) |",
            file(t)
        );
    }
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
    // Crops of the region where the renders are furthest from the reference, enlarged to the
    // whole images' size.
    let region = worst_region(finals, reference);
    let crop_zoom = (ZOOM * reference.width / region.2).max(1);
    let write_both = |name: &str, film: &Film| -> Result<()> {
        write_image(&images.join(format!("{name}.png")), &zoomed(film), &[])?;
        let cropped = enlarged(&crop(film, region), crop_zoom);
        write_image(&images.join(format!("{name}-crop.png")), &cropped, &[])?;
        Ok(())
    };
    write_both("reference", reference)?;
    let scale = error_scale(finals, reference);
    for (t, film) in finals {
        write_both(&file(t), film)?;
        write_both(
            &format!("{}-error", file(t)),
            &error_map(film, reference, scale),
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
         (the 99th percentile over all maps).\n\n",
        report.reference.display(),
        table(&report.rows, |r| format!("{:.1} / {:.4} / {:.1}", r.ms, r.rmse, r.mrays)),
        table(&report.rows, |r| format!("{:.4}", r.flip)),
    );
    image_grid(&mut md, finals, "");
    let _ = write!(
        md,
        "\n\nCrops of the {side}x{side} pixels at ({x}, {y}) where the renders differ most from \
         the reference:\n\n",
        side = region.2,
        x = region.0,
        y = region.1
    );
    image_grid(&mut md, finals, "-crop");
    md.push('\n');
    if !report.skipped.is_empty() {
        md.push_str("\nNot run: ");
        md.push_str(&report.skipped.join("; "));
        md.push_str(".\n");
    }
    platoon_core::output::write_text(&dir.join("report.md"), &md)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> Film {
        Film {
            width: w,
            height: h,
            pixels: (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| [f(x, y); 3])
                .collect(),
        }
    }

    #[test]
    fn the_crop_goes_where_the_renders_differ_most() {
        let reference = film(32, 32, |_, _| 0.5);
        // One render wrong in the block at (20..28, 4..12).
        let wrong = film(32, 32, |x, y| {
            if (20..28).contains(&x) && (4..12).contains(&y) {
                2.0
            } else {
                0.5
            }
        });
        let region = worst_region(&[("t".into(), wrong.clone())], &reference);
        assert_eq!(region, (20, 4, 8));
        let c = crop(&wrong, region);
        assert_eq!((c.width, c.height), (8, 8));
        assert!(c.pixels.iter().all(|p| p[0] == 2.0));
        assert_eq!(enlarged(&c, 3).width, 24);
    }
}

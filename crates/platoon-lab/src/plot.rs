//! Line plots of per-frame series: the balance bench (idle % per frame, one panel per table
//! column, one line per balancer) and the dynamic bench (times per frame). Text is drawn with
//! DejaVu Sans (fonts-dejavu-core); without it the plots have no labels.

use std::path::Path;

use anyhow::{anyhow, Result};
use plotters::prelude::*;

use crate::balance_bench::{cell, columns, rows, Cell};

const FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

fn register_font() -> bool {
    static ONCE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *ONCE.get_or_init(|| match std::fs::read(FONT) {
        Ok(bytes) => plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            Box::leak(bytes.into_boxed_slice()),
        )
        .is_ok(),
        Err(_) => false,
    })
}

const COLORS: [RGBColor; 6] = [
    RGBColor(120, 120, 120),
    RGBColor(214, 39, 40),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(31, 119, 180),
];

/// A named line: its label and (frame, value) points.
type Series = (String, Vec<(usize, f64)>);

/// Draws `series` as lines on `area`, under `caption`, with a legend when text can be drawn.
fn draw_lines(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    caption: &str,
    y_desc: &str,
    series: &[Series],
    first_color: usize,
    text: bool,
) -> Result<()> {
    let frames = series
        .iter()
        .map(|(_, v)| v.len())
        .max()
        .unwrap_or(1)
        .max(2);
    let top = series
        .iter()
        .flat_map(|(_, v)| v.iter().map(|p| p.1))
        .filter(|v| v.is_finite())
        .fold(1e-3f64, f64::max);
    let mut builder = ChartBuilder::on(area);
    builder.margin(12);
    if text {
        builder
            .caption(caption, ("sans-serif", 18))
            .x_label_area_size(30)
            .y_label_area_size(50);
    }
    let mut chart = builder
        .build_cartesian_2d(0..frames, 0.0..top * 1.05)
        .map_err(|e| anyhow!("{e}"))?;
    if text {
        chart
            .configure_mesh()
            .x_desc("frame")
            .y_desc(y_desc)
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
    }
    for (k, (name, points)) in series.iter().enumerate() {
        let color = COLORS[(k + first_color) % COLORS.len()];
        let drawn = chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                color.stroke_width(2),
            ))
            .map_err(|e| anyhow!("{e}"))?;
        if text {
            drawn.label(name.as_str()).legend(move |(x, y)| {
                PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3))
            });
        }
    }
    if text {
        draw_legend(&mut chart)?;
    }
    Ok(())
}

/// The chart's legend of its labelled series, on a light box (every plot's).
pub(crate) fn draw_legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> Result<()> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| anyhow!("{e}"))
}

/// Draws a `size` image under `title` with `draw` into `path`, through a temporary file.
pub(crate) fn write_through_temp(
    path: &Path,
    size: (u32, u32),
    title: &str,
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>, bool) -> Result<()>,
) -> Result<()> {
    let text = register_font();
    let tmp = path.with_extension("part.png");
    {
        let root = BitMapBackend::new(&tmp, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let root = if text {
            root.titled(title, ("sans-serif", 22))
                .map_err(|e| anyhow!("{e}"))?
        } else {
            root
        };
        draw(&root, text)?;
        root.present()
            .map_err(|e| anyhow!("{}: {e}", path.display()))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    Ok(())
}

/// The bench balance plot: one panel per table column, one line per balancer.
pub fn write_png(path: &Path, cells: &[Cell], title: &str) -> Result<()> {
    write_through_temp(path, (1500, 800), title, |root, text| {
        let columns = columns(cells);
        // One row per device count.
        let per_row = columns
            .iter()
            .filter(|(d, _)| *d == columns[0].0)
            .count()
            .max(1);
        let panels = root.split_evenly((columns.len().div_ceil(per_row), per_row));
        for (area, (devices, camera)) in panels.iter().zip(columns) {
            let series: Vec<Series> = rows(cells)
                .iter()
                .filter_map(|n| cell(cells, n, devices, &camera).map(|c| (n, c)))
                .map(|(name, c)| {
                    let points = c.per_frame.iter().enumerate();
                    let points = points.map(|(f, v)| (f, 100.0 * v)).collect();
                    (format!("{name} ({:.1}%)", c.idle_pct), points)
                })
                .collect();
            let caption = format!("{devices} devices, {camera} camera");
            draw_lines(area, &caption, "idle %", &series, 0, text)?;
        }
        Ok(())
    })
}

/// One chart of named series over frames (index on x).
pub fn write_series_png(path: &Path, title: &str, series: &[(&str, Vec<f64>)]) -> Result<()> {
    let series: Vec<Series> = series
        .iter()
        .map(|(name, v)| (name.to_string(), v.iter().copied().enumerate().collect()))
        .collect();
    write_through_temp(path, (1200, 600), title, |root, text| {
        draw_lines(root, "", "", &series, 1, text)
    })
}

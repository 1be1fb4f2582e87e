//! The balance-bench plot: idle % per frame, one panel per table column, one line per balancer.
//! Text is drawn with DejaVu Sans (fonts-dejavu-core); without it the plot has no labels.

use std::path::Path;

use anyhow::{anyhow, Result};
use platoon_core::balance::NAMES;
use plotters::prelude::*;

use crate::balance_bench::{cell, CameraSpeed, Cell};

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

pub fn write_png(path: &Path, cells: &[Cell], title: &str) -> Result<()> {
    let text = register_font();
    let tmp = path.with_extension("part.png");
    {
        let root = BitMapBackend::new(&tmp, (1200, 800)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let root = if text {
            root.titled(title, ("sans-serif", 22))
                .map_err(|e| anyhow!("{e}"))?
        } else {
            root
        };
        let panels = root.split_evenly((2, 2));
        let columns = [
            (2, CameraSpeed::Slow),
            (2, CameraSpeed::Fast),
            (3, CameraSpeed::Slow),
            (3, CameraSpeed::Fast),
        ];
        for (area, (devices, camera)) in panels.iter().zip(columns) {
            let series: Vec<(&str, &Cell)> = NAMES
                .iter()
                .filter_map(|n| cell(cells, n, devices, camera).map(|c| (*n, c)))
                .collect();
            let frames = series
                .iter()
                .map(|(_, c)| c.per_frame.len())
                .max()
                .unwrap_or(1)
                .max(2);
            let top = series
                .iter()
                .flat_map(|(_, c)| c.per_frame.iter())
                .fold(1.0f64, |m, v| m.max(100.0 * v));
            let mut builder = ChartBuilder::on(area);
            builder.margin(12);
            if text {
                builder
                    .caption(
                        format!("{devices} devices, {} camera", camera.name()),
                        ("sans-serif", 18),
                    )
                    .x_label_area_size(30)
                    .y_label_area_size(45);
            }
            let mut chart = builder
                .build_cartesian_2d(0..frames, 0.0..top * 1.05)
                .map_err(|e| anyhow!("{e}"))?;
            if text {
                chart
                    .configure_mesh()
                    .x_desc("frame")
                    .y_desc("idle %")
                    .draw()
                    .map_err(|e| anyhow!("{e}"))?;
            }
            for (k, (name, c)) in series.iter().enumerate() {
                let color = COLORS[k % COLORS.len()];
                let drawn = chart
                    .draw_series(LineSeries::new(
                        c.per_frame.iter().enumerate().map(|(f, v)| (f, 100.0 * v)),
                        color.stroke_width(2),
                    ))
                    .map_err(|e| anyhow!("{e}"))?;
                if text {
                    drawn
                        .label(format!("{name} ({:.1}%)", c.idle_pct))
                        .legend(move |(x, y)| {
                            PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3))
                        });
                }
            }
            if text {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .draw()
                    .map_err(|e| anyhow!("{e}"))?;
            }
        }
        root.present()
            .map_err(|e| anyhow!("{}: {e}", path.display()))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    Ok(())
}

/// One chart of named series over frames (index on x), written through a temporary file.
pub fn write_series_png(path: &Path, title: &str, series: &[(&str, Vec<f64>)]) -> Result<()> {
    let text = register_font();
    let tmp = path.with_extension("part.png");
    {
        let root = BitMapBackend::new(&tmp, (1200, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let frames = series
            .iter()
            .map(|(_, v)| v.len())
            .max()
            .unwrap_or(1)
            .max(2);
        let top = series
            .iter()
            .flat_map(|(_, v)| v.iter())
            .filter(|v| v.is_finite())
            .fold(1e-3f64, |m, v| m.max(*v));
        let mut builder = ChartBuilder::on(&root);
        builder.margin(16);
        if text {
            builder
                .caption(title, ("sans-serif", 22))
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
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
        }
        for (k, (name, values)) in series.iter().enumerate() {
            let color = COLORS[(k + 1) % COLORS.len()];
            let drawn = chart
                .draw_series(LineSeries::new(
                    values.iter().copied().enumerate(),
                    color.stroke_width(2),
                ))
                .map_err(|e| anyhow!("{e}"))?;
            if text {
                drawn.label(*name).legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3))
                });
            }
        }
        if text {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
        }
        root.present()
            .map_err(|e| anyhow!("{}: {e}", path.display()))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| anyhow!("{}: {e}", path.display()))?;
    Ok(())
}

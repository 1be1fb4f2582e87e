//! The sweep's plots: error against time on log-log axes, one line per technique (lower left
//! is better; a line that flattens has hit its bias), and efficiency per technique as bars.

use std::path::Path;

use anyhow::{anyhow, Result};
use plotters::prelude::*;

use super::Row;
use crate::plot::{draw_legend, write_through_temp};

/// Ten distinguishable colours (a sweep has up to a dozen techniques).
const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// A number for a log axis: few digits, no float noise.
fn short(v: f64) -> String {
    if v >= 10.0 {
        format!("{v:.0}")
    } else {
        format!("{:.3}", v)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    }
}

/// The techniques of `rows` in order, each with its rows by sample count.
fn by_technique(rows: &[Row]) -> Vec<(&str, Vec<&Row>)> {
    let mut out: Vec<(&str, Vec<&Row>)> = Vec::new();
    for r in rows {
        match out.iter_mut().find(|(t, _)| *t == r.technique) {
            Some((_, v)) => v.push(r),
            None => out.push((&r.technique, vec![r])),
        }
    }
    for (_, v) in &mut out {
        v.sort_by_key(|r| r.spp);
    }
    out
}

/// RMSE against milliseconds, log-log.
pub fn write_error_png(path: &Path, rows: &[Row], title: &str) -> Result<()> {
    let usable: Vec<&Row> = rows
        .iter()
        .filter(|r| r.ms > 0.0 && r.rmse > 0.0 && r.rmse.is_finite())
        .collect();
    if usable.is_empty() {
        return Err(anyhow!("no row with a positive time and error to plot"));
    }
    let range = |f: fn(&Row) -> f64| {
        let lo = usable.iter().map(|r| f(r)).fold(f64::INFINITY, f64::min);
        let hi = usable.iter().map(|r| f(r)).fold(0.0, f64::max);
        (lo / 1.3)..(hi * 1.3)
    };
    let (x, y) = (range(|r| r.ms), range(|r| r.rmse));
    write_through_temp(path, (900, 650), title, |root, text| {
        let mut builder = ChartBuilder::on(root);
        builder.margin(14);
        if text {
            builder.x_label_area_size(40).y_label_area_size(60);
        }
        let mut chart = builder
            .build_cartesian_2d(x.log_scale(), y.log_scale())
            .map_err(|e| anyhow!("{e}"))?;
        if text {
            chart
                .configure_mesh()
                .x_desc("time (ms)")
                .y_desc("RMSE")
                .x_label_formatter(&|x| short(*x))
                .y_label_formatter(&|y| short(*y))
                .light_line_style(WHITE)
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
        }
        for (k, (name, rows)) in by_technique(rows).into_iter().enumerate() {
            let color = COLORS[k % COLORS.len()];
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.ms > 0.0 && r.rmse > 0.0)
                .map(|r| (r.ms, r.rmse))
                .collect();
            let style = if rows.iter().any(|r| r.biased) {
                ShapeStyle::from(color).stroke_width(1)
            } else {
                color.stroke_width(2)
            };
            let drawn = chart
                .draw_series(LineSeries::new(points.iter().copied(), style))
                .map_err(|e| anyhow!("{e}"))?;
            if text {
                let label = if rows.iter().any(|r| r.biased) {
                    format!("{name} (biased)")
                } else {
                    name.to_string()
                };
                drawn.label(label).legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 18, y)], color.stroke_width(3))
                });
            }
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(|e| anyhow!("{e}"))?;
        }
        if text {
            draw_legend(&mut chart)?;
        }
        Ok(())
    })
}

/// Efficiency 1 / (RMSE^2 x seconds) of each technique at its highest sample count, as bars
/// (biased techniques hatched lighter: their efficiency ignores the error they cannot lose).
pub fn write_efficiency_png(path: &Path, rows: &[Row], title: &str) -> Result<()> {
    let bars: Vec<(&str, f64, bool)> = by_technique(rows)
        .into_iter()
        .filter_map(|(name, rows)| {
            let last = rows.last()?;
            Some((name, last.efficiency, last.biased))
        })
        .filter(|b| b.1.is_finite())
        .collect();
    if bars.is_empty() {
        return Err(anyhow!("no finite efficiency to plot"));
    }
    let top = bars.iter().map(|b| b.1).fold(0.0, f64::max).max(1e-12) * 1.15;
    let names: Vec<String> = bars.iter().map(|b| b.0.to_string()).collect();
    write_through_temp(path, (900, 500), title, |root, text| {
        let mut builder = ChartBuilder::on(root);
        builder.margin(14);
        if text {
            builder.x_label_area_size(40).y_label_area_size(70);
        }
        let mut chart = builder
            .build_cartesian_2d(0.0..bars.len() as f64, 0.0..top)
            .map_err(|e| anyhow!("{e}"))?;
        if text {
            chart
                .configure_mesh()
                .disable_x_mesh()
                .x_labels(bars.len() * 2 + 1)
                .x_label_formatter(&|x| {
                    let i = x.floor() as usize;
                    if (x - i as f64 - 0.5).abs() < 0.01 {
                        names.get(i).cloned().unwrap_or_default()
                    } else {
                        String::new()
                    }
                })
                .y_desc("efficiency = 1 / (RMSE² x seconds)")
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
        }
        chart
            .draw_series(bars.iter().enumerate().map(|(i, (_, e, biased))| {
                let color = COLORS[i % COLORS.len()];
                let fill = if *biased {
                    color.mix(0.35)
                } else {
                    color.mix(1.0)
                };
                Rectangle::new(
                    [(i as f64 + 0.15, 0.0), (i as f64 + 0.85, *e)],
                    fill.filled(),
                )
            }))
            .map_err(|e| anyhow!("{e}"))?;
        Ok(())
    })
}

//! `platoon bench lhb --plot`: the thesis' scaling curves for platoon, time against triangles
//! on log-log axes, one line per setting for the build and one for the image pass.

use std::path::Path;

use anyhow::{anyhow, Result};
use plotters::prelude::*;

use super::bench::LhbRow;
use crate::plot::{draw_legend, write_through_temp};

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(127, 127, 127),
];

/// Build and image-pass milliseconds against triangles, a line per setting (rows of one
/// setting in the order of their triangle counts); solid: build, thin: image pass.
pub fn write_png(path: &Path, rows: &[LhbRow], title: &str) -> Result<()> {
    let mut settings: Vec<&str> = Vec::new();
    for r in rows {
        if !settings.contains(&r.setting.as_str()) {
            settings.push(&r.setting);
        }
    }
    let points = |setting: &str, f: fn(&LhbRow) -> f64| -> Vec<(f64, f64)> {
        let mut p: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.setting == setting && f(r) > 0.0)
            .map(|r| (r.triangles as f64, f(r)))
            .collect();
        p.sort_by(|a, b| a.0.total_cmp(&b.0));
        p
    };
    let build = |r: &LhbRow| r.build_s * 1e3;
    let image = |r: &LhbRow| r.image_s * 1e3;
    let all: Vec<(f64, f64)> = settings
        .iter()
        .flat_map(|s| [points(s, build), points(s, image)].concat())
        .collect();
    if all.is_empty() {
        return Err(anyhow!("no row with a positive time to plot"));
    }
    let range = |k: fn(&(f64, f64)) -> f64| {
        let lo = all.iter().map(k).fold(f64::INFINITY, f64::min);
        let hi = all.iter().map(k).fold(0.0, f64::max);
        (lo / 1.5)..(hi * 1.5)
    };
    let (x, y) = (range(|p| p.0), range(|p| p.1));
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
                .x_desc("triangles")
                .y_desc("device time (ms)")
                .light_line_style(WHITE)
                .draw()
                .map_err(|e| anyhow!("{e}"))?;
        }
        for (k, setting) in settings.iter().enumerate() {
            let color = COLORS[k % COLORS.len()];
            for (what, f, width) in [
                ("build", build as fn(&LhbRow) -> f64, 3),
                ("image", image, 1),
            ] {
                let p = points(setting, f);
                let drawn = chart
                    .draw_series(LineSeries::new(
                        p.iter().copied(),
                        color.stroke_width(width),
                    ))
                    .map_err(|e| anyhow!("{e}"))?;
                if text {
                    drawn
                        .label(format!("{setting} {what}"))
                        .legend(move |(x, y)| {
                            PathElement::new([(x, y), (x + 18, y)], color.stroke_width(width))
                        });
                }
                chart
                    .draw_series(p.iter().map(|&q| Circle::new(q, 3, color.filled())))
                    .map_err(|e| anyhow!("{e}"))?;
            }
        }
        if text {
            draw_legend(&mut chart)?;
        }
        Ok(())
    })
}

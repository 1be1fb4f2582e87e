//! Layered hit buffers as a rendering method: its options, the tables its preparation makes
//! from the scene, and its place among the methods (`RenderMethod`).

use super::options::RasterVariant;
use super::prepared::Lhb;
use crate::flatten::features::KernelOption;
use crate::flatten::GpuScene;
use crate::frame::{FrameParams, Output};
use crate::method::render_method::{DeviceRun, RenderMethod, Report};
use crate::method::Method;

impl RenderMethod for Lhb {
    fn name(&self) -> &'static str {
        "lhb"
    }

    fn describe(&self) -> String {
        let o = &self.options;
        format!(
            "layered hit buffers: {} directions ({}), {}^2 texels, {} layers, {} rasterizer, \
             cone {} texels, {} bounces, {}",
            o.directions.count(),
            o.directions,
            o.resolution,
            o.layers,
            o.variant.name(),
            o.cone,
            o.bounces,
            if o.rebuild || o.variant == RasterVariant::Exact {
                "every buffer rebuilt each frame"
            } else {
                "what did not move kept between frames"
            }
        )
    }

    fn validate(&self, params: &FrameParams) -> Result<(), String> {
        self.options.validate()?;
        if self.tables.is_none() {
            return Err("lhb: the frame has no tables yet (platoon::render prepares them)".into());
        }
        if params.output != Output::Radiance {
            return Err("layered hit buffers render radiance only".into());
        }
        Ok(())
    }

    fn kernel_options(&self, _params: &FrameParams) -> Vec<KernelOption> {
        vec![
            ("lhb", "METHOD_LHB", true),
            (
                "lhb-exact",
                "LHB_EXACT",
                self.options.variant == RasterVariant::Exact,
            ),
        ]
    }

    fn approximations(&self) -> Vec<String> {
        self.options.approximations()
    }

    /// The tables, when the frame has none yet (CPU work only).
    fn prepare(
        &self,
        g: &GpuScene,
        _params: &FrameParams,
        _run: &mut DeviceRun,
    ) -> crate::error::Result<Option<Method>> {
        if self.tables.is_some() {
            return Ok(None);
        }
        Ok(Some(Method::new(Lhb::prepared_after(
            self.options,
            g,
            self.previous.as_deref(),
        ))))
    }

    fn ready(&self) -> bool {
        self.tables.is_some()
    }

    /// A changed scene needs its own tables (its triangles), in this one's frame if it fits.
    fn renewal(&self) -> Option<Method> {
        Some(Method::new(Lhb {
            options: self.options,
            tables: None,
            previous: self.tables.clone().or_else(|| self.previous.clone()),
        }))
    }

    fn report(&self, entries: &[(String, String)]) -> Report {
        let entry = |key| crate::frame::report_entry(entries, key);
        let mut report = Report::default();
        if let Some(build) = entry("lhb_build") {
            report.lines.push(format!("layered hit buffers: {build}"));
        }
        if let Some(lost) = entry("lhb_lost_layers").filter(|l| *l != "0") {
            report.warnings.push(format!(
                "{lost} layers did not fit the buffers' lists and are missing from the \
                 lookups: raise --lhb-layers or use --lhb-variant exact"
            ));
        }
        report
    }

    fn metadata(&self) -> Vec<(String, String)> {
        let Some(t) = &self.tables else {
            return Vec::new();
        };
        vec![(
            "lhb_tables".into(),
            format!(
                "{} placed triangles, frame centre {:?} radius {}, directional map {}x{} \
                 (at most {} candidates a texel)",
                t.placed.len(),
                t.frame.centre.to_array(),
                t.frame.radius,
                t.map.width,
                t.map.height,
                t.map.longest()
            ),
        )]
    }
}

#[cfg(test)]
mod report_tests {
    use super::*;

    #[test]
    fn the_report_shows_the_build_and_warns_of_lost_layers_only() {
        let lhb = Lhb::new(Default::default());
        let entries = |lost: &str| {
            vec![
                ("lhb_build".to_string(), "320 buffers".to_string()),
                ("lhb_lost_layers".to_string(), lost.to_string()),
            ]
        };
        let r = lhb.report(&entries("3"));
        assert_eq!(r.lines, ["layered hit buffers: 320 buffers"]);
        assert_eq!(r.warnings.len(), 1);
        assert!(r.warnings[0].starts_with("3 layers did not fit"), "{r:?}");
        assert!(lhb.report(&entries("0")).warnings.is_empty());
        assert_eq!(lhb.report(&[]), Report::default());
    }
}

//! Layered hit buffers as a rendering method: its options, the tables its preparation makes
//! from the scene, and its place among the methods (`RenderMethod`).

use super::build_report::LhbBuild;
use super::kind::LhbKind;
use super::options::RasterVariant;
use super::prepared::Lhb;
use crate::flatten::features::KernelOption;
use crate::flatten::GpuScene;
use crate::frame::{FrameParams, MethodReport, Output};
use crate::method::kind::MethodKind;
use crate::method::render_method::{DeviceRun, RenderMethod, Report};
use crate::method::Method;

impl RenderMethod for Lhb {
    fn kind(&self) -> &'static dyn MethodKind {
        &LhbKind
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

    fn report(&self, report: &MethodReport) -> Report {
        (report.value::<LhbBuild>())
            .map(|b| b.report())
            .unwrap_or_default()
    }

    fn report_metadata(&self, report: &MethodReport) -> Vec<(String, String)> {
        (report.value::<LhbBuild>())
            .map(|b| b.metadata())
            .unwrap_or_default()
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
        let built = |lost| {
            MethodReport::of(&LhbBuild {
                layers: 320,
                lost,
                ..Default::default()
            })
        };
        let r = lhb.report(&built(3));
        assert_eq!(r.lines.len(), 1);
        assert!(r.lines[0].starts_with("layered hit buffers: 320 layer slots, 3 lost"));
        assert_eq!(r.warnings.len(), 1);
        assert!(r.warnings[0].starts_with("3 layers did not fit"), "{r:?}");
        assert!(lhb.report(&built(0)).warnings.is_empty());
        assert_eq!(lhb.report(&MethodReport::default()), Report::default());
        let meta = lhb.report_metadata(&built(3));
        assert!(
            meta.contains(&("lhb_lost_layers".into(), "3".into())),
            "{meta:?}"
        );
    }
}

//! What layered hit buffers' passes report of a band (`Band::method_report`): what the build
//! made and cost on the device, and the lookups of the image passes; the image's metadata and
//! the lines a user reads are made from it here.

use crate::frame::ReportValue;
use crate::method::render_method::Report;

#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LhbBuild {
    /// Layers the lists hold (with lists of a capacity: the slots).
    pub layers: u64,
    /// Lists without a capacity (`layers` counts the layers), else with one.
    pub exact: bool,
    /// Layers past the lists' capacity, missing from the lookups.
    pub lost: u64,
    pub blocks: u64,
    pub bytes: u64,
    /// Device time of the build.
    pub seconds: f64,
    pub attempts: u32,
    /// With the kept part: whether it was kept as it was (else built again), and the moving
    /// instances added to it.
    pub kept: Option<(bool, u32)>,
    /// Lookups queued by the image passes.
    pub lookups: u32,
}

impl ReportValue for LhbBuild {
    const KIND: &'static str = "lhb.build";
}

impl LhbBuild {
    /// The build's line (`lhb_build`): what it made and cost.
    pub fn line(&self) -> String {
        format!(
            "{}{} {}{}, {} blocks of large triangles, {} bytes, {:.6} s device time ({} attempts)",
            match self.kept {
                Some((true, n)) => format!("kept part reused, {n} moving instances added: "),
                Some((false, n)) => format!("kept part built, {n} moving instances added: "),
                None => String::new(),
            },
            self.layers,
            if self.exact { "layers" } else { "layer slots" },
            if self.lost > 0 {
                format!(", {} lost past the capacity", self.lost)
            } else {
                ", none lost".to_string()
            },
            self.blocks,
            self.bytes,
            self.seconds,
            self.attempts
        )
    }

    pub fn metadata(&self) -> Vec<(String, String)> {
        vec![
            ("lhb_build".into(), self.line()),
            ("lhb_build_s".into(), format!("{:.6}", self.seconds)),
            ("lhb_layers".into(), self.layers.to_string()),
            ("lhb_lost_layers".into(), self.lost.to_string()),
            ("lhb_bytes".into(), self.bytes.to_string()),
            ("lhb_lookups".into(), self.lookups.to_string()),
        ]
    }

    pub fn report(&self) -> Report {
        let mut report = Report::default();
        report
            .lines
            .push(format!("layered hit buffers: {}", self.line()));
        if self.lost > 0 {
            report.warnings.push(format!(
                "{} layers did not fit the buffers' lists and are missing from the \
                 lookups: raise --lhb-layers or use --lhb-variant exact",
                self.lost
            ));
        }
        report
    }
}

//! Instant global illumination (Keller 1997), with the three accelerations of Marques and Santos'
//! IGI on OptiX: a second rendering method beside the path tracer, which stays the default and
//! the reference. Per frame the tracers shoot particles from the lights and leave a virtual
//! point light (VPL) at each hit on a surface with a diffuse component; the first diffuse hit
//! of each camera path gathers its indirect diffuse light from them, while direct light and
//! specular chains are traced exactly as the path tracer does.
//!
//! This module holds the method's options (`options`), the structs its kernels share with the
//! tracer, its place among the methods (`RenderMethod`) and the filters that need neighbouring pixels (`filter`): the
//! discontinuity buffer of interleaved sampling and the joint bilateral upsampling of a
//! downsampled gather. Those run once on the assembled frame, after every band is in, so the
//! image is the same bits for any split between devices (see `filter`).

pub mod filter;
mod kind;
mod layout;
pub use kind::IgiKind;
mod options;

pub use layout::{IgiTexel, IgiVertex, Vpl};
pub use options::{Grid, IgiOptions, DEPTH_THRESHOLD, MAX_BOUNCES, NORMAL_THRESHOLD};

use crate::flatten::features::KernelOption;
use crate::frame::{Band, FrameParams, Output};
use crate::method::kind::MethodKind;
use crate::method::render_method::RenderMethod;

impl RenderMethod for IgiOptions {
    fn kind(&self) -> &'static dyn MethodKind {
        &IgiKind
    }

    fn brief(&self) -> Option<String> {
        Some(format!("IGI {} VPLs", self.slots()))
    }

    fn describe(&self) -> String {
        format!(
            "instant global illumination: {} VPLs ({} paths x {} bounces), min distance {}, \
             visibility {}, downsample {}, interleave {}x{}",
            self.slots(),
            self.paths,
            self.bounces,
            self.min_distance,
            if self.imperfect_visibility {
                "leaf boxes"
            } else {
                "exact"
            },
            self.downsample,
            self.interleave[0],
            self.interleave[1]
        )
    }

    fn validate(&self, params: &FrameParams) -> Result<(), String> {
        IgiOptions::validate(self)?;
        if params.output != Output::Radiance {
            return Err("IGI renders radiance only".into());
        }
        Ok(())
    }

    fn kernel_options(&self, _params: &FrameParams) -> Vec<KernelOption> {
        vec![
            ("igi", "METHOD_IGI", true),
            (
                "igi-imperfect-visibility",
                "IGI_IMPERFECT_VISIBILITY",
                self.imperfect_visibility,
            ),
            ("igi-bounded", "IGI_BOUNDED", self.min_distance > 0.0),
            ("igi-filtered", "IGI_FILTERED", self.filtered()),
            ("igi-downsampled", "IGI_DOWNSAMPLED", self.downsample > 1),
            (
                "igi-interleaved",
                "IGI_INTERLEAVED",
                self.interleave != [1, 1],
            ),
        ]
    }

    fn approximations(&self) -> Vec<String> {
        IgiOptions::approximations(self)
    }

    /// Its VPLs are shot, and its pixels gathered and filtered, on the devices and from the
    /// bands: nothing reads the scene on the host.
    fn reads_scene_on_host(&self) -> bool {
        false
    }

    fn finish(&self, params: &FrameParams, bands: &mut [Band]) {
        filter::finish_bands(self, params, bands);
    }
}

//! Vertex links (Schmitz, Tavenrath and Kobbelt, "Interactive Global Illumination for Deformable
//! Geometry in CUDA"; `../shared/briefs/links.md`): diffuse indirect light solved per *element*
//! (an instance's welded vertex) over links found by shooting one fixed set of cosine-distributed
//! directions from every element. A hit at barycentrics (u, v, w) on a triangle ABC makes the
//! links x<-A, x<-B, x<-C weighted u, v, w, each over the n_C rays; cosine sampling has absorbed
//! the geometry and area terms, so the weights of an element sum to the fraction of its rays
//! that hit anything, and the gather needs no other factor. The camera paths are the path
//! tracer's; the first vertex with a diffuse lobe adds the diffuse reflection of the indirect
//! irradiance interpolated from its triangle's elements, in place of its diffuse bounce.
//!
//! - [`elements`]: a mesh's vertices welded into elements (seams joined, creases kept), with
//!   their one-rings; [`scene_elements`]: those of a flattened scene's instances, in render
//!   space, and the element of a hit's corner;
//! - [`directions`]: the n_C directions every element shoots, in the order rays are numbered;
//! - [`reduce`]: the raw links of each element (ray order) summed per peer into compressed
//!   link groups (CSR), in a fixed order whatever split shot them;
//! - [`gather`]: the Jacobi gather of `n_B` bounces and the feature-preserving smoothing;
//! - [`shoot_cpu`]: link shooting through the CPU ray queries (the devices' oracle);
//! - [`job`]: what a frame asks of the devices (shoot, light, render) and the solution;
//! - [`solve`]: the update, run over the devices' frames (relighting an unchanged geometry,
//!   revalidating a moved one, or shooting every ray);
//! - [`revalidate`]: which rays of an earlier shooting can have changed after geometry moved.
//!
//! The game loop follows a living scene's generations with the update (`drive::gi`).

pub mod directions;
pub mod elements;
pub mod gather;
pub mod job;
mod kind;
pub use kind::LinksKind;
mod options;
pub mod reduce;
pub mod revalidate;
pub mod scene_elements;
pub mod shoot_cpu;
pub mod solve;

pub use job::{ElementAlbedo, Job, Links, ShotHit, Solution};
pub use options::{LinksOptions, MAX_BOUNCES, MAX_DIRECTIONS};

use std::sync::Arc;

use crate::flatten::features::KernelOption;
use crate::flatten::GpuScene;
use crate::frame::{FrameParams, Output};
use crate::method::kind::MethodKind;
use crate::method::render_method::{DeviceRun, RenderMethod};
use crate::method::Method;

impl RenderMethod for Links {
    fn kind(&self) -> &'static dyn MethodKind {
        &LinksKind
    }

    fn describe(&self) -> String {
        let o = &self.options;
        format!(
            "vertex links: {} directions per element, {} bounces, feature angle {} degrees, \
             smoothing {}, {} light samples per element {}",
            o.directions,
            o.bounces,
            o.feature_angle,
            if o.smooth { "on" } else { "off" },
            o.light_samples,
            if o.fan_light {
                "over its fan"
            } else {
                "at its position"
            }
        )
    }

    fn validate(&self, params: &FrameParams) -> Result<(), String> {
        self.options.validate()?;
        if self.job.is_none() {
            return Err("links: the frame has no solution yet (platoon::render solves it)".into());
        }
        if params.output != Output::Radiance {
            return Err("vertex links render radiance only".into());
        }
        Ok(())
    }

    fn kernel_options(&self, _params: &FrameParams) -> Vec<KernelOption> {
        vec![
            ("links", "METHOD_LINKS", true),
            ("links-fan-light", "LINKS_FAN_LIGHT", self.options.fan_light),
        ]
    }

    fn approximations(&self) -> Vec<String> {
        let o = &self.options;
        let mut a = vec![
            format!(
                "vertex links: indirect diffuse light at the first diffuse vertex interpolated \
                 from the scene's vertices ({} fixed directions each, {} bounces; light \
                 reflected more often, and glossy indirect light, are lost)",
                o.directions, o.bounces
            ),
            "vertex links: one value per vertex, on its normal's side (back faces get no \
             indirect light); the albedo at each vertex at normal incidence"
                .into(),
        ];
        if o.smooth {
            a.push(format!(
                "vertex links: indirect light smoothed over one-rings within {} degrees",
                o.feature_angle
            ));
        }
        a
    }

    /// The update (`solve`), when the frame has no solution yet.
    fn prepare(
        &self,
        g: &GpuScene,
        params: &FrameParams,
        run: &mut DeviceRun,
    ) -> crate::error::Result<Option<Method>> {
        if self.job.is_some() {
            return Ok(None);
        }
        let solution = solve::solve(g, &self.options, params, self.previous.as_deref(), run)?;
        Ok(Some(Method::new(Links {
            options: self.options,
            job: Some(Job::Render(Arc::new(solution))),
            previous: None,
        })))
    }

    fn ready(&self) -> bool {
        self.job.is_some()
    }

    /// Unsolved, with this solution as the earlier one (`Links::previous`).
    fn renewal(&self) -> Option<Method> {
        let previous = match &self.job {
            Some(Job::Render(s)) => Some(s.clone()),
            _ => self.previous.clone(),
        };
        Some(Method::new(Links {
            options: self.options,
            job: None,
            previous,
        }))
    }

    /// `links_update`: what the update made and its stages' times.
    fn metadata(&self) -> Vec<(String, String)> {
        let Some(Job::Render(s)) = &self.job else {
            return Vec::new();
        };
        let u = &s.stats;
        vec![(
            "links_update".into(),
            format!(
                "{} elements, {} rays{}, {} raw links -> {} ({} bytes); seconds: weld {:.3}, \
                 revalidate {:.3}, shoot {:.3}, reduce {:.3}, direct light {:.3}, gather {:.3}, \
                 smooth {:.3}, total {:.3}",
                u.elements,
                u.rays,
                if u.relit {
                    " (relit: an earlier solution's links)".to_string()
                } else if u.revalidated {
                    format!(
                        " (revalidated: {} instances moved, only the rays that can have changed \
                         shot again, {} elements regrouped)",
                        u.moved_instances, u.regrouped
                    )
                } else {
                    String::new()
                },
                u.raw_links,
                u.links,
                u.link_bytes,
                u.weld_s,
                u.revalidate_s,
                u.shoot_s,
                u.reduce_s,
                u.light_s,
                u.gather_s,
                u.smooth_s,
                u.total_s()
            ),
        )]
    }
}

//! The rendering method's flags: the path tracer (default) or instant global illumination with
//! its options (platoon::core::method).

use anyhow::{bail, Result};
use clap::ValueEnum;
use platoon::core::method::igi::IgiOptions;
use platoon::core::method::lhb::directions::DirectionSet;
use platoon::core::method::lhb::{Lhb, LhbOptions, RasterVariant};
use platoon::core::method::links::{Links, LinksOptions};
use platoon::core::method::path::PathKernel;
use platoon::core::Method;

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// Path tracing with NEE and MIS: unbiased, the reference.
    #[default]
    Path,
    /// Instant global illumination: indirect diffuse light from virtual point lights.
    Igi,
    /// Vertex links: indirect diffuse light solved per mesh vertex over fixed-direction links.
    Links,
    /// Layered hit buffers: indirect rays answered by lookups in buffers of fixed directions.
    Lhb,
}

#[derive(clap::Args, Debug)]
pub struct MethodArgs {
    /// Rendering method.
    #[arg(long, value_enum, default_value = "path")]
    pub method: MethodArg,
    /// IGI: VPLs per frame (light paths x --vpl-bounces).
    #[arg(long)]
    pub vpls: Option<u32>,
    /// IGI: VPLs a light path leaves at most (light bounced more often is lost).
    #[arg(long)]
    pub vpl_bounces: Option<u32>,
    /// IGI: bound the geometry term below this distance (0: unbounded).
    #[arg(long)]
    pub vpl_min_distance: Option<f32>,
    /// IGI: VPL shadow rays against BVH leaf boxes instead of triangles.
    #[arg(long)]
    pub igi_imperfect_visibility: bool,
    /// IGI: gather indirect light at one pixel in K x K and upsample it.
    #[arg(long)]
    pub igi_downsample: Option<u32>,
    /// IGI: interleave M x N subsets of the VPLs (e.g. 3x3), recombined by a discontinuity
    /// buffer.
    #[arg(long, value_parser = parse_tile)]
    pub igi_interleave: Option<[u32; 2]>,
    /// Links: directions every vertex shoots (a square: 16, 64, 256, 1024).
    #[arg(long)]
    pub links_directions: Option<u32>,
    /// Links: bounces of indirect light the gather carries.
    #[arg(long)]
    pub links_bounces: Option<u32>,
    /// Links: vertices within this angle (degrees) are one element; smoothing stops at it.
    #[arg(long)]
    pub links_feature_angle: Option<f32>,
    /// Links: no smoothing of the gathered light over vertex neighbourhoods.
    #[arg(long)]
    pub links_no_smoothing: bool,
    /// Links: next-event samples of the direct light at each vertex.
    #[arg(long)]
    pub links_light_samples: Option<u32>,
    /// Links: direct light taken at each vertex alone, not averaged over its triangles (the
    /// paper without its light-link oversampling).
    #[arg(long)]
    pub links_vertex_light: bool,
    /// LHB: the buffers' directions (ico20|80|320|1280, oct8|32|128, haltonN).
    #[arg(long)]
    pub lhb_directions: Option<String>,
    /// LHB: texels on a side of every buffer.
    #[arg(long)]
    pub lhb_resolution: Option<u32>,
    /// LHB: layers a texel keeps (the capacity rasterizer).
    #[arg(long)]
    pub lhb_layers: Option<u32>,
    /// LHB: radius of the cone jitter in texels.
    #[arg(long)]
    pub lhb_cone: Option<f32>,
    /// LHB: indirect bounces answered by lookups.
    #[arg(long)]
    pub lhb_bounces: Option<u32>,
    /// LHB: rasterizer, capacity (fixed lists, overflow lost) or exact (count, prefix sum,
    /// fill).
    #[arg(long)]
    pub lhb_variant: Option<String>,
    /// LHB: rebuild every buffer every frame, instead of keeping the layers of what did not move.
    #[arg(long)]
    pub lhb_rebuild: bool,
    /// Path tracing: the megakernel (mega), streaming path tracing (spt), or the one measured
    /// faster on each kind of device (auto). The same image either way.
    #[arg(long, default_value = "auto", value_parser = parse_kernel)]
    pub kernel: PathKernel,
}

fn parse_kernel(s: &str) -> Result<PathKernel, String> {
    PathKernel::by_name(s).ok_or_else(|| {
        format!(
            "unknown kernel {s}: one of {}",
            PathKernel::NAMES.join(", ")
        )
    })
}

fn parse_tile(s: &str) -> Result<[u32; 2], String> {
    let bad = || format!("{s:?}: an interleaving tile is MxN, e.g. 3x3");
    let (m, n) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    Ok([
        m.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    ])
}

impl MethodArgs {
    fn any_links_flag(&self) -> bool {
        self.links_directions.is_some()
            || self.links_bounces.is_some()
            || self.links_feature_angle.is_some()
            || self.links_no_smoothing
            || self.links_light_samples.is_some()
            || self.links_vertex_light
    }

    fn links(&self) -> Result<Method> {
        let mut o = LinksOptions::default();
        if let Some(n) = self.links_directions {
            o.directions = n;
        }
        if let Some(b) = self.links_bounces {
            o.bounces = b;
        }
        if let Some(a) = self.links_feature_angle {
            o.feature_angle = a;
        }
        o.smooth = !self.links_no_smoothing;
        if let Some(k) = self.links_light_samples {
            o.light_samples = k;
        }
        o.fan_light = !self.links_vertex_light;
        if let Err(e) = o.validate() {
            bail!("{e}");
        }
        Ok(Method::Links(Links::new(o)))
    }

    fn any_lhb_flag(&self) -> bool {
        self.lhb_directions.is_some()
            || self.lhb_resolution.is_some()
            || self.lhb_layers.is_some()
            || self.lhb_cone.is_some()
            || self.lhb_bounces.is_some()
            || self.lhb_variant.is_some()
            || self.lhb_rebuild
    }

    fn lhb(&self) -> Result<Method> {
        let mut o = LhbOptions::default();
        if let Some(d) = &self.lhb_directions {
            o.directions = DirectionSet::parse(d).map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        if let Some(r) = self.lhb_resolution {
            o.resolution = r;
        }
        if let Some(l) = self.lhb_layers {
            o.layers = l;
        }
        if let Some(c) = self.lhb_cone {
            o.cone = c;
        }
        if let Some(b) = self.lhb_bounces {
            o.bounces = b;
        }
        if let Some(v) = &self.lhb_variant {
            o.variant = RasterVariant::parse(v).map_err(|e| anyhow::anyhow!("{e}"))?;
        }
        o.rebuild = self.lhb_rebuild;
        if let Err(e) = o.validate() {
            bail!("{e}");
        }
        Ok(Method::Lhb(Lhb::new(o)))
    }

    /// The method with its options; refuses one method's flags given to another.
    pub fn method(&self) -> Result<Method> {
        if self.method != MethodArg::Links && self.any_links_flag() {
            bail!("the --links-* flags set vertex links: add --method links");
        }
        if self.method != MethodArg::Lhb && self.any_lhb_flag() {
            bail!("the --lhb-* flags set layered hit buffers: add --method lhb");
        }
        let any_igi_flag = self.vpls.is_some()
            || self.vpl_bounces.is_some()
            || self.vpl_min_distance.is_some()
            || self.igi_imperfect_visibility
            || self.igi_downsample.is_some()
            || self.igi_interleave.is_some();
        if self.method != MethodArg::Igi && any_igi_flag {
            bail!("the --vpl* and --igi-* flags set instant global illumination: add --method igi");
        }
        if self.method == MethodArg::Links {
            return self.links();
        }
        if self.method == MethodArg::Lhb {
            return self.lhb();
        }
        if self.method == MethodArg::Path {
            if any_igi_flag {
                bail!("the --vpl* and --igi-* flags set instant global illumination: add --method igi");
            }
            return Ok(Method::PathTracing);
        }
        let mut o = IgiOptions::default();
        if let Some(b) = self.vpl_bounces {
            o.bounces = b;
        }
        if let Some(n) = self.vpls {
            o.paths = n.div_ceil(o.bounces.max(1)).max(1);
        }
        if let Some(d) = self.vpl_min_distance {
            o.min_distance = d;
        }
        o.imperfect_visibility = self.igi_imperfect_visibility;
        if let Some(k) = self.igi_downsample {
            o.downsample = k;
        }
        if let Some(t) = self.igi_interleave {
            o.interleave = t;
        }
        if let Err(e) = o.validate() {
            bail!("{e}");
        }
        Ok(Method::Igi(o))
    }
}

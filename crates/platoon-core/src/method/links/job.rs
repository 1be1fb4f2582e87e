//! What a frame of vertex links asks of the devices. The update runs as virtual frames through
//! the tracers' band machinery (so the balancer splits it and a lost tracer's part is redone
//! like a lost band's): a shooting frame whose pixels are rays (a line per element, a column
//! per direction), a lighting frame whose pixels are elements, and then the image's frames,
//! which read the solution. Each carries its data in an `Arc`, shared by every tracer.

use std::sync::Arc;

use super::options::LinksOptions;
use super::reduce::LinkGroups;
use crate::frame::PixelRecord;

/// The method as a frame names it: its options and, once the update has run, its work.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Links {
    pub options: LinksOptions,
    /// None until the facade's update (`solve`) has run: a tracer refuses such a frame.
    pub job: Option<Job>,
    /// An earlier solution the update may take its links from: when the scene's geometry and
    /// the options that shape links are unchanged (only lights or materials moved on), it
    /// relights (direct light and gather) instead of shooting again.
    pub previous: Option<Arc<Solution>>,
}

impl Links {
    /// Vertex links with `options`, to be solved.
    pub fn new(options: LinksOptions) -> Links {
        Links {
            options,
            job: None,
            previous: None,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum Job {
    /// Rays from `elements` (a batch): pixel (d, e) is element e's ray in direction d; or, with
    /// `ElementRays::single_rays`, pixel i (lines of `RAY_WIDTH`) is entry i's one ray. Each
    /// pixel leaves its ray's closest hit (`Band::per_pixel`, a [`ShotHit`]).
    Shoot(Arc<ElementRays>),
    /// The direct irradiance at `elements` (pixel i of a frame `LIGHT_WIDTH` wide is element
    /// i): the frame's radiance is E_d, `Band::per_pixel` the element's [`ElementAlbedo`].
    Light(Arc<ElementRays>),
    /// The image, with the indirect irradiance of `Solution` at each first diffuse vertex.
    Render(Arc<Solution>),
}

/// A shooting frame's pixel (shoot.comp's output): its ray's closest hit, instance
/// `u32::MAX` for a miss.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShotHit {
    pub instance: u32,
    pub triangle: u32,
    /// The hit's barycentrics b1, b2 in the triangle.
    pub b: [f32; 2],
}

impl PixelRecord for ShotHit {
    const KIND: &'static str = "links.shot_hit";
}

impl ShotHit {
    pub fn missed(&self) -> bool {
        self.instance == u32::MAX
    }
}

/// A lighting frame's pixel (light.comp's output): the element's diffuse albedo.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ElementAlbedo {
    pub albedo: [f32; 3],
    pub _unused: f32,
}

impl PixelRecord for ElementAlbedo {
    const KIND: &'static str = "links.element_albedo";
}

// One vec4 each, as shoot.comp and light.comp write them.
const _: () = {
    assert!(std::mem::size_of::<ShotHit>() == 16);
    assert!(std::mem::size_of::<ElementAlbedo>() == 16);
};

/// Width of a lighting frame (its pixels are elements, line after line).
pub const LIGHT_WIDTH: u32 = 64;
/// Width of a shooting frame of single rays (revalidation's).
pub const RAY_WIDTH: u32 = 256;

/// The elements a shooting or lighting frame reads, with the directions they shoot.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ElementRays {
    pub elements: Vec<ElementRay>,
    /// The n_C directions in the element frame (xyz; w unused), in ray order.
    pub directions: Vec<[f32; 4]>,
    /// The elements' fans (`SceneElements::fans`): triangle, corner, cumulative area (f32
    /// bits), 0. What a lighting frame samples its points from with `LinksOptions::fan_light`.
    pub fans: Vec<[u32; 4]>,
    /// Each entry is one ray, in direction `directions[fan[2]]` of its frame (the rays a
    /// revalidation shoots again), rather than an element shooting every direction.
    pub single_rays: bool,
}

/// One element as the kernels read it (`ElementRay` in shaders/links/links.glsl, std430): its
/// rays' origin (lifted off the surface) and frame, and one triangle corner it is, where its
/// material is read.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ElementRay {
    pub origin: [f32; 4],
    pub tangent: [f32; 4],
    pub bitangent: [f32; 4],
    pub normal: [f32; 4],
    /// Instance, triangle (scene-global), corner (0-2); w unused.
    pub corner: [u32; 4],
    /// Its fan in `ElementRays::fans` (first entry, count); z: the direction of a single ray
    /// (`ElementRays::single_rays`); w unused.
    pub fan: [u32; 4],
}

const _: () = assert!(std::mem::size_of::<ElementRay>() == 96);

/// The indirect irradiance of every element, and how a hit's corners find their elements.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Solution {
    /// E_ind per element (rgb; w unused).
    pub irradiance: Vec<[f32; 4]>,
    /// The first element of each instance, then each scene vertex's element within its mesh
    /// (`u32::MAX` for a vertex of no triangle): element = table\[instance\] +
    /// table\[instances + vertex\].
    pub table: Vec<u32>,
    pub instances: u32,
    /// The compressed links it gathered over: what relighting a still scene reuses.
    pub links: Arc<LinkGroups>,
    /// A digest of what shaped the links (the scene's geometry and instances, the directions
    /// and the feature angle): a later update with the same may reuse them.
    pub geometry: u64,
    /// What the shooting found, when the options keep it (`LinksOptions::revalidate`).
    pub shot: Option<Arc<Shot>>,
    /// What the update that made it did, for the output's metadata.
    pub stats: UpdateStats,
}

/// What a shooting found, for a later update of moved geometry to revalidate
/// (`revalidate::stale_rays`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Shot {
    /// The elements as they shot (their rays' origins and frames), with the directions.
    pub rays: Arc<ElementRays>,
    /// Every ray's closest hit as a shooting frame leaves it, element after element, each
    /// element's rays in direction order.
    pub hits: Vec<ShotHit>,
    /// A digest of each instance's shape (`revalidate::shapes`).
    pub shapes: Vec<u64>,
    /// A digest of the arrays' layout (`revalidate::layout`): hits index into it.
    pub layout: u64,
}

/// The update's stages, timed apart from the frame, and what it made.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UpdateStats {
    pub elements: u32,
    pub rays: u64,
    pub raw_links: u64,
    pub links: u64,
    /// Bytes of the compressed link groups.
    pub link_bytes: u64,
    /// Seconds: welding, revalidation, shooting (device frames), reduction, direct light
    /// (device frames), gather, smoothing.
    pub weld_s: f64,
    /// Finding the rays that can have changed (revalidation), and copying the earlier hits.
    pub revalidate_s: f64,
    pub shoot_s: f64,
    pub reduce_s: f64,
    pub light_s: f64,
    pub gather_s: f64,
    pub smooth_s: f64,
    /// Of shoot_s and light_s, the devices' dispatch time (summed over tracers).
    pub shoot_device_s: f64,
    pub light_device_s: f64,
    /// The links were an earlier solution's (relighting: nothing shot, nothing reduced).
    pub relit: bool,
    /// An earlier solution's links revalidated: only `rays` of them shot again (those that can
    /// have changed), the groups of `regrouped` elements reduced again.
    pub revalidated: bool,
    pub regrouped: u32,
    /// Instances whose shape or place changed since the earlier solution, and elements that
    /// moved (of `rays`, theirs are all stale).
    pub moved_instances: u32,
    pub moved_elements: u32,
}

impl UpdateStats {
    pub fn total_s(&self) -> f64 {
        self.weld_s
            + self.revalidate_s
            + self.shoot_s
            + self.reduce_s
            + self.light_s
            + self.gather_s
            + self.smooth_s
    }
}

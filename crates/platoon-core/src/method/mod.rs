//! Rendering methods. Each is one unit: a module here (its options, their validation, the
//! approximations it lists in the output's metadata, its pass after assembly), a module of the
//! tracer (its kernels and buffers on one device, `platoon-tracer/src/method/`), a shader folder
//! and one line in each registry (`Method::unit` in `registry` here, the tracer's
//! `method::passes_of`). docs/ARCHITECTURE.md, "Adding a rendering method", lists the files.
//!
//! - [`path`]: unidirectional path tracing, the default and the reference;
//! - [`igi`]: instant global illumination (VPLs) with Marques and Santos' accelerations.
//! - [`links`]: vertex links (Schmitz et al.): indirect diffuse light from per-vertex links.
//! - [`lhb`]: layered hit buffers (Yu): indirect rays answered by lookups in buffers of fixed
//!   directions.

pub mod igi;
pub mod lhb;
pub mod links;
pub mod path;
pub mod path_kernel;
pub mod registry;
pub mod render_method;
pub mod variant;

/// How a frame is rendered: a method and its options.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Method {
    /// Path tracing (`path`): unbiased.
    #[default]
    PathTracing,
    /// Instant global illumination (`igi`; biased, listed as an approximation).
    Igi(igi::IgiOptions),
    /// Vertex links (`links`; biased, listed as approximations).
    Links(links::Links),
    /// Layered hit buffers (`lhb`; biased, listed as approximations).
    Lhb(lhb::Lhb),
}

impl Method {
    /// IGI's options when the method is IGI.
    pub fn igi(&self) -> Option<&igi::IgiOptions> {
        match self {
            Method::Igi(o) => Some(o),
            _ => None,
        }
    }

    /// Vertex links' options and job when the method is vertex links.
    pub fn links(&self) -> Option<&links::Links> {
        match self {
            Method::Links(l) => Some(l),
            _ => None,
        }
    }

    /// Layered hit buffers' options and tables when the method is layered hit buffers.
    pub fn lhb(&self) -> Option<&lhb::Lhb> {
        match self {
            Method::Lhb(l) => Some(l),
            _ => None,
        }
    }
}

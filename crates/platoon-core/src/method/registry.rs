//! The one place that maps a `Method` to its unit: a new method adds its variant to `Method`
//! and one arm to `Method::unit`.

use crate::method::path::PathTracing;
use crate::method::render_method::RenderMethod;
use crate::method::Method;

impl Method {
    /// The method's unit: the registration of every method.
    pub fn unit(&self) -> &dyn RenderMethod {
        match self {
            Method::PathTracing => &PathTracing,
            Method::Igi(options) => options,
            Method::Links(links) => links,
            Method::Lhb(lhb) => lhb,
        }
    }
}

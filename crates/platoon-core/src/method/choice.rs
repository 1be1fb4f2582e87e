//! Which method renders a frame, with its options: plain data that `FrameParams` carries, naming
//! each method's options and prepared state but none of their code (`registry` registers that).

use std::any::Any;
use std::sync::Arc;

use super::igi::IgiOptions;
use super::lhb::Lhb;
use super::links::Links;

/// How a frame is rendered: a method and its options.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Method {
    /// Path tracing (`path`): unbiased.
    #[default]
    PathTracing,
    /// Instant global illumination (`igi`; biased, listed as an approximation).
    Igi(IgiOptions),
    /// Vertex links (`links`; biased, listed as approximations).
    Links(Links),
    /// Layered hit buffers (`lhb`; biased, listed as approximations).
    Lhb(Lhb),
    /// A method registered at run time (`registry::register`), from outside this crate.
    External(External),
}

/// A method registered at run time: its name, its state (a type of its kind's own, which
/// `MethodKind::unit` reads back) and a summary of its settings, which tells two apart.
#[derive(Clone)]
pub struct External {
    pub name: &'static str,
    pub summary: String,
    pub state: Arc<dyn Any + Send + Sync>,
}

impl External {
    /// The state as its kind's type.
    pub fn state<T: Any>(&self) -> Option<&T> {
        self.state.downcast_ref()
    }
}

impl PartialEq for External {
    fn eq(&self, other: &External) -> bool {
        self.name == other.name && self.summary == other.summary
    }
}

impl std::fmt::Debug for External {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}({})", self.name, self.summary)
    }
}

impl Method {
    /// IGI's options when the method is IGI.
    pub fn igi(&self) -> Option<&IgiOptions> {
        match self {
            Method::Igi(o) => Some(o),
            _ => None,
        }
    }

    /// Vertex links' options and job when the method is vertex links.
    pub fn links(&self) -> Option<&Links> {
        match self {
            Method::Links(l) => Some(l),
            _ => None,
        }
    }

    /// Layered hit buffers' options and tables when the method is layered hit buffers.
    pub fn lhb(&self) -> Option<&Lhb> {
        match self {
            Method::Lhb(l) => Some(l),
            _ => None,
        }
    }
}

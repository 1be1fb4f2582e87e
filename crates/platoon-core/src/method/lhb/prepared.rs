//! Layered hit buffers as a frame carries them (`Method::state::<Lhb>`): the options and, once prepared,
//! the tables made from the scene.

use std::sync::Arc;

use super::options::LhbOptions;
use super::tables::Tables;
use crate::flatten::GpuScene;

/// The method with its options and, once prepared, the tables of the scene it renders.
#[derive(Clone, Debug)]
pub struct Lhb {
    pub options: LhbOptions,
    /// None until the preparation (`RenderMethod::prepare`) has made them from the scene.
    pub tables: Option<Arc<Tables>>,
    /// The tables of the scene's earlier generation, whose frame a living scene keeps.
    pub previous: Option<Arc<Tables>>,
}

fn same(a: &Option<Arc<Tables>>, b: &Option<Arc<Tables>>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) => Arc::ptr_eq(a, b),
        (None, None) => true,
        _ => false,
    }
}

impl PartialEq for Lhb {
    fn eq(&self, other: &Lhb) -> bool {
        self.options == other.options
            && same(&self.tables, &other.tables)
            && same(&self.previous, &other.previous)
    }
}

impl Lhb {
    /// Layered hit buffers with `options`, to be prepared.
    pub fn new(options: LhbOptions) -> Lhb {
        Lhb {
            options,
            tables: None,
            previous: None,
        }
    }

    /// Prepared for `g` now (what `prepare` does, without the device frames it does not need).
    pub fn prepared(options: LhbOptions, g: &GpuScene) -> Lhb {
        Lhb::prepared_after(options, g, None)
    }

    /// Prepared for `g`, a later generation of the scene `previous` was made for (its frame is
    /// kept while `g` fits in it).
    pub fn prepared_after(options: LhbOptions, g: &GpuScene, previous: Option<&Tables>) -> Lhb {
        Lhb {
            options,
            tables: Some(Arc::new(Tables::after(g, &options, previous))),
            previous: None,
        }
    }
}

//! Which method renders a frame, with its options: the state `FrameParams` carries. It names no
//! method: each unit makes its own (`Method::new` of its options, `render_method.rs`) and reads
//! them back (`Method::state`); the state renders itself (`Method::unit`), so no list of
//! methods is asked which one it is; `path` gives the default. (This module imports neither
//! the units' trait nor the frame: the frame carries a `Method`, whose units render frames.)

use std::any::Any;
use std::fmt;
use std::sync::Arc;

/// A method's state in a frame: its options and what its preparation made, which tells two
/// frames' methods apart (`PartialEq`), and which renders it (`RenderMethod`, which every
/// state `Method::new` takes implements).
pub trait MethodState: Any + Send + Sync + fmt::Debug {
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
    /// Whether `other` is the same method with equal state.
    fn same(&self, other: &dyn MethodState) -> bool;
}

impl<T: Any + Send + Sync + fmt::Debug + PartialEq> MethodState for T {
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
    fn same(&self, other: &dyn MethodState) -> bool {
        other.as_any().downcast_ref::<T>() == Some(self)
    }
}

/// How a frame is rendered: a method and its options. Cloning shares the state.
#[derive(Clone)]
pub struct Method {
    state: Arc<dyn MethodState>,
    /// What reads the state as the unit that renders it (`render_method::ReadUnit`, made by
    /// `Method::new` for the state's type, used by `Method::unit`): unnamed here, since the
    /// frame holds a `Method` and the units' trait names the frame.
    read_unit: &'static (dyn Any + Sync),
}

impl Method {
    /// The method of `state` (`Method::new`'s), read as its unit by `read_unit`.
    pub(crate) fn of_parts(
        state: Arc<dyn MethodState>,
        read_unit: &'static (dyn Any + Sync),
    ) -> Method {
        Method { state, read_unit }
    }

    pub(crate) fn parts(&self) -> (&dyn MethodState, &'static (dyn Any + Sync)) {
        (&*self.state, self.read_unit)
    }

    /// The state as its unit's type, when the method is that unit's.
    pub fn state<T: Any>(&self) -> Option<&T> {
        self.state.as_any().downcast_ref()
    }

    /// The state as its unit's type to change, when the method is that unit's: this method's
    /// own copy (the clones sharing it keep theirs as it was).
    pub fn state_mut<T: MethodState + Clone>(&mut self) -> Option<&mut T> {
        let own = self.state::<T>()?.clone();
        self.state = Arc::new(own);
        Arc::get_mut(&mut self.state)?.as_any_mut().downcast_mut()
    }
}

impl PartialEq for Method {
    fn eq(&self, other: &Method) -> bool {
        self.state.same(&*other.state)
    }
}

impl fmt::Debug for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.state)
    }
}

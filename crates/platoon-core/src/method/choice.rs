//! Which method renders a frame, with its options: the state `FrameParams` carries. It names no
//! method: each unit makes its own (`Method::new` of its options) and reads them back
//! (`Method::state`); `registry` lists the methods and finds the unit that renders a state
//! (`Method::unit`), `path` gives the default. (This module imports neither, nor the frame:
//! the frame carries a `Method`, whose units render frames.)

use std::any::Any;
use std::fmt;
use std::sync::Arc;

/// A method's state in a frame: its options and what its preparation made, which tells two
/// frames' methods apart (`PartialEq`); its kind reads it back as what renders it
/// (`MethodKind::unit`).
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
pub struct Method(Arc<dyn MethodState>);

impl Method {
    /// The method whose state is `state` (a unit's options: `IgiOptions`, `Links`...).
    pub fn new<T: MethodState>(state: T) -> Method {
        Method(Arc::new(state))
    }

    /// The state as its unit's type, when the method is that unit's.
    pub fn state<T: Any>(&self) -> Option<&T> {
        self.0.as_any().downcast_ref()
    }

    /// The state as its unit's type to change, when the method is that unit's: this method's
    /// own copy (the clones sharing it keep theirs as it was).
    pub fn state_mut<T: MethodState + Clone>(&mut self) -> Option<&mut T> {
        let own = self.state::<T>()?.clone();
        self.0 = Arc::new(own);
        Arc::get_mut(&mut self.0)?.as_any_mut().downcast_mut()
    }
}

impl PartialEq for Method {
    fn eq(&self, other: &Method) -> bool {
        self.0.same(&*other.0)
    }
}

impl fmt::Debug for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::igi::IgiOptions;
    use crate::method::path::PathTracing;

    #[test]
    fn methods_are_equal_when_their_units_and_states_are() {
        let igi = |vpls| Method::new(IgiOptions::with_vpls(vpls));
        assert_eq!(igi(30), igi(30));
        assert_ne!(igi(30), igi(31));
        assert_ne!(igi(30), Method::path_tracing());
        assert_ne!(Method::path_tracing(), igi(30));
        assert_eq!(Method::default(), Method::path_tracing());
        assert!(Method::default().is_path_tracing() && !igi(30).is_path_tracing());
        assert_eq!(
            igi(30).state::<IgiOptions>(),
            Some(&IgiOptions::with_vpls(30))
        );
        assert!(igi(30).state::<PathTracing>().is_none());
        assert_eq!(igi(30).unit().name(), "igi");
    }
}

//! A rendering method from outside platoon's crates, registered at run time in one call: its
//! kind (the core's half: its name, settings, frame state and what the core asks of it) and,
//! where it brings kernels, its device half (the tracer's: its passes and GLSL). From then on
//! the front door, the CLI's `--method`, technique strings and the wire between ranks know it.

use platoon_core::method::kind::MethodKind;
use platoon_core::method::registry;
use platoon_tracer::device::{self, DeviceMethodKind};

/// Registers `kind` and its device half `device_half` (None: its frames render with the path
/// kernel, its kernel options as defines). Refused, with nothing registered, when a method of
/// its name or one of its flags exists, when the halves' names differ, or when one of its
/// shaders has the name of another kernel source.
pub fn register_method(
    kind: &'static dyn MethodKind,
    device_half: Option<&'static DeviceMethodKind>,
) -> Result<(), String> {
    if let Some(d) = device_half {
        if d.name != kind.name() {
            return Err(format!(
                "cannot register {}: its device half is named {}",
                kind.name(),
                d.name
            ));
        }
        if let Some(why) = device::refusal(d) {
            return Err(why);
        }
    }
    registry::register(kind)?;
    match device_half {
        Some(d) => device::register(d),
        None => Ok(()),
    }
}

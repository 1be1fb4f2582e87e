//! The device halves of methods by name: the built-in ones (`BUILT_IN`, their kernels shaders/'s)
//! and those registered at run time from outside platoon's crates with the GLSL they bring,
//! whose shaders join the kernel sources (`kernel::add_sources`) under the names their
//! `#include`s and entry files use, beside shaders/'s own, which they may include.

use std::sync::RwLock;

use super::MethodPasses;

/// A method's device half, built in or registered from outside: what `passes_of` makes for
/// its frames.
pub struct DeviceMethodKind {
    /// The method's name (`RenderMethod::name` of its frames' state).
    pub name: &'static str,
    /// Its GLSL sources by the path its entry files and `#include`s name them (say
    /// `"toy/grey.comp"`): none may have the name of a file of shaders/.
    pub shaders: &'static [(&'static str, &'static str)],
    /// Its passes on one device, made once per tracer.
    pub passes: fn() -> Box<dyn MethodPasses>,
}

/// The built-in methods' device halves, one line each (their kernels are shaders/'s).
static BUILT_IN: &[DeviceMethodKind] = &[
    DeviceMethodKind {
        name: "path",
        shaders: &[],
        passes: super::path::path_passes,
    },
    DeviceMethodKind {
        name: "igi",
        shaders: &[],
        passes: || Box::<super::igi::IgiPasses>::default(),
    },
    DeviceMethodKind {
        name: "links",
        shaders: &[],
        passes: || Box::<super::links::LinksPasses>::default(),
    },
    DeviceMethodKind {
        name: "lhb",
        shaders: &[],
        passes: || Box::<super::lhb::LhbPasses>::default(),
    },
];

/// The device halves registered from outside, after `BUILT_IN`.
static REGISTERED: RwLock<Vec<&'static DeviceMethodKind>> = RwLock::new(Vec::new());

/// Why `kind` cannot be registered (a method of its name has a device half already, or one of
/// its shaders would take the name of another source), or None.
pub fn refusal(kind: &DeviceMethodKind) -> Option<String> {
    refusal_among(&REGISTERED.read().unwrap_or_else(|e| e.into_inner()), kind)
}

fn refusal_among(registered: &[&DeviceMethodKind], kind: &DeviceMethodKind) -> Option<String> {
    let mut all = BUILT_IN.iter().chain(registered.iter().copied());
    if all.any(|k| k.name == kind.name) {
        return Some(format!(
            "cannot register the device half of {}: it has one",
            kind.name
        ));
    }
    let twice = |name: &str| kind.shaders.iter().filter(|(n, _)| *n == name).count() > 1;
    let taken = |name: &str| crate::kernel::source_named(name) || twice(name);
    kind.shaders.iter().find(|(n, _)| taken(n)).map(|(n, _)| {
        format!(
            "cannot register the device half of {}: a kernel source is named {n} already",
            kind.name
        )
    })
}

/// Registers a method's device half; refused as `refusal` says.
pub fn register(kind: &'static DeviceMethodKind) -> Result<(), String> {
    let mut registered = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    match refusal_among(&registered, kind) {
        Some(why) => Err(why),
        None => {
            crate::kernel::add_sources(kind.shaders);
            registered.push(kind);
            Ok(())
        }
    }
}

/// The device half of the method named `name`: built-in, or registered from outside.
pub(crate) fn registered(name: &str) -> Option<&'static DeviceMethodKind> {
    if let Some(kind) = BUILT_IN.iter().find(|k| k.name == name) {
        return Some(kind);
    }
    let registered = REGISTERED.read().unwrap_or_else(|e| e.into_inner());
    registered.iter().copied().find(|k| k.name == name)
}

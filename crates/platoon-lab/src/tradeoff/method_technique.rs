//! A rendering method as a technique: `NAME=PRIMARY+OPTION...`, read and written by the
//! method's own description (`platoon_core::method::technique`), so this names no method; with
//! the lab's `+subK` (every mesh subdivided 1:4 K times before: the same surfaces with more
//! vertices, the tessellation sweep). A method's preparation (vertex links' update, layered hit
//! buffers' build) is in its time.

use std::fmt;

use platoon_core::method::kind::MethodKind;
use platoon_core::method::registry::{self, KINDS};
use platoon_core::method::settings::{token_form, Settings};
use platoon_core::method::technique;
use platoon_core::Method;

/// The most subdivisions a technique asks for (each multiplies the triangles by four).
pub const MAX_SUBDIVISIONS: u32 = 5;

#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct MethodTechnique {
    /// The method's name (`MethodKind::name`).
    pub method: &'static str,
    /// The settings the technique gives; the others default.
    pub given: Settings,
    /// Times every mesh is subdivided before (`variant::Variant::Subdivided`).
    pub subdivisions: u32,
}

impl MethodTechnique {
    /// `value` (what follows `NAME=` in the technique `whole`) for `kind`.
    pub fn parse(
        kind: &'static dyn MethodKind,
        whole: &str,
        value: &str,
    ) -> Result<MethodTechnique, String> {
        let mut subdivisions = 0;
        let mut rest = Vec::new();
        for part in value.split('+') {
            match part.trim().strip_prefix("sub").map(str::parse::<u32>) {
                Some(Ok(k)) if k > MAX_SUBDIVISIONS => {
                    return Err(format!(
                        "technique {whole:?}: at most {MAX_SUBDIVISIONS} subdivisions, not {k}"
                    ))
                }
                Some(Ok(k)) => subdivisions = k,
                _ => rest.push(part),
            }
        }
        Ok(MethodTechnique {
            method: kind.name(),
            given: technique::parse(kind, whole, &rest.join("+"))?,
            subdivisions,
        })
    }

    fn kind(&self) -> &'static dyn MethodKind {
        registry::kind(self.method).expect("a technique's method is registered")
    }

    /// The method of a frame this technique renders (prepared before its first render where
    /// it needs it).
    pub fn method(&self) -> Method {
        self.kind()
            .build(&self.given)
            .expect("a technique's settings were validated when parsed")
    }
}

impl fmt::Display for MethodTechnique {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", technique::format(self.kind(), &self.given))?;
        if self.subdivisions > 0 {
            write!(f, "+sub{}", self.subdivisions)?;
        }
        Ok(())
    }
}

/// How every method is written as a technique: `igi=VPLS[+boxes][+downN]...`.
pub fn methods_help() -> String {
    let forms: Vec<String> = KINDS
        .iter()
        .filter_map(|k| {
            let primary = k.setting(k.primary()?)?;
            let options: String = k
                .settings()
                .iter()
                .filter(|s| s.key != primary.key)
                .filter_map(token_form)
                .chain(k.presets().iter().map(|(name, _)| name.to_string()))
                .chain(["subK".to_string()])
                .map(|o| format!("[+{o}]"))
                .collect();
            Some(format!(
                "{}={}{options}",
                k.name(),
                primary.key.to_uppercase()
            ))
        })
        .collect();
    forms.join(", ")
}

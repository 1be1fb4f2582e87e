//! The registration of every method: how it is chosen (`KINDS`: its name, settings and sweep;
//! its frames carry its state as a `Method`, which renders it). A new method of this crate is
//! one entry here (and one in the tracer's `method::registry::BUILT_IN` for its kernels); a
//! method from outside registers its kind at run time (`register`; `platoon::register_method`
//! registers it with its device half and GLSL, `platoon_tracer::device`), and without a device
//! half its frames render with the path kernel (its kernel options as defines) and its pass
//! after assembly.

use std::sync::RwLock;

use crate::method::igi::IgiKind;
use crate::method::kind::MethodKind;
use crate::method::lhb::LhbKind;
use crate::method::links::LinksKind;
use crate::method::path::PathKind;
use crate::method::render_method::RenderMethod;

/// Every method, the default first.
pub static KINDS: &[&dyn MethodKind] = &[&PathKind, &IgiKind, &LinksKind, &LhbKind];

/// The methods registered at run time, after `KINDS`.
static REGISTERED: RwLock<Vec<&'static dyn MethodKind>> = RwLock::new(Vec::new());

/// Registers a method from outside this crate; refused when its name or one of its flags is
/// taken.
pub fn register(kind: &'static dyn MethodKind) -> Result<(), String> {
    let mut registered = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    let taken = KINDS.iter().chain(registered.iter()).find_map(|k| {
        let flag = k.settings().iter().find_map(|s| {
            let same = kind.settings().iter().any(|t| t.flag == s.flag);
            same.then_some(s.flag)
        });
        (k.name() == kind.name())
            .then(|| format!("a method named {}", k.name()))
            .or_else(|| flag.map(|f| format!("the flag --{f} of method {}", k.name())))
    });
    match taken {
        Some(what) => Err(format!("cannot register {}: there is {what}", kind.name())),
        None => {
            registered.push(kind);
            Ok(())
        }
    }
}

/// Every method: the built-in ones, then those registered.
pub fn all() -> Vec<&'static dyn MethodKind> {
    let registered = REGISTERED.read().unwrap_or_else(|e| e.into_inner());
    KINDS.iter().chain(registered.iter()).copied().collect()
}

/// The method named `name`.
pub fn kind(name: &str) -> Option<&'static dyn MethodKind> {
    all().into_iter().find(|k| k.name() == name)
}

/// The names of every method, comma-separated (for messages).
pub fn names() -> String {
    let names: Vec<&str> = all().iter().map(|k| k.name()).collect();
    names.join(", ")
}

/// The names of the methods, comma-separated, whose state as their defaults build it `can`
/// says yes of (what a refusal offers instead; a method whose build needs a setting is left
/// out).
pub fn names_that(can: fn(&dyn RenderMethod) -> bool) -> String {
    let able: Vec<&str> = all()
        .into_iter()
        .filter(|k| {
            let state = k.build(&crate::method::settings::Settings::default());
            state.is_ok_and(|m| can(m.unit()))
        })
        .map(|k| k.name())
        .collect();
    able.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::technique;

    #[test]
    fn every_flag_names_one_setting_of_one_method() {
        let mut flags: Vec<&str> = KINDS
            .iter()
            .flat_map(|k| k.settings().iter().map(|s| s.flag))
            .collect();
        let all = flags.len();
        flags.sort();
        flags.dedup();
        assert_eq!(flags.len(), all, "a flag is given twice: {flags:?}");
    }

    #[test]
    fn a_method_is_rebuilt_from_its_settings_and_writes_its_techniques_back() {
        for kind in KINDS {
            let defaults = kind.build(&Default::default()).unwrap();
            assert_eq!(defaults.kind().name(), kind.name());
            let own = format!("{}=", kind.name());
            // (`+subK` is the lab's: the scene subdivided.)
            let own_techniques = kind.sweep().iter().filter(|t| t.starts_with(&own));
            for t in own_techniques.filter(|t| !t.contains("+sub")) {
                let given = technique::parse(*kind, t, &t[own.len()..]).unwrap();
                assert_eq!(technique::format(*kind, &given), *t);
                let method = kind.build(&given).unwrap();
                // What the wire sends rebuilds the same method.
                assert_eq!(kind.build(&method.settings()).unwrap(), method, "{t}");
            }
        }
    }

    #[test]
    fn an_unknown_option_is_refused_with_the_ones_there_are() {
        let igi = kind("igi").unwrap();
        let e = technique::parse(igi, "igi=30+sideways", "30+sideways").unwrap_err();
        assert!(e.contains("unknown IGI option \"sideways\""), "{e}");
        assert!(e.contains("boxes, downN, interMxN, minX, all"), "{e}");
        let e = technique::parse(igi, "igi=", "").unwrap_err();
        assert!(e.contains("igi needs its vpls"), "{e}");
        let e = technique::parse(igi, "igi=0", "0").unwrap_err();
        assert!(e.contains("at least one VPL"), "{e}");
    }
}

//! The last line of defence of the loader: a panic inside a dependency while a file is read
//! (a case `validate` does not foresee) becomes the usual one-line error naming the file. The
//! default panic hook would print the panic and a backtrace hint first, so while a guarded
//! load runs, the hook stays silent on that thread (other threads report as usual).

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::path::Path;
use std::sync::Once;

use crate::error::{Error, Result};

thread_local! {
    static GUARDED: Cell<bool> = const { Cell::new(false) };
}

static QUIET_HOOK: Once = Once::new();

/// Runs `load`, turning a panic into an error about `path`.
pub fn catching_panics<T>(path: &Path, load: impl FnOnce() -> Result<T>) -> Result<T> {
    QUIET_HOOK.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if !GUARDED.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let outer = GUARDED.with(|g| g.replace(true));
    let result = panic::catch_unwind(AssertUnwindSafe(load));
    GUARDED.with(|g| g.set(outer));
    result.unwrap_or_else(|payload| {
        let why = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown cause".into())
            .replace('\n', " ");
        Err(Error::file(
            path,
            format!("malformed glTF: reading it failed ({why})"),
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_an_error_naming_the_file() {
        let r: Result<()> = catching_panics(Path::new("bad.glb"), || panic!("index out of range"));
        let e = r.unwrap_err().to_string();
        assert!(e.starts_with("bad.glb: malformed glTF"), "{e}");
        assert!(e.contains("index out of range"), "{e}");
        assert!(!GUARDED.with(Cell::get));
    }
}

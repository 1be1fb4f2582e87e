//! Rebuilds this crate's integration tests when one changes. They live in the workspace's
//! `tests/`, outside the package, so their dependency info holds absolute paths: with a target
//! folder shared by two checkouts (a CI clone beside a working tree), an edit in one would
//! otherwise be missed by the other. A path given here is resolved from the package.
//!
//! With the feature `oidn`, the binary also records where Open Image Denoise's library is
//! (`$OIDN_DIR/lib`, which tools/oidn.sh prints) as its run path: the library is in no system
//! folder, and `platoon` must start without LD_LIBRARY_PATH.
fn main() {
    println!("cargo:rerun-if-changed=../../tests");
    println!("cargo:rerun-if-env-changed=OIDN_DIR");
    if std::env::var_os("CARGO_FEATURE_OIDN").is_some() {
        if let Some(dir) = std::env::var_os("OIDN_DIR") {
            let lib = std::path::Path::new(&dir).join("lib");
            println!("cargo:rustc-link-arg-bins=-Wl,-rpath,{}", lib.display());
        }
    }
}

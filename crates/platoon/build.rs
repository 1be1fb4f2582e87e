//! Rebuilds this crate's integration tests when one changes. They live in the workspace's
//! `tests/`, outside the package, so their dependency info holds absolute paths: with a target
//! folder shared by two checkouts (a CI clone beside a working tree), an edit in one would
//! otherwise be missed by the other. A path given here is resolved from the package.
fn main() {
    println!("cargo:rerun-if-changed=../../tests");
}

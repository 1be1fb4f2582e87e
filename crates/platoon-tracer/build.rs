//! Rebuilds this crate when a kernel source changes. The shaders live outside the package, so
//! `include_str!` records them by absolute path: with a target folder shared by two checkouts
//! (a CI clone beside a working tree), an edit in one would otherwise be missed by the other.
//! A path given here is resolved from the package, in whichever checkout builds it.
fn main() {
    println!("cargo:rerun-if-changed=../../shaders");
}

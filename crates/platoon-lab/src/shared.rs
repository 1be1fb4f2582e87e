//! The shared data folder: the real glTF scenes and CC0 HDR maps beside the repository
//! (`../shared`) that the benches measure and the tests read. Found from any working folder, so
//! that an installed `platoon` (`cargo install --path crates/platoon-cli`) runs its benches
//! from anywhere: `$PLATOON_SHARED_DIR`, else `../shared` from the working folder (the
//! repository root, as the README runs commands), else the folder beside the checkout the
//! binary was built from.

use std::path::{Path, PathBuf};

/// The first of the candidates that is a folder; `../shared` when none is (so that a message
/// about a missing file names where it was looked for).
pub fn dir() -> PathBuf {
    candidates()
        .into_iter()
        .find(|d| d.is_dir())
        .unwrap_or_else(|| PathBuf::from("../shared"))
}

/// `rel` inside the shared folder.
pub fn path(rel: &str) -> PathBuf {
    dir().join(rel)
}

fn candidates() -> Vec<PathBuf> {
    let mut out = Vec::new();
    if let Some(d) = std::env::var_os("PLATOON_SHARED_DIR") {
        out.push(PathBuf::from(d));
    }
    out.push(PathBuf::from("../shared"));
    // crates/platoon-lab -> the repository -> its parent, where shared/ sits beside it.
    out.push(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared"));
    out
}

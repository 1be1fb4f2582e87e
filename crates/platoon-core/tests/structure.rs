//! The code's shape: no import circle between the modules (files) of any crate of the
//! workspace (tools/module_cycles.py says what counts as one).

use std::path::Path;
use std::process::Command;

#[test]
fn no_module_imports_itself_through_others() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = Command::new("python3")
        .arg(root.join("tools/module_cycles.py"))
        .arg(root.join("crates"))
        .output()
        .expect("python3 runs tools/module_cycles.py");
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "import circles:\n{report}");
    assert!(report.contains("0 import circle(s)"), "{report}");
}

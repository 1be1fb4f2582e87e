//! The code's shape: no import circle between the modules (files) of any crate of the
//! workspace (tools/module_cycles.py says what counts as one).

use std::path::Path;
use std::process::Command;

#[test]
fn no_module_imports_itself_through_others() {
    let root = manifest_dir().join("../..");
    let out = Command::new("python3")
        .arg(root.join("tools/module_cycles.py"))
        .arg(root.join("crates"))
        .output()
        .expect("python3 runs tools/module_cycles.py");
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "import circles:\n{report}");
    assert!(report.contains("0 import circle(s)"), "{report}");
}

/// Issue 60's targets, as a ratchet: `tools/code_targets.py` measures the largest crate, the
/// crates over 10k lines, `FrameParams`' fields and how many source files name one of them;
/// none may pass the ceilings of `tools/code_targets.json`, which each step of the redesign
/// lowers to what it reached.
#[test]
fn the_code_keeps_what_the_redesign_reached() {
    let root = manifest_dir().join("../..");
    let out = Command::new("python3")
        .arg(root.join("tools/code_targets.py"))
        .arg("--ceilings")
        .arg(root.join("tools/code_targets.json"))
        .arg(&root)
        .output()
        .expect("python3 runs tools/code_targets.py");
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "past the ceilings:\n{report}");
    assert!(report.contains("FrameParams: "), "{report}");
}

/// `tools/module_cycles.py` over a crate of `files` (path under src, text): its report.
fn cycles_report(files: &[(&str, &str)]) -> String {
    let dir = tempfile::tempdir().expect("a temporary folder");
    for (path, text) in files {
        let file = dir.path().join("toy/src").join(path);
        std::fs::create_dir_all(file.parent().unwrap()).unwrap();
        std::fs::write(file, text).unwrap();
    }
    let root = manifest_dir().join("../..");
    let out = Command::new("python3")
        .arg(root.join("tools/module_cycles.py"))
        .arg(dir.path())
        .output()
        .expect("python3 runs tools/module_cycles.py");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The check sees a parent and its child importing each other (a module and its children are
/// not one unit), and follows a re-export (a glob too) to the module that defines what it names.
#[test]
fn the_cycle_check_sees_parents_and_children() {
    let circle = cycles_report(&[
        ("lib.rs", "pub mod balance;\n"),
        (
            "balance/mod.rs",
            "mod even;\npub use even::Even;\npub trait Policy {}\n",
        ),
        (
            "balance/even.rs",
            "use super::Policy;\npub struct Even;\nimpl Policy for Even {}\n",
        ),
    ]);
    assert!(circle.contains("toy: balance <-> balance/even"), "{circle}");
    let apart = cycles_report(&[
        ("lib.rs", "pub mod balance;\n"),
        (
            "balance/mod.rs",
            "mod even;\nmod policy;\npub use even::Even;\npub use policy::*;\n",
        ),
        ("balance/policy.rs", "pub trait Policy {}\n"),
        (
            "balance/even.rs",
            "use super::Policy;\npub struct Even;\nimpl Policy for Even {}\n",
        ),
    ]);
    assert!(apart.contains("0 import circle(s)"), "{apart}");
}

/// The names in the `[dependencies]` table of `manifest` (a Cargo.toml), one a line as this
/// workspace writes them (`name.workspace = true`, `name = ...`).
fn dependencies(manifest: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(manifest).expect("read the manifest");
    let mut inside = false;
    let mut names = Vec::new();
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            inside = line == "[dependencies]";
        } else if inside && !line.is_empty() && !line.starts_with('#') {
            let name = line.split(['=', '.', ' ']).next().unwrap_or_default();
            names.push(name.to_string());
        }
    }
    names
}

/// The embedding API is a library: no argument parser, no plotter, no test-scene generator, no
/// lab (issue 40: "the facade depends on core, tracer and the crates a library needs").
#[test]
fn the_facade_depends_on_no_generator_parser_or_lab() {
    let root = manifest_dir().join("../..");
    let deps = dependencies(&root.join("crates/platoon/Cargo.toml"));
    assert!(deps.iter().any(|d| d == "platoon-core"), "{deps:?}");
    for refused in ["platoon-scenegen", "platoon-lab", "clap", "plotters"] {
        assert!(
            !deps.iter().any(|d| d == refused),
            "crates/platoon/Cargo.toml depends on {refused}: {deps:?}"
        );
    }
}

/// The schedule of a frame over its tracers, and the fixtures that stand in for tracers, are
/// built on the frame contract alone (issue 60: "frame contract (what the tracer depends on)"):
/// they name no method's code, so neither depends on the crate of the methods.
#[test]
fn the_schedule_and_the_fixtures_know_the_frame_contract_not_the_methods() {
    let root = manifest_dir().join("../..");
    for krate in ["platoon-schedule", "platoon-test-support"] {
        let deps = dependencies(&root.join(format!("crates/{krate}/Cargo.toml")));
        assert!(
            deps.iter().any(|d| d == "platoon-frame"),
            "{krate}: {deps:?}"
        );
        assert!(
            !deps
                .iter()
                .any(|d| d == "platoon-core" || d == "platoon-tracer"),
            "crates/{krate}/Cargo.toml depends on the methods' crate: {deps:?}"
        );
    }
}

/// The `.rs` files under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read a source folder") {
        let path = entry.expect("a folder entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The library returns its errors and logs its warnings (`log`): an application embedding it,
/// a Python session or a game, decides what reaches the terminal, so the facade writes nothing
/// to standard output or error itself.
#[test]
fn the_facade_prints_nothing_itself() {
    let src = manifest_dir().join("../platoon/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    assert!(files.len() > 5, "{files:?}");
    let mut printing = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).expect("read a source file");
        for (i, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or_default();
            if [
                "eprintln!",
                "println!",
                "eprint!",
                "print!",
                "stderr()",
                "stdout()",
            ]
            .iter()
            .any(|p| code.contains(p))
            {
                printing.push(format!("{}:{}: {}", file.display(), i + 1, line.trim()));
            }
        }
    }
    assert!(
        printing.is_empty(),
        "the facade prints:\n{}",
        printing.join("\n")
    );
}

/// This crate's folder: where `cargo test` says it is when it runs the test (a target folder
/// shared between checkouts may hold a binary built in another one), else where it was built.
fn manifest_dir() -> std::path::PathBuf {
    std::env::var_os("CARGO_MANIFEST_DIR")
        .map(Into::into)
        .unwrap_or_else(|| env!("CARGO_MANIFEST_DIR").into())
}

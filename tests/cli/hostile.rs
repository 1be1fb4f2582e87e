//! `platoon render` over the whole adversarial suite (tools/scenegen): valid files render
//! finite images; malformed and hostile ones (and the seeded mutations of the shared scenes that
//! break them) are refused with one line `error: FILE: problem`, no panic and no output file.

#[path = "../common/mod.rs"]
mod common;

use std::path::Path;
use std::process::Command;

use common::*;
use platoon_scenegen::adversarial::{self, Case, Expect};

/// Mutants of each shared scene, and the fixed seed that makes them the same on every run.
const MUTANTS: usize = 16;
const SEED: u64 = 2026;

struct Outcome {
    success: bool,
    stderr: String,
    output_written: bool,
    non_finite: usize,
}

fn render(dir: &Path, case: &Case) -> Outcome {
    let out = dir.join(format!("{}.exr", case.name));
    let o = Command::new(env!("CARGO_BIN_EXE_platoon"))
        .args([
            "render", "--width", "12", "--height", "12", "--spp", "2", "--out",
        ])
        .arg(&out)
        .arg(dir.join(case.scene_path()))
        .output()
        .expect("run platoon");
    let written = out.exists();
    let non_finite = if written {
        platoon::core::output::read_exr(&out)
            .map(|(f, _)| f.count_non_finite())
            .unwrap_or(usize::MAX)
    } else {
        0
    };
    Outcome {
        success: o.status.success(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
        output_written: written,
        non_finite,
    }
}

/// A refusal: non-zero exit, exactly one line `error: <scene path>: ...`, nothing written.
fn refusal_problem(case: &Case, o: &Outcome, dir: &Path, text: &str) -> Option<String> {
    let scene = dir.join(case.scene_path());
    let line = o.stderr.trim_end();
    let expected_start = format!("error: {}: ", scene.display());
    if o.success {
        Some("it rendered".into())
    } else if o.output_written {
        Some("an output file was written".into())
    } else if line.lines().count() != 1 || !line.starts_with(&expected_start) {
        Some(format!("not one line naming the file: {line:?}"))
    } else if !line.contains(text) || line.contains("panicked") {
        Some(format!("does not say '{text}': {line:?}"))
    } else {
        None
    }
}

#[test]
fn every_file_of_the_adversarial_suite_renders_or_is_refused_cleanly() {
    init();
    let dir = tempfile::tempdir().unwrap();
    let cases = adversarial::suite(&shared("scenes"), MUTANTS, SEED);
    adversarial::write(dir.path(), &cases).unwrap();
    let mut problems = Vec::new();
    let (mut rendered, mut refused) = (0, 0);
    for case in &cases {
        let o = render(dir.path(), case);
        assert!(
            !o.stderr.contains("panicked"),
            "{}: panic:\n{}",
            case.name,
            o.stderr
        );
        let finite_image = || match (o.success, o.output_written, o.non_finite) {
            (true, true, 0) => None,
            _ => Some(format!(
                "no finite image ({} non-finite): {}",
                o.non_finite, o.stderr
            )),
        };
        let problem = match &case.expect {
            Expect::Refused(text) => refusal_problem(case, &o, dir.path(), text),
            Expect::FiniteOrRefused if !o.success => refusal_problem(case, &o, dir.path(), ""),
            _ => finite_image(),
        };
        if o.success {
            rendered += 1;
        } else {
            refused += 1;
        }
        if let Some(p) = problem {
            problems.push(format!("{}: {p}", case.name));
        }
    }
    eprintln!(
        "adversarial suite: {} files, {rendered} rendered, {refused} refused",
        cases.len()
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(
        cases.len() > 50 && rendered > 15 && refused > 20,
        "{rendered} rendered, {refused} refused"
    );
}

#[test]
fn external_files_are_read_only_when_allowed() {
    init();
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<Case> = adversarial::suite(Path::new("/nonexistent"), 0, 0)
        .into_iter()
        .filter(|c| c.name == "uri_climbing")
        .collect();
    adversarial::write(dir.path(), &cases).unwrap();
    let out = dir.path().join("out.exr");
    let o = Command::new(env!("CARGO_BIN_EXE_platoon"))
        .args([
            "render",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
            "--allow-external-files",
            "--out",
        ])
        .arg(&out)
        .arg(dir.path().join(cases[0].scene_path()))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.exists());
}

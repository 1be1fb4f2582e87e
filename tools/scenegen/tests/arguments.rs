//! The generator's command line: `--help` says what it takes, and a mistyped option or a
//! second output is refused by name, writing nothing (an unknown option became the output's
//! name: `platoon-scenegen --help` wrote a 190 KB file called `--help`).

use std::process::Command;

fn run(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_platoon-scenegen"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the generator runs")
}

#[test]
fn help_and_mistakes_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(dir.path(), &["--help"]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).contains("usage: platoon-scenegen OUT.glb"));
    let o = run(dir.path(), &["box.glb", "--spheers"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("unknown option --spheers"));
    let o = run(dir.path(), &["a.glb", "b.glb"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("one output file"));
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "{left:?}");
    let o = run(dir.path(), &["box.glb", "--spheres"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("box.glb").is_file());
}

//! Running the `platoon` binary in the CLI tests: the command line built flag by flag, and
//! what its outputs say.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

pub fn platoon(args: &[&str]) -> Output {
    platoon_in(Path::new("."), args)
}

/// A `platoon` command line, built flag by flag: `Cli::new("render").spp(4).size(32, 32)
/// .out(&png).run()`. Every invocation of this file goes through it.
pub struct Cli {
    args: Vec<std::ffi::OsString>,
}

impl Cli {
    pub fn new(command: &str) -> Cli {
        Cli {
            args: vec![command.into()],
        }
    }
    /// A positional argument or a switch.
    pub fn arg(mut self, a: impl AsRef<std::ffi::OsStr>) -> Cli {
        self.args.push(a.as_ref().to_owned());
        self
    }
    /// Arguments in order.
    pub fn args(self, args: &[&str]) -> Cli {
        args.iter().fold(self, |cli, a| cli.arg(a))
    }
    pub fn flag(self, name: &str, value: impl AsRef<std::ffi::OsStr>) -> Cli {
        self.arg(name).arg(value)
    }
    pub fn spp(self, spp: u32) -> Cli {
        self.flag("--spp", spp.to_string())
    }
    pub fn size(self, width: u32, height: u32) -> Cli {
        self.flag("--width", width.to_string())
            .flag("--height", height.to_string())
    }
    pub fn out(self, path: impl AsRef<std::ffi::OsStr>) -> Cli {
        self.flag("--out", path)
    }
    pub fn strs(&self) -> Vec<&str> {
        self.args
            .iter()
            .map(|a| a.to_str().expect("a UTF-8 argument"))
            .collect()
    }
    pub fn run(&self) -> Output {
        platoon(&self.strs())
    }
    pub fn run_in(&self, dir: &Path) -> Output {
        platoon_in(dir, &self.strs())
    }
    /// Runs it with environment variables set (`Some`) or removed (`None`).
    pub fn run_with_env(&self, vars: &[(&str, Option<&str>)]) -> Output {
        crate::common::init();
        let mut command = Command::new(env!("CARGO_BIN_EXE_platoon"));
        command.args(self.strs());
        for &(name, value) in vars {
            match value {
                Some(v) => command.env(name, v),
                None => command.env_remove(name),
            };
        }
        command.output().expect("run platoon")
    }
    /// Runs it and checks it fails naming `names`, writing nothing at `out`.
    pub fn fails_naming(&self, names: &str, out: &Path) {
        assert_fails_naming(&self.strs(), names, out)
    }
}

/// The value of EXR metadata entry `platoon:<key>` ("" when absent).
pub fn metadata_value(meta: &[(String, String)], key: &str) -> String {
    meta.iter()
        .find(|(k, _)| k == &format!("platoon:{key}"))
        .map(|(_, v)| v.clone())
        .unwrap_or_default()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn assert_fails_naming(args: &[&str], names: &str, out: &Path) {
    let o = platoon(args);
    let err = stderr(&o);
    assert!(!o.status.success(), "succeeded: {args:?}");
    assert!(err.contains(names), "message does not name {names}: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert!(!out.exists(), "an output file was written");
    let Ok(entries) = std::fs::read_dir(out.parent().unwrap()) else {
        return;
    };
    let leftovers: Vec<_> = entries
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".part"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left behind");
}

/// `platoon ARGS` run from `dir`.
pub fn platoon_in(dir: &Path, args: &[&str]) -> Output {
    crate::common::init();
    Command::new(env!("CARGO_BIN_EXE_platoon"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run platoon")
}

//! The adversarial suite: scenes that are valid but numerically hard, each with a known answer
//! (a twin it must match, or an exactly black image), and files that are malformed or hostile,
//! each of which a renderer must refuse cleanly; plus seeded random mutations of real assets.
//! `platoon-scenegen --adversarial DIR` writes it; tests/cli/hostile.rs and tests/kernel/hard_cases.rs
//! render it.

mod malformed;
mod mutate;
mod valid;

use std::path::Path;

pub use mutate::mutations;
pub use valid::{thicket, valid};

/// What rendering a case must give.
#[derive(Clone, Debug, PartialEq)]
pub enum Expect {
    /// A finite image in which every pixel is exactly zero (all light is sealed away).
    Black,
    /// A finite image whose mean matches that of the named case within noise.
    Twin(&'static str),
    /// A finite image; nothing more is known.
    Finite,
    /// A refusal: non-zero exit, one line `error: FILE: ...` containing this text.
    Refused(&'static str),
    /// Either a finite image or a clean refusal (random mutations).
    FiniteOrRefused,
}

/// One file of a case, relative to the suite's folder.
pub enum File {
    Bytes(Vec<u8>),
    /// A symbolic link to this path (relative to the link's folder).
    Symlink(String),
}

pub struct Case {
    pub name: String,
    /// The scene to render: the first file.
    pub files: Vec<(String, File)>,
    pub expect: Expect,
}

impl Case {
    fn glb(name: &str, bytes: Vec<u8>, expect: Expect) -> Case {
        Case {
            name: name.into(),
            files: vec![(format!("{name}.glb"), File::Bytes(bytes))],
            expect,
        }
    }

    pub fn scene_path(&self) -> &str {
        &self.files[0].0
    }
}

/// The whole suite: valid, malformed, and `mutants` mutations of each shared scene found in
/// `shared_scenes` (none when the folder is absent).
pub fn suite(shared_scenes: &Path, mutants: usize, seed: u64) -> Vec<Case> {
    let mut cases = valid();
    cases.extend(malformed::malformed());
    cases.extend(mutations(shared_scenes, mutants, seed));
    cases
}

/// Writes every case under `dir` (files first to a temporary name, then renamed).
pub fn write(dir: &Path, cases: &[Case]) -> std::io::Result<()> {
    for case in cases {
        for (rel, file) in &case.files {
            let path = dir.join(rel);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent)?;
            }
            match file {
                File::Bytes(bytes) => {
                    let tmp = path.with_extension("part");
                    std::fs::write(&tmp, bytes)?;
                    std::fs::rename(&tmp, &path)?;
                }
                File::Symlink(target) => {
                    let _ = std::fs::remove_file(&path);
                    #[cfg(unix)]
                    std::os::unix::fs::symlink(target, &path)?;
                }
            }
        }
    }
    Ok(())
}

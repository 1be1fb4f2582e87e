//! The kernel registry's sources: every file under shaders/, embedded by `include_str!` through a
//! generated list (`$OUT_DIR/shaders.rs`), so a method's new shader folder needs no hand list.
//! Rebuilds this crate when a kernel source changes. The shaders live outside the package, so
//! `include_str!` records them by absolute path: with a target folder shared by two checkouts
//! (a CI clone beside a working tree), an edit in one would otherwise be missed by the other.
//! A path given here is resolved from the package, in whichever checkout builds it.
use std::path::{Path, PathBuf};

fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("a shader folder entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            files(&p, out);
        } else if matches!(
            p.extension().and_then(|e| e.to_str()),
            Some("glsl" | "comp")
        ) {
            out.push(p);
        }
    }
}

fn main() {
    println!("cargo:rerun-if-changed=../../shaders");
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by Cargo"));
    let root = manifest.join("../../shaders");
    let root = root.canonicalize().unwrap_or(root);
    let mut list = Vec::new();
    files(&root, &mut list);
    let mut code = String::from("&[\n");
    for p in &list {
        let name = p.strip_prefix(&root).expect("under shaders/");
        let name = name
            .to_str()
            .expect("a UTF-8 shader path")
            .replace('\\', "/");
        code += &format!(
            "    ({name:?}, include_str!({:?})),\n",
            p.display().to_string()
        );
    }
    code += "]\n";
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("set by Cargo"));
    std::fs::write(out.join("shaders.rs"), code).expect("writing the shader list");
}

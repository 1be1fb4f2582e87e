//! The kernel registry's sources: every file under shaders/, embedded by `include_str!` through a
//! generated list (`$OUT_DIR/shaders.rs`), so a method's new shader folder needs no hand list.
//! Rebuilds this crate when a kernel source changes. The shaders live outside the package, so
//! `include_str!` records them by absolute path: with a target folder shared by two checkouts
//! (a CI clone beside a working tree), an edit in one would otherwise be missed by the other.
//! A path given here is resolved from the package, in whichever checkout builds it.
//!
//! It also completes the link against the system's shaderc (see `system_shaderc`).
use std::path::{Path, PathBuf};

/// What Debian's `libshaderc_combined.a` leaves undefined, in link order: glslang's and
/// SPIRV-Tools' static libraries (`glslang-dev`, `spirv-tools`).
const GLSLANG_LIBS: [&str; 8] = [
    "glslang",
    "SPIRV",
    "MachineIndependent",
    "GenericCodeGen",
    "OSDependent",
    "OGLCompiler",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

/// The folder shaderc-sys searches (`SHADERC_LIB_DIR`, else the multiarch library folder).
fn system_lib_dir() -> PathBuf {
    if let Some(dir) = std::env::var_os("SHADERC_LIB_DIR") {
        return PathBuf::from(dir);
    }
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let multiarch = PathBuf::from(format!("/usr/lib/{arch}-linux-gnu"));
    if multiarch.is_dir() {
        multiarch
    } else {
        PathBuf::from("/usr/lib64")
    }
}

/// shaderc-sys (with `prefer-static-linking`) links the system's `libshaderc_combined.a` when it
/// finds one; Debian's lacks glslang and SPIRV-Tools, so they are added here, unbundled, which
/// puts them after every rlib on the final link line (after shaderc-sys's archive that needs
/// them). Without a system shaderc, shaderc-sys builds it from source and nothing is added.
fn system_shaderc() {
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    if std::env::var_os("CARGO_FEATURE_SHADERC_FROM_SOURCE").is_some()
        || std::env::var("CARGO_CFG_TARGET_OS").as_deref() != Ok("linux")
    {
        return;
    }
    let dir = system_lib_dir();
    let combined = dir.join("libshaderc_combined.a");
    println!("cargo:rerun-if-changed={}", combined.display());
    if !combined.is_file() {
        println!(
            "cargo:warning=no system shaderc in {} (Debian: libshaderc-dev glslang-dev spirv-tools, \
             which tools/install-deps.sh installs): shaderc is built from source, about 13 minutes",
            dir.display()
        );
        return;
    }
    let missing: Vec<&str> = GLSLANG_LIBS
        .iter()
        .copied()
        .filter(|l| !dir.join(format!("lib{l}.a")).is_file())
        .collect();
    if !missing.is_empty() {
        panic!(
            "{} is installed but not the libraries it needs ({}) in {}: install glslang-dev and \
             spirv-tools (tools/install-deps.sh), or build with --features shaderc-from-source",
            combined.display(),
            missing.join(", "),
            dir.display()
        );
    }
    println!("cargo:rustc-link-search=native={}", dir.display());
    for l in GLSLANG_LIBS {
        println!("cargo:rustc-link-lib=static:-bundle={l}");
    }
}

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
    system_shaderc();
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
        // Through CARGO_MANIFEST_DIR, not this checkout's absolute path: a target folder
        // shared by two checkouts (a clean clone's CI beside the work tree) may keep this list
        // from the other one while the shader folder looks unchanged, and must still read this
        // checkout's files.
        code += &format!(
            "    ({name:?}, include_str!(concat!(env!(\"CARGO_MANIFEST_DIR\"), {:?}))),\n",
            format!("/../../shaders/{name}")
        );
    }
    code += "]\n";
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("set by Cargo"));
    std::fs::write(out.join("shaders.rs"), code).expect("writing the shader list");
}

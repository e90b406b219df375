//! Embeds every WGSL file under `shaders/`: writes `$OUT_DIR/shader_sources.rs`, the list `hairlab::shaders::SOURCES`
//! is made of (path relative to `shaders/`, contents by `include_str!`), so a new shader file needs no edit.

use std::path::{Path, PathBuf};

fn wgsl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("reading {}: {e}", dir.display()))
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            wgsl_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "wgsl") {
            out.push(p);
        }
    }
}

fn main() {
    let root = Path::new(&std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"))
        .join("shaders");
    // A directory: cargo scans all of it, so a new, removed or edited file re-runs this script.
    println!("cargo:rerun-if-changed=shaders");
    let mut files = Vec::new();
    wgsl_files(&root, &mut files);
    let mut list = String::from("&[\n");
    for f in &files {
        let rel = f
            .strip_prefix(&root)
            .expect("under shaders/")
            .to_string_lossy()
            .replace('\\', "/");
        list.push_str(&format!(
            "    ({rel:?}, include_str!({:?})),\n",
            f.display().to_string()
        ));
    }
    list.push(']');
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("shader_sources.rs");
    std::fs::write(&out, list).unwrap_or_else(|e| panic!("writing {}: {e}", out.display()));
}

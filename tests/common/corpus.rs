//! The shared outside corpus (`../shared/corpus`, or `RELIEF_CORPUS`): real glTF scenes and the
//! glTF validator's malformed files. Tests read it where present and say that they skipped where
//! not; nothing from it is copied into the project.

use std::path::{Path, PathBuf};

/// The corpus folder, or `None` after printing SKIPPED (failing under `RELIEF_REQUIRE_CORPUS=1`).
pub fn corpus(test: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("RELIEF_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus"));
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        !std::env::var("RELIEF_REQUIRE_CORPUS").is_ok_and(|v| v == "1"),
        "{test}: corpus {} missing and RELIEF_REQUIRE_CORPUS=1",
        dir.display()
    );
    eprintln!("SKIPPED: corpus {} not present ({test})", dir.display());
    None
}

/// Every `.gltf` and `.glb` file under `dir`, sorted.
pub fn gltf_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .and_then(|x| x.to_str())
                .is_some_and(|x| x.eq_ignore_ascii_case("gltf") || x.eq_ignore_ascii_case("glb"))
            {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

//! The commit relief is built from, for `results.json` (src/bench/provenance.rs): sets
//! `RELIEF_GIT_COMMIT` (the full hash, or "unknown" outside a git checkout or without git, so a
//! source archive still builds) and `RELIEF_GIT_DIRTY` ("true" when tracked files differ from it).
//!
//! The build script reruns when HEAD, the branch it points at or the index changes (a commit, a
//! checkout, `git add`) and when a file under `src/` changes, so the flag follows the code the
//! binary is built from (an edit elsewhere, say in docs/, is seen at the next of those). A rerun
//! recompiles the shaders, a few seconds beside the crate's own compile.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs `git args` in `root`; its trimmed output when it succeeds.
fn git(root: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(root)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

/// The files whose change means a new commit or a changed index, as git places them (a worktree
/// keeps its HEAD apart from the shared refs); only those that exist, since cargo reruns a build
/// script on every build for a path that is missing.
fn watched_files(root: &Path) -> Vec<PathBuf> {
    // logs/HEAD (the reflog) grows with every commit even where the branch's ref is packed.
    let mut names = vec![
        "HEAD".to_owned(),
        "logs/HEAD".into(),
        "index".into(),
        "packed-refs".into(),
    ];
    names.extend(git(root, &["symbolic-ref", "-q", "HEAD"]));
    names
        .iter()
        .filter_map(|name| git(root, &["rev-parse", "--git-path", name]))
        .map(|p| root.join(p))
        .filter(|p| p.exists())
        .collect()
}

/// Whether `root` is the top of its own git checkout, not a source archive unpacked inside some
/// other repository (whose commit would say nothing about this code).
fn own_checkout(root: &Path) -> bool {
    let top = git(root, &["rev-parse", "--show-toplevel"]).map(PathBuf::from);
    let canonical = |p: &Path| p.canonicalize().ok();
    top.is_some_and(|t| canonical(&t).is_some() && canonical(&t) == canonical(root))
}

/// Prints the two variables and the rerun triggers.
pub fn emit(root: &Path) {
    let commit = own_checkout(root)
        .then(|| git(root, &["rev-parse", "HEAD"]))
        .flatten()
        .filter(|c| !c.is_empty());
    // `--no-optional-locks` keeps status from refreshing the index, which would rerun this script.
    let dirty = commit.is_some()
        && git(
            root,
            &[
                "--no-optional-locks",
                "status",
                "--porcelain",
                "--untracked-files=no",
            ],
        )
        .is_some_and(|s| !s.is_empty());
    if commit.is_some() {
        for file in watched_files(root) {
            println!("cargo:rerun-if-changed={}", file.display());
        }
        println!("cargo:rerun-if-changed=src");
    }
    let commit = commit.unwrap_or_else(|| "unknown".to_owned());
    println!("cargo:rustc-env=RELIEF_GIT_COMMIT={commit}");
    println!("cargo:rustc-env=RELIEF_GIT_DIRTY={dirty}");
}

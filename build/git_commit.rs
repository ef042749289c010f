//! The commit relief is built from, for `results.json` (src/bench/provenance.rs): sets
//! `RELIEF_GIT_COMMIT` (the full hash, or "unknown" outside a git checkout or without git, so a
//! source archive still builds) and `RELIEF_GIT_DIRTY` ("true" when tracked files differ from it).
//!
//! The build script reruns when HEAD, the branch it points at or the index changes (a commit, a
//! checkout, `git add`), not on every edit of a source file: that would recompile every shader
//! each time. So "dirty" says what the tree was when the script last ran; results measured for a
//! record should come from a build made after the last commit.

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
    let mut names = vec!["HEAD".to_owned(), "index".into(), "packed-refs".into()];
    names.extend(git(root, &["symbolic-ref", "-q", "HEAD"]));
    names
        .iter()
        .filter_map(|name| git(root, &["rev-parse", "--git-path", name]))
        .map(|p| root.join(p))
        .filter(|p| p.exists())
        .collect()
}

/// Prints the two variables and the rerun triggers.
pub fn emit(root: &Path) {
    let commit = git(root, &["rev-parse", "HEAD"]).filter(|c| !c.is_empty());
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
    }
    let commit = commit.unwrap_or_else(|| "unknown".to_owned());
    println!("cargo:rustc-env=RELIEF_GIT_COMMIT={commit}");
    println!("cargo:rustc-env=RELIEF_GIT_DIRTY={dirty}");
}

//! `scripts/lavapipe.sh` decides where lavapipe comes from without surprising anyone: Debian 12's
//! backports only as root on a machine without a GPU, advice (and no change) everywhere else,
//! silence where the installed lavapipe already holds memory flat. Run as a dry run with the
//! machine described by `RELIEF_SETUP_FACTS`, so no case installs anything.

use std::path::Path;
use std::process::Command;

/// What the script says (its stderr) on a machine with these facts.
fn decide(facts: &str, keep: bool) -> String {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/lavapipe.sh");
    let mut cmd = Command::new("bash");
    cmd.arg(script)
        .env("RELIEF_SETUP_DRY_RUN", "1")
        .env("RELIEF_SETUP_FACTS", facts)
        .env_remove("RELIEF_KEEP_MESA");
    if keep {
        cmd.env("RELIEF_KEEP_MESA", "1");
    }
    let out = cmd.output().expect("bash runs");
    assert!(out.status.success(), "the script failed on {facts:?}");
    String::from_utf8_lossy(&out.stderr).into_owned()
}

const INSTALL: &str =
    "would run: apt-get install -y -qq --no-install-recommends -t bookworm-backports mesa-vulkan-drivers libdrm2 libdrm-amdgpu1";

#[test]
fn lavapipe_comes_from_backports_only_where_it_surprises_nobody() {
    if Command::new("dpkg").arg("--version").output().is_err() {
        // The script compares versions with dpkg; without it, it does nothing at all.
        eprintln!("SKIPPED: no dpkg on this machine (lavapipe_comes_from_backports)");
        return;
    }
    let old = "mesa=22.3.6-1+deb12u2";
    // CI, containers, cluster nodes: Debian 12, root, no GPU, the release's own Mesa.
    let said = decide(&format!("codename=bookworm root=1 gpu=0 {old}"), false);
    assert!(
        said.contains("leaks about 5 MB a frame") && said.contains(INSTALL),
        "{said}"
    );
    // A fresh machine of that kind takes backports' Mesa at once.
    let said = decide("codename=bookworm root=1 gpu=0 mesa=", false);
    assert!(said.contains(INSTALL), "{said}");
    // A desktop with a GPU keeps its drivers: advice only.
    let said = decide(&format!("codename=bookworm root=1 gpu=1 {old}"), false);
    assert!(
        said.contains("has a GPU") && !said.contains("would run"),
        "{said}"
    );
    assert!(
        said.contains("sudo apt-get install -y -t bookworm-backports mesa-vulkan-drivers"),
        "prints the upgrade line: {said}"
    );
    // Not root: the lines to run, nothing run.
    let said = decide(&format!("codename=bookworm root=0 gpu=0 {old}"), false);
    assert!(
        said.contains("sudo tee") && !said.contains("would run"),
        "{said}"
    );
    // Another distribution with an old Mesa: pointed to its own updates.
    let said = decide("codename=jammy root=1 gpu=0 mesa=22.0.1-1ubuntu2", false);
    assert!(
        said.contains("from your distribution's updates") && !said.contains("would run"),
        "{said}"
    );
    // Asked to keep it.
    let said = decide(&format!("codename=bookworm root=1 gpu=0 {old}"), true);
    assert!(
        said.contains("keeping it") && !said.contains("would run"),
        "{said}"
    );
    // Mesa 23.0 or later (Debian's backports, Ubuntu 22.04's updates) is left alone, silently.
    for mesa in ["25.0.7-2~bpo12+1", "23.2.1-1ubuntu3.1~22.04.4"] {
        let said = decide(
            &format!("codename=bookworm root=1 gpu=0 mesa={mesa}"),
            false,
        );
        assert!(said.is_empty(), "{mesa}: {said}");
    }
}

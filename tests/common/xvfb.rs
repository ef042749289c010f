//! An Xvfb server for the window tests, on a display it chose; without Xvfb they print SKIPPED.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};

/// An Xvfb server on a display it chose, stopped on drop.
pub struct Xvfb {
    child: Child,
    /// The `DISPLAY` value that reaches it (`:N`).
    pub display: String,
}

impl Xvfb {
    /// Starts Xvfb, or `None` (after printing SKIPPED) when it is not installed.
    pub fn start(test: &str) -> Option<Xvfb> {
        let spawned = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "1024x768x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn();
        let mut child = match spawned {
            Ok(child) => child,
            Err(e) => {
                eprintln!(
                    "SKIPPED: no display ({test}): Xvfb could not start ({e}); \
                     scripts/setup.sh installs it (package xvfb) when run as root"
                );
                return None;
            }
        };
        let mut line = String::new();
        let stdout = child.stdout.take().expect("piped stdout");
        BufReader::new(stdout)
            .read_line(&mut line)
            .expect("Xvfb says its display");
        let number = line.trim();
        assert!(
            !number.is_empty() && number.chars().all(|c| c.is_ascii_digit()),
            "Xvfb printed {line:?} for its display"
        );
        Some(Xvfb {
            child,
            display: format!(":{number}"),
        })
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

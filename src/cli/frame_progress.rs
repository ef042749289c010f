//! Progress of a frame sequence: a bar with frames per second and time left on a terminal, and
//! about ten plain lines in a log (stderr not a terminal); nothing for one frame, or when the
//! output is JSON.

use std::io::IsTerminal as _;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};

/// How many plain lines a sequence written to a log gets.
const LOG_LINES: u32 = 10;

pub struct FrameProgress {
    total: u32,
    done: u32,
    started: Instant,
    shown: Shown,
}

enum Shown {
    Nothing,
    Bar(ProgressBar),
    Lines { next: u32 },
}

impl FrameProgress {
    /// Progress over `total` frames; `quiet` (JSON output, a plan) shows none.
    pub fn new(total: u32, quiet: bool) -> FrameProgress {
        let shown = if quiet || total < 2 {
            Shown::Nothing
        } else if std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(u64::from(total));
            let style = ProgressStyle::with_template(
                "{elapsed_precise} [{bar:30}] {pos}/{len} frames, {per_sec}, {eta} left",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar());
            bar.set_style(style);
            Shown::Bar(bar)
        } else {
            Shown::Lines {
                next: step(total, 1),
            }
        };
        FrameProgress {
            total,
            done: 0,
            started: Instant::now(),
            shown,
        }
    }

    /// One more frame is done (written, or found written by `--resume`).
    pub fn advance(&mut self) {
        self.done += 1;
        let (done, total) = (self.done, self.total);
        match &mut self.shown {
            Shown::Nothing => {}
            Shown::Bar(bar) => bar.inc(1),
            Shown::Lines { next } if done >= *next || done == total => {
                *next = step(total, done * LOG_LINES / total.max(1) + 1);
                eprintln!("{}", self.line());
            }
            Shown::Lines { .. } => {}
        }
    }

    /// Clears the bar (the report follows it).
    pub fn finish(self) {
        if let Shown::Bar(bar) = self.shown {
            bar.finish_and_clear();
        }
    }

    fn line(&self) -> String {
        let seconds = self.started.elapsed().as_secs_f64();
        let rate = f64::from(self.done) / seconds.max(1e-9);
        let left = f64::from(self.total - self.done) / rate.max(1e-9);
        format!(
            "relief: frame {}/{} ({:.0}%), {rate:.2} frames/s, {left:.0} s left",
            self.done,
            self.total,
            100.0 * f64::from(self.done) / f64::from(self.total.max(1))
        )
    }
}

/// The frame count at which plain line `k` (1-based) of `LOG_LINES` is printed.
fn step(total: u32, k: u32) -> u32 {
    (total * k).div_ceil(LOG_LINES).max(1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_gets_about_ten_lines_whatever_the_length() {
        for total in [2, 7, 10, 95, 1000] {
            let mut lines = 0;
            let mut next = step(total, 1);
            for done in 1..=total {
                if done >= next || done == total {
                    lines += 1;
                    next = step(total, done * LOG_LINES / total + 1);
                }
            }
            assert_eq!(lines, total.min(LOG_LINES), "{total} frames");
        }
    }
}

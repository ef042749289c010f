//! The viewer's readout, shown in the window title: the device, what is being drawn, frames per
//! second and each pass's mean GPU time (the renderer's timestamp scopes) over the last half
//! second, refreshed every half second so the numbers can be read.

use std::time::{Duration, Instant};

use crate::render::{Pass, PassTiming};

/// How often the readout changes.
pub const REFRESH: Duration = Duration::from_millis(500);

/// Pass timings gathered since the last refresh.
#[derive(Debug)]
pub struct Overlay {
    since: Instant,
    frames: u32,
    /// (pass, summed ms, frames that ran it)
    sums: Vec<(Pass, f64, u32)>,
    line: String,
}

impl Overlay {
    /// An empty readout whose first half second starts at `now`.
    pub fn new(now: Instant) -> Overlay {
        Overlay {
            since: now,
            frames: 0,
            sums: Vec::new(),
            line: "waiting for the first frame".into(),
        }
    }

    /// Adds one retired frame's timings.
    pub fn add(&mut self, timings: &[PassTiming]) {
        self.frames += 1;
        for t in timings {
            match self.sums.iter_mut().find(|(p, _, _)| *p == t.pass) {
                Some(entry) => {
                    entry.1 += t.gpu_ms;
                    entry.2 += 1;
                }
                None => self.sums.push((t.pass, t.gpu_ms, 1)),
            }
        }
    }

    /// The readout; recomputed when `REFRESH` has passed since the last time, so `Some` means the
    /// title should change.
    pub fn refresh(&mut self, now: Instant) -> Option<&str> {
        if now.duration_since(self.since) < REFRESH {
            return None;
        }
        self.flush(now)
    }

    /// The readout over the frames added since the last refresh, however short the time: what a
    /// bounded run reports when it ends, which may come before the first `REFRESH` has passed.
    /// `None` (the readout kept) when no frame was added.
    pub fn flush(&mut self, now: Instant) -> Option<&str> {
        if self.frames == 0 {
            return None;
        }
        let elapsed = now.duration_since(self.since).max(Duration::from_micros(1));
        let fps = f64::from(self.frames) / elapsed.as_secs_f64();
        self.sums.sort_by_key(|(p, _, _)| *p);
        let passes: Vec<String> = self
            .sums
            .iter()
            .map(|(pass, ms, n)| format!("{} {:.2} ms", pass.name(), ms / f64::from(*n)))
            .collect();
        self.line = format!("{fps:.1} fps | {}", passes.join(", "));
        self.since = now;
        self.frames = 0;
        self.sums.clear();
        Some(&self.line)
    }

    /// The last readout.
    pub fn line(&self) -> &str {
        &self.line
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flush_reports_frames_before_the_first_refresh() {
        let start = Instant::now();
        let mut overlay = Overlay::new(start);
        assert!(overlay.flush(start).is_none(), "no frame, no readout");
        overlay.add(&[timing(Pass::Surface, 2.0)]);
        let soon = start + Duration::from_millis(10);
        assert!(overlay.refresh(soon).is_none(), "before REFRESH");
        let line = overlay.flush(soon).expect("a frame was added").to_owned();
        assert!(line.contains("surface 2.00 ms"), "{line}");
        assert_eq!(overlay.line(), line);
    }

    fn timing(pass: Pass, gpu_ms: f64) -> PassTiming {
        PassTiming {
            pass,
            gpu_ms,
            counts: None,
        }
    }

    #[test]
    fn refreshes_every_half_second_with_mean_times_per_pass() {
        let t0 = Instant::now();
        let mut overlay = Overlay::new(t0);
        overlay.add(&[timing(Pass::Pyramid, 4.0), timing(Pass::Surface, 10.0)]);
        overlay.add(&[timing(Pass::Surface, 20.0)]);
        assert!(overlay.refresh(t0 + Duration::from_millis(100)).is_none());
        let line = overlay
            .refresh(t0 + Duration::from_millis(500))
            .unwrap()
            .to_owned();
        assert!(line.starts_with("4.0 fps"), "{line}");
        assert!(line.contains("pyramid 4.00 ms"), "{line}");
        assert!(line.contains("surface 15.00 ms"), "{line}");
        // Nothing new: the readout stays.
        assert!(overlay.refresh(t0 + Duration::from_secs(2)).is_none());
        assert_eq!(overlay.line(), line);
    }
}

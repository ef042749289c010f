//! Soaks: a long run of frames judged by whether anything grows. The process's resident memory
//! and the context's live Vulkan objects are sampled every few frames, and growth is judged by a
//! fitted slope after a warm-up, not by one reading (allocators and drivers settle in steps).
//! `relief soak` and the soak tests share it.

use crate::vk::{Context, LiveObjects};

/// One reading, taken after `frame` frames had retired.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    /// Frames retired when it was taken.
    pub frame: u32,
    /// Resident set size in bytes.
    pub rss: u64,
    /// The context's live Vulkan objects and allocated bytes.
    pub alive: LiveObjects,
}

impl std::fmt::Display for Sample {
    /// One line: the frame, resident memory, the main live objects and the device's bytes.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "frame {:>6}: resident {:>8.1} MiB, {} buffers, {} images, {} sets, {:.1} MiB on the device",
            self.frame,
            self.rss as f64 / 1048576.0,
            self.alive.buffers,
            self.alive.images,
            self.alive.descriptor_sets,
            self.alive.allocated_bytes as f64 / 1048576.0
        )
    }
}

/// This process's resident set size in bytes (`VmRSS` of `/proc/self/status`), or `None` where
/// there is no procfs.
pub fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// A sample of `ctx` now, after `frame` frames; `None` where the resident size cannot be read.
pub fn sample(ctx: &Context, frame: u32) -> Option<Sample> {
    Some(Sample {
        frame,
        rss: resident_bytes()?,
        alive: ctx.alive(),
    })
}

/// The least-squares slope of `ys` against `xs` (per unit of x); 0 when the xs do not vary.
pub fn slope(xs: &[f64], ys: &[f64]) -> f64 {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (x, y) in xs.iter().zip(ys) {
        sxy += (x - mx) * (y - my);
        sxx += (x - mx) * (x - mx);
    }
    if sxx == 0.0 {
        0.0
    } else {
        sxy / sxx
    }
}

/// How much growth a soak tolerates after its warm-up.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Frames whose samples are left out of the fit.
    pub warm_up: u32,
    /// Resident bytes a frame may add, on the fitted line.
    pub rss_per_frame: f64,
}

/// Samples a fit needs after the warm-up.
pub const MIN_FITTED_SAMPLES: usize = 3;

/// The fitted growth per frame of every sampled quantity after the warm-up, as (name, slope);
/// `None` with fewer than [`MIN_FITTED_SAMPLES`] samples after it.
pub fn growth(samples: &[Sample], warm_up: u32) -> Option<Vec<(&'static str, f64)>> {
    let kept: Vec<&Sample> = samples.iter().filter(|s| s.frame >= warm_up).collect();
    if kept.len() < MIN_FITTED_SAMPLES {
        return None;
    }
    let xs: Vec<f64> = kept.iter().map(|s| f64::from(s.frame)).collect();
    let rss: Vec<f64> = kept.iter().map(|s| s.rss as f64).collect();
    let mut out = vec![("rss", slope(&xs, &rss))];
    for (k, (name, _)) in kept[0].alive.fields().iter().enumerate() {
        let ys: Vec<f64> = kept.iter().map(|s| s.alive.fields()[k].1 as f64).collect();
        out.push((name, slope(&xs, &ys)));
    }
    Some(out)
}

/// `Ok` when nothing grows after the warm-up: resident memory within `limits`, and no live
/// Vulkan object or allocated byte at all (a fixed scene's frames create nothing for good, so
/// any slope is a leak). `Err` names what grew and by how much, or says that the samples are
/// too few to judge.
pub fn judge(samples: &[Sample], limits: Limits) -> Result<(), String> {
    let Some(growth) = growth(samples, limits.warm_up) else {
        return Err(format!(
            "fewer than {MIN_FITTED_SAMPLES} samples after the {} warm-up frames: nothing to fit",
            limits.warm_up
        ));
    };
    let span = f64::from(samples.last().map_or(0, |s| s.frame) - limits.warm_up);
    let grew: Vec<String> = growth
        .into_iter()
        .filter(|&(name, per_frame)| {
            if name == "rss" {
                per_frame > limits.rss_per_frame
            } else {
                // Less than one object over the whole fitted span is no growth.
                per_frame * span >= 1.0
            }
        })
        .map(|(name, per_frame)| format!("{name} grows {per_frame:.1} a frame"))
        .collect();
    if grew.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "after {} warm-up frames: {}",
            limits.warm_up,
            grew.join(", ")
        ))
    }
}

/// The samples as CSV: frame, resident bytes, then every live-object count.
pub fn samples_csv(samples: &[Sample]) -> String {
    let mut out = String::from("frame,rss_bytes");
    if let Some(first) = samples.first() {
        for (name, _) in first.alive.fields() {
            out.push(',');
            out.push_str(name);
        }
    }
    out.push('\n');
    for s in samples {
        out.push_str(&format!("{},{}", s.frame, s.rss));
        for (_, value) in s.alive.fields() {
            out.push_str(&format!(",{value}"));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(rss: impl Fn(u32) -> u64) -> Vec<Sample> {
        (0..10)
            .map(|k| Sample {
                frame: 10 * k,
                rss: rss(10 * k),
                alive: LiveObjects::default(),
            })
            .collect()
    }

    #[test]
    fn slope_of_a_line_and_of_a_constant() {
        let xs = [0.0, 10.0, 20.0, 30.0];
        assert!((slope(&xs, &[5.0, 25.0, 45.0, 65.0]) - 2.0).abs() < 1e-12);
        assert_eq!(slope(&xs, &[7.0; 4]), 0.0);
    }

    #[test]
    fn growth_beyond_the_limit_fails_and_too_few_samples_are_no_verdict() {
        let limits = Limits {
            warm_up: 20,
            rss_per_frame: 1024.0,
        };
        assert!(judge(&samples(|_| 1 << 30), limits).is_ok());
        let leak = judge(&samples(|f| (1 << 30) + 4096 * u64::from(f)), limits);
        assert!(leak.is_err_and(|why| why.contains("rss grows 4096.0 a frame")));
        let late = Limits {
            warm_up: 85,
            ..limits
        };
        assert!(judge(&samples(|_| 1 << 30), late).is_err_and(|why| why.contains("fewer than")));
    }

    #[test]
    fn the_csv_has_a_header_and_a_row_a_sample() {
        let csv = samples_csv(&samples(u64::from));
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), 11);
        assert!(lines[0].starts_with("frame,rss_bytes,"));
        assert!(lines[2].starts_with("10,10,"));
    }
}

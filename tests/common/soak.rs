//! A short soak: draw a sequence, sample the process's resident memory and the context's live
//! Vulkan objects every few frames, and judge growth by a fitted slope after a warm-up, not by
//! one reading (allocators and drivers settle in steps).

use relief::vk::{Context, LiveObjects};

/// One reading, taken after `frame` frames had retired.
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    pub frame: u32,
    /// Resident set size in bytes.
    pub rss: u64,
    pub alive: LiveObjects,
}

/// This process's resident set size in bytes (`VmRSS` of `/proc/self/status`), or `None` where
/// there is no procfs.
pub fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Takes a sample of `ctx` now.
pub fn sample(ctx: &Context, frame: u32) -> Sample {
    Sample {
        frame,
        rss: resident_bytes().expect("/proc/self/statm is readable"),
        alive: ctx.alive(),
    }
}

/// The least-squares slope of `ys` against `xs` (per unit of x).
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

/// The fitted growth per frame of every sampled quantity after the warm-up, as (name, slope).
pub fn growth(samples: &[Sample], warm_up: u32) -> Vec<(&'static str, f64)> {
    let kept: Vec<&Sample> = samples.iter().filter(|s| s.frame >= warm_up).collect();
    assert!(
        kept.len() >= 3,
        "a soak needs at least three samples after its warm-up"
    );
    let xs: Vec<f64> = kept.iter().map(|s| f64::from(s.frame)).collect();
    let mut out = vec![(
        "rss",
        slope(&xs, &kept.iter().map(|s| s.rss as f64).collect::<Vec<_>>()),
    )];
    for (k, (name, _)) in kept[0].alive.fields().iter().enumerate() {
        let ys: Vec<f64> = kept.iter().map(|s| s.alive.fields()[k].1 as f64).collect();
        out.push((name, slope(&xs, &ys)));
    }
    out
}

/// `Ok` when nothing grows after the warm-up: resident memory within `limits`, and no live
/// Vulkan object or allocated byte at all (a fixed scene's frames create nothing for good, so
/// any slope is a leak). `Err` names what grew and by how much.
pub fn judge(samples: &[Sample], limits: Limits) -> Result<(), String> {
    let span = f64::from(samples.last().map_or(0, |s| s.frame) - limits.warm_up);
    let grew: Vec<String> = growth(samples, limits.warm_up)
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

#[cfg(test)]
mod tests {
    use super::slope;

    #[test]
    fn slope_of_a_line_and_of_a_constant() {
        let xs = [0.0, 10.0, 20.0, 30.0];
        assert!((slope(&xs, &[5.0, 25.0, 45.0, 65.0]) - 2.0).abs() < 1e-12);
        assert_eq!(slope(&xs, &[7.0; 4]), 0.0);
    }
}

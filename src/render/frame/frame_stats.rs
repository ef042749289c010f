//! Statistics of a frame sequence's GPU times: the first frame apart (it builds the pyramids and
//! pays pipeline compilation and first-use JIT), and per pass the min, median, p95 and mean over
//! the frames after it.

use serde::Serialize;

use crate::render::kit::pass::Pass;
use crate::render::kit::pass_timer::PassTiming;
use crate::vk::PipelineCounts;

/// One pass over the steady frames (every frame after the first).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassStats {
    /// The pass timed.
    pub pass: Pass,
    /// How many steady frames recorded the pass.
    pub frames: usize,
    /// Fastest steady frame's GPU time for the pass, ms.
    pub min_ms: f64,
    /// Median over the steady frames, ms.
    pub median_ms: f64,
    /// 95th percentile (nearest rank) over the steady frames, ms.
    pub p95_ms: f64,
    /// Mean over the steady frames, ms.
    pub mean_ms: f64,
    /// Each pipeline statistic's median over the steady frames, where every one was counted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub counts: Option<PipelineCounts>,
}

/// Each field's median (the lower middle of an even count) over `counts`; `None` if empty.
fn median_counts(counts: &[PipelineCounts]) -> Option<PipelineCounts> {
    if counts.is_empty() {
        return None;
    }
    let median = |field: fn(&PipelineCounts) -> u64| {
        let mut v: Vec<u64> = counts.iter().map(field).collect();
        v.sort_unstable();
        v[(v.len() - 1) / 2]
    };
    Some(PipelineCounts {
        vertex_invocations: median(|c| c.vertex_invocations),
        clipped_primitives: median(|c| c.clipped_primitives),
        fragment_invocations: median(|c| c.fragment_invocations),
        compute_invocations: median(|c| c.compute_invocations),
    })
}

/// A sequence's timings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SequenceStats {
    /// Frames in the sequence, the first included.
    pub frames: usize,
    /// The first frame's passes.
    pub first: Vec<PassTiming>,
    /// Every pass seen after the first frame; empty for a one-frame sequence.
    pub steady: Vec<PassStats>,
}

/// The value at percentile `p` (0..=100) of sorted `values`, by the nearest-rank rule.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    let rank = ((p / 100.0) * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

/// Statistics of `frames[k]`, the pass timings of frame `k` in submission order.
pub fn sequence_stats(frames: &[Vec<PassTiming>]) -> SequenceStats {
    let first = frames.first().cloned().unwrap_or_default();
    let rest = frames.get(1..).unwrap_or_default();
    let mut passes: Vec<Pass> = rest.iter().flatten().map(|t| t.pass).collect();
    passes.sort_unstable();
    passes.dedup();
    let steady = passes
        .into_iter()
        .map(|pass| {
            let mut ms: Vec<f64> = rest
                .iter()
                .flatten()
                .filter(|t| t.pass == pass)
                .map(|t| t.gpu_ms)
                .collect();
            ms.sort_by(f64::total_cmp);
            let counted: Option<Vec<PipelineCounts>> = rest
                .iter()
                .flatten()
                .filter(|t| t.pass == pass)
                .map(|t| t.counts)
                .collect();
            PassStats {
                counts: counted.and_then(|c| median_counts(&c)),
                pass,
                frames: ms.len(),
                min_ms: ms[0],
                median_ms: percentile(&ms, 50.0),
                p95_ms: percentile(&ms, 95.0),
                mean_ms: ms.iter().sum::<f64>() / ms.len() as f64,
            }
        })
        .collect();
    SequenceStats {
        frames: frames.len(),
        first,
        steady,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(pairs: &[(Pass, f64)]) -> Vec<PassTiming> {
        pairs
            .iter()
            .map(|&(pass, gpu_ms)| PassTiming {
                pass,
                gpu_ms,
                counts: Some(PipelineCounts {
                    fragment_invocations: gpu_ms as u64,
                    ..PipelineCounts::default()
                }),
            })
            .collect()
    }

    #[test]
    fn the_first_frame_is_kept_apart_from_the_steady_statistics() {
        let mut frames = vec![frame(&[(Pass::Pyramid, 5.0), (Pass::Surface, 100.0)])];
        for k in 1..=20 {
            frames.push(frame(&[(Pass::Surface, k as f64)]));
        }
        let stats = sequence_stats(&frames);
        assert_eq!(stats.frames, 21);
        assert_eq!(stats.first.len(), 2);
        assert_eq!(
            stats.steady.len(),
            1,
            "the pyramid ran in the first frame only"
        );
        let surface = &stats.steady[0];
        assert_eq!(surface.pass, Pass::Surface);
        assert_eq!(surface.frames, 20);
        assert_eq!(surface.min_ms, 1.0);
        assert_eq!(surface.median_ms, 10.0, "nearest rank: the 10th of 20");
        assert_eq!(surface.p95_ms, 19.0, "nearest rank: the 19th of 20");
        assert!((surface.mean_ms - 10.5).abs() < 1e-12);
        let counts = surface.counts.expect("every frame counted");
        assert_eq!(
            counts.fragment_invocations, 10,
            "the lower middle of 1..=20"
        );
    }

    #[test]
    fn one_frame_has_no_steady_statistics() {
        let stats = sequence_stats(&[frame(&[(Pass::Surface, 3.0)])]);
        assert_eq!(stats.frames, 1);
        assert!(stats.steady.is_empty());
        assert!(sequence_stats(&[]).first.is_empty());
    }
}

//! A frame's timeline: what the host did for it (recording, submission, waiting and reading it
//! back) and when each GPU pass ran, both on the host's clock, so a trace viewer can lay the two
//! side by side. GPU timestamps reach the host's clock through a calibration taken as the frame
//! is submitted (`VK_EXT_calibrated_timestamps`); a device without it has its passes laid from
//! the end of the submission, which places them no earlier than they can have started and says
//! so in [`ClockAlignment`].

use std::time::{Duration, Instant};

use serde::Serialize;

use crate::render::kit::pass::Pass;
use crate::render::kit::pass_timer::{PassTimer, TimedScope};
use crate::vk::{ClockPair, PipelineCounts};

/// What the host did for a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum HostWork {
    /// Recording the frame's commands (the graph's passes).
    Record,
    /// Everything `Renderer::submit` did: uniforms, recording and the queue submission.
    Submit,
    /// Waiting for the frame's fence and reading its timings and pixels back.
    Retire,
}

impl HostWork {
    /// The name a trace shows.
    pub fn name(self) -> &'static str {
        match self {
            HostWork::Record => "record",
            HostWork::Submit => "submit",
            HostWork::Retire => "retire",
        }
    }
}

/// A stretch of host time spent on a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HostSpan {
    /// What was done.
    pub work: HostWork,
    /// When it started.
    pub start: Instant,
    /// When it ended.
    pub end: Instant,
}

/// One timed scope of a pass, on the host's clock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpuSpan {
    /// The pass.
    pub pass: Pass,
    /// For passes recorded per height map, AO map or shadow map, which one.
    pub part: Option<usize>,
    /// When the device reached the scope's first timestamp.
    pub start: Instant,
    /// When it reached the second.
    pub end: Instant,
    /// The scope's pipeline statistics, where counted.
    pub counts: Option<PipelineCounts>,
}

/// How GPU times were placed on the host's clock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ClockAlignment {
    /// Through a calibration read as the frame was submitted; the two clocks' readings were at
    /// most `uncertainty` apart.
    Calibrated {
        /// How far apart the calibration's two readings may have been.
        uncertainty: Duration,
    },
    /// The device cannot calibrate: the first pass is placed at the end of the submission and the
    /// rest by their timestamps after it, so the GPU track may sit early by up to the queue's
    /// latency.
    FromSubmission,
}

/// A frame's host and GPU work on the host's clock.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameTimeline {
    /// The host's spans, in the order they started.
    pub host: Vec<HostSpan>,
    /// The GPU's scopes, in recording order.
    pub gpu: Vec<GpuSpan>,
    /// How the GPU's spans were placed.
    pub alignment: ClockAlignment,
}

/// What a frame's submission noted for its timeline.
#[derive(Debug, Clone)]
pub(in crate::render) struct SubmittedTimeline {
    /// The host's spans so far (recording and submission).
    pub host: Vec<HostSpan>,
    /// The calibration taken as the frame went out, if the device has one.
    pub calibration: Option<ClockPair>,
    /// When the submission returned.
    pub submitted: Instant,
}

impl SubmittedTimeline {
    /// The frame's timeline once it retired: `scopes` as read from `timer`, `retire` the host's
    /// wait and read-back.
    pub fn finish(
        self,
        timer: &PassTimer,
        scopes: &[TimedScope],
        retire: HostSpan,
    ) -> FrameTimeline {
        let (alignment, place): (ClockAlignment, Box<dyn Fn(u64) -> Instant>) =
            match self.calibration {
                Some(pair) => (
                    ClockAlignment::Calibrated {
                        uncertainty: pair.uncertainty,
                    },
                    Box::new(move |ticks| timer.host_time(&pair, ticks)),
                ),
                None => {
                    let first = scopes.first().map_or(0, |s| s.ticks[0]);
                    let ms_per_tick = timer.ms_per_tick();
                    let submitted = self.submitted;
                    (
                        ClockAlignment::FromSubmission,
                        Box::new(move |ticks| {
                            let ms = ticks.saturating_sub(first) as f64 * ms_per_tick;
                            submitted + Duration::from_secs_f64(ms * 1e-3)
                        }),
                    )
                }
            };
        let gpu = scopes
            .iter()
            .map(|s| GpuSpan {
                pass: s.scope.pass,
                part: s.scope.part,
                start: place(s.ticks[0]),
                end: place(s.ticks[1]).max(place(s.ticks[0])),
                counts: s.counts,
            })
            .collect();
        let mut host = self.host;
        host.push(retire);
        FrameTimeline {
            host,
            gpu,
            alignment,
        }
    }
}

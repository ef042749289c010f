//! Frames' timelines as trace-event JSON, the format chrome://tracing and ui.perfetto.dev open:
//! one process, a track for the host's recording and submission and a track for the GPU's
//! passes, every span a complete event (`"ph": "X"`) in microseconds from the first span.

use std::time::{Duration, Instant};

use serde_json::{json, Value};

use crate::render::kit::frame_timeline::{ClockAlignment, FrameTimeline};

/// The host's track.
const HOST_TRACK: u32 = 1;
/// The GPU's track.
const GPU_TRACK: u32 = 2;

/// What a trace says about itself.
#[derive(Debug, Clone)]
pub struct TraceHeader {
    /// The process's name in the viewer, e.g. "relief render default scene".
    pub title: String,
    /// The device, as one line.
    pub device: String,
    /// Anything else worth keeping beside the events (command, commit, date).
    pub other: Value,
}

/// One frame laid on the trace.
#[derive(Debug, Clone, Copy)]
pub struct TracedFrame<'a> {
    /// What drew it, where frames of several renderers share the trace (the bench's); empty for
    /// one renderer's sequence.
    pub label: &'a str,
    /// Its number, shown on its spans.
    pub number: u32,
    /// Its host and GPU spans.
    pub timeline: &'a FrameTimeline,
}

/// The trace of `frames`.
pub fn timeline_trace(header: &TraceHeader, frames: &[TracedFrame]) -> Value {
    let origin = frames
        .iter()
        .map(|f| f.timeline)
        .flat_map(|t| {
            let host = t.host.iter().map(|s| s.start);
            host.chain(t.gpu.iter().map(|s| s.start))
        })
        .min();
    // Whole nanoseconds, so equal spans print equal and durations carry no rounding noise.
    let nanos = |at: Instant| -> u128 {
        origin.map_or(0, |o| {
            at.checked_duration_since(o).unwrap_or_default().as_nanos()
        })
    };
    let span = |start: Instant, end: Instant| {
        let (a, b) = (nanos(start), nanos(end));
        (a as f64 / 1e3, b.saturating_sub(a) as f64 / 1e3)
    };
    let mut events = vec![
        metadata("process_name", 0, &header.title),
        metadata(
            "thread_name",
            HOST_TRACK,
            "host: recording, submission, retiring",
        ),
        metadata("thread_name", GPU_TRACK, &format!("GPU: {}", header.device)),
    ];
    let mut worst = Duration::ZERO;
    let mut calibrated = true;
    for f in frames {
        let (frame, timeline) = (f.number, f.timeline);
        let frame_args = || {
            let mut args = json!({ "frame": frame });
            if !f.label.is_empty() {
                args["renderer"] = json!(f.label);
            }
            args
        };
        for h in &timeline.host {
            let (ts, dur) = span(h.start, h.end);
            events.push(json!({
                "name": h.work.name(), "cat": "host", "ph": "X", "pid": 1, "tid": HOST_TRACK,
                "ts": ts, "dur": dur, "args": frame_args(),
            }));
        }
        for g in &timeline.gpu {
            let (ts, dur) = span(g.start, g.end);
            let mut args = frame_args();
            if let Some(part) = g.part {
                args["part"] = json!(part);
            }
            if let Some(counts) = g.counts {
                args["counts"] = json!(counts);
            }
            events.push(json!({
                "name": g.pass.name(), "cat": "gpu", "ph": "X", "pid": 1, "tid": GPU_TRACK,
                "ts": ts, "dur": dur, "args": args,
            }));
        }
        match timeline.alignment {
            ClockAlignment::Calibrated { uncertainty } => worst = worst.max(uncertainty),
            ClockAlignment::FromSubmission => calibrated = false,
        }
    }
    let alignment = if calibrated {
        format!(
            "GPU times placed on the host's clock by VK_EXT_calibrated_timestamps, read as each \
             frame was submitted; the two clocks' readings at most {:.1} us apart",
            worst.as_secs_f64() * 1e6
        )
    } else {
        "the device cannot calibrate its clock: each frame's first pass is placed at the end of \
         its submission and the rest by their timestamps, so the GPU track may sit early by the \
         queue's latency"
            .to_owned()
    };
    json!({
        "traceEvents": events,
        "displayTimeUnit": "ms",
        "otherData": {
            "device": header.device,
            "clock_alignment": alignment,
            // How early a GPU span may sit on the host's clock: the calibration's half-window
            // (0 without one, whose spans sit late, not early).
            "clock_uncertainty_us": if calibrated { worst.as_secs_f64() * 1e6 } else { 0.0 },
            "frames": frames.len(),
            "other": header.other,
        },
    })
}

fn metadata(name: &str, tid: u32, value: &str) -> Value {
    json!({ "name": name, "ph": "M", "pid": 1, "tid": tid, "args": { "name": value } })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::kit::frame_timeline::{GpuSpan, HostSpan, HostWork};
    use crate::render::kit::pass::Pass;

    #[test]
    fn spans_become_complete_events_from_the_first_start() {
        let t0 = Instant::now();
        let ms = |m: u64| t0 + Duration::from_millis(m);
        let timeline = FrameTimeline {
            host: vec![HostSpan {
                work: HostWork::Submit,
                start: ms(0),
                end: ms(2),
            }],
            gpu: vec![GpuSpan {
                pass: Pass::Surface,
                part: None,
                start: ms(3),
                end: ms(7),
                counts: None,
            }],
            alignment: ClockAlignment::FromSubmission,
        };
        let header = TraceHeader {
            title: "t".into(),
            device: "d".into(),
            other: Value::Null,
        };
        let frame = TracedFrame {
            label: "plain",
            number: 4,
            timeline: &timeline,
        };
        let trace = timeline_trace(&header, &[frame]);
        let events = trace["traceEvents"].as_array().unwrap();
        let complete: Vec<&Value> = events.iter().filter(|e| e["ph"] == "X").collect();
        assert_eq!(complete.len(), 2);
        assert_eq!(complete[0]["ts"], 0.0);
        assert_eq!(complete[0]["dur"], 2000.0);
        assert_eq!(complete[1]["name"], "surface");
        assert_eq!(complete[1]["ts"], 3000.0);
        assert_eq!(complete[1]["dur"], 4000.0);
        assert_eq!(complete[1]["args"]["frame"], 4);
        assert_eq!(complete[1]["args"]["renderer"], "plain");
        assert!(trace["otherData"]["clock_alignment"]
            .as_str()
            .unwrap()
            .contains("cannot calibrate"));
    }
}

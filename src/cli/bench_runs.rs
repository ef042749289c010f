//! The sweep's runs for `relief bench`: each job the plan wants measured once (its error and its
//! first pass's frames), then timed again in each later pass, in the same order.

use anyhow::Context as _;
use indicatif::ProgressBar;
use relief::bench::{depth_match_settled, Job, Run, Runner, StepOrigins};

use super::bench::note;
use super::bench_shard::StepPlan;

/// The sweep: every job the plan wants, but those [`depth_match_settled`] skips. The first pass
/// times and measures each job; each later pass times them all again in the same order, adding
/// frames to their samples.
pub(super) fn measure_runs(
    runner: &mut Runner,
    jobs: &[Job],
    plan: &StepPlan,
    origins: &mut StepOrigins,
    bar: &ProgressBar,
    quiet: bool,
) -> anyhow::Result<Vec<Run>> {
    let passes = runner.config().effective_passes();
    let mut runs = Vec::with_capacity(jobs.len());
    let mut measured = Vec::with_capacity(jobs.len());
    for (j, job) in jobs.iter().enumerate() {
        let step = plan.layout.job(j);
        if !plan.wants(step) {
            continue;
        }
        if depth_match_settled(job, &runs) {
            bar.inc(u64::from(passes));
            continue;
        }
        note(bar, &job_label(job, 0, passes), quiet);
        let run = runner.measure(job).with_context(|| measuring(job))?;
        runs.push(run);
        measured.push(job);
        origins.runs.push(step);
        origins.note_maps(step, runner.map_builds.len());
        bar.inc(1);
    }
    for pass in 1..passes {
        for (run, job) in runs.iter_mut().zip(&measured) {
            note(bar, &job_label(job, pass, passes), quiet);
            runner
                .time_again(job, pass, run)
                .with_context(|| measuring(job))?;
            bar.inc(1);
        }
    }
    Ok(runs)
}

fn job_label(job: &Job, pass: u32, passes: u32) -> String {
    let what = format!(
        "{} {} {}^2 {} deg",
        job.method,
        job.field.name(),
        job.size,
        job.angle
    );
    if passes > 1 {
        format!("{what} (pass {} of {passes})", pass + 1)
    } else {
        what
    }
}

fn measuring(job: &Job) -> String {
    format!(
        "measuring {} on {} at {} deg",
        job.method,
        job.field.name(),
        job.angle
    )
}

//! Section 3 (depth scale) matches the fixed-step baseline (POM) to the tree baseline (QDM) for
//! error at every depth scale, as Drobot compares them at equal quality (Tables 1.3 and 1.4).
//! The quality to match is QDM's with the paper's refinement where the sweep runs it (that is
//! Drobot's QDM; with the exact leaf QDM's error is float rounding, which no fixed-step search
//! reaches), else QDM's default. The step method's cap doubles from its default up to
//! `MAX_STEP_BUDGET`, and stops growing at a depth scale once a cap has matched or cost more than
//! `MAX_COST_RATIO` times QDM's time. The tree baseline's jobs run first so the step jobs can stop.

use super::results::Run;
use super::runner::{Job, Section};
use crate::method::{BenchRole, Budget, Leaf, Method};

/// The largest cap tried on the step baseline.
pub const MAX_STEP_BUDGET: u32 = 2048;
/// Past this multiple of the tree baseline's time, larger caps are not tried.
pub const MAX_COST_RATIO: f64 = 20.0;

/// The caps section 3 tries for `method` besides `listed`: for the step baseline, doubling from
/// the largest listed cap up to [`MAX_STEP_BUDGET`].
pub fn depth_budgets(method: Method, listed: Vec<Budget>) -> Vec<Budget> {
    if method.info().bench_role != Some(BenchRole::StepBaseline) {
        return listed;
    }
    let mut list = listed;
    let default = method.info().default_budget;
    let largest = list.iter().map(|b| b.max_steps).max().unwrap_or(1).max(1);
    let more = std::iter::successors(Some(largest * 2), |c| Some(c * 2))
        .take_while(|&c| c <= MAX_STEP_BUDGET)
        .map(|max_steps| Budget {
            max_steps,
            ..default
        });
    list.extend(more);
    list
}

/// Whether `job` need not run: a step-baseline job of section 3 whose depth scale already has a
/// step run at a smaller cap that matched the tree baseline's error or cost too much.
pub fn settled(job: &Job, runs: &[Run]) -> bool {
    if job.section != Section::DepthScale
        || job.method.info().bench_role != Some(BenchRole::StepBaseline)
    {
        return false;
    }
    let field = job.field.name();
    let same_view = |r: &&Run| {
        r.section == Section::DepthScale
            && r.depth_scale == job.depth_scale
            && r.angle_deg == job.angle
            && r.heightfield == field
    };
    let Some(target) = match_target(runs.iter().filter(same_view)) else {
        return false;
    };
    runs.iter()
        .filter(same_view)
        .filter(|r| r.method == job.method.id() && r.budget.max_steps < job.budget.max_steps)
        .any(|r| {
            r.error_texels.mean <= target.error_texels.mean
                || r.gpu_ms.median > MAX_COST_RATIO * target.gpu_ms.median
        })
}

/// Among runs of one view, the tree baseline's run whose error the step baseline must match: the
/// paper's refinement if it ran and holds up (gross misses on at most `PAPER_GROSS_LIMIT` of the
/// rays: on one-texel spikes it misses nearly all), else the default budget.
pub fn match_target<'a>(runs: impl Iterator<Item = &'a Run>) -> Option<&'a Run> {
    let tree = Method::with_role(BenchRole::TreeBaseline)?;
    let default = tree.info().default_budget;
    let paper = Budget {
        leaf: Leaf::Paper,
        ..default
    };
    let ours: Vec<&Run> = runs.filter(|r| r.method == tree.id()).collect();
    let pick = |b: Budget| ours.iter().copied().find(|r| r.budget == b);
    pick(paper)
        .filter(|r| r.gross_rate <= PAPER_GROSS_LIMIT)
        .or_else(|| pick(default))
}

/// The share of gross misses above which the paper's refinement is no quality to match.
pub const PAPER_GROSS_LIMIT: f64 = 0.01;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_step_baseline_doubles_up_to_the_largest_cap_and_others_keep_theirs() {
        let pom = Method::with_role(BenchRole::StepBaseline).unwrap();
        let listed = vec![
            pom.info().default_budget,
            Budget {
                max_steps: 128,
                ..pom.info().default_budget
            },
        ];
        let caps: Vec<u32> = depth_budgets(pom, listed)
            .iter()
            .map(|b| b.max_steps)
            .collect();
        assert_eq!(caps.last(), Some(&MAX_STEP_BUDGET));
        assert!(caps.ends_with(&[128, 256, 512, 1024, 2048]), "{caps:?}");
        let qdm = Method::with_role(BenchRole::TreeBaseline).unwrap();
        let own = vec![qdm.info().default_budget];
        assert_eq!(depth_budgets(qdm, own.clone()), own);
    }
}

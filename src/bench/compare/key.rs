//! Which cell of one results file is which cell of another: a run's key is everything that
//! chose what was measured (section, method, height field, size, depth scale, view, addressing,
//! budget and leaf), and never what was measured.

use std::fmt;

use crate::bench::results::Run;
use crate::bench::runner::Section;
use crate::method::Leaf;

/// What identifies a cell of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct CellKey {
    /// The report section.
    pub section: Section,
    /// Method id.
    pub method: String,
    /// Height field name.
    pub field: String,
    /// Map `[width, height]`, texels.
    pub size: [u32; 2],
    /// uv units.
    pub depth_scale: f64,
    /// View elevation, degrees.
    pub angle_deg: f64,
    /// View azimuth, degrees.
    pub azimuth_deg: f64,
    /// "repeat" or "clamp".
    pub address: String,
    /// Main loop cap.
    pub max_steps: u32,
    /// Refinement steps.
    pub refine_steps: u32,
    /// The cap's growth limit with the ray's extent (0: none).
    pub extent_limit: u32,
    /// How the leaf is solved.
    pub leaf: Leaf,
}

impl CellKey {
    /// The key of `run`.
    pub fn of(run: &Run) -> CellKey {
        CellKey {
            section: run.section,
            method: run.method.clone(),
            field: run.heightfield.clone(),
            size: run.size,
            depth_scale: run.depth_scale,
            angle_deg: run.angle_deg,
            azimuth_deg: run.azimuth_deg,
            address: run.address.clone(),
            max_steps: run.budget.max_steps,
            refine_steps: run.budget.refine_steps,
            extent_limit: run.budget.extent_limit,
            leaf: run.budget.leaf,
        }
    }

    fn section_name(&self) -> &'static str {
        match self.section {
            Section::ErrorVsTime => "error_vs_time",
            Section::Scaling => "scaling",
            Section::MatchedScaling => "matched_scaling",
            Section::DepthScale => "depth_scale",
            Section::DepthCurve => "depth_curve",
        }
    }
}

/// One line: `error_vs_time pom fbm 64x64 d0.1 30/30deg repeat 32+8 exact`; the extent limit
/// only where set.
impl fmt::Display for CellKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} {} {} {}x{} d{} {}/{}deg {} {}+{}",
            self.section_name(),
            self.method,
            self.field,
            self.size[0],
            self.size[1],
            self.depth_scale,
            self.angle_deg,
            self.azimuth_deg,
            self.address,
            self.max_steps,
            self.refine_steps,
        )?;
        if self.extent_limit > 0 {
            write!(f, "<{}", self.extent_limit)?;
        }
        write!(f, " {}", self.leaf)
    }
}

/// The cells two files share, each as (BASE run, NEW run) in BASE's order, and those only one of
/// them has, in its own order. A key a file holds twice (which a sweep never writes) is matched
/// once and its repeats counted as one-sided.
pub struct Matched<'a> {
    /// Cells in both.
    pub pairs: Vec<(&'a Run, &'a Run)>,
    /// Cells only BASE has.
    pub only_base: Vec<&'a Run>,
    /// Cells only NEW has.
    pub only_new: Vec<&'a Run>,
}

/// Matches `base`'s runs with `new`'s by key.
pub fn match_cells<'a>(base: &'a [Run], new: &'a [Run]) -> Matched<'a> {
    let keys_new: Vec<CellKey> = new.iter().map(CellKey::of).collect();
    let mut taken = vec![false; new.len()];
    let mut pairs = Vec::new();
    let mut only_base = Vec::new();
    for b in base {
        let key = CellKey::of(b);
        let found = (0..new.len()).find(|&i| !taken[i] && keys_new[i] == key);
        match found {
            Some(i) => {
                taken[i] = true;
                pairs.push((b, &new[i]));
            }
            None => only_base.push(b),
        }
    }
    let only_new = new
        .iter()
        .zip(&taken)
        .filter(|(_, t)| !**t)
        .map(|(r, _)| r)
        .collect();
    Matched {
        pairs,
        only_base,
        only_new,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::results_fixture::run;

    #[test]
    fn runs_match_by_key_whatever_their_order_and_measurements() {
        let base = vec![run("pom", 30.0, &[1.0], 0.1), run("qdm", 30.0, &[1.0], 0.1)];
        let new = vec![run("qdm", 30.0, &[9.0], 5.0), run("pom", 30.0, &[2.0], 0.2)];
        let m = match_cells(&base, &new);
        assert_eq!(m.pairs.len(), 2);
        assert!(m.only_base.is_empty() && m.only_new.is_empty());
        for (b, n) in &m.pairs {
            assert_eq!(b.method, n.method);
        }
    }

    #[test]
    fn every_part_of_the_key_tells_cells_apart() {
        let a = run("pom", 30.0, &[1.0], 0.1);
        let mut changes: Vec<Run> = Vec::new();
        let mut push = |f: &dyn Fn(&mut Run)| {
            let mut r = a.clone();
            f(&mut r);
            changes.push(r);
        };
        push(&|r| r.section = Section::Scaling);
        push(&|r| r.method = "qdm".into());
        push(&|r| r.heightfield = "bricks".into());
        push(&|r| r.size = [128, 128]);
        push(&|r| r.depth_scale = 0.5);
        push(&|r| r.angle_deg = 10.0);
        push(&|r| r.azimuth_deg = 0.0);
        push(&|r| r.address = "clamp".into());
        push(&|r| r.budget.max_steps += 1);
        push(&|r| r.budget.refine_steps += 1);
        push(&|r| r.budget.extent_limit += 1);
        push(&|r| {
            r.budget.leaf = match r.budget.leaf {
                Leaf::Paper => Leaf::Exact,
                Leaf::Exact => Leaf::Paper,
            }
        });
        for changed in &changes {
            assert_ne!(
                CellKey::of(&a),
                CellKey::of(changed),
                "{}",
                CellKey::of(changed)
            );
        }
        // Measurements are not part of the key.
        let mut measured = a.clone();
        measured.gpu_ms = crate::bench::GpuMs::of(&[5.0]);
        measured.error_texels.mean = 3.0;
        assert_eq!(CellKey::of(&a), CellKey::of(&measured));
    }

    #[test]
    fn one_sided_cells_are_listed_on_their_side() {
        let base = vec![run("pom", 30.0, &[1.0], 0.1), run("pom", 10.0, &[1.0], 0.1)];
        let new = vec![run("pom", 30.0, &[1.0], 0.1), run("qdm", 30.0, &[1.0], 0.1)];
        let m = match_cells(&base, &new);
        assert_eq!(m.pairs.len(), 1);
        assert_eq!(m.only_base.len(), 1);
        assert_eq!(m.only_base[0].angle_deg, 10.0);
        assert_eq!(m.only_new.len(), 1);
        assert_eq!(m.only_new[0].method, "qdm");
    }
}

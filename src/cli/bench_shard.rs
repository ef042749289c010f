//! `relief bench --shard K/N`: which steps of the sweep this run measures, the fingerprint that
//! tells shards of one sweep from shards of another, and the record of where each result came
//! from (see `relief bench merge`).

use std::collections::HashSet;

use relief::bench::{
    partition, work_units, BlendingConfig, FieldSource, LodConfig, ReliefBuild, Shard, ShardInfo,
    StepLayout, StepOrigins, SweepConfig, SweepOptions, SweepSections, UnitCost,
};

/// The steps a run measures: every one, or its shard's.
pub struct StepPlan {
    pub layout: StepLayout,
    /// `None`: every step.
    picked: Option<HashSet<u32>>,
    shard: Option<(Shard, Vec<u32>)>,
    steps_total: u32,
    /// For a shard: its units, all units, its estimated load and the largest shard's (seconds on
    /// lavapipe, roughly).
    pub estimate: Option<(usize, usize, f64, f64)>,
}

impl StepPlan {
    /// The plan of `sections`, split when `shard` is given.
    pub fn new(shard: Option<Shard>, cfg: &SweepConfig, sections: &SweepSections) -> StepPlan {
        let layout = StepLayout::new(cfg, sections);
        let units = work_units(cfg, sections);
        let steps_total = units.iter().map(|u| u.steps.len() as u32).sum();
        let Some(shard) = shard else {
            return StepPlan {
                layout,
                picked: None,
                shard: None,
                steps_total,
                estimate: None,
            };
        };
        let costs: Vec<UnitCost> = units.iter().map(|u| u.cost.clone()).collect();
        let (shard_of, loads) = partition(&costs, shard.count);
        let mine = shard_of.iter().filter(|&&s| s + 1 == shard.index).count();
        let most = loads.iter().copied().fold(0.0, f64::max);
        let estimate = Some((mine, units.len(), loads[shard.index as usize - 1], most));
        let mut steps: Vec<u32> = units
            .iter()
            .zip(&shard_of)
            .filter(|(_, &s)| s + 1 == shard.index)
            .flat_map(|(u, _)| u.steps.iter().copied())
            .collect();
        steps.sort_unstable();
        StepPlan {
            layout,
            picked: Some(steps.iter().copied().collect()),
            shard: Some((shard, steps)),
            steps_total,
            estimate,
        }
    }

    /// Whether this run measures `step`.
    pub fn wants(&self, step: u32) -> bool {
        self.picked.as_ref().is_none_or(|p| p.contains(&step))
    }

    /// The `shard` object of the results, for a shard.
    pub fn info(&self, fingerprint: String, origins: StepOrigins) -> Option<ShardInfo> {
        let (shard, steps) = self.shard.clone()?;
        Some(ShardInfo {
            shard,
            fingerprint,
            steps_total: self.steps_total,
            steps,
            origins,
        })
    }
}

/// A hash of everything that decides what a sweep measures and how: the effective options, the
/// contents of its height maps, the sections that run with their settings, and the relief build. The shard, the output folder and
/// `--json` are left out, so every shard of one sweep gets the same one.
pub fn fingerprint(
    cfg: &SweepConfig,
    sections: &SweepSections,
    lod: &LodConfig,
    blending: &BlendingConfig,
) -> String {
    let build = ReliefBuild::current();
    // A height map is named by its path, which says nothing of what a node finds there.
    let maps: Vec<String> = cfg
        .fields
        .iter()
        .filter_map(|f| match f {
            FieldSource::File(path) => Some(std::fs::read(path).map_or_else(
                |e| format!("{}: {e}", path.display()),
                |bytes| format!("{:016x}", fnv1a(&bytes)),
            )),
            FieldSource::Synthetic(_) => None,
        })
        .collect();
    let text = serde_json::json!({
        "height_maps": maps,
        "options": SweepOptions::from(cfg),
        "sections": format!("{sections:?}"),
        "lod": format!("{lod:?}"),
        "blending": format!("{blending:?}"),
        "relief": [build.version, build.commit],
    })
    .to_string();
    format!("{:016x}", fnv1a(text.as_bytes()))
}

/// FNV-1a, 64 bits: stable across Rust releases and platforms, unlike std's `DefaultHasher`; a
/// fingerprint needs no cryptographic strength.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_its_published_values() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }
}

//! What a shard's `results.json` says about itself, so that `relief bench merge` can check that
//! shards belong together, that none is missing or repeated, and put their entries back in the
//! order one unsharded run writes them.

use serde::{Deserialize, Serialize};

use super::shard::Shard;

/// The `shard` object of a shard's results (absent from an unsharded run's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardInfo {
    /// Which shard of how many (1-based).
    #[serde(flatten)]
    pub shard: Shard,
    /// A hash of the sweep's effective options, the shard left out: shards of one sweep share it.
    pub fingerprint: String,
    /// How many steps the whole sweep has (see [`crate::bench::StepLayout`]; their numbers need
    /// not be contiguous): all shards together measure that many, each once.
    pub steps_total: u32,
    /// The steps this shard measured, increasing.
    pub steps: Vec<u32>,
    /// The step each entry of the results' lists came from.
    pub origins: StepOrigins,
}

/// For each list of the results, the step of each of its entries, in the same order.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StepOrigins {
    /// One per entry of `runs`.
    pub runs: Vec<u32>,
    /// One per entry of `maps`: the step during which the map was built.
    pub maps: Vec<u32>,
    /// One per entry of `stability`.
    pub stability: Vec<u32>,
    /// One per entry of `shadows`.
    pub shadows: Vec<u32>,
    /// One per entry of `ao`.
    pub ao: Vec<u32>,
}

impl StepOrigins {
    /// Gives every map build after the ones already noted (of `builds` in all) to `step`.
    pub fn note_maps(&mut self, step: u32, builds: usize) {
        let noted = self.maps.len();
        self.maps
            .extend(std::iter::repeat_n(step, builds.saturating_sub(noted)));
    }
}

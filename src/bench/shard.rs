//! `relief bench --shard K/N`: which shard a run is, and the split of a sweep's work units between
//! N shards. The split is balanced by each unit's expected cost, not by its position: units are
//! placed longest first, each on the shard that would finish it earliest (the classic greedy
//! "longest processing time" rule, within 4/3 of the best possible largest load when units share
//! nothing). A unit also names the setups it needs (a height field's pyramid, a method's map) with
//! their cost: a shard pays each setup once, and a shard that has not paid it yet is charged its
//! cost twice when choosing (once on its load, once for the work the sweep as a whole repeats), so
//! units that share a setup stay together unless that unbalances the shards by more than the
//! setup costs. The same units always give the same split, so shards started separately agree on
//! it without talking.

use std::collections::HashSet;
use std::fmt;
use std::str::FromStr;

/// Shard `index` of `count`, numbered from 1 (`--shard 1/3` .. `--shard 3/3`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    /// 1-based.
    pub index: u32,
    /// How many shards the sweep is split into.
    pub count: u32,
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(text: &str) -> Result<Shard, String> {
        let expected = "expected K/N with 1 <= K <= N, e.g. 2/4";
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| format!("{text:?}: {expected}"))?;
        let number = |s: &str| {
            s.trim()
                .parse::<u32>()
                .map_err(|_| format!("{text:?}: {s:?} is not a whole number ({expected})"))
        };
        let (index, count) = (number(k)?, number(n)?);
        if count == 0 || index == 0 || index > count {
            return Err(format!(
                "{text:?}: shard {index} of {count} does not exist ({expected})"
            ));
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// What one unit of work is expected to cost, in any unit shared by every unit of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitCost {
    /// The unit's own cost.
    pub cost: f64,
    /// Setups it needs, by a name that says what is built, with their cost; a shard pays each
    /// named setup once whatever number of its units need it.
    pub setups: Vec<(String, f64)>,
}

/// The 0-based shard of each unit when `units` are split between `count` shards, and the load of
/// every shard (costs plus the setups it pays).
pub fn partition(units: &[UnitCost], count: u32) -> (Vec<u32>, Vec<f64>) {
    let count = count.max(1) as usize;
    let mut order: Vec<usize> = (0..units.len()).collect();
    // Longest first, counting a unit's setups as if it paid them; ties keep the plan's order so
    // that equal inputs give the same split.
    let whole = |u: &UnitCost| u.cost + u.setups.iter().map(|s| s.1).sum::<f64>();
    order.sort_by(|&a, &b| {
        whole(&units[b])
            .total_cmp(&whole(&units[a]))
            .then(a.cmp(&b))
    });
    let mut loads = vec![0.0; count];
    let mut paid: Vec<HashSet<&str>> = vec![HashSet::new(); count];
    let mut shard_of = vec![0; units.len()];
    for u in order {
        let unit = &units[u];
        let new_setups = |s: usize| -> f64 {
            unit.setups
                .iter()
                .filter(|(name, _)| !paid[s].contains(name.as_str()))
                .map(|s| s.1)
                .sum()
        };
        let finish = |s: usize| loads[s] + unit.cost + new_setups(s);
        let charge = |s: usize| finish(s) + new_setups(s);
        // The lowest-numbered of the cheapest shards.
        let best = (0..count)
            .min_by(|&a, &b| charge(a).total_cmp(&charge(b)).then(a.cmp(&b)))
            .unwrap_or(0);
        loads[best] = finish(best);
        paid[best].extend(unit.setups.iter().map(|s| s.0.as_str()));
        shard_of[u] = best as u32;
    }
    (shard_of, loads)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(cost: f64, setups: &[(&str, f64)]) -> UnitCost {
        UnitCost {
            cost,
            setups: setups.iter().map(|(n, c)| ((*n).to_owned(), *c)).collect(),
        }
    }

    #[test]
    fn k_of_n_parses_and_bad_ones_say_why() {
        assert_eq!("2/3".parse(), Ok(Shard { index: 2, count: 3 }));
        assert_eq!("1/1".parse::<Shard>().unwrap().to_string(), "1/1");
        for (text, needle) in [
            ("0/2", "does not exist"),
            ("3/2", "does not exist"),
            ("1/0", "does not exist"),
            ("garbage", "expected K/N"),
            ("a/2", "not a whole number"),
            ("1/", "not a whole number"),
            ("-1/2", "not a whole number"),
        ] {
            let err = text.parse::<Shard>().expect_err(text);
            assert!(err.contains(needle), "{text}: {err}");
        }
    }

    #[test]
    fn the_longest_units_spread_first_and_small_ones_fill_the_gaps() {
        let units = [5.0, 1.0, 4.0, 3.0, 3.0, 2.0].map(|c| unit(c, &[]));
        let (shard_of, loads) = partition(&units, 2);
        // 5 | 4, 5 | 7, 8 | 7, 8 | 9, 9 | 9.
        assert_eq!(shard_of, [0, 0, 1, 1, 0, 1]);
        assert_eq!(loads, [9.0, 9.0]);
    }

    #[test]
    fn units_sharing_a_setup_go_together_while_that_is_cheapest() {
        let units = [
            unit(1.0, &[("map a", 10.0)]),
            unit(1.0, &[("map a", 10.0)]),
            unit(1.0, &[("map b", 10.0)]),
            unit(1.0, &[("map b", 10.0)]),
        ];
        let (shard_of, loads) = partition(&units, 2);
        assert_eq!(shard_of[0], shard_of[1]);
        assert_eq!(shard_of[2], shard_of[3]);
        assert_ne!(shard_of[0], shard_of[2]);
        assert_eq!(loads, [12.0, 12.0]);
    }

    #[test]
    fn more_shards_than_units_leaves_some_empty() {
        let (shard_of, loads) = partition(&[unit(1.0, &[])], 3);
        assert_eq!(shard_of, [0]);
        assert_eq!(loads, [1.0, 0.0, 0.0]);
    }
}

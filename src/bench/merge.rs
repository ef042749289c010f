//! `relief bench merge`: the shards of one sweep (`relief bench --shard K/N`) joined into the
//! results one unsharded run writes, every list back in that run's order. Shards of different
//! sweeps, relief builds or devices are refused, and a missing or repeated shard is named.

use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;

use super::results::{BenchResults, MapBuild};
use super::shard_info::ShardInfo;

/// Why shards could not be merged. Each names the files involved.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    /// Nothing to merge.
    #[error("no shard folders given")]
    Empty,
    /// A file written without `--shard`.
    #[error("{0} is not a shard: it has no `shard` field (write shards with `relief bench --shard K/N`)")]
    NotAShard(PathBuf),
    /// A shard's origins do not match its lists.
    #[error("{path} is damaged: {what}")]
    Damaged {
        /// The file.
        path: PathBuf,
        /// What does not add up.
        what: String,
    },
    /// Two shards of different sweeps, builds, devices or schema versions.
    #[error("{first} and {other} are not shards of one sweep: {why}")]
    Mismatch {
        /// The first shard given.
        first: PathBuf,
        /// The shard that differs from it.
        other: PathBuf,
        /// What differs.
        why: String,
    },
    /// One shard given twice with different contents.
    #[error("shard {shard} is given twice with different results: {first} and {other}")]
    Duplicate {
        /// "K/N".
        shard: String,
        /// Its first file.
        first: PathBuf,
        /// Its second.
        other: PathBuf,
    },
    /// Shards not given.
    #[error("shard(s) {missing} of {count} missing (given: {given})")]
    Missing {
        /// The missing indices, comma-separated.
        missing: String,
        /// N.
        count: u32,
        /// The indices given.
        given: String,
    },
}

/// A shard's results as read from `path`, with the file's bytes (to tell a harmless repeat of the
/// same file from two different runs of one shard).
pub struct ShardFile {
    /// Where it was read from.
    pub path: PathBuf,
    /// Its text.
    pub text: String,
    /// Its results.
    pub results: BenchResults,
}

/// Joins `shards` into one run's results. Repeats of a shard with the same contents are dropped
/// and returned as notes for the caller to print.
pub fn merge_shards(shards: Vec<ShardFile>) -> Result<(BenchResults, Vec<String>), MergeError> {
    let first = shards.first().ok_or(MergeError::Empty)?;
    let base = info(first)?.clone();
    let mut notes = Vec::new();
    let mut by_index: BTreeMap<u32, ShardFile> = BTreeMap::new();
    for file in shards {
        check_same(first_of(&by_index).unwrap_or(&file), &file, &base)?;
        let index = info(&file)?.shard.index;
        if let Some(seen) = by_index.get(&index) {
            if seen.text != file.text {
                return Err(MergeError::Duplicate {
                    shard: info(&file)?.shard.to_string(),
                    first: seen.path.clone(),
                    other: file.path,
                });
            }
            notes.push(format!(
                "{} repeats {} (same contents): used once",
                file.path.display(),
                seen.path.display()
            ));
            continue;
        }
        by_index.insert(index, file);
    }
    let missing: Vec<String> = (1..=base.shard.count)
        .filter(|k| !by_index.contains_key(k))
        .map(|k| k.to_string())
        .collect();
    if !missing.is_empty() {
        return Err(MergeError::Missing {
            missing: missing.join(", "),
            count: base.shard.count,
            given: by_index
                .keys()
                .map(u32::to_string)
                .collect::<Vec<_>>()
                .join(", "),
        });
    }
    check_steps(&by_index, base.steps_total)?;
    Ok((join(by_index.into_values().collect()), notes))
}

fn first_of(map: &BTreeMap<u32, ShardFile>) -> Option<&ShardFile> {
    map.values().next()
}

fn info(file: &ShardFile) -> Result<&ShardInfo, MergeError> {
    file.results
        .shard
        .as_ref()
        .ok_or_else(|| MergeError::NotAShard(file.path.clone()))
}

/// Checks that `file` belongs to the sweep of `first` (whose shard object is `base`).
fn check_same(first: &ShardFile, file: &ShardFile, base: &ShardInfo) -> Result<(), MergeError> {
    let shard = info(file)?;
    let (a, b) = (&first.results, &file.results);
    let why = if a.schema_version != b.schema_version {
        Some(format!(
            "results schema versions {} and {}",
            a.schema_version, b.schema_version
        ))
    } else if !a.device.same_as(&b.device) {
        Some(format!(
            "measured on different devices ({} / {} and {} / {})",
            a.device.name, a.device.driver, b.device.name, b.device.driver
        ))
    } else if a.relief != b.relief {
        Some(format!(
            "different relief builds ({} at {} and {} at {})",
            a.relief.version, a.relief.commit, b.relief.version, b.relief.commit
        ))
    } else if shard.shard.count != base.shard.count {
        Some(format!(
            "split into {} and {} shards",
            base.shard.count, shard.shard.count
        ))
    } else if shard.fingerprint != base.fingerprint {
        Some(format!(
            "different sweeps (fingerprints {} and {}{})",
            base.fingerprint,
            shard.fingerprint,
            options_differing(a, b)
        ))
    } else {
        None
    };
    match why {
        Some(why) => Err(MergeError::Mismatch {
            first: first.path.clone(),
            other: file.path.clone(),
            why,
        }),
        None => Ok(()),
    }
}

/// "; options differ: frames, sizes" when the recorded options say what differs.
fn options_differing(a: &BenchResults, b: &BenchResults) -> String {
    let as_map = |r: &BenchResults| match serde_json::to_value(&r.options) {
        Ok(serde_json::Value::Object(m)) => m,
        _ => serde_json::Map::new(),
    };
    let (a, b) = (as_map(a), as_map(b));
    let differ: Vec<&str> = a
        .iter()
        .filter(|(k, v)| b.get(*k) != Some(v))
        .map(|(k, _)| k.as_str())
        .collect();
    if differ.is_empty() {
        "; the options agree, so the sections run or their settings differ".into()
    } else {
        format!("; options differ: {}", differ.join(", "))
    }
}

/// Every step measured by exactly one shard (together as many as the sweep has), and every
/// shard's origins as long as its lists.
fn check_steps(shards: &BTreeMap<u32, ShardFile>, total: u32) -> Result<(), MergeError> {
    let mut owner: HashMap<u32, &PathBuf> = HashMap::new();
    for file in shards.values() {
        let s = info(file)?;
        let r = &file.results;
        let damaged = |what: String| MergeError::Damaged {
            path: file.path.clone(),
            what,
        };
        let o = &s.origins;
        for (name, origins, len) in [
            ("runs", &o.runs, r.runs.len()),
            ("maps", &o.maps, r.maps.len()),
            ("stability", &o.stability, r.stability.len()),
            ("shadows", &o.shadows, r.shadows.len()),
            ("ao", &o.ao, r.ao.len()),
        ] {
            if origins.len() != len {
                return Err(damaged(format!(
                    "{} origins for {len} {name} entries",
                    origins.len()
                )));
            }
        }
        for &step in &s.steps {
            if let Some(other) = owner.insert(step, &file.path) {
                return Err(damaged(format!(
                    "step {step} is measured by {} too",
                    other.display()
                )));
            }
        }
    }
    if owner.len() != total as usize {
        let first = (0..total).find(|t| !owner.contains_key(t)).unwrap_or(0);
        let path = shards
            .values()
            .next()
            .map(|f| f.path.clone())
            .unwrap_or_default();
        return Err(MergeError::Damaged {
            path,
            what: format!(
                "the shards measure {} of the sweep's {total} steps (step {first} is in none)",
                owner.len()
            ),
        });
    }
    Ok(())
}

/// Entries of one list from every shard, in the unsharded run's order: by step, then as each
/// shard wrote them.
fn ordered<T: Clone>(
    shards: &[ShardFile],
    list: impl Fn(&ShardFile) -> (&[T], &[u32]),
) -> Vec<(u32, T)> {
    let mut all: Vec<(u32, T)> = shards
        .iter()
        .flat_map(|f| {
            let (items, origins) = list(f);
            origins
                .iter()
                .copied()
                .zip(items.iter().cloned())
                .collect::<Vec<_>>()
        })
        .collect();
    all.sort_by_key(|(step, _)| *step);
    all
}

/// Joins checked shards, sorted by index.
fn join(shards: Vec<ShardFile>) -> BenchResults {
    fn strip<T>(v: Vec<(u32, T)>) -> Vec<T> {
        v.into_iter().map(|(_, x)| x).collect()
    }
    let runs = strip(ordered(&shards, |f| {
        (&f.results.runs, origins_of(f, |o| &o.runs))
    }));
    let stability = strip(ordered(&shards, |f| {
        (&f.results.stability, origins_of(f, |o| &o.stability))
    }));
    let shadows = strip(ordered(&shards, |f| {
        (&f.results.shadows, origins_of(f, |o| &o.shadows))
    }));
    let ao = strip(ordered(&shards, |f| {
        (&f.results.ao, origins_of(f, |o| &o.ao))
    }));
    let maps = first_builds(ordered(&shards, |f| {
        (&f.results.maps, origins_of(f, |o| &o.maps))
    }));
    let mut merged = shards[0].results.clone();
    merged.date = shards
        .iter()
        .map(|f| f.results.date.clone())
        .max()
        .unwrap_or_default();
    merged.argv = without_shard(&merged.argv);
    // One busy shard makes the merged figures doubtful.
    if let Some(machine) = &mut merged.machine {
        machine.busy = machine.busy.take().or_else(|| {
            let busy = |f: &ShardFile| f.results.machine.as_ref()?.busy.clone();
            shards.iter().find_map(busy)
        });
    }
    merged.command = merged.argv.join(" ");
    merged.runs = runs;
    merged.stability = stability;
    merged.shadows = shadows;
    merged.ao = ao;
    merged.maps = maps;
    // Sections that run whole: in exactly one shard.
    merged.shadow_stability = shards
        .iter()
        .flat_map(|f| f.results.shadow_stability.clone())
        .collect();
    merged.edits = shards
        .iter()
        .flat_map(|f| f.results.edits.clone())
        .collect();
    merged.paint_edits = shards
        .iter()
        .flat_map(|f| f.results.paint_edits.clone())
        .collect();
    merged.lod = shards.iter().find_map(|f| f.results.lod.clone());
    merged.blending = shards.iter().find_map(|f| f.results.blending.clone());
    merged.scene_shadows = shards.iter().find_map(|f| f.results.scene_shadows.clone());
    merged.frame_features = shards.iter().find_map(|f| f.results.frame_features.clone());
    merged.silhouettes = shards.iter().find_map(|f| f.results.silhouettes.clone());
    merged.frame_costs = shards.iter().find_map(|f| f.results.frame_costs.clone());
    merged.shard = None;
    merged
}

fn origins_of<'a>(
    f: &'a ShardFile,
    pick: impl Fn(&'a super::shard_info::StepOrigins) -> &'a Vec<u32>,
) -> &'a [u32] {
    f.results
        .shard
        .as_ref()
        .map_or(&[][..], |s| pick(&s.origins))
}

/// Each map once, from the earliest step that built it: shards that shared a field or a method
/// each built its map, where one run builds it once at the first step that needs it. A map is
/// told by kind, field, size and builder: each method map kind belongs to one method.
fn first_builds(all: Vec<(u32, MapBuild)>) -> Vec<MapBuild> {
    let mut seen = std::collections::HashSet::new();
    all.into_iter()
        .filter(|(_, m)| seen.insert((m.kind.clone(), m.heightfield.clone(), m.size, m.on.clone())))
        .map(|(_, m)| m)
        .collect()
}

/// The command line without its `--shard K/N` (or `--shard=K/N`): the unsharded run's.
fn without_shard(argv: &[String]) -> Vec<String> {
    let mut out = Vec::with_capacity(argv.len());
    let mut skip = false;
    for word in argv {
        if std::mem::take(&mut skip) {
            continue;
        }
        if word == "--shard" {
            skip = true;
        } else if !word.starts_with("--shard=") {
            out.push(word.clone());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::results_fixture::{device, results, run};
    use crate::bench::{Shard, StepOrigins};

    /// Shard `index` of `count` holding runs at these angles, each its own step.
    fn shard(index: u32, count: u32, steps: &[u32], maps: &[(u32, &str)]) -> ShardFile {
        let mut r = results(
            device("llvmpipe"),
            steps
                .iter()
                .map(|&s| run("pom", f64::from(s), &[1.0], 0.1))
                .collect(),
        );
        r.maps = maps
            .iter()
            .map(|(_, kind)| MapBuild {
                kind: (*kind).into(),
                heightfield: "fbm".into(),
                size: [64, 64],
                ms: f64::from(index),
                on: "gpu".into(),
            })
            .collect();
        r.shard = Some(ShardInfo {
            shard: Shard { index, count },
            fingerprint: "f00d".into(),
            steps_total: 4,
            steps: steps.to_vec(),
            origins: StepOrigins {
                runs: steps.to_vec(),
                maps: maps.iter().map(|m| m.0).collect(),
                ..StepOrigins::default()
            },
        });
        let text = serde_json::to_string(&r).unwrap();
        ShardFile {
            path: format!("shard{index}/results.json").into(),
            text,
            results: r,
        }
    }

    #[test]
    fn runs_come_back_in_step_order_and_each_map_once_from_its_first_step() {
        let a = shard(1, 2, &[0, 3], &[(0, "max_pyramid"), (3, "cone")]);
        let b = shard(2, 2, &[1, 2], &[(1, "cone"), (1, "max_pyramid")]);
        let (merged, notes) = merge_shards(vec![b, a]).expect("one sweep");
        assert!(notes.is_empty());
        let angles: Vec<f64> = merged.runs.iter().map(|r| r.angle_deg).collect();
        assert_eq!(angles, [0.0, 1.0, 2.0, 3.0]);
        let maps: Vec<(&str, f64)> = merged
            .maps
            .iter()
            .map(|m| (m.kind.as_str(), m.ms))
            .collect();
        assert_eq!(maps, [("max_pyramid", 1.0), ("cone", 2.0)]);
        assert!(merged.shard.is_none());
    }

    #[test]
    fn shards_of_other_devices_builds_or_sweeps_are_refused() {
        let mut other_device = shard(2, 2, &[1, 2], &[]);
        other_device.results.device = device("NVIDIA GeForce RTX 4090");
        let mut other_sweep = shard(2, 2, &[1, 2], &[]);
        other_sweep.results.shard.as_mut().unwrap().fingerprint = "beef".into();
        other_sweep.results.options.frames += 1;
        let mut other_build = shard(2, 2, &[1, 2], &[]);
        other_build.results.relief.commit = "0123".into();
        let mut other_count = shard(2, 3, &[1, 2], &[]);
        other_count.results.shard.as_mut().unwrap().steps_total = 4;
        let mut other_version = shard(2, 2, &[1, 2], &[]);
        other_version.results.schema_version += 1;
        for (file, needle) in [
            (other_device, "different devices"),
            (other_sweep, "options differ: frames"),
            (other_build, "different relief builds"),
            (other_count, "split into 2 and 3 shards"),
            (other_version, "schema versions"),
        ] {
            let err = merge_shards(vec![shard(1, 2, &[0, 3], &[]), file]).expect_err(needle);
            let text = err.to_string();
            assert!(text.contains(needle) && text.contains("shard2"), "{text}");
        }
    }

    #[test]
    fn a_whole_run_missing_or_repeated_shards_and_overlapping_steps_are_named() {
        let mut whole = shard(1, 2, &[0, 3], &[]);
        whole.results.shard = None;
        let err = merge_shards(vec![whole]).unwrap_err().to_string();
        assert!(err.contains("shard1/results.json is not a shard"), "{err}");

        let err = merge_shards(vec![shard(2, 2, &[1, 2], &[])])
            .unwrap_err()
            .to_string();
        assert!(err.contains("shard(s) 1 of 2 missing (given: 2)"), "{err}");

        let (_, notes) = merge_shards(vec![
            shard(1, 2, &[0, 3], &[]),
            shard(2, 2, &[1, 2], &[]),
            shard(2, 2, &[1, 2], &[]),
        ])
        .expect("a repeat with the same contents is harmless");
        assert_eq!(notes.len(), 1, "{notes:?}");
        let err = merge_shards(vec![
            shard(1, 2, &[0, 3], &[]),
            shard(2, 2, &[1, 2], &[]),
            shard(2, 2, &[1, 3], &[]),
        ])
        .unwrap_err()
        .to_string();
        assert!(err.contains("shard 2/2 is given twice"), "{err}");

        let err = merge_shards(vec![shard(1, 2, &[0, 3], &[]), shard(2, 2, &[1, 3], &[])])
            .unwrap_err()
            .to_string();
        assert!(err.contains("step 3 is measured by shard1"), "{err}");
    }
}

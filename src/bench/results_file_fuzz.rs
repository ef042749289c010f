//! Generated bad `results.json` files, read as `bench compare` and `bench merge` read them:
//! mutations of a written file (wrong types, extreme numbers, NaN and infinities spliced in as
//! raw tokens, deep nesting, keys removed, bytes cut or flipped). Parsing must return a value
//! or an error naming the file, never panic; a file that parses must survive being compared
//! with the original both ways and reported. Lives beside the parser (not in `tests/`) because
//! its seed is built from the crate's own fixtures. `PROPTEST_CASES=N` runs more cases.

use std::path::Path;

use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence};

use super::compare::{compare, markdown_report, ratio_plot, terminal_report, DEFAULT_MIN_EFFECT};
use super::results::BenchResults;
use super::results_file::parse_results;
use super::results_fixture::{device, results, run};

#[path = "../../tests/fuzz_support/mutate.rs"]
#[allow(dead_code)]
mod mutate;

fn seed() -> BenchResults {
    results(
        device("llvmpipe"),
        vec![
            run("pom", 30.0, &[1.0, 1.25, 0.75], 0.5),
            run("qdm", 10.0, &[2.0, 2.5, 2.25], 0.01),
            run("qdm", 30.0, &[2.0, 2.5, 2.25], 0.02),
        ],
    )
}

fn config() -> Config {
    Config {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(150),
        failure_persistence: Some(Box::new(FileFailurePersistence::Off)),
        ..Config::default()
    }
}

/// Parses `text` as `results.json`, then compares and reports it against the seed both ways.
fn read_and_compare(text: &str) -> Result<(), TestCaseError> {
    let path = Path::new("fuzzed/results.json");
    match parse_results(text, path) {
        Err(e) => {
            let message = e.to_string();
            prop_assert!(message.contains("fuzzed/results.json"), "{}", message);
        }
        Ok(read) => {
            let original = seed();
            for (base, new) in [(&original, &read), (&read, &original)] {
                let c = compare(base, new, DEFAULT_MIN_EFFECT);
                let _ = (terminal_report(&c), markdown_report(&c), ratio_plot(&c));
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn mutated_results_are_refused_by_name_or_compared(edits in mutate::json_edits()) {
        let value = serde_json::to_value(seed()).expect("serialises");
        read_and_compare(&mutate::apply_json(&value, &edits))?;
    }

    #[test]
    fn damaged_results_text_is_refused_by_name(edits in mutate::byte_edits()) {
        let text = serde_json::to_string_pretty(&seed()).expect("serialises");
        let bytes = mutate::apply_bytes(text.as_bytes(), &edits);
        read_and_compare(&String::from_utf8_lossy(&bytes))?;
    }
}

//! Reads a `results.json` back: from the file or from the folder `relief bench --out` wrote,
//! refusing a file of another schema version with a message that names both versions.

use std::path::{Path, PathBuf};

use super::results::{BenchResults, SCHEMA_VERSION};

/// Why a results file could not be read. Each names the file.
#[derive(Debug, thiserror::Error)]
pub enum ResultsFileError {
    /// The file (or the folder's `results.json`) could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// What the system said.
        source: std::io::Error,
    },
    /// Not JSON, or JSON of another shape.
    #[error("{path} is not a relief results file: {message}")]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },
    /// Written before samples were kept: nothing to compute an interval from.
    #[error(
        "{path} is results schema version 1 (no schema_version field), which predates the \
         per-frame samples; this relief reads version {SCHEMA_VERSION}: measure it again with \
         this relief's `relief bench`"
    )]
    Version1 {
        /// The file.
        path: PathBuf,
    },
    /// A version this relief does not read.
    #[error(
        "{path} is results schema version {found}; this relief reads version {SCHEMA_VERSION} \
         ({advice})"
    )]
    OtherVersion {
        /// The file.
        path: PathBuf,
        /// The version it says it is.
        found: u64,
        /// What to do about it.
        advice: &'static str,
    },
}

impl ResultsFileError {
    /// The version the file holds, when it was refused for its version.
    pub fn found_version(&self) -> Option<u64> {
        match self {
            ResultsFileError::Version1 { .. } => Some(1),
            ResultsFileError::OtherVersion { found, .. } => Some(*found),
            _ => None,
        }
    }
}

/// The `results.json` a path names: the path itself, or the file of that name inside a folder.
pub fn results_path(path: &Path) -> PathBuf {
    if path.is_dir() {
        path.join("results.json")
    } else {
        path.to_owned()
    }
}

/// Reads and checks the results at `path` (a file, or a folder holding `results.json`).
pub fn load_results(path: &Path) -> Result<BenchResults, ResultsFileError> {
    let path = results_path(path);
    let text = std::fs::read_to_string(&path).map_err(|source| ResultsFileError::Read {
        path: path.clone(),
        source,
    })?;
    parse_results(&text, &path)
}

/// Checks the version first, so an old or newer file is refused for its version rather than
/// for whichever field it happens to lack.
pub fn parse_results(text: &str, path: &Path) -> Result<BenchResults, ResultsFileError> {
    let malformed = |e: serde_json::Error| ResultsFileError::Malformed {
        path: path.to_owned(),
        message: e.to_string(),
    };
    let value: serde_json::Value = serde_json::from_str(text).map_err(malformed)?;
    let Some(object) = value.as_object() else {
        return Err(ResultsFileError::Malformed {
            path: path.to_owned(),
            message: "the top level is not an object".into(),
        });
    };
    let version = match object.get("schema_version") {
        None if object.contains_key("runs") => {
            return Err(ResultsFileError::Version1 {
                path: path.to_owned(),
            })
        }
        None => {
            return Err(ResultsFileError::Malformed {
                path: path.to_owned(),
                message: "it has neither schema_version nor runs".into(),
            })
        }
        Some(v) => v.as_u64().ok_or_else(|| ResultsFileError::Malformed {
            path: path.to_owned(),
            message: format!("schema_version is {v}, not a whole number"),
        })?,
    };
    if version != u64::from(SCHEMA_VERSION) {
        let advice = if version < u64::from(SCHEMA_VERSION) {
            "measure it again with this relief"
        } else {
            "read it with the newer relief that wrote it"
        };
        return Err(ResultsFileError::OtherVersion {
            path: path.to_owned(),
            found: version,
            advice,
        });
    }
    serde_json::from_value(value).map_err(malformed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::results::StabilityCell;
    use crate::bench::results_fixture::{device, results, run};
    use crate::bench::shadow_stability::ShadowStabilityCell;

    fn written() -> BenchResults {
        let mut r = results(
            device("llvmpipe"),
            vec![
                run("pom", 30.0, &[1.0, 1.25, 0.75], 0.5),
                run("qdm", 10.0, &[2.0, 2.5], 0.01),
            ],
        );
        r.stability.push(StabilityCell {
            method: "pom".into(),
            case: "spikes".into(),
            nan_pixels: 0,
            capped_rate: 0.0,
            gross_rate: 0.0,
            max_error_texels: f64::NAN,
            gpu_ms: None,
            failed: Some("out of memory".into()),
        });
        r.shadow_stability.push(ShadowStabilityCell {
            mode: "cone".into(),
            case: "flat".into(),
            bad_values: 0,
            max_error: f64::NAN,
            mean_error: f64::NAN,
            failed: Some("failed".into()),
        });
        r
    }

    #[test]
    fn a_written_file_reads_back_with_its_samples_and_provenance() {
        let original = written();
        let text = serde_json::to_string_pretty(&original).unwrap();
        let back = parse_results(&text, Path::new("r.json")).unwrap();
        assert_eq!(back.schema_version, SCHEMA_VERSION);
        assert_eq!(back.relief, original.relief);
        assert_eq!(back.device, original.device);
        assert_eq!(back.options, original.options);
        assert_eq!((&back.date, &back.argv), (&original.date, &original.argv));
        assert_eq!(back.runs.len(), 2);
        for (a, b) in back.runs.iter().zip(&original.runs) {
            assert_eq!(a.gpu_ms, b.gpu_ms);
            assert_eq!(a.gpu_ms.samples, b.gpu_ms.samples);
            assert_eq!(
                (a.section, &a.method, a.budget),
                (b.section, &b.method, b.budget)
            );
            assert_eq!(a.error_texels, b.error_texels);
        }
        // NaN goes out as null and comes back as NaN.
        assert!(back.stability[0].max_error_texels.is_nan());
        assert!(back.shadow_stability[0].mean_error.is_nan());
        // What is read writes out the same again.
        assert_eq!(serde_json::to_string_pretty(&back).unwrap(), text);
    }

    #[test]
    fn a_folder_names_its_results_json() {
        let dir = std::env::temp_dir().join(format!("relief-results-file-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let text = serde_json::to_string(&written()).unwrap();
        std::fs::write(dir.join("results.json"), text).unwrap();
        let read = load_results(&dir);
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(read.unwrap().runs.len(), 2);
    }

    #[test]
    fn version_1_and_unknown_versions_are_refused_by_name() {
        let mut value = serde_json::to_value(written()).unwrap();
        let object = value.as_object_mut().unwrap();
        object.remove("schema_version");
        let err = parse_results(&value.to_string(), Path::new("old.json")).unwrap_err();
        assert_eq!(err.found_version(), Some(1));
        let text = err.to_string();
        assert!(
            text.contains("old.json") && text.contains("version 1"),
            "{text}"
        );
        assert!(
            text.contains("predates") && text.contains("reads version 2"),
            "{text}"
        );

        value["schema_version"] = 3.into();
        let err = parse_results(&value.to_string(), Path::new("new.json")).unwrap_err();
        assert_eq!(err.found_version(), Some(3));
        assert!(err.to_string().contains("version 3"), "{err}");
        assert!(err.to_string().contains("reads version 2"), "{err}");
    }

    #[test]
    fn other_json_is_refused_with_the_file_named() {
        for text in ["[]", "{}", "not json", r#"{"schema_version": 2}"#] {
            let err = parse_results(text, Path::new("x.json")).unwrap_err();
            assert!(
                matches!(err, ResultsFileError::Malformed { .. }),
                "{text}: {err}"
            );
            assert!(err.to_string().contains("x.json"), "{err}");
        }
        let missing = load_results(Path::new("/nonexistent/results.json")).unwrap_err();
        assert!(missing.to_string().contains("/nonexistent/results.json"));
    }
}

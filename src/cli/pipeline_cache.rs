//! Where `relief render` and `relief view` keep compiled pipelines between runs, and reading and writing that file.
//! This is policy, so it lives in the CLI; `relief::vk` checks the bytes (header, device, driver
//! build) before Vulkan sees them, so whatever is in the file can at worst cost a warning.
//!
//! Flow: `load(path)` -> `ContextOptions::pipeline_cache` (or `Context::merge_pipeline_cache`
//! once the device, and so `default_path`, is known) -> render -> `save(path,
//! &ctx.pipeline_cache_data()?)`.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::Args;
use relief::vk::{Context, DeviceInfo};

/// The pipeline cache flags of `relief render` and `relief view`.
#[derive(Args)]
pub struct CacheArgs {
    /// Where compiled pipelines are kept between runs (default: relief/pipelines-VENDOR-DEVICE.bin
    /// under $XDG_CACHE_HOME or ~/.cache).
    #[arg(long, value_name = "PATH")]
    pipeline_cache: Option<PathBuf>,
    /// Neither read nor write a pipeline cache file.
    #[arg(long, conflicts_with = "pipeline_cache")]
    no_pipeline_cache: bool,
}

impl CacheArgs {
    /// The pipeline cache file this run reads and writes, if any.
    pub fn file(&self, ctx: &Context) -> Option<PathBuf> {
        if self.no_pipeline_cache {
            return None;
        }
        self.pipeline_cache
            .clone()
            .or_else(|| default_path(ctx.info()))
    }
}

/// Merges the cache file into the context's pipeline cache; whether it was used. A missing file
/// is a first run; an unreadable, corrupt or foreign one is ignored with a warning.
pub fn seed(ctx: &Context, path: Option<&Path>) -> bool {
    let Some(bytes) = path.and_then(load) else {
        return false;
    };
    match ctx.merge_pipeline_cache(&bytes) {
        Ok(seeded) => seeded,
        Err(e) => {
            log::warn!("ignoring the pipeline cache: {e}");
            false
        }
    }
}

/// Writes the pipeline cache back; a failure costs the next run its head start, not this one.
pub fn persist(ctx: &Context, path: &Path) {
    let saved = ctx
        .pipeline_cache_data()
        .map_err(anyhow::Error::from)
        .and_then(|bytes| save(path, &bytes));
    if let Err(e) = saved {
        log::warn!(
            "could not save the pipeline cache to {}: {e:#}",
            path.display()
        );
    }
}

/// The cache file for `info`'s device: `$XDG_CACHE_HOME/relief/pipelines-<vendor>-<device>.bin`,
/// else `~/.cache/relief/...`; `None` when neither variable is set.
pub fn default_path(info: &DeviceInfo) -> Option<PathBuf> {
    default_path_from(
        std::env::var_os("XDG_CACHE_HOME"),
        std::env::var_os("HOME"),
        info,
    )
}

/// [`default_path`] for given values of `XDG_CACHE_HOME` and `HOME` (empty counts as unset, and
/// a relative `XDG_CACHE_HOME` is ignored, as the XDG spec says).
pub fn default_path_from(
    xdg_cache_home: Option<OsString>,
    home: Option<OsString>,
    info: &DeviceInfo,
) -> Option<PathBuf> {
    let xdg = xdg_cache_home
        .map(PathBuf::from)
        .filter(|p| p.is_absolute());
    let home = home
        .filter(|h| !h.is_empty())
        .map(|h| Path::new(&h).join(".cache"));
    let base = xdg.or(home)?;
    let file = format!(
        "pipelines-{:04x}-{:04x}.bin",
        info.vendor_id, info.device_id
    );
    Some(base.join("relief").join(file))
}

/// The bytes of the cache file at `path`, or `None` when there is none yet (silently) or it cannot
/// be read (with a warning): a missing or unreadable cache only makes the run slower.
pub fn load(path: &Path) -> Option<Vec<u8>> {
    match std::fs::read(path) {
        Ok(bytes) => Some(bytes),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            log::debug!("no pipeline cache at {} yet", path.display());
            None
        }
        Err(e) => {
            log::warn!(
                "cannot read the pipeline cache {}: {e}; compiling pipelines afresh",
                path.display()
            );
            None
        }
    }
}

/// Writes `bytes` to `path` atomically (a temporary file in the same folder, then a rename), so
/// a crash or a concurrent run never leaves a half-written cache; creates the folder.
pub fn save(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating the pipeline cache folder {}", dir.display()))?;
    let mut temp = path.as_os_str().to_owned();
    temp.push(format!(".tmp{}", std::process::id()));
    let temp = PathBuf::from(temp);
    let written = std::fs::write(&temp, bytes)
        .with_context(|| format!("writing the pipeline cache {}", temp.display()))
        .and_then(|()| {
            std::fs::rename(&temp, path)
                .with_context(|| format!("replacing the pipeline cache {}", path.display()))
        });
    if written.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info() -> DeviceInfo {
        DeviceInfo {
            pipeline_statistics: true,
            fragment_stores: true,
            calibrated_timestamps: false,
            device_uuid: String::new(),
            driver_uuid: String::new(),
            name: "test".into(),
            driver: String::new(),
            api: "1.3.0".into(),
            kind: "cpu",
            max_image_dimension_2d: 4096,
            max_storage_buffer_range: u32::MAX,
            timestamp_period_ns: 1.0,
            timestamp_valid_bits: 64,
            queue_family: 0,
            storage_r16: true,
            subgroup_size: 8,
            vendor_id: 0x10005,
            device_id: 0,
            pipeline_cache_uuid: [0; 16],
            max_samples: 1,
            ray_query: false,
            acceleration_structure: false,
            known_frame_leak: None,
        }
    }

    fn scratch(test: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("relief-cli-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn default_path_prefers_xdg_cache_home() {
        let p = default_path_from(Some("/x/cache".into()), Some("/home/u".into()), &info());
        assert_eq!(
            p,
            Some(PathBuf::from("/x/cache/relief/pipelines-10005-0000.bin"))
        );
    }

    #[test]
    fn default_path_falls_back_to_home_cache() {
        for xdg in [None, Some("".into()), Some("relative".into())] {
            let p = default_path_from(xdg, Some("/home/u".into()), &info());
            assert_eq!(
                p,
                Some(PathBuf::from(
                    "/home/u/.cache/relief/pipelines-10005-0000.bin"
                ))
            );
        }
        assert_eq!(default_path_from(None, None, &info()), None);
    }

    #[test]
    fn save_then_load_round_trips_and_replaces() {
        let path = scratch("round-trip").join("nested").join("cache.bin");
        save(&path, b"first").expect("save");
        save(&path, b"second").expect("save over");
        assert_eq!(load(&path).as_deref(), Some(&b"second"[..]));
        let leftovers: Vec<_> = std::fs::read_dir(path.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(leftovers, ["cache.bin"], "no temporary file is left behind");
    }

    #[test]
    fn missing_or_unreadable_files_load_as_none() {
        let dir = scratch("missing");
        assert_eq!(load(&dir.join("nothing.bin")), None);
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(load(&dir), None, "a folder is not a cache file");
    }
}

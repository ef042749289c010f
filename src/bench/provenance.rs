//! Where and how a `results.json` was measured: the device, the relief build, and the sweep's
//! effective options. `relief bench compare` reads these to tell runs of one device from runs of
//! several, and to show what differed between two runs.

use serde::{Deserialize, Serialize};

use super::sweep::{FieldSource, SweepConfig};
use crate::render::HeightFormat;
use crate::vk::DeviceInfo;

/// The device every number was measured on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BenchDevice {
    /// The device name the driver reports.
    pub name: String,
    /// Driver name and version, trimmed.
    pub driver: String,
    /// The Vulkan API version the device reports, "major.minor.patch".
    pub api: String,
    /// "discrete", "integrated", "virtual", "cpu" or "other".
    pub kind: String,
    /// PCI vendor id (`vendorID`).
    pub vendor_id: u32,
    /// Vendor-specific device id (`deviceID`).
    pub device_id: u32,
    /// Nanoseconds per timestamp tick (`timestampPeriod`).
    pub timestamp_period: f32,
    /// Whether the device traces ray queries (`VK_KHR_ray_query`); false in files written before
    /// relief recorded it.
    #[serde(default)]
    pub ray_query: bool,
    /// Whether the device builds acceleration structures (`VK_KHR_acceleration_structure`).
    #[serde(default)]
    pub acceleration_structure: bool,
    /// `deviceUUID` in hex; empty in files written before relief recorded it.
    #[serde(default)]
    pub device_uuid: String,
    /// `driverUUID` in hex (changes with the driver build); empty in older files.
    #[serde(default)]
    pub driver_uuid: String,
}

impl BenchDevice {
    /// Whether two files were measured on the same device and driver: their times compare
    /// directly only then.
    pub fn same_as(&self, other: &BenchDevice) -> bool {
        (&self.name, &self.driver, self.vendor_id, self.device_id)
            == (&other.name, &other.driver, other.vendor_id, other.device_id)
    }
}

impl From<&DeviceInfo> for BenchDevice {
    fn from(i: &DeviceInfo) -> Self {
        BenchDevice {
            name: i.name.clone(),
            driver: i.driver.trim().to_owned(),
            api: i.api.clone(),
            kind: i.kind.to_owned(),
            vendor_id: i.vendor_id,
            device_id: i.device_id,
            timestamp_period: i.timestamp_period_ns,
            ray_query: i.ray_query,
            acceleration_structure: i.acceleration_structure,
            device_uuid: i.device_uuid.clone(),
            driver_uuid: i.driver_uuid.clone(),
        }
    }
}

/// The relief that wrote a file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReliefBuild {
    /// The crate version (`CARGO_PKG_VERSION`).
    pub version: String,
    /// The git commit it was built from, or "unknown" when built outside a git checkout.
    pub commit: String,
    /// Whether tracked files differed from that commit when it was built.
    pub dirty: bool,
}

impl ReliefBuild {
    /// This build, as `build.rs` saw its checkout.
    pub fn current() -> ReliefBuild {
        ReliefBuild {
            version: env!("CARGO_PKG_VERSION").to_owned(),
            commit: env!("RELIEF_GIT_COMMIT").to_owned(),
            dirty: env!("RELIEF_GIT_DIRTY") == "true",
        }
    }
}

/// [`SweepConfig`] as `results.json` stores it: names instead of types, so the file reads the
/// same whatever relief's types become.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepOptions {
    /// Method ids.
    pub methods: Vec<String>,
    /// Synthetic fields by generator name, height maps by their path.
    pub fields: Vec<String>,
    /// Map sides, in texels; the first is every section's but scaling.
    pub sizes: Vec<u32>,
    /// View elevations, in degrees.
    pub angles: Vec<f64>,
    /// View azimuths, in degrees.
    pub azimuths: Vec<f64>,
    /// Depth scales, in uv units; the first is every section's but the depth-scale one.
    pub depth_scales: Vec<f64>,
    /// Iteration caps tried on fixed-step methods besides their defaults.
    pub budgets: Vec<u32>,
    /// Rays per timed frame, `[width, height]`.
    pub resolution: [u32; 2],
    /// Timed frames per configuration.
    pub frames: u32,
    /// Untimed frames before them, in every pass.
    pub warmup: u32,
    /// Passes over the sweep's runs that share each configuration's frames. Read as 1 in files
    /// written before interleaved passes existed.
    #[serde(default = "one_pass")]
    pub passes: u32,
    /// Rays per configuration for the error measurement, `[width, height]`.
    pub error_grid: [u32; 2],
    /// "repeat" or "clamp".
    pub address: String,
    /// "r16_unorm" or "r32_float".
    pub format: HeightFormat,
    /// Seed of the synthetic generators.
    pub seed: u64,
    /// Whether the stability matrix was asked for.
    pub stability: bool,
    /// Whether methods with a leaf choice also ran with the paper's refinement.
    pub paper_leaf: bool,
    /// Whether this was the `--quick` sweep.
    pub quick: bool,
    /// Methods slowed on purpose, `METHOD=FACTOR` (`--slow-down`): their times are not
    /// measurements. Absent in files written before the option existed.
    #[serde(default)]
    pub slow_down: Vec<String>,
}

impl From<&SweepConfig> for SweepOptions {
    fn from(c: &SweepConfig) -> Self {
        SweepOptions {
            methods: c.methods.iter().map(|m| m.id().to_owned()).collect(),
            fields: c
                .fields
                .iter()
                .map(|f| match f {
                    FieldSource::Synthetic(g) => g.name().to_owned(),
                    FieldSource::File(p) => p.display().to_string(),
                })
                .collect(),
            sizes: c.sizes.clone(),
            angles: c.angles.clone(),
            azimuths: c.azimuths.clone(),
            depth_scales: c.depth_scales.clone(),
            budgets: c.budgets.clone(),
            resolution: [c.resolution.0, c.resolution.1],
            frames: c.frames,
            warmup: c.warmup,
            passes: c.effective_passes(),
            error_grid: [c.error_grid.0, c.error_grid.1],
            address: c.address.to_string(),
            format: c.format,
            seed: c.seed,
            stability: c.stability,
            paper_leaf: c.paper_leaf,
            quick: c.quick,
            slow_down: c.slow_down.iter().map(ToString::to_string).collect(),
        }
    }
}

fn one_pass() -> u32 {
    1
}

/// Now, UTC, RFC 3339 to the second.
pub fn utc_now_rfc3339() -> String {
    humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_build_names_a_version_and_a_commit_or_unknown() {
        let build = ReliefBuild::current();
        assert_eq!(build.version, env!("CARGO_PKG_VERSION"));
        let hex = build.commit.len() == 40 && build.commit.chars().all(|c| c.is_ascii_hexdigit());
        assert!(hex || build.commit == "unknown", "{}", build.commit);
    }

    #[test]
    fn dates_are_utc_rfc3339() {
        let date = utc_now_rfc3339();
        assert!(humantime::parse_rfc3339(&date).is_ok(), "{date}");
        assert!(date.ends_with('Z') && date.len() == 20, "{date}");
    }
}

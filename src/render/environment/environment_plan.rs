//! What a frame builds for its ambient light, chosen before anything is built.

use serde::Serialize;

use crate::environment::Environment;

/// Width and height of the irradiance map: the cosine lobe is smooth, so a few degrees a texel
/// is plenty.
pub const IRRADIANCE_SIZE: [u32; 2] = [32, 16];
/// Width and height of the prefiltered specular map's finest level (roughness 0).
pub const SPECULAR_SIZE: [u32; 2] = [128, 64];
/// Levels of the prefiltered map: roughness 0, 0.2, ... 1, one per level.
pub const SPECULAR_LEVELS: u32 = 6;
/// Width (view cosines) and height (roughnesses) of the BRDF table.
pub const BRDF_SIZE: [u32; 2] = [32, 32];
/// GGX samples per texel of the prefiltered levels.
pub const PREFILTER_SAMPLES: u32 = 256;
/// GGX samples per texel of the BRDF table.
pub const BRDF_SAMPLES: u32 = 2048;
/// The widest source level uploaded: the maps read nothing finer (the finest prefiltered level
/// is 128 wide), so larger images are box-filtered down on the CPU first.
pub const MAX_SOURCE_WIDTH: u32 = 1024;
/// The widest source level the irradiance kernel sums texel by texel.
pub const IRRADIANCE_SOURCE_WIDTH: u32 = 64;

/// The environment maps a frame builds, for the plan and `--explain`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnvironmentPlan {
    /// The environment's name (a file name, "built-in sky").
    pub name: String,
    /// Its size as read, and as uploaded.
    pub source_size: [u32; 2],
    /// The uploaded level 0's size.
    pub uploaded_size: [u32; 2],
    /// The irradiance map's size.
    pub irradiance_size: [u32; 2],
    /// The prefiltered map's finest size and its levels.
    pub specular_size: [u32; 2],
    /// Levels of the prefiltered map, roughness 0 to 1.
    pub specular_levels: u32,
    /// The BRDF table's size.
    pub brdf_size: [u32; 2],
    /// The environment is drawn behind the scene (its uploaded image kept for it).
    pub background: bool,
}

impl EnvironmentPlan {
    /// The maps built for `env`.
    pub fn of(env: &Environment) -> EnvironmentPlan {
        let mut uploaded = [env.width, env.height];
        while uploaded[0] > MAX_SOURCE_WIDTH {
            uploaded = [(uploaded[0] / 2).max(1), (uploaded[1] / 2).max(1)];
        }
        EnvironmentPlan {
            name: env.name.clone(),
            source_size: [env.width, env.height],
            uploaded_size: uploaded,
            irradiance_size: IRRADIANCE_SIZE,
            specular_size: SPECULAR_SIZE,
            specular_levels: SPECULAR_LEVELS,
            brdf_size: BRDF_SIZE,
            background: false,
        }
    }
}

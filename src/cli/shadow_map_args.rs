//! The render flags of the lights' shadow maps: on or off, size, cascades and filter. Size and
//! cascades override what each light's extras say, as the shading flags do for materials.

use clap::{Args, ValueEnum};
use relief::render::{ShadowFilter, ShadowOptions};
use relief::scene::{LightKind, Scene, SHADOW_CASCADES, SHADOW_MAP_SIZES};

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum OnOff {
    On,
    Off,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FilterArg {
    Hard,
    Pcf,
    Pcss,
}

#[derive(Args)]
pub struct ShadowMapArgs {
    /// Shadow maps for the shadow-casting lights (objects shadowing objects); `off` leaves only
    /// each relief material's own self-shadows.
    #[arg(long, value_enum, value_name = "on|off", default_value = "on")]
    shadow_maps: OnOff,
    /// Texels per side of each shadow map (each cascade, each cube face), 16..=8192 (default:
    /// each light's extras.relief.shadow_map_size, else 1024).
    #[arg(long, value_name = "N")]
    shadow_map_size: Option<u32>,
    /// Cascades of a directional light's shadow map, 1..=4 (default: each light's
    /// extras.relief.shadow_cascades, else 1).
    #[arg(long, value_name = "N")]
    shadow_cascades: Option<u32>,
    /// Shadow-map filter: hard (one texel), pcf (fixed 1.5-texel footprint) or pcss (penumbra
    /// from the light's size) (default: pcss for a light with a size, hard for one without).
    #[arg(long, value_enum, value_name = "FILTER")]
    shadow_filter: Option<FilterArg>,
}

impl ShadowMapArgs {
    /// Checks the flags and applies size and cascades to `scene`'s lights.
    pub fn apply(&self, scene: &mut Scene) -> anyhow::Result<()> {
        if let Some(n) = self
            .shadow_map_size
            .filter(|n| !SHADOW_MAP_SIZES.contains(n))
        {
            return Err(super::usage(format!(
                "--shadow-map-size must be in {}..={}, got {n}",
                SHADOW_MAP_SIZES.start(),
                SHADOW_MAP_SIZES.end()
            )));
        }
        if let Some(n) = self
            .shadow_cascades
            .filter(|n| !SHADOW_CASCADES.contains(n))
        {
            return Err(super::usage(format!(
                "--shadow-cascades must be in {}..={}, got {n}",
                SHADOW_CASCADES.start(),
                SHADOW_CASCADES.end()
            )));
        }
        for light in &mut scene.lights {
            if let Some(n) = self.shadow_map_size {
                light.shadow_map_size = Some(n);
            }
            if let (Some(n), LightKind::Directional) = (self.shadow_cascades, light.kind) {
                light.shadow_cascades = Some(n);
            }
        }
        Ok(())
    }

    /// The renderer's shadow options (the defaults for lights the scene adds itself).
    pub fn options(&self) -> ShadowOptions {
        let defaults = ShadowOptions::DEFAULT;
        ShadowOptions::default()
            .with_enabled(matches!(self.shadow_maps, OnOff::On))
            .with_map_size(self.shadow_map_size.unwrap_or(defaults.map_size))
            .with_cascades(self.shadow_cascades.unwrap_or(defaults.cascades))
            .with_filter(self.shadow_filter.map(|f| match f {
                FilterArg::Hard => ShadowFilter::Hard,
                FilterArg::Pcf => ShadowFilter::Pcf,
                FilterArg::Pcss => ShadowFilter::Pcss,
            }))
    }
}

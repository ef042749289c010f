//! How a relief material is shaded beyond its hit: the self-shadow mode toward each light, the
//! ambient occlusion mode, and level of detail. Plain data with stable ids (`extras.relief`,
//! `--shadows`, `--ao`, `--lod`); the renderer turns them into pipeline variants and maps.

use std::fmt;
use std::str::FromStr;

/// How a relief surface is shadowed by its own height field, per light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ShadowMode {
    /// No self-shadowing.
    None,
    /// One ray toward the light's centre, traced by the material's method: lit or not.
    #[default]
    Hard,
    /// Tatarchuk 2006: linear samples along the light ray, penumbra from the blocker/receiver ratio.
    PomSoft,
    /// Paper 001 Listing 1.4: a few distance-weighted samples from coarser pyramid levels.
    Horizon,
    /// The light's cone traced through the max pyramid; visible fraction from the tightest
    /// clearance/distance ratio against the light's angular size.
    Cone,
}

impl ShadowMode {
    /// Every mode, in the order reports list them.
    pub const ALL: [ShadowMode; 5] = [
        ShadowMode::None,
        ShadowMode::Hard,
        ShadowMode::PomSoft,
        ShadowMode::Horizon,
        ShadowMode::Cone,
    ];

    /// The stable id.
    pub fn id(self) -> &'static str {
        match self {
            ShadowMode::None => "none",
            ShadowMode::Hard => "hard",
            ShadowMode::PomSoft => "pom-soft",
            ShadowMode::Horizon => "horizon",
            ShadowMode::Cone => "cone",
        }
    }

    /// Whether the mode shades at all.
    pub fn is_some(self) -> bool {
        self != ShadowMode::None
    }

    /// Whether it reads the max pyramid (the height map then gets one even when the method does
    /// not read it).
    pub fn reads_pyramid(self) -> bool {
        matches!(self, ShadowMode::Horizon | ShadowMode::Cone)
    }

    /// Its default `SHADOW_STEPS`: samples along the light (pom-soft, horizon; Drobot uses 5
    /// horizon samples) or the cap on the pyramid walk (cone); unused by `none` and `hard`.
    pub fn default_steps(self) -> u32 {
        match self {
            ShadowMode::None | ShadowMode::Hard => 1,
            ShadowMode::PomSoft => 16,
            ShadowMode::Horizon => 5,
            ShadowMode::Cone => 128,
        }
    }
}

impl fmt::Display for ShadowMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.id())
    }
}

impl FromStr for ShadowMode {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ShadowMode::ALL
            .into_iter()
            .find(|m| m.id() == s)
            .ok_or_else(|| {
                let ids: Vec<&str> = ShadowMode::ALL.iter().map(|m| m.id()).collect();
                format!("unknown shadow mode {s:?}; known modes: {}", ids.join(", "))
            })
    }
}

/// A material's shadow mode with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowSettings {
    /// How shadow rays are traced.
    pub mode: ShadowMode,
    /// Samples (pom-soft, horizon; Drobot's iteration count) or the pyramid walk's cap
    /// (cone); `None` takes [`ShadowMode::default_steps`].
    pub steps: Option<u32>,
    /// Horizon mode: how far its samples reach, as a multiple of the distance at which the
    /// light's lowest direction clears the top plane (Drobot's light vector scale); finite, > 0.
    pub horizon_reach: f32,
}

impl ShadowSettings {
    /// `mode` with its default parameters.
    pub fn new(mode: ShadowMode) -> ShadowSettings {
        ShadowSettings {
            mode,
            steps: None,
            horizon_reach: 1.0,
        }
    }

    /// The `SHADOW_STEPS` the pipeline is built with.
    pub fn resolved_steps(&self) -> u32 {
        self.steps.unwrap_or(self.mode.default_steps())
    }
}

// `horizon_reach` is finite wherever settings are made (extras and flags check it), so equality
// is an equivalence and pipelines can be told apart by their settings.
impl Eq for ShadowSettings {}

impl Default for ShadowSettings {
    fn default() -> Self {
        ShadowSettings::new(ShadowMode::default())
    }
}

/// Ambient occlusion of a relief material: a texture-space map built once per static field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum AoMode {
    /// No ambient occlusion from the height field.
    #[default]
    None,
    /// Paper 001: horizon queries on the max pyramid in `directions` (4, 8 or 16) evenly spaced
    /// azimuths, rotated by a per-texel hash when `rotated`.
    Horizon {
        /// Azimuths queried per texel (4, 8 or 16).
        directions: u32,
        /// Whether a per-texel hash rotates the azimuths.
        rotated: bool,
    },
    /// The exact horizon per direction by a line sweep over the field (Timonen and Westerholm 2010).
    ExactHorizon,
}

/// The direction counts `horizon-N` accepts.
pub const AO_HORIZON_DIRECTIONS: [u32; 3] = [4, 8, 16];

impl AoMode {
    /// Every mode, in the order reports list them.
    pub fn all() -> Vec<AoMode> {
        let mut all = vec![AoMode::None];
        for rotated in [false, true] {
            for directions in AO_HORIZON_DIRECTIONS {
                all.push(AoMode::Horizon {
                    directions,
                    rotated,
                });
            }
        }
        all.push(AoMode::ExactHorizon);
        all
    }

    /// Whether the mode builds an AO map.
    pub fn is_some(self) -> bool {
        self != AoMode::None
    }
}

impl fmt::Display for AoMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AoMode::None => f.write_str("none"),
            AoMode::Horizon {
                directions,
                rotated,
            } => {
                write!(f, "horizon-{directions}")?;
                if *rotated {
                    f.write_str("-rotated")?;
                }
                Ok(())
            }
            AoMode::ExactHorizon => f.write_str("exact-horizon"),
        }
    }
}

impl FromStr for AoMode {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        AoMode::all()
            .into_iter()
            .find(|m| m.to_string() == s)
            .ok_or_else(|| {
                let ids: Vec<String> = AoMode::all().iter().map(|m| m.to_string()).collect();
                format!("unknown AO mode {s:?}; known modes: {}", ids.join(", "))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_round_trip() {
        for m in ShadowMode::ALL {
            assert_eq!(m.id().parse::<ShadowMode>(), Ok(m));
        }
        for m in AoMode::all() {
            assert_eq!(m.to_string().parse::<AoMode>(), Ok(m));
        }
        assert_eq!(
            "horizon-8".parse::<AoMode>(),
            Ok(AoMode::Horizon {
                directions: 8,
                rotated: false
            })
        );
    }

    #[test]
    fn unknown_ids_list_the_known_ones() {
        let e = "soft".parse::<ShadowMode>().unwrap_err();
        assert!(e.contains("pom-soft") && e.contains("cone"), "{e}");
        let e = "horizon-5".parse::<AoMode>().unwrap_err();
        assert!(
            e.contains("horizon-16") && e.contains("exact-horizon"),
            "{e}"
        );
    }
}

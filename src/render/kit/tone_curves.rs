//! The tone curves, defined on the CPU: exposure, then none (clamped), Khronos PBR Neutral or
//! ACES. `shaders/include/tone_curves.glsl` applies the same curves in the tone-mapping pass,
//! and the tests compare the two; `relief render --bit-depth 16` applies them here.

use std::fmt;
use std::str::FromStr;

use serde::Serialize;

use crate::render::shader_interface::{TONE_CURVE_ACES, TONE_CURVE_NONE, TONE_CURVE_PBR_NEUTRAL};

/// The largest finite half float: the radiance target holds nothing brighter.
const HALF_MAX: f32 = 65504.0;

/// How linear radiance becomes a displayable value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ToneMap {
    /// Clamped to [0, 1]: what relief drew before tone mapping, and what timing runs use.
    #[default]
    None,
    /// Khronos PBR Neutral: base colours under direct light up to about 0.76 pass unchanged,
    /// highlights roll off toward white keeping their hue.
    PbrNeutral,
    /// ACES filmic (Narkowicz's fit): more contrast, shifts hues.
    Aces,
}

impl ToneMap {
    /// The curve's value in the shaders' `curve` field.
    pub(in crate::render) fn shader_value(self) -> u32 {
        match self {
            ToneMap::None => TONE_CURVE_NONE,
            ToneMap::PbrNeutral => TONE_CURVE_PBR_NEUTRAL,
            ToneMap::Aces => TONE_CURVE_ACES,
        }
    }

    /// The curve applied to linear `rgb` (already scaled by the exposure).
    pub fn apply(self, rgb: [f32; 3]) -> [f32; 3] {
        // As the pass reads a half-float target: nothing beyond its largest finite value.
        let rgb = rgb.map(|c| {
            if c.is_nan() {
                0.0
            } else {
                c.clamp(0.0, HALF_MAX)
            }
        });
        let out = match self {
            ToneMap::None => rgb,
            ToneMap::PbrNeutral => pbr_neutral(rgb),
            ToneMap::Aces => rgb.map(|c| (c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14)),
        };
        out.map(|c| c.clamp(0.0, 1.0))
    }
}

fn pbr_neutral(mut c: [f32; 3]) -> [f32; 3] {
    const START: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let low = c[0].min(c[1]).min(c[2]);
    let offset = if low < 0.08 {
        low - 6.25 * low * low
    } else {
        0.04
    };
    c = c.map(|x| x - offset);
    let peak = c[0].max(c[1]).max(c[2]);
    if peak < START {
        return c;
    }
    let d = 1.0 - START;
    let mapped = 1.0 - d * d / (peak + d - START);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - mapped) + 1.0);
    c.map(|x| {
        let scaled = x * mapped / peak;
        scaled + (mapped - scaled) * g
    })
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ToneMap::None => "none",
            ToneMap::PbrNeutral => "pbr-neutral",
            ToneMap::Aces => "aces",
        })
    }
}

impl FromStr for ToneMap {
    type Err = String;

    fn from_str(s: &str) -> Result<ToneMap, String> {
        match s {
            "none" => Ok(ToneMap::None),
            "pbr-neutral" => Ok(ToneMap::PbrNeutral),
            "aces" => Ok(ToneMap::Aces),
            _ => Err(format!(
                "unknown tone map {s:?}: use pbr-neutral, aces or none"
            )),
        }
    }
}

/// The frame's tone mapping, for the plan and `--explain`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ToneMapping {
    /// The curve.
    pub curve: ToneMap,
    /// Exposure in stops: radiance is scaled by 2^EV before the curve.
    pub exposure_ev: f32,
}

impl ToneMapping {
    /// No curve, no exposure change: radiance clamped, as before tone mapping.
    pub const NONE: ToneMapping = ToneMapping {
        curve: ToneMap::None,
        exposure_ev: 0.0,
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pbr_neutral_keeps_mid_tones_and_rolls_highlights_off() {
        // Above the toe and below the compression start: only the fixed 0.04 offset.
        let mid = ToneMap::PbrNeutral.apply([0.5, 0.3, 0.2]);
        for (out, x) in mid.iter().zip([0.46, 0.26, 0.16]) {
            assert!((out - x).abs() < 1e-6, "{mid:?}");
        }
        // Black stays black; the toe is continuous where it meets the offset.
        assert_eq!(ToneMap::PbrNeutral.apply([0.0; 3]), [0.0; 3]);
        let toe = 0.08f32 - 6.25 * 0.08 * 0.08;
        assert!((toe - 0.04).abs() < 1e-6);
        // Highlights: monotonic, below 1, and hue toward white as they grow.
        let mut last = 0.0;
        for x in [0.8f32, 1.0, 2.0, 10.0, 1e4] {
            let y = ToneMap::PbrNeutral.apply([x, x * 0.5, x * 0.25]);
            assert!(y[0] > last && y[0] <= 1.0, "{x}: {y:?}");
            last = y[0];
        }
        let sun = ToneMap::PbrNeutral.apply([1e4, 5e3, 2.5e3]);
        assert!(sun.iter().all(|c| c.is_finite() && *c > 0.99), "{sun:?}");
    }

    #[test]
    fn aces_and_none_are_bounded_and_nan_free() {
        for curve in [ToneMap::None, ToneMap::Aces, ToneMap::PbrNeutral] {
            for x in [f32::NAN, -1.0, 0.0, 0.18, 1.0, 1e4, f32::INFINITY] {
                let y = curve.apply([x; 3]);
                assert!(
                    y.iter().all(|c| (0.0..=1.0).contains(c)),
                    "{curve} {x}: {y:?}"
                );
            }
        }
        assert_eq!("pbr-neutral".parse::<ToneMap>(), Ok(ToneMap::PbrNeutral));
        assert!("filmic"
            .parse::<ToneMap>()
            .unwrap_err()
            .contains("pbr-neutral"));
    }
}

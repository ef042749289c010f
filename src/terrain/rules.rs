//! Layer weights generated from a terrain's elevation by rules, as terrain tools paint a first
//! splat map: each layer covers a band of altitude and a band of slope, with soft edges, and the
//! weights at a texel are the layers' coverages normalised to sum 1 (the last layer takes a
//! texel no rule covers).

use super::layers::{LayerError, SplatMap, MAX_LAYERS};
use crate::heightfield::Heightfield;

/// Where a layer lies: a band of elevation (0..1 of the map's range) and of slope (degrees), each
/// with a soft edge of `softness` of its unit on both sides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayerRule {
    pub altitude: (f32, f32),
    pub slope_deg: (f32, f32),
    /// Width of the fade at each band edge: altitude units, and ten times that in degrees.
    pub softness: f32,
}

impl LayerRule {
    /// The built-in four: sand low and flat, grass above it, rock on slopes, cliff on the
    /// steepest ground and the tops.
    pub const GROUND: [LayerRule; 4] = [
        LayerRule {
            altitude: (0.0, 0.18),
            slope_deg: (0.0, 22.0),
            softness: 0.05,
        },
        LayerRule {
            altitude: (0.12, 0.75),
            slope_deg: (0.0, 28.0),
            softness: 0.06,
        },
        LayerRule {
            altitude: (0.0, 1.0),
            slope_deg: (24.0, 42.0),
            softness: 0.06,
        },
        LayerRule {
            altitude: (0.0, 1.0),
            slope_deg: (38.0, 90.0),
            softness: 0.06,
        },
    ];

    fn coverage(&self, altitude: f32, slope_deg: f32) -> f32 {
        band(altitude, self.altitude, self.softness)
            * band(slope_deg, self.slope_deg, self.softness * 10.0)
    }
}

/// 1 inside `lo..=hi`, fading linearly to 0 over `soft` outside it.
fn band(x: f32, (lo, hi): (f32, f32), soft: f32) -> f32 {
    let soft = soft.max(1e-6);
    let below = ((x - lo) / soft + 1.0).clamp(0.0, 1.0);
    let above = ((hi - x) / soft + 1.0).clamp(0.0, 1.0);
    below.min(above)
}

/// A `size` x `size` splat map of `rules` (one per layer) over `elevation`, whose texels are
/// `texel_world` apart and whose elevation 1 stands `height_world` above 0 (for slopes).
pub fn splat_from_rules(
    elevation: &Heightfield,
    rules: &[LayerRule],
    texel_world: f32,
    height_world: f32,
    size: u32,
) -> Result<SplatMap, LayerError> {
    if rules.is_empty() || rules.len() > MAX_LAYERS {
        return Err(LayerError::Count { count: rules.len() });
    }
    let (lo, hi) = elevation
        .data()
        .iter()
        .fold((f32::MAX, f32::MIN), |(a, b), &h| (a.min(h), b.max(h)));
    let range = (hi - lo).max(f32::EPSILON);
    let (w, h) = (elevation.width(), elevation.height());
    let at = |i: i64, j: i64| {
        elevation.get(
            i.clamp(0, i64::from(w) - 1) as u32,
            j.clamp(0, i64::from(h) - 1) as u32,
        )
    };
    let texels = (0..size * size)
        .map(|t| {
            let (x, y) = (t % size, t / size);
            // The elevation texel under this splat texel's centre.
            let i = ((f64::from(x) + 0.5) / f64::from(size) * f64::from(w)) as i64;
            let j = ((f64::from(y) + 0.5) / f64::from(size) * f64::from(h)) as i64;
            let altitude = (at(i, j) - lo) / range;
            let dx = (at(i + 1, j) - at(i - 1, j)) * height_world / (2.0 * texel_world);
            let dz = (at(i, j + 1) - at(i, j - 1)) * height_world / (2.0 * texel_world);
            let slope = dx.hypot(dz).atan().to_degrees();
            let mut weights = [0.0f32; 4];
            for (k, rule) in rules.iter().enumerate() {
                weights[k] = rule.coverage(altitude, slope);
            }
            let sum: f32 = weights.iter().sum();
            if sum > 0.0 {
                weights.map(|w| w / sum)
            } else {
                let mut last = [0.0; 4];
                last[rules.len() - 1] = 1.0;
                last
            }
        })
        .collect();
    SplatMap::new(size, size, texels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_low_ground_is_sand_and_steep_ground_is_cliff() {
        // A ramp: flat at 0 on the left half, then rising steeply.
        let data = (0..64 * 64)
            .map(|t| {
                let i = (t % 64) as f32;
                if i < 32.0 {
                    0.0
                } else {
                    (i - 32.0) / 32.0
                }
            })
            .collect();
        let elevation = Heightfield::from_valid(64, 64, data);
        // 1 world unit per texel, 100 units of height: the ramp climbs about 72 degrees.
        let splat = splat_from_rules(&elevation, &LayerRule::GROUND, 1.0, 100.0, 64).unwrap();
        let flat = splat.sample(0.1, 0.5);
        assert!(flat[0] > 0.99, "{flat:?}");
        let steep = splat.sample(0.8, 0.5);
        assert!(steep[3] > 0.99, "{steep:?}");
        for w in [flat, steep] {
            assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn too_many_rules_are_refused() {
        let elevation = Heightfield::from_valid(2, 2, vec![0.0; 4]);
        let rules = [LayerRule::GROUND[0]; 5];
        assert_eq!(
            splat_from_rules(&elevation, &rules, 1.0, 1.0, 4).unwrap_err(),
            LayerError::Count { count: 5 }
        );
    }
}

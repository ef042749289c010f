//! Layer weights generated from a terrain's elevation by rules, as terrain tools paint a first
//! splat map: each layer covers a band of altitude and a band of slope, with soft edges, and the
//! weights at a texel are the layers' coverages normalised to sum 1 (the last layer takes a
//! texel no rule covers).

use super::brush::TexelRect;
use super::layers::{LayerError, SplatMap, MAX_LAYERS};
use crate::heightfield::Heightfield;

/// Where a layer lies: a band of elevation (0..1 of the map's range) and of slope (degrees), each
/// with a soft edge of `softness` of its unit on both sides.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayerRule {
    /// Band of elevation, 0..1 of the map's range.
    pub altitude: (f32, f32),
    /// Band of slope, degrees.
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

/// The rules' weighing of one terrain: its rules, its loaded elevation's range (altitude bands are
/// fractions of it, kept fixed as strokes move the ground, so that a stroke re-weighs only the
/// texels near it), the world size of an elevation texel and of a unit of height, and the side
/// of the splat map it paints.
#[derive(Debug, Clone)]
pub struct RuleWeights {
    rules: Vec<LayerRule>,
    low: f32,
    range: f32,
    texel_world: f32,
    height_world: f32,
    size: u32,
}

impl RuleWeights {
    /// `rules` (1 to 4) over `elevation` as loaded, painting a `size`^2 splat map.
    pub fn new(
        elevation: &Heightfield,
        rules: &[LayerRule],
        texel_world: f32,
        height_world: f32,
        size: u32,
    ) -> Result<RuleWeights, LayerError> {
        if rules.is_empty() || rules.len() > MAX_LAYERS {
            return Err(LayerError::Count { count: rules.len() });
        }
        let (lo, hi) = elevation
            .data()
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), &h| (a.min(h), b.max(h)));
        Ok(RuleWeights {
            rules: rules.to_vec(),
            low: lo,
            range: (hi - lo).max(f32::EPSILON),
            texel_world,
            height_world,
            size,
        })
    }

    /// The elevation texel splat texel `x` of `size` reads along an axis of `n` texels.
    fn elevation_texel(&self, x: u32, n: u32) -> i64 {
        ((f64::from(x) + 0.5) / f64::from(self.size) * f64::from(n)) as i64
    }

    /// The weights of splat texel `(x, y)` over `elevation` (the one the rules were made for, or
    /// it edited): each rule's coverage of the altitude and slope read there, normalised.
    pub fn weights_at(&self, elevation: &Heightfield, x: u32, y: u32) -> [f32; 4] {
        let (w, h) = (elevation.width(), elevation.height());
        let at = |i: i64, j: i64| {
            elevation.get(
                i.clamp(0, i64::from(w) - 1) as u32,
                j.clamp(0, i64::from(h) - 1) as u32,
            )
        };
        let (i, j) = (self.elevation_texel(x, w), self.elevation_texel(y, h));
        let altitude = (at(i, j) - self.low) / self.range;
        let (hw, tw) = (self.height_world, self.texel_world);
        let dx = (at(i + 1, j) - at(i - 1, j)) * hw / (2.0 * tw);
        let dz = (at(i, j + 1) - at(i, j - 1)) * hw / (2.0 * tw);
        let slope = dx.hypot(dz).atan().to_degrees();
        let mut weights = [0.0f32; 4];
        for (k, rule) in self.rules.iter().enumerate() {
            weights[k] = rule.coverage(altitude, slope);
        }
        let sum: f32 = weights.iter().sum();
        if sum > 0.0 {
            weights.map(|w| w / sum)
        } else {
            let mut last = [0.0; 4];
            last[self.rules.len() - 1] = 1.0;
            last
        }
    }

    /// The splat map over `elevation`.
    pub fn splat(&self, elevation: &Heightfield) -> Result<SplatMap, LayerError> {
        let n = self.size;
        let texels = (0..n * n)
            .map(|t| self.weights_at(elevation, t % n, t / n))
            .collect();
        SplatMap::new(n, n, texels)
    }

    /// The splat texels whose weights read elevation texels `rect` of a `width` x `height` map
    /// (each reads its own texel and its four neighbours), `None` when none does.
    pub fn splat_rect_reading(
        &self,
        rect: &TexelRect,
        width: u32,
        height: u32,
    ) -> Option<TexelRect> {
        let span = |a: u32, b: u32, n: u32| {
            let reads = |x: u32| {
                let i = self.elevation_texel(x, n);
                i + 1 >= i64::from(a) && i - 1 <= i64::from(b)
            };
            let first = (0..self.size).find(|&x| reads(x))?;
            let last = (0..self.size).rev().find(|&x| reads(x))?;
            Some((first, last))
        };
        let (x0, x1) = span(rect.x0, rect.x1, width)?;
        let (y0, y1) = span(rect.y0, rect.y1, height)?;
        Some(TexelRect { x0, y0, x1, y1 })
    }
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
    RuleWeights::new(elevation, rules, texel_world, height_world, size)?.splat(elevation)
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

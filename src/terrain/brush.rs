//! Brush strokes on a terrain: raise, lower, flatten and crater on its elevation, paint on a
//! layer's weight in its splat map; each a disk of a radius in texels with a smooth falloff, and
//! the texels each stroke and each pyramid level above it touch, so that an edit rebuilds only
//! those (`relief render --edits`, the GPU's `brush.comp`). The formulas here are the shader's,
//! so the CPU can check it.

use serde::Deserialize;

/// What a stroke does to the elevation under it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BrushKind {
    /// Adds `strength` at the centre, fading to 0 at the radius.
    Raise,
    /// Subtracts it.
    Lower,
    /// Moves heights toward `target` by `strength` (0 to 1) of the way, with the falloff.
    Flatten,
    /// A bowl `strength` deep at the centre with a rim `strength / 4` high at 0.8 of the radius.
    Crater,
    /// Moves the weights of the splat map toward layer `layer` alone by `strength` (0 to 1) of
    /// the way, with the falloff; a weight sum stays what it was.
    Paint,
}

/// One stroke, in texels of the elevation map.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stroke {
    /// What the stroke does.
    pub kind: BrushKind,
    /// Centre, texel coordinates (texel `(i, j)`'s centre is at `(i + 0.5, j + 0.5)`).
    pub x: f32,
    /// Centre along v, texel coordinates.
    pub y: f32,
    /// Radius in texels.
    pub radius: f32,
    /// How much one stroke changes, at its centre.
    pub strength: f32,
    /// The height `flatten` moves toward (ignored by the others).
    #[serde(default)]
    pub target: f32,
    /// The layer `paint` weighs up (ignored by the others).
    #[serde(default)]
    pub layer: u32,
}

/// Why a stroke cannot be applied. One line each, naming the stroke.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StrokeError {
    #[error("stroke {index}: {field} is {value} (must be a finite number)")]
    /// A number that is not finite.
    NotFinite {
        /// Which stroke.
        index: usize,
        /// Which of its fields.
        field: &'static str,
        /// Its value.
        value: f32,
    },
    #[error("stroke {index}: radius {radius} (must be above 0 and at most {max}, the map's larger side)")]
    /// A radius not above 0 or larger than the map.
    Radius {
        /// Which stroke.
        index: usize,
        /// Its radius.
        radius: f32,
        /// The map's larger side.
        max: u32,
    },
    #[error(transparent)]
    /// A stroke for the other map.
    Target(#[from] StrokeTarget),
    #[error(
        "stroke {index}: centre ({x}, {y}) with radius {radius} misses the {width}x{height} map"
    )]
    /// A stroke that misses the map.
    Outside {
        /// Which stroke.
        index: usize,
        /// Its centre along u.
        x: f32,
        /// Its centre along v.
        y: f32,
        /// Its radius.
        radius: f32,
        /// The map's width.
        width: u32,
        /// The map's height.
        height: u32,
    },
}

/// Why a stroke went to the wrong map: elevation brushes move heights, `paint` moves weights.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StrokeTarget {
    #[error(
        "stroke {index}: paint weighs layers; the elevation takes raise, lower, flatten and crater"
    )]
    /// A `paint` stroke given to the elevation.
    PaintOnElevation {
        /// Which stroke.
        index: usize,
    },
    #[error("stroke {index}: {kind:?} moves the elevation; the layers' weights take paint")]
    /// An elevation brush given to the weights.
    ShapeOnWeights {
        /// Which stroke.
        index: usize,
        /// Its brush.
        kind: BrushKind,
    },
    #[error("stroke {index}: layer {layer}, but the material has {layers} layers (0 to {last})", last = layers - 1)]
    /// A layer the material does not have.
    Layer {
        /// Which stroke.
        index: usize,
        /// The layer it paints.
        layer: u32,
        /// The material's layer count.
        layers: usize,
    },
}

/// An inclusive rectangle of texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TexelRect {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// Last column.
    pub x1: u32,
    /// Last row.
    pub y1: u32,
}

impl TexelRect {
    /// Columns covered.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0 + 1
    }

    /// Rows covered.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0 + 1
    }

    /// Texels covered.
    pub fn texels(&self) -> u64 {
        u64::from(self.width()) * u64::from(self.height())
    }
}

impl Stroke {
    /// Checks the stroke against a `width` x `height` map; `index` names it in errors.
    pub fn check(&self, index: usize, width: u32, height: u32) -> Result<(), StrokeError> {
        for (field, value) in [
            ("x", self.x),
            ("y", self.y),
            ("radius", self.radius),
            ("strength", self.strength),
            ("target", self.target),
        ] {
            if !value.is_finite() {
                return Err(StrokeError::NotFinite {
                    index,
                    field,
                    value,
                });
            }
        }
        let max = width.max(height);
        if !(self.radius > 0.0 && self.radius <= max as f32) {
            return Err(StrokeError::Radius {
                index,
                radius: self.radius,
                max,
            });
        }
        if self.rect(width, height).is_none() {
            return Err(StrokeError::Outside {
                index,
                x: self.x,
                y: self.y,
                radius: self.radius,
                width,
                height,
            });
        }
        Ok(())
    }

    /// The texels whose centres lie within the radius's bounding square, clipped to the map;
    /// `None` when that misses the map.
    pub fn rect(&self, width: u32, height: u32) -> Option<TexelRect> {
        let span = |c: f32, n: u32| {
            let lo = (c - self.radius - 0.5).ceil().max(0.0);
            let hi = (c + self.radius - 0.5).floor().min(n as f32 - 1.0);
            (lo <= hi).then_some((lo as u32, hi as u32))
        };
        let (x0, x1) = span(self.x, width)?;
        let (y0, y1) = span(self.y, height)?;
        Some(TexelRect { x0, y0, x1, y1 })
    }

    /// Whether texel `(i, j)`'s centre lies inside the stroke's disk.
    pub fn covers(&self, i: u32, j: u32) -> bool {
        self.falloff(i, j).is_some()
    }

    /// Whether the stroke paints weights rather than moving the elevation.
    pub fn paints(&self) -> bool {
        self.kind == BrushKind::Paint
    }

    /// The distance of texel `(i, j)`'s centre from the centre over the radius, and the falloff
    /// there: smoothstep from the rim (0) to the centre (1); `None` outside the disk.
    fn falloff(&self, i: u32, j: u32) -> Option<(f32, f32)> {
        let dx = i as f32 + 0.5 - self.x;
        let dy = j as f32 + 0.5 - self.y;
        let r = (dx * dx + dy * dy).sqrt() / self.radius;
        if r >= 1.0 {
            return None;
        }
        let t = 1.0 - r;
        Some((r, t * t * (3.0 - 2.0 * t)))
    }

    /// The weights at texel `(i, j)` after a `paint` stroke, from `w` before it (others leave
    /// them): `w (1 - t) + t e_layer` with `t` the clamped strength times the falloff, so a
    /// stroke of strength 1 leaves the layer alone at its centre.
    pub fn paint(&self, i: u32, j: u32, w: [f32; 4]) -> [f32; 4] {
        let Some((_, falloff)) = self.falloff(i, j).filter(|_| self.paints()) else {
            return w;
        };
        let t = self.strength.clamp(0.0, 1.0) * falloff;
        std::array::from_fn(|k| {
            let own = if k as u32 == self.layer { t } else { 0.0 };
            w[k] * (1.0 - t) + own
        })
    }

    /// The height at texel `(i, j)` after the stroke, from `h` before it; clamped to [0, 1].
    /// `brush.comp` computes the same in the same order. A `paint` stroke leaves heights.
    pub fn apply(&self, i: u32, j: u32, h: f32) -> f32 {
        let Some((r, falloff)) = self.falloff(i, j) else {
            return h;
        };
        let out = match self.kind {
            BrushKind::Paint => return h,
            BrushKind::Raise => h + self.strength * falloff,
            BrushKind::Lower => h - self.strength * falloff,
            BrushKind::Flatten => h + (self.target - h) * (self.strength.clamp(0.0, 1.0) * falloff),
            BrushKind::Crater => {
                // A bowl inside 0.8 of the radius, a rim just outside it.
                let bowl = 1.0 - (r / 0.8) * (r / 0.8);
                let rim = (1.0 - ((r - 0.8) / 0.2).abs()).max(0.0);
                h - self.strength * bowl.max(0.0) + 0.25 * self.strength * rim
            }
        };
        out.clamp(0.0, 1.0)
    }
}

/// The coarse texels, along one axis of a pyramid level of `coarse_len`, whose covered range
/// (`heightfield::covered_range` of the finer level's `fine_len`, widened by `margin` texels and
/// wrapped when `wrap`) meets finer texels `first..=last`: one or two inclusive intervals.
pub fn coarse_span(
    (first, last): (u32, u32),
    fine_len: u32,
    coarse_len: u32,
    margin: u32,
    wrap: bool,
) -> Vec<(u32, u32)> {
    let (lo, hi) = (
        i64::from(first) - i64::from(margin),
        i64::from(last) + i64::from(margin),
    );
    let n = i64::from(fine_len);
    // The finer texels read: the widened interval, wrapped into range or clamped.
    let mut fine: Vec<(i64, i64)> = Vec::new();
    if hi - lo + 1 >= n {
        fine.push((0, n - 1));
    } else if wrap && lo < 0 {
        fine.extend([(0, hi), (lo + n, n - 1)]);
    } else if wrap && hi >= n {
        fine.extend([(lo, n - 1), (0, hi - n)]);
    } else {
        fine.push((lo.max(0), hi.min(n - 1)));
    }
    let covered = |c: u32| crate::heightfield::covered_range(c, coarse_len, fine_len);
    let mut spans: Vec<(u32, u32)> = fine
        .into_iter()
        .filter_map(|(p, q)| {
            let hits = |c: &u32| {
                let (f, l) = covered(*c);
                i64::from(l) >= p && i64::from(f) <= q
            };
            let c0 = (0..coarse_len).find(hits)?;
            let c1 = (0..coarse_len).rev().find(hits)?;
            Some((c0, c1))
        })
        .collect();
    spans.sort_unstable();
    spans.dedup();
    spans
}

/// A stroke of strength 0.2 (flattening toward 0.5), for the terrain module's tests.
#[cfg(test)]
pub(super) fn test_stroke(kind: BrushKind, x: f32, y: f32, radius: f32) -> Stroke {
    Stroke {
        kind,
        x,
        y,
        radius,
        strength: 0.2,
        target: 0.5,
        layer: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::test_stroke as stroke;
    use super::*;

    #[test]
    fn strokes_change_only_their_disk_and_each_kind_goes_its_way() {
        let s = stroke(BrushKind::Raise, 10.5, 10.5, 4.0);
        assert_eq!(
            s.apply(10, 10, 0.5),
            0.7,
            "the centre gets the full strength"
        );
        assert_eq!(s.apply(14, 10, 0.5), 0.5, "the rim gets none");
        assert!(s.apply(12, 10, 0.5) > 0.5 && s.apply(12, 10, 0.5) < 0.7);
        assert_eq!(
            stroke(BrushKind::Lower, 10.5, 10.5, 4.0).apply(10, 10, 0.1),
            0.0
        );
        let flat = Stroke {
            strength: 1.0,
            ..stroke(BrushKind::Flatten, 10.5, 10.5, 4.0)
        };
        assert_eq!(flat.apply(10, 10, 0.9), 0.5);
        let crater = stroke(BrushKind::Crater, 10.5, 10.5, 10.0);
        assert!(crater.apply(10, 10, 0.5) < 0.5, "a bowl at the centre");
        assert!(crater.apply(18, 10, 0.5) > 0.5, "a rim near the edge");
        // Every changed texel lies in the stroke's rect.
        let rect = s.rect(32, 32).unwrap();
        for j in 0..32 {
            for i in 0..32 {
                if s.apply(i, j, 0.5) != 0.5 {
                    assert!(i >= rect.x0 && i <= rect.x1 && j >= rect.y0 && j <= rect.y1);
                }
            }
        }
    }

    #[test]
    fn paint_moves_weights_toward_its_layer_and_keeps_their_sum() {
        let s = Stroke {
            strength: 1.0,
            layer: 2,
            ..stroke(BrushKind::Paint, 10.5, 10.5, 4.0)
        };
        let before = [0.5, 0.25, 0.0, 0.25];
        assert_eq!(s.paint(10, 10, before), [0.0, 0.0, 1.0, 0.0]);
        assert_eq!(s.paint(14, 10, before), before, "the rim keeps its weights");
        let half = s.paint(12, 10, before);
        assert!(half[2] > 0.0 && half[2] < 1.0 && half[0] < 0.5);
        assert!((half.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert_eq!(s.apply(10, 10, 0.3), 0.3, "paint leaves the elevation");
        let raise = stroke(BrushKind::Raise, 10.5, 10.5, 4.0);
        assert_eq!(
            raise.paint(10, 10, before),
            before,
            "a raise leaves the weights"
        );
    }

    #[test]
    fn bad_strokes_are_named_and_explained() {
        let ok = stroke(BrushKind::Raise, 3.0, 3.0, 2.0);
        assert_eq!(ok.check(0, 8, 8), Ok(()));
        let nan = Stroke { x: f32::NAN, ..ok };
        assert!(matches!(
            nan.check(4, 8, 8),
            Err(StrokeError::NotFinite {
                index: 4,
                field: "x",
                ..
            })
        ));
        let zero = Stroke { radius: 0.0, ..ok };
        assert!(zero
            .check(1, 8, 8)
            .unwrap_err()
            .to_string()
            .contains("radius 0"));
        let huge = Stroke {
            radius: 100.0,
            ..ok
        };
        assert!(matches!(
            huge.check(1, 8, 8),
            Err(StrokeError::Radius { .. })
        ));
        let away = Stroke { x: -20.0, ..ok };
        let err = away.check(2, 8, 8).unwrap_err();
        assert!(err.to_string().contains("misses the 8x8 map"), "{err}");
        // A stroke hanging over the edge is clipped, not refused.
        let edge = Stroke { x: 0.0, ..ok };
        assert_eq!(edge.rect(8, 8).unwrap().x0, 0);
    }

    #[test]
    fn coarse_spans_cover_every_node_that_reads_a_changed_texel() {
        for (fine, coarse) in [(64, 32), (37, 18), (5, 2), (2, 1)] {
            for margin in [0, 1] {
                for wrap in [false, true] {
                    for first in 0..fine {
                        for last in first..fine.min(first + 4) {
                            let spans = coarse_span((first, last), fine, coarse, margin, wrap);
                            for c in 0..coarse {
                                let (f, l) = crate::heightfield::covered_range(c, coarse, fine);
                                let reads = (i64::from(f) - i64::from(margin)
                                    ..=i64::from(l) + i64::from(margin))
                                    .map(|k| {
                                        let n = i64::from(fine);
                                        if wrap {
                                            k.rem_euclid(n)
                                        } else {
                                            k.clamp(0, n - 1)
                                        }
                                    })
                                    .any(|k| k >= i64::from(first) && k <= i64::from(last));
                                let listed = spans.iter().any(|&(a, b)| c >= a && c <= b);
                                assert_eq!(
                                    reads, listed,
                                    "{fine}->{coarse} m{margin} wrap {wrap} [{first},{last}] node {c}: {spans:?}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}

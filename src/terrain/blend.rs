//! The blend modes and the blended field they define (see the module docs for the formulas).

use super::layers::LayerStack;
use crate::heightfield::Heightfield;

/// How a terrain's layers combine into one surface and one material.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BlendMode {
    /// Weighted sum of heights; the material blends by the weights.
    Alpha,
    /// The alpha surface; the material blends by height times weight (Drobot, Listing 1.6).
    Height,
    /// The highest weighted layer is the surface (Listing 1.7); the material blends as `Height`.
    HeightIntersect,
}

impl BlendMode {
    /// Every mode, in the order tables list them.
    pub const ALL: [BlendMode; 3] = [
        BlendMode::Alpha,
        BlendMode::Height,
        BlendMode::HeightIntersect,
    ];

    /// The mode's name on the command line and in files.
    pub fn id(self) -> &'static str {
        match self {
            BlendMode::Alpha => "alpha",
            BlendMode::Height => "height",
            BlendMode::HeightIntersect => "height-intersect",
        }
    }

    /// The blended height at a texel whose layers have heights `h` and weights `w` (layers past
    /// the stack's have weight 0). The sums run in layer order with no reassociation, so that a
    /// one-hot weight returns its layer's height exactly (`1 * h + 0 + 0 + 0 = h`, `/ 1`), and the
    /// shaders must keep that order.
    pub fn surface(self, h: [f32; 4], w: [f32; 4]) -> f32 {
        match self {
            BlendMode::Alpha | BlendMode::Height => {
                let sum = ((w[0] + w[1]) + w[2]) + w[3];
                if sum > 0.0 {
                    let weighted = ((w[0] * h[0] + w[1] * h[1]) + w[2] * h[2]) + w[3] * h[3];
                    (weighted / sum).min(1.0)
                } else {
                    0.0
                }
            }
            BlendMode::HeightIntersect => (w[0] * h[0])
                .max(w[1] * h[1])
                .max(w[2] * h[2])
                .max(w[3] * h[3]),
        }
    }

    /// How much each layer's material shows at a texel with heights `h` and weights `w`; they sum
    /// to 1 (all 0 where every weight is 0).
    pub fn shading_weights(self, h: [f32; 4], w: [f32; 4]) -> [f32; 4] {
        let by: [f32; 4] = match self {
            BlendMode::Alpha => w,
            BlendMode::Height | BlendMode::HeightIntersect => std::array::from_fn(|k| h[k] * w[k]),
        };
        let sum: f32 = by.iter().sum();
        if sum > 0.0 {
            by.map(|x| x / sum)
        } else if w.iter().sum::<f32>() > 0.0 {
            // Every weighted layer at height 0: the weights alone decide.
            BlendMode::Alpha.shading_weights(h, w)
        } else {
            [0.0; 4]
        }
    }
}

impl std::fmt::Display for BlendMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.id())
    }
}

impl std::str::FromStr for BlendMode {
    type Err = String;

    fn from_str(text: &str) -> Result<BlendMode, String> {
        BlendMode::ALL
            .into_iter()
            .find(|m| m.id() == text)
            .ok_or_else(|| {
                let ids: Vec<&str> = BlendMode::ALL.iter().map(|m| m.id()).collect();
                format!("unknown blend mode {text:?} (one of {})", ids.join(", "))
            })
    }
}

/// The surface `mode` makes of `stack`, texel by texel: what the exact reference traces.
pub fn blended_field(stack: &LayerStack, mode: BlendMode) -> Heightfield {
    let (w, h) = (stack.width(), stack.height());
    let data = (0..w as usize * h as usize)
        .map(|t| mode.surface(stack.heights_at(t), stack.weights_at(t)))
        .collect();
    Heightfield::from_valid(w, h, data)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Generator;

    #[test]
    fn one_hot_weights_give_the_layer_back_bit_for_bit() {
        let layers: Vec<Heightfield> = (0..4)
            .map(|seed| Generator::Fbm.generate(32, 32, seed))
            .collect();
        for mode in BlendMode::ALL {
            for only in 0..4 {
                let stack = LayerStack::one_hot(layers.clone(), only).unwrap();
                let field = blended_field(&stack, mode);
                let same = field
                    .data()
                    .iter()
                    .zip(layers[only].data())
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "{mode}: layer {only} changed under a one-hot weight");
            }
        }
    }

    #[test]
    fn the_modes_blend_as_the_paper_writes_them() {
        let h = [0.2, 0.8, 0.5, 0.0];
        let w = [0.5, 0.5, 0.0, 0.0];
        assert!((BlendMode::Alpha.surface(h, w) - 0.5).abs() < 1e-6);
        assert_eq!(
            BlendMode::Alpha.surface(h, w),
            BlendMode::Height.surface(h, w)
        );
        assert!((BlendMode::HeightIntersect.surface(h, w) - 0.4).abs() < 1e-6);
        // Alpha blends the material by weight; height by height times weight (0.1 against 0.4).
        assert_eq!(BlendMode::Alpha.shading_weights(h, w), [0.5, 0.5, 0.0, 0.0]);
        let s = BlendMode::Height.shading_weights(h, w);
        assert!(
            (s[0] - 0.2).abs() < 1e-6 && (s[1] - 0.8).abs() < 1e-6,
            "{s:?}"
        );
        assert_eq!(BlendMode::Alpha.surface(h, [0.0; 4]), 0.0);
        assert_eq!(BlendMode::Height.shading_weights(h, [0.0; 4]), [0.0; 4]);
        // Weighted layers all at height 0 still shade by their weights.
        assert_eq!(
            BlendMode::Height.shading_weights([0.0; 4], w),
            [0.5, 0.5, 0.0, 0.0]
        );
        for mode in BlendMode::ALL {
            assert_eq!(mode.id().parse::<BlendMode>(), Ok(mode));
        }
        assert!("max"
            .parse::<BlendMode>()
            .unwrap_err()
            .contains("height-intersect"));
    }
}

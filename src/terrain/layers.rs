//! A terrain's layers: up to four height fields of one size, and each layer's weight at every
//! texel of them (from a low-resolution splat map, or given texel by texel).

use super::brush::{Stroke, TexelRect};
use crate::heightfield::Heightfield;

/// Layers a stack holds at most: the channels of one RGBA image.
pub const MAX_LAYERS: usize = 4;

/// Why layers or weights cannot be stacked. Every message is one line.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum LayerError {
    #[error("a layer stack needs 1 to {MAX_LAYERS} layers, got {count}")]
    /// Not 1 to `MAX_LAYERS` layers.
    Count {
        /// Layers given.
        count: usize,
    },
    #[error("{what} is {got_w}x{got_h}, but the first layer is {want_w}x{want_h}; every layer and weight map of a stack has one size")]
    /// A layer or weight map whose size is not the first layer's.
    Size {
        /// Which map.
        what: String,
        /// Its width.
        got_w: u32,
        /// Its height.
        got_h: u32,
        /// The first layer's width.
        want_w: u32,
        /// The first layer's height.
        want_h: u32,
    },
    #[error("{layers} layers, but weights for {weights}")]
    /// Not one weight map per layer.
    WeightCount {
        /// Layers given.
        layers: usize,
        /// Weight maps given.
        weights: usize,
    },
    #[error("splat map: {width}x{height} texels need {expected} RGBA values, got {got}")]
    /// A splat map whose value count does not fit its size.
    SplatLength {
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// Values that size needs.
        expected: usize,
        /// Values given.
        got: usize,
    },
    #[error("splat map: texel {texel} has weight {value} (weights are finite and at least 0)")]
    /// A splat weight that is negative or not finite.
    SplatValue {
        /// Which texel.
        texel: usize,
        /// Its weight.
        value: f32,
    },
}

/// A low-resolution RGBA weight map (a splat map): channel k weighs layer k. Clamp-addressed and
/// bilinear between texel centres, like every map in relief.
#[derive(Debug, Clone, PartialEq)]
pub struct SplatMap {
    width: u32,
    height: u32,
    texels: Vec<[f32; 4]>,
}

impl SplatMap {
    /// `texels` row-major, `width * height` of them, each weight finite and >= 0.
    pub fn new(width: u32, height: u32, texels: Vec<[f32; 4]>) -> Result<SplatMap, LayerError> {
        let expected = width as usize * height as usize;
        if width == 0 || height == 0 || texels.len() != expected {
            return Err(LayerError::SplatLength {
                width,
                height,
                expected,
                got: texels.len(),
            });
        }
        let bad = texels
            .iter()
            .flatten()
            .enumerate()
            .find(|(_, w)| !(w.is_finite() && **w >= 0.0));
        if let Some((k, &value)) = bad {
            return Err(LayerError::SplatValue {
                texel: k / 4,
                value,
            });
        }
        Ok(SplatMap {
            width,
            height,
            texels,
        })
    }

    /// Width and height in texels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The weights of texel `(i, j)`.
    pub fn texel(&self, i: u32, j: u32) -> [f32; 4] {
        self.texels[j as usize * self.width as usize + i as usize]
    }

    /// The weights at `(u, v)`, bilinear between texel centres, clamped at the edges.
    pub fn sample(&self, u: f64, v: f64) -> [f32; 4] {
        let axis = |t: f64, n: u32| {
            let x = (t * f64::from(n) - 0.5).clamp(0.0, f64::from(n - 1));
            let i0 = x.floor() as u32;
            (i0, (i0 + 1).min(n - 1), (x - f64::from(i0)) as f32)
        };
        let (i0, i1, fu) = axis(u, self.width);
        let (j0, j1, fv) = axis(v, self.height);
        let at = |i: u32, j: u32| self.texels[j as usize * self.width as usize + i as usize];
        let (a, b, c, d) = (at(i0, j0), at(i1, j0), at(i0, j1), at(i1, j1));
        std::array::from_fn(|k| {
            let top = a[k] + (b[k] - a[k]) * fu;
            let bottom = c[k] + (d[k] - c[k]) * fu;
            top + (bottom - top) * fv
        })
    }

    /// The weights of texel `(i, j)` of a `width` x `height` stack weighed by this map: the map
    /// at the texel's centre, each clamped to [0, 1]. What [`LayerStack::from_splat`] stores,
    /// so that a painted region can be weighed again alone and match a full rebuild bit for bit.
    pub fn stack_weights(&self, i: u32, j: u32, width: u32, height: u32) -> [f32; 4] {
        let at = self.sample(
            (f64::from(i) + 0.5) / f64::from(width),
            (f64::from(j) + 0.5) / f64::from(height),
        );
        at.map(|w| w.clamp(0.0, 1.0))
    }

    /// The texels of a `width` x `height` stack whose weights read texels `rect` of this map
    /// (bilinear: a stack texel reads the two map texels about its centre on each axis).
    pub fn stack_rect(&self, rect: &TexelRect, width: u32, height: u32) -> TexelRect {
        // Stack texel i reads map texels floor(x) and floor(x) + 1, x = (i + 0.5) n / size - 0.5:
        // those from a - 1 to b read [a, b]; one texel of slack on each side covers rounding.
        let span = |a: u32, b: u32, n: u32, size: u32| {
            let scale = f64::from(size) / f64::from(n);
            let first = ((f64::from(a) - 0.5) * scale - 0.5).floor() - 1.0;
            let last = ((f64::from(b) + 1.5) * scale - 0.5).ceil() + 1.0;
            (first.max(0.0) as u32, (last.max(0.0) as u32).min(size - 1))
        };
        let (x0, x1) = span(rect.x0, rect.x1, self.width, width);
        let (y0, y1) = span(rect.y0, rect.y1, self.height, height);
        TexelRect { x0, y0, x1, y1 }
    }

    /// Applies a `paint` stroke (in this map's texels; checked by the caller) and returns the
    /// texels it may have changed, `None` when it misses the map.
    pub fn paint(&mut self, stroke: &Stroke) -> Option<TexelRect> {
        let rect = stroke.rect(self.width, self.height)?;
        for j in rect.y0..=rect.y1 {
            for i in rect.x0..=rect.x1 {
                let t = j as usize * self.width as usize + i as usize;
                self.texels[t] = stroke.paint(i, j, self.texels[t]);
            }
        }
        Some(rect)
    }

    /// Sets texel `(i, j)`'s weights, each clamped to [0, 1] (a NaN to 0), so the map stays valid.
    pub fn set_texel(&mut self, i: u32, j: u32, weights: [f32; 4]) {
        let t = j as usize * self.width as usize + i as usize;
        self.texels[t] = weights.map(|w| if w.is_nan() { 0.0 } else { w.clamp(0.0, 1.0) });
    }

    /// Rounds texels `rect` to 16-bit unorm steps, as a splat image stores them: what painting
    /// leaves is then exactly what saving the map and loading it back gives.
    pub fn quantize_unorm16(&mut self, rect: &TexelRect) {
        for j in rect.y0..=rect.y1 {
            for i in rect.x0..=rect.x1 {
                let t = j as usize * self.width as usize + i as usize;
                self.texels[t] = self.texels[t].map(|c| {
                    f32::from((c.clamp(0.0, 1.0) * 65535.0).round() as u16) / f32::from(u16::MAX)
                });
            }
        }
    }

    /// Texels `rect` as 16-bit unorm RGBA, row-major (how the shading's splat image holds them).
    pub fn unorm16_rect(&self, rect: &TexelRect) -> Vec<u16> {
        let mut out = Vec::with_capacity(rect.texels() as usize * 4);
        for j in rect.y0..=rect.y1 {
            for i in rect.x0..=rect.x1 {
                let w = self.texel(i, j);
                out.extend(w.map(|c| (c.clamp(0.0, 1.0) * 65535.0).round() as u16));
            }
        }
        out
    }
}

/// Layers of one size with their weights at every texel.
#[derive(Debug, Clone, PartialEq)]
pub struct LayerStack {
    heights: Vec<Heightfield>,
    /// One per layer, the layers' size; values in [0, 1].
    weights: Vec<Heightfield>,
}

impl LayerStack {
    /// `heights` weighed texel by texel by `weights` (one map per layer, each value in [0, 1]).
    pub fn new(
        heights: Vec<Heightfield>,
        weights: Vec<Heightfield>,
    ) -> Result<LayerStack, LayerError> {
        check_layers(&heights)?;
        if weights.len() != heights.len() {
            return Err(LayerError::WeightCount {
                layers: heights.len(),
                weights: weights.len(),
            });
        }
        for (k, w) in weights.iter().enumerate() {
            check_size(&heights[0], w, format!("weight map {k}"))?;
        }
        Ok(LayerStack { heights, weights })
    }

    /// `heights` weighed by `splat` sampled at each texel centre; channels past the layers are
    /// ignored. Weights above 1 are clamped to 1.
    pub fn from_splat(
        heights: Vec<Heightfield>,
        splat: &SplatMap,
    ) -> Result<LayerStack, LayerError> {
        check_layers(&heights)?;
        let (w, h) = (heights[0].width(), heights[0].height());
        let mut channels = vec![Vec::with_capacity(w as usize * h as usize); heights.len()];
        for j in 0..h {
            for i in 0..w {
                let at = splat.stack_weights(i, j, w, h);
                for (k, channel) in channels.iter_mut().enumerate() {
                    channel.push(at[k]);
                }
            }
        }
        let weights = channels
            .into_iter()
            .map(|data| Heightfield::from_valid(w, h, data))
            .collect();
        Ok(LayerStack { heights, weights })
    }

    /// `heights` with layer `only` weighing 1 everywhere and the others 0.
    pub fn one_hot(heights: Vec<Heightfield>, only: usize) -> Result<LayerStack, LayerError> {
        check_layers(&heights)?;
        let (w, h) = (heights[0].width(), heights[0].height());
        let n = w as usize * h as usize;
        let weights = (0..heights.len())
            .map(|k| Heightfield::from_valid(w, h, vec![if k == only { 1.0 } else { 0.0 }; n]))
            .collect();
        Ok(LayerStack { heights, weights })
    }

    /// The stack as 16-bit unorm images hold it: every height and weight rounded to the nearest step.
    pub fn quantized_unorm16(&self) -> LayerStack {
        let q = |maps: &[Heightfield]| maps.iter().map(Heightfield::quantized_unorm16).collect();
        LayerStack {
            heights: q(&self.heights),
            weights: q(&self.weights),
        }
    }

    /// How many layers it stacks.
    pub fn len(&self) -> usize {
        self.heights.len()
    }

    /// Whether it stacks no layer.
    pub fn is_empty(&self) -> bool {
        self.heights.is_empty()
    }

    /// Width of every layer, in texels.
    pub fn width(&self) -> u32 {
        self.heights[0].width()
    }

    /// Height of every layer, in texels.
    pub fn height(&self) -> u32 {
        self.heights[0].height()
    }

    /// Each layer's heights.
    pub fn heights(&self) -> &[Heightfield] {
        &self.heights
    }

    /// Each layer's weights.
    pub fn weights(&self) -> &[Heightfield] {
        &self.weights
    }

    /// The layers' heights at texel `index` (row-major), 0 past the last layer.
    pub fn heights_at(&self, index: usize) -> [f32; 4] {
        std::array::from_fn(|k| self.heights.get(k).map_or(0.0, |h| h.data()[index]))
    }

    /// The layers' weights at texel `index`, 0 past the last layer.
    pub fn weights_at(&self, index: usize) -> [f32; 4] {
        std::array::from_fn(|k| self.weights.get(k).map_or(0.0, |w| w.data()[index]))
    }
}

fn check_layers(heights: &[Heightfield]) -> Result<(), LayerError> {
    if heights.is_empty() || heights.len() > MAX_LAYERS {
        return Err(LayerError::Count {
            count: heights.len(),
        });
    }
    for (k, h) in heights.iter().enumerate().skip(1) {
        check_size(&heights[0], h, format!("layer {k}"))?;
    }
    Ok(())
}

fn check_size(first: &Heightfield, other: &Heightfield, what: String) -> Result<(), LayerError> {
    if (other.width(), other.height()) == (first.width(), first.height()) {
        return Ok(());
    }
    Err(LayerError::Size {
        what,
        got_w: other.width(),
        got_h: other.height(),
        want_w: first.width(),
        want_h: first.height(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Generator;

    #[test]
    fn painting_changes_stack_weights_only_inside_the_stack_rect() {
        use crate::terrain::BrushKind;
        let texels: Vec<[f32; 4]> = (0..13 * 9)
            .map(|t| {
                let a = (t % 7) as f32 / 7.0;
                [a, 1.0 - a, 0.0, 0.0]
            })
            .collect();
        for (size, (x, y, radius)) in [
            (40, (3.2, 4.0, 2.5)),
            (16, (0.5, 8.5, 3.0)),
            (57, (12.9, 0.1, 1.5)),
        ] {
            let mut splat = SplatMap::new(13, 9, texels.clone()).unwrap();
            let before = splat.clone();
            let stroke = Stroke {
                kind: BrushKind::Paint,
                x,
                y,
                radius,
                strength: 0.8,
                target: 0.0,
                layer: 2,
            };
            let rect = splat.paint(&stroke).unwrap();
            let stack = splat.stack_rect(&rect, size, size);
            let mut changed = 0;
            for j in 0..size {
                for i in 0..size {
                    let differs = splat.stack_weights(i, j, size, size)
                        != before.stack_weights(i, j, size, size);
                    let inside = i >= stack.x0 && i <= stack.x1 && j >= stack.y0 && j <= stack.y1;
                    assert!(
                        !differs || inside,
                        "{size}: texel ({i}, {j}) outside {stack:?}"
                    );
                    changed += usize::from(differs);
                }
            }
            assert!(changed > 0, "the stroke changed nothing at {size}");
        }
    }

    #[test]
    fn a_splat_map_is_bilinear_between_centres_and_clamped_outside() {
        let splat = SplatMap::new(2, 1, vec![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]]).unwrap();
        assert_eq!(splat.sample(0.25, 0.5), [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(splat.sample(0.5, 0.5), [0.5, 0.5, 0.0, 0.0]);
        assert_eq!(splat.sample(0.0, 0.0), [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(splat.sample(1.0, 1.0), [0.0, 1.0, 0.0, 0.0]);
    }

    #[test]
    fn bad_stacks_and_splats_are_refused_in_one_line() {
        let field = |n| Generator::Fbm.generate(n, n, 1);
        let err = LayerStack::one_hot(vec![field(8); 5], 0).unwrap_err();
        assert_eq!(err, LayerError::Count { count: 5 });
        let err = LayerStack::one_hot(vec![field(8), field(4)], 0).unwrap_err();
        assert!(err.to_string().contains("layer 1 is 4x4"), "{err}");
        let err = LayerStack::new(vec![field(8)], vec![]).unwrap_err();
        assert_eq!(
            err,
            LayerError::WeightCount {
                layers: 1,
                weights: 0
            }
        );
        let err = SplatMap::new(1, 1, vec![[0.0, f32::NAN, 0.0, 0.0]]).unwrap_err();
        assert!(
            matches!(err, LayerError::SplatValue { texel: 0, .. }),
            "{err}"
        );
        let err = SplatMap::new(2, 2, vec![[0.0; 4]; 3]).unwrap_err();
        assert!(!err.to_string().contains('\n'));
        assert!(SplatMap::new(1, 1, vec![[0.0, -0.5, 0.0, 0.0]]).is_err());
    }
}

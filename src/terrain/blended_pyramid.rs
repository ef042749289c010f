//! The conservative max pyramid of a blended surface, from the layers' and the weights' own max
//! pyramids (Drobot, 1.7.4), so that pyramid methods (QDM, PDM, QRM, maxmip) trace blended
//! terrain without the blended field's pyramid being built from the full-size field. Level 0 is
//! the blended field itself; every node of level 1 up bounds each blended texel under it:
//!
//! - `height-intersect`: `max_k(H_k * W_k)`, since `max(w h) <= max(w) * max(h)` over a node for
//!   weights and heights >= 0;
//! - `alpha` and `height`: the lower of `max_k(H_k)` over the layers with `W_k > 0` (a convex
//!   blend never rises above the highest layer it blends; 0 where no layer has weight) and
//!   `sum_k(W_k H_k) / S` where `S`, the least weight sum under the node (capped at 1), is above 0:
//!   `sum(w h) / sum(w)` has a numerator at most `sum(W H)` and a denominator at least `S`. The
//!   first alone was measured 2.9x the exact pyramid's QDM steps at 5 degrees on a smooth splat:
//!   in a blend zone it ignores how little weight the highest layer has. `S` comes from the max
//!   pyramid of `1 - min(sum(w), 1)` ([`least_sum_slack`]), the second term carries a margin of a
//!   few ulps for the rounding of the texels' own division.
//!
//! `H_k` and `W_k` are the nodes of layer k's height and weight pyramids, both built by `build`
//! (`MaxPyramid::build` or `MaxPyramid::build_bilinear_bound`), so the bound holds for whatever
//! footprint those pyramids give their nodes. One-hot weights give the layer's own pyramid back
//! exactly (`H * 1`, and `H * 0 = 0` for the others).

use super::blend::{blended_field, BlendMode};
use super::layers::LayerStack;
use crate::heightfield::{Heightfield, MaxPyramid, PyramidLevel};

/// The conservative pyramid of `stack` blended by `mode`, its layers' and weights' pyramids made
/// by `build`.
pub fn blended_pyramid(
    stack: &LayerStack,
    mode: BlendMode,
    build: impl Fn(&Heightfield) -> MaxPyramid,
) -> MaxPyramid {
    let heights: Vec<MaxPyramid> = stack.heights().iter().map(&build).collect();
    let weights: Vec<MaxPyramid> = stack.weights().iter().map(&build).collect();
    let slack = build(&least_sum_slack(stack));
    let field = blended_field(stack, mode);
    let mut levels = vec![PyramidLevel {
        width: field.width(),
        height: field.height(),
        data: field.data().to_vec(),
    }];
    for level in 1..heights[0].level_count() {
        let h: Vec<&[f32]> = heights
            .iter()
            .map(|p| p.level(level).data.as_slice())
            .collect();
        let w: Vec<&[f32]> = weights
            .iter()
            .map(|p| p.level(level).data.as_slice())
            .collect();
        let least = &slack.level(level).data;
        let data = (0..h[0].len())
            .map(|t| {
                let hk: [f32; 4] = std::array::from_fn(|k| h.get(k).map_or(0.0, |l| l[t]));
                let wk: [f32; 4] = std::array::from_fn(|k| w.get(k).map_or(0.0, |l| l[t]));
                node_bound(mode, hk, wk, 1.0 - least[t])
            })
            .collect();
        let (width, height) = (
            heights[0].level(level).width,
            heights[0].level(level).height,
        );
        levels.push(PyramidLevel {
            width,
            height,
            data,
        });
    }
    MaxPyramid::from_levels(levels)
}

/// How far each texel's weight sum falls short of 1 (`1 - min(sum(w), 1)`): its max pyramid gives,
/// per node, 1 minus the least weight sum under it.
pub fn least_sum_slack(stack: &LayerStack) -> Heightfield {
    let (w, h) = (stack.width(), stack.height());
    let data = (0..w as usize * h as usize)
        .map(|t| {
            let w = stack.weights_at(t);
            1.0 - (((w[0] + w[1]) + w[2]) + w[3]).min(1.0)
        })
        .collect();
    Heightfield::from_valid(w, h, data)
}

/// Relative margin on the convex blends' weighted bound: a few ulps of f32, for the texels' own
/// rounding and the slack's inversion.
const WEIGHTED_MARGIN: f32 = 1.0 + 8.0 * f32::EPSILON;

/// One node's bound from its layers' height and weight maxima and its least weight sum (the
/// module docs give the formulas; `blended_pyramid.comp` computes the same in the same order).
pub fn node_bound(mode: BlendMode, h: [f32; 4], w: [f32; 4], least_sum: f32) -> f32 {
    match mode {
        BlendMode::HeightIntersect => (h[0] * w[0])
            .max(h[1] * w[1])
            .max(h[2] * w[2])
            .max(h[3] * w[3]),
        BlendMode::Alpha | BlendMode::Height => {
            let highest = (0..4)
                .filter(|&k| w[k] > 0.0)
                .map(|k| h[k])
                .fold(0.0f32, f32::max);
            if least_sum > 0.0 {
                let weighted = ((w[0] * h[0] + w[1] * h[1]) + w[2] * h[2]) + w[3] * h[3];
                highest.min(weighted / least_sum * WEIGHTED_MARGIN)
            } else {
                highest
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::rng::SplitMix64;
    use crate::heightfield::Generator;
    use crate::terrain::SplatMap;

    fn random_stack(size: u32, layers: usize, seed: u64) -> LayerStack {
        let generators = [
            Generator::Fbm,
            Generator::Bricks,
            Generator::Spikes,
            Generator::Fbm,
        ];
        let heights = (0..layers)
            .map(|k| generators[k].generate(size, size, seed + k as u64))
            .collect();
        let mut rng = SplitMix64::new(seed);
        // A coarse splat map with some texels where a layer has no weight at all.
        let texels = (0..36)
            .map(|_| {
                std::array::from_fn(|_| {
                    if rng.next_f32() < 0.3 {
                        0.0
                    } else {
                        rng.next_f32()
                    }
                })
            })
            .collect();
        LayerStack::from_splat(heights, &SplatMap::new(6, 6, texels).unwrap()).unwrap()
    }

    #[test]
    fn every_node_bounds_the_blended_texels_under_it() {
        for (seed, size, layers) in [(1, 64, 4), (2, 37, 3), (3, 16, 2), (4, 1, 1)] {
            let stack = random_stack(size, layers, seed);
            for mode in BlendMode::ALL {
                let field = blended_field(&stack, mode);
                for (build, exact) in [
                    (
                        MaxPyramid::build as fn(&Heightfield) -> MaxPyramid,
                        MaxPyramid::build(&field),
                    ),
                    (
                        |hf: &Heightfield| MaxPyramid::build_bilinear_bound(hf, false),
                        MaxPyramid::build_bilinear_bound(&field, false),
                    ),
                ] {
                    let bound = blended_pyramid(&stack, mode, build);
                    assert_eq!(bound.level_count(), exact.level_count());
                    assert_eq!(
                        bound.level(0),
                        exact.level(0),
                        "level 0 is the blended field"
                    );
                    for (level, (b, e)) in bound.levels().iter().zip(exact.levels()).enumerate() {
                        assert_eq!((b.width, b.height), (e.width, e.height));
                        for (t, (b, e)) in b.data.iter().zip(&e.data).enumerate() {
                            assert!(
                                b >= e,
                                "{mode}, {size}^2, level {level}, node {t}: {b} below the blended {e}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn one_hot_weights_give_the_layers_own_pyramid() {
        let heights: Vec<Heightfield> =
            (0..3).map(|s| Generator::Fbm.generate(32, 32, s)).collect();
        for mode in BlendMode::ALL {
            let stack = LayerStack::one_hot(heights.clone(), 1).unwrap();
            let build = |hf: &Heightfield| MaxPyramid::build_bilinear_bound(hf, true);
            assert_eq!(
                blended_pyramid(&stack, mode, build),
                build(&heights[1]),
                "{mode}"
            );
        }
    }

    #[test]
    fn the_bound_is_close_where_the_weights_are_smooth() {
        // Two layers faded across the map: the bound's coarse levels stay near the blended field's
        // own pyramid, which is what keeps blended QDM's iterations near the single layer's.
        let heights: Vec<Heightfield> =
            (0..2).map(|s| Generator::Fbm.generate(64, 64, s)).collect();
        let splat = SplatMap::new(2, 1, vec![[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]]).unwrap();
        let stack = LayerStack::from_splat(heights, &splat).unwrap();
        let mode = BlendMode::HeightIntersect;
        let bound = blended_pyramid(&stack, mode, MaxPyramid::build);
        let exact = MaxPyramid::build(&blended_field(&stack, mode));
        let level = bound.level(2);
        let excess: f32 = level
            .data
            .iter()
            .zip(&exact.level(2).data)
            .map(|(b, e)| b - e)
            .sum::<f32>()
            / level.data.len() as f32;
        assert!(
            excess < 0.1,
            "the bound is {excess} above the blended pyramid on average"
        );
    }
}

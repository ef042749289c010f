//! Which texels of a horizon AO map a change of the heights can reach: the horizon pass's sample
//! pattern, and from it the radius within which a texel's AO reads the heights
//! ([`influence_radius`]) and the region a changed rectangle makes stale ([`influence_region`]),
//! so that edits rebuild the AO near them alone (`AoMapPass::record_region`).

use crate::render::shader_interface;

/// The horizon pass's sample pattern: the first sample a texel away, each next one twice as far
/// (log2 n samples per azimuth, the paper's count), read from the pyramid level two below the one
/// whose nodes match the distance (nodes a quarter of the distance wide). Measured against the
/// exact reference on 128x128 fbm and bricks at depth 0.05 and 0.1 (200 texels each): one level
/// below gave mean errors up to 0.053 (the max nodes raise far horizons), two below at most 0.011,
/// three below 0.022 (near features missed between samples); starting each horizon from the
/// surface's tangent then brought two below to at most 0.009.
pub(in crate::render) const HORIZON_FIRST_DISTANCE: f32 = 1.0;
pub(in crate::render) const HORIZON_GROWTH: f32 = 2.0;
pub(in crate::render) const HORIZON_LEVEL_BIAS: i32 = 2;
/// The shader's cap on samples per azimuth.
const HORIZON_MAX_SAMPLES: u32 = shader_interface::AO_HORIZON_MAX_SAMPLES;
/// Texels added to the derived influence radius, against rounding in the shader's sample
/// positions (`p + x dir` in uv, floored to a node) that the derivation treats as exact.
const INFLUENCE_SAFETY_TEXELS: u32 = 2;

/// A radius R in level-0 texels (per axis, so a square of side 2R + 1) such that a texel's AO
/// depends on the heights within R of it only, for horizons reaching `reach_uv` over a
/// `width` x `height` map whose pyramid has `levels` mips.
///
/// Why it bounds every read of ao_horizon.comp: the normal and the surface tangent read the
/// four neighbours (1). A sample at distance d (d <= the reach; per axis its offset is at most
/// d texels) reads level L = floor(log2 d) - level_bias clamped to the image's mips, or level 0
/// outside a clamped map. Level 0 is bilinear: the two texels about the sample, so d + 1. A
/// level-L node contains the sample and spans r_L = n / n_L level-0 texels (n_L the level's
/// size: more than 2^L for odd sizes); it is the max of the level L-1 texels it overlaps,
/// which reach at most r_{L-1} past it, and so on down to level 1, whose nodes also take the
/// level-0 texels one beyond those they overlap (the bilinear bound). So its reads lie within
/// d + r_L + (r_{L-1} + ... + r_1 + 1) + 1 of the texel; 2^(L+1) + d for power-of-two sizes.
/// Clamped reads beyond a clamped map's edge only come closer; repeat wraps distances.
pub fn influence_radius(reach_uv: f32, (width, height): (u32, u32), levels: u32) -> u32 {
    let longer = width.max(height);
    // The shader compares d / longer with the reach in uv, in its own rounding: include a
    // sample it may keep even where this side would drop it.
    let limit = f64::from(reach_uv) * f64::from(longer) * (1.0 + 1e-4);
    let mut radius = 1.0f64;
    let mut distance = f64::from(HORIZON_FIRST_DISTANCE);
    for _ in 0..HORIZON_MAX_SAMPLES {
        if distance > limit {
            break;
        }
        let level = sample_level(distance, levels);
        let node = node_reach(level, width).max(node_reach(level, height));
        radius = radius.max(distance + node);
        distance *= f64::from(HORIZON_GROWTH);
    }
    radius.ceil() as u32 + INFLUENCE_SAFETY_TEXELS
}

/// `changed` (x0, y0, width, height, level-0 texels) grown by `radius` and clipped to a `width`
/// x `height` map, or, under `wrap`, the whole of an axis where the grown rectangle wraps around
/// it (one rectangle stands for both sides); an empty rectangle when `changed` misses the map.
pub fn influence_region(
    changed: [u32; 4],
    (width, height): (u32, u32),
    radius: u32,
    wrap: bool,
) -> [u32; 4] {
    let Some(changed) = clip_region(changed, width, height) else {
        return [0; 4];
    };
    let (x0, w) = grow_span(changed[0], changed[2], width, radius, wrap);
    let (y0, h) = grow_span(changed[1], changed[3], height, radius, wrap);
    [x0, y0, w, h]
}

/// The pyramid level ao_horizon.comp reads `distance` texels away (`horizon_sample`), among
/// `levels` mips.
fn sample_level(distance: f64, levels: u32) -> u32 {
    let level = distance.log2().floor() as i32 - HORIZON_LEVEL_BIAS;
    level.clamp(0, levels.max(1) as i32 - 1) as u32
}

/// How far past a sample point, in level-0 texels of an axis of `n`, the heights behind a
/// level-`level` read lie (see [`influence_radius`]): the second bilinear texel at level 0;
/// the node's span, the spans of the finer texels it overlaps and the bilinear bound's margin
/// above. The mips' sizes follow the Vulkan rule, `max(1, n >> level)`.
fn node_reach(level: u32, n: u32) -> f64 {
    if level == 0 {
        return 1.0;
    }
    let span = |k: u32| f64::from(n) / f64::from((n >> k).max(1));
    (1..=level).map(span).sum::<f64>() + 1.0 + 1.0
}

/// `region` (x0, y0, width, height) clipped to a `w` x `h` map; `None` when nothing is left.
pub(in crate::render) fn clip_region(region: [u32; 4], w: u32, h: u32) -> Option<[u32; 4]> {
    let x1 = region[0].saturating_add(region[2]).min(w);
    let y1 = region[1].saturating_add(region[3]).min(h);
    (region[0] < x1 && region[1] < y1)
        .then(|| [region[0], region[1], x1 - region[0], y1 - region[1]])
}

/// The span (first, length) of `len` texels from `first` (within an axis of `n`) grown by
/// `radius` on both sides and clipped to the axis; the whole axis under `wrap` when the grown
/// span crosses an edge, since it then continues from the other side.
fn grow_span(first: u32, len: u32, n: u32, radius: u32, wrap: bool) -> (u32, u32) {
    let lo = i64::from(first) - i64::from(radius);
    let hi = i64::from(first) + i64::from(len) + i64::from(radius);
    if wrap && (lo < 0 || hi > i64::from(n)) {
        return (0, n);
    }
    let lo = lo.max(0) as u32;
    (lo, hi.min(i64::from(n)) as u32 - lo)
}

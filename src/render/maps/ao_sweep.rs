//! The host side of the exact-horizon AO sweep (`shaders/passes/ao_sweep.comp`): which azimuths
//! are swept and with what weight, and how one azimuth's lines are enumerated, one invocation each.
//! Pure arithmetic, tested without a GPU.
//!
//! Azimuths are primitive integer steps `(a, b)` in texels (so a line through one texel centre
//! meets another at every step and every texel lies on exactly one line); their uv angles
//! `atan2(b / H, a / W)` are picked near `count` evenly spaced targets, preferring short steps
//! (each step costs `|a| + |b|` profile points), and weighted by the share of the circle nearer to
//! them than to their neighbours. The weights sum to 1.
//!
//! Lines under repeat are the orbits of the step on the W x H torus: the x coordinates of an orbit
//! form a coset of `g_a = gcd(|a|, W)`, and at a fixed x its y coordinates a coset of
//! `g_d = gcd(b * W / g_a mod H, H)`, so `(x mod g_a, y mod g_d)` names the orbit and each has
//! `period = (W / g_a) (H / g_d)` texels. Under clamp, line `c` is the set of lattice points with
//! `x b - y a = c`, which passes through `c * euclid` (`euclid.0 * b - euclid.1 * a = 1`).

use std::f64::consts::TAU;

use crate::render::shader_interface;

/// Hull entries per line.
pub(crate) const HULL_CAPACITY: u64 = shader_interface::AO_HULL_CAPACITY as u64;

/// Slots of 16 bytes per line after its hull ring: the walk's state between dispatches.
pub(crate) const STATE_SLOTS: u64 = shader_interface::AO_STATE_SLOTS as u64;

/// Lattice steps one invocation walks per dispatch: a longer walk is resumed by the next dispatch
/// from the state it saved. Lavapipe (llvmpipe's gallivm) gives a shader invocation 65535 loop
/// iterations in all, shared by every loop in it, and silently ends every loop once they are
/// spent; a step of the steepest azimuth costs a few dozen (its crossings, hull pops), so whole
/// walks of 2 x 256 steps under repeat ran out and lost the rest of their texels' occlusion.
pub(crate) const CHUNK_STEPS: u32 = 256;

/// Orbits longer than this many map sides are walked in segments (see [`SweepLines`]).
const LONG_ORBIT: u64 = 4;

/// The longest step component considered when picking directions.
const MAX_STEP: i32 = 12;

/// The most grid-line crossings inside one lattice step (`|a| + |b| - 2 < 2 MAX_STEP`).
pub(crate) const MAX_CROSSINGS: usize = 2 * MAX_STEP as usize;

/// One crossing of a texel-centre grid line strictly inside a lattice step (`Crossing` in
/// ao_sweep.comp): the same for every step of every line of an azimuth, so the host lists them once
/// and the walks do no integer division.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Crossing {
    /// The crossed edge's lower end, from the step's first lattice point, in texels.
    pub offset: [i32; 2],
    /// The edge's direction: (0, 1) for a column crossing, (1, 0) for a row.
    pub along: [i32; 2],
    /// Where along the step (0..1) and where along the edge (0..1) the crossing lies.
    pub fractions: [f32; 2],
}

const _: () = assert!(std::mem::size_of::<Crossing>() == 24);

/// The crossings inside one step of `walk`, in walking order.
pub(crate) fn crossings(walk: [i32; 2]) -> Vec<Crossing> {
    let [wx, wy] = walk;
    let (ax, ay) = (wx.abs(), wy.abs());
    let (mut mx, mut my) = (1, 1);
    let mut out = Vec::with_capacity(MAX_CROSSINGS);
    while mx < ax || my < ay {
        // mx / ax < my / ay without division; never equal for a primitive step.
        let column = my >= ay || (mx < ax && mx * ay < my * ax);
        let (m, a, across) = if column {
            (mx, ax, mx * wy)
        } else {
            (my, ay, my * wx)
        };
        let q = across.div_euclid(a);
        let edge = (across - q * a) as f32 / a as f32;
        let step = m as f32 / a as f32;
        out.push(if column {
            mx += 1;
            Crossing {
                offset: [wx.signum() * m, q],
                along: [0, 1],
                fractions: [step, edge],
            }
        } else {
            my += 1;
            Crossing {
                offset: [q, wy.signum() * m],
                along: [1, 0],
                fractions: [step, edge],
            }
        });
    }
    out
}

/// One swept azimuth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SweepDirection {
    /// The horizon's direction as a primitive lattice step (the walk goes the other way).
    pub step: [i32; 2],
    /// The azimuth in uv, radians from +u toward +v, in [0, 2 pi).
    pub angle: f64,
    /// Its share of the circle; the weights of a set sum to 1.
    pub weight: f64,
}

/// How one azimuth's lines are laid out for the shader.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SweepLines {
    pub lines: u32,
    /// Clamp: `c` of line 0.
    pub c_min: i32,
    /// `(x, y)` with `x * walk.1 - y * walk.0 = 1`.
    pub euclid: [i32; 2],
    /// Repeat: steps around one orbit, and the x coset count.
    pub period: u32,
    pub g_a: u32,
    /// Repeat: each orbit is walked as `segments` lines (one invocation each) recording
    /// `segment_steps` texels after `warm_steps` steps of warm-up (line `l` is segment
    /// `l % segments` of orbit `l / segments`).
    pub segments: u32,
    pub segment_steps: u32,
    pub warm_steps: u32,
    /// The most lattice steps any line walks (warm-up included): the walk takes
    /// `ceil(max_steps / CHUNK_STEPS)` dispatches.
    pub max_steps: u32,
}

impl SweepLines {
    /// Dispatches one azimuth's walks take, [`CHUNK_STEPS`] steps per line each.
    pub(crate) fn chunks(&self) -> u32 {
        self.max_steps.div_ceil(CHUNK_STEPS).max(1)
    }
}

fn gcd(a: u64, b: u64) -> u64 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// The uv angle of lattice step `(a, b)` on a `w` x `h` map, in [0, 2 pi).
fn uv_angle(step: [i32; 2], w: u32, h: u32) -> f64 {
    let angle = (f64::from(step[1]) / f64::from(h)).atan2(f64::from(step[0]) / f64::from(w));
    angle.rem_euclid(TAU)
}

/// The distance between two angles on the circle.
fn angle_gap(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

/// About `count` azimuths for a `w` x `h` map (fewer when targets share a step), sorted by angle.
pub(crate) fn sweep_directions(count: u32, w: u32, h: u32) -> Vec<SweepDirection> {
    let mut dirs: Vec<SweepDirection> = pick_steps(count.max(1), w, h)
        .into_iter()
        .map(|step| SweepDirection {
            step,
            angle: uv_angle(step, w, h),
            weight: 0.0,
        })
        .collect();
    dirs.sort_by(|x, y| x.angle.total_cmp(&y.angle));
    // Each azimuth stands for the arc nearer to it than to either neighbour.
    let n = dirs.len();
    for k in 0..n {
        let prev = dirs[(k + n - 1) % n].angle;
        let next = dirs[(k + 1) % n].angle;
        let here = dirs[k].angle;
        let width = if n == 1 {
            TAU
        } else {
            (angle_gap(here, prev) + angle_gap(next, here)) / 2.0
        };
        dirs[k].weight = width / TAU;
    }
    dirs
}

/// For each of `count` evenly spaced target angles, the shortest primitive step within a third of
/// the spacing (else the nearest in angle), without repeats.
fn pick_steps(count: u32, w: u32, h: u32) -> Vec<[i32; 2]> {
    let candidates: Vec<[i32; 2]> = (-MAX_STEP..=MAX_STEP)
        .flat_map(|a| (-MAX_STEP..=MAX_STEP).map(move |b| [a, b]))
        .filter(|&[a, b]| gcd(a.unsigned_abs().into(), b.unsigned_abs().into()) == 1)
        .collect();
    let spacing = TAU / f64::from(count);
    let mut steps: Vec<[i32; 2]> = Vec::new();
    for k in 0..count {
        let target = spacing * (f64::from(k) + 0.5);
        let cost = |s: &[i32; 2]| {
            let gap = angle_gap(uv_angle(*s, w, h), target);
            let short = f64::from(s[0].abs() + s[1].abs());
            if gap <= spacing / 3.0 {
                (0.0, short, gap)
            } else {
                (1.0, gap, short)
            }
        };
        let best = candidates.iter().min_by(|x, y| {
            cost(x)
                .partial_cmp(&cost(y))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        if let Some(&s) = best.filter(|s| !steps.contains(s)) {
            steps.push(s);
        }
    }
    steps
}

/// `(x, y)` with `x * b - y * a = 1` for a primitive `(a, b)` (extended Euclid).
fn euclid(a: i32, b: i32) -> [i32; 2] {
    // Solve x * b + y' * a = 1 with y' = -y.
    let (mut r0, mut r1) = (i64::from(b), i64::from(a));
    let (mut s0, mut s1) = (1i64, 0i64);
    let (mut t0, mut t1) = (0i64, 1i64);
    while r1 != 0 {
        let q = r0.div_euclid(r1);
        (r0, r1) = (r1, r0 - q * r1);
        (s0, s1) = (s1, s0 - q * s1);
        (t0, t1) = (t1, t0 - q * t1);
    }
    // r0 = s0 * b + t0 * a = +-1.
    let sign = r0.signum();
    [(s0 * sign) as i32, (-t0 * sign) as i32]
}

/// The lines of walk step `walk` over a `w` x `h` map under repeat (orbits) or clamp.
pub(crate) fn sweep_lines(walk: [i32; 2], w: u32, h: u32, repeat: bool) -> SweepLines {
    let [a, b] = walk;
    let euclid = euclid(a, b);
    if repeat {
        let (w64, h64) = (u64::from(w), u64::from(h));
        let g_a = gcd(u64::from(a.unsigned_abs()), w64);
        let shift = (i64::from(b).rem_euclid(h64 as i64) as u64 * (w64 / g_a)) % h64;
        let g_d = gcd(shift, h64);
        let period = (w64 / g_a) * (h64 / g_d);
        // A whole period of warm-up is exact; an orbit longer than LONG_ORBIT sides (sizes with
        // few common factors) would leave one invocation walking most of the map, so it is cut
        // into side-long segments, each warmed by LONG_ORBIT sides of profile only.
        let side = w64.max(h64);
        let (segments, segment_steps, warm_steps) = if period > LONG_ORBIT * side {
            (period.div_ceil(side), side, LONG_ORBIT * side)
        } else {
            (1, period, period)
        };
        return SweepLines {
            lines: (g_a * g_d * segments) as u32,
            c_min: 0,
            euclid,
            period: period as u32,
            g_a: g_a as u32,
            segments: segments as u32,
            segment_steps: segment_steps as u32,
            warm_steps: warm_steps as u32,
            max_steps: (warm_steps + segment_steps.min(period)) as u32,
        };
    }
    let corners = [
        (0, 0),
        (w as i64 - 1, 0),
        (0, h as i64 - 1),
        (w as i64 - 1, h as i64 - 1),
    ];
    let cs = corners.map(|(x, y)| x * i64::from(b) - y * i64::from(a));
    let (lo, hi) = (cs.iter().min(), cs.iter().max());
    let (lo, hi) = (lo.copied().unwrap_or(0), hi.copied().unwrap_or(0));
    // A line starts one step before entering the map along its last-entered moving axis and ends
    // at its last texel inside: at most (n - 1) / |w| + 2 steps for each moving axis.
    let axis = |n: u32, w: i32| (w != 0).then(|| (n - 1) / w.unsigned_abs() + 2);
    let max_steps = axis(w, a).into_iter().chain(axis(h, b)).max().unwrap_or(1);
    SweepLines {
        lines: (hi - lo + 1) as u32,
        c_min: lo as i32,
        euclid,
        period: 0,
        g_a: 1,
        segments: 1,
        segment_steps: 0,
        warm_steps: 0,
        max_steps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_cover_the_circle_with_weights_summing_to_one() {
        for (count, w, h) in [(64, 64, 64), (64, 3, 5), (16, 257, 129), (1, 1, 1)] {
            let dirs = sweep_directions(count, w, h);
            assert!(!dirs.is_empty() && dirs.len() <= count as usize);
            let total: f64 = dirs.iter().map(|d| d.weight).sum();
            assert!((total - 1.0).abs() < 1e-12, "{count} {w}x{h}: {total}");
            assert!(dirs.windows(2).all(|p| p[0].angle < p[1].angle));
        }
        // On a square map 64 targets get 64 distinct steps, none wider than a twentieth of a turn.
        let dirs = sweep_directions(64, 128, 128);
        assert_eq!(dirs.len(), 64);
        assert!(dirs.iter().all(|d| d.weight < 0.05), "{dirs:?}");
    }

    #[test]
    fn crossings_lie_on_the_step_in_order() {
        for walk in [[1, 0], [0, -1], [3, 2], [-5, 7], [2, -9], [-12, 11]] {
            let list = crossings(walk);
            let expected = (walk[0].abs() - 1).max(0) + (walk[1].abs() - 1).max(0);
            assert_eq!(list.len(), expected as usize, "{walk:?}");
            assert!(list.len() <= MAX_CROSSINGS);
            assert!(list
                .windows(2)
                .all(|p| p[0].fractions[0] < p[1].fractions[0]));
            for c in &list {
                // The crossing point, from the edge and from the step, is the same point.
                let t = f64::from(c.fractions[0]);
                let e = f64::from(c.fractions[1]);
                let on_edge = [
                    f64::from(c.offset[0]) + e * f64::from(c.along[0]),
                    f64::from(c.offset[1]) + e * f64::from(c.along[1]),
                ];
                let on_step = [t * f64::from(walk[0]), t * f64::from(walk[1])];
                assert!((on_edge[0] - on_step[0]).abs() < 1e-5, "{walk:?} {c:?}");
                assert!((on_edge[1] - on_step[1]).abs() < 1e-5, "{walk:?} {c:?}");
                assert!((0.0..1.0).contains(&e), "{walk:?} {c:?}");
            }
        }
    }

    #[test]
    fn euclid_solves_the_line_equation() {
        for a in -MAX_STEP..=MAX_STEP {
            for b in -MAX_STEP..=MAX_STEP {
                if gcd(a.unsigned_abs().into(), b.unsigned_abs().into()) == 1 {
                    let [x, y] = euclid(a, b);
                    assert_eq!(x * b - y * a, 1, "({a}, {b})");
                }
            }
        }
    }

    /// Walks every orbit from its named start and checks they partition the torus.
    #[test]
    fn repeat_orbits_partition_the_map() {
        for (w, h) in [(1, 1), (3, 5), (8, 8), (12, 18), (7, 4), (37, 23)] {
            for walk in [[1, 0], [0, -1], [3, 2], [-5, 7], [2, -9], [1, 1]] {
                let lines = sweep_lines(walk, w, h, true);
                let mut seen = vec![0u32; (w * h) as usize];
                for l in 0..lines.lines {
                    let (orbit, segment) = (l / lines.segments, l % lines.segments);
                    let (mut x, mut y) = ((orbit % lines.g_a) as i64, (orbit / lines.g_a) as i64);
                    let first = segment * lines.segment_steps;
                    let steps = lines.segment_steps.min(lines.period - first);
                    x = (x + i64::from(walk[0]) * i64::from(first)).rem_euclid(w.into());
                    y = (y + i64::from(walk[1]) * i64::from(first)).rem_euclid(h.into());
                    for _ in 0..steps {
                        seen[(y * i64::from(w) + x) as usize] += 1;
                        x = (x + i64::from(walk[0])).rem_euclid(w.into());
                        y = (y + i64::from(walk[1])).rem_euclid(h.into());
                    }
                }
                assert!(seen.iter().all(|&n| n == 1), "{w}x{h} {walk:?}: {seen:?}");
            }
        }
        // 37x23 along the diagonal: one orbit of 851 texels, cut into side-long segments.
        let long = sweep_lines([1, 1], 37, 23, true);
        assert_eq!(
            (long.period, long.segments, long.segment_steps),
            (851, 23, 37)
        );
        assert_eq!(long.warm_steps, 148);
    }

    /// The clamp walks' lengths (from the shader's `line_span`) stay within `max_steps`, which the
    /// host's dispatch count rests on.
    #[test]
    fn clamp_walks_fit_max_steps() {
        // The steps k at which p0 + k * rate lies in [0, n - 1] (`inside_steps` in the shader).
        let inside = |p0: i64, rate: i64, n: i64| -> Option<(i64, i64)> {
            if rate == 0 {
                return None;
            }
            let (a, b) = if rate > 0 {
                (-p0, n - 1 - p0)
            } else {
                (n - 1 - p0, -p0)
            };
            // floor(x / rate) for either sign (div_euclid floors only for rate > 0).
            let floor = |x: i64| (x as f64 / rate as f64).floor() as i64;
            Some((-floor(-a), floor(b)))
        };
        for (w, h) in [(5, 3), (64, 64), (37, 23), (256, 256)] {
            for walk in [[1, 0], [0, -1], [3, -2], [-1, 4], [-12, -1], [7, 6]] {
                let lines = sweep_lines(walk, w, h, false);
                let mut longest = 0;
                for l in 0..i64::from(lines.lines) {
                    let c = i64::from(lines.c_min) + l;
                    let origin = [
                        c * i64::from(lines.euclid[0]),
                        c * i64::from(lines.euclid[1]),
                    ];
                    let ix = inside(origin[0], walk[0].into(), w.into());
                    let iy = inside(origin[1], walk[1].into(), h.into());
                    let lo = ix.iter().chain(&iy).map(|r| r.0).max().unwrap_or(0);
                    let hi = ix.iter().chain(&iy).map(|r| r.1).min().unwrap_or(0);
                    if lo > hi {
                        continue;
                    }
                    let start = ix.iter().chain(&iy).map(|r| r.0 - 1).min().unwrap_or(0);
                    longest = longest.max(hi - start + 1);
                }
                assert!(longest > 0, "{w}x{h} {walk:?}");
                assert!(
                    longest <= i64::from(lines.max_steps),
                    "{w}x{h} {walk:?}: {longest} > {}",
                    lines.max_steps
                );
            }
        }
        // Under repeat: a whole period of warm-up, then the period (or one segment) recorded.
        let lines = sweep_lines([-12, -1], 256, 256, true);
        assert_eq!((lines.max_steps, lines.chunks()), (512, 2));
    }

    #[test]
    fn clamp_lines_reach_every_texel() {
        let (w, h) = (5, 3);
        for walk in [[1, 0], [0, 1], [3, -2], [-1, 4]] {
            let lines = sweep_lines(walk, w, h, false);
            let mut seen = [0u32; 15];
            for l in 0..lines.lines as i64 {
                let c = i64::from(lines.c_min) + l;
                for y in 0..i64::from(h) {
                    for x in 0..i64::from(w) {
                        if x * i64::from(walk[1]) - y * i64::from(walk[0]) == c {
                            seen[(y * 5 + x) as usize] += 1;
                        }
                    }
                }
            }
            assert!(seen.iter().all(|&n| n == 1), "{walk:?}");
        }
    }
}

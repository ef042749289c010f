//! Quadratic displacement maps (Kiglics, Valasek, Bálint, Bán, Kiglics et al.): for every texel a surface of revolution,
//! a cone continued by a revolved parabola, that the height field never pokes through; the map builder and a CPU
//! model of the tracer (the paper's Algorithm 1 with its stable solver, Algorithm 2).
//!
//! # Units and the stored profile
//! The paper works in the plane through the axis: `x` horizontal distance from the axis, `y` height above the apex,
//! upward. Here `x = r` is a distance in uv (one unit = the texture width, isotropic in (u, v) as rays are) and `y`
//! is normalized height (the map's [0, 1], upward), so nothing stored depends on the depth scale `s`. Texel
//! `[a, b, c, h]` holds the profile
//!
//! ```text
//! F(r) = b r / a                  0 <= r <= a   cone, slope b/a (height per uv)
//! F(r) = b + (r - a)(2c - r - a)  a <= r <= c   the paper's y = -(r - c)^2 + b + (c - a)^2
//! F(r) = b + (c - a)^2            r >= c        flat cap at the parabola's apex
//! ```
//!
//! - `a` (uv, > 0): where the cone meets the parabola; `b` (normalized height, >= 0): the cone's rim height;
//! - `c` (uv, >= a): the parabola's apex; the cap lies `b + (c - a)^2` above the apex of the profile;
//! - `h`: the texel's own height, the paper's fourth channel. The apex is not at `h` (see below); a one-texture port
//!   can rebuild the bilinear surface from this channel, the CPU model reads the height field itself.
//!
//! The paper's form fixes the parabola's curvature: in these units it falls by the whole height range over one uv
//! squared, i.e. it is nearly straight over a few texels of a large map. The depth scale enters only in the tracer:
//! in depth units (uv, downward) the bound below the ray is `depth(q) - s F(r)`.
//!
//! # The guarantee
//! Let `B` be the bilinear surface (the default ground truth) under the map's addressing and `T` the closed
//! footprint `[i, i+1]/W x [j, j+1]/H` of texel `(i, j)`. For every `q` in `T` and every `x`:
//! `B(x) <= B(q) + F_T(|x - q|)`, with `|x - q|` measured on the torus under `Repeat`. So nothing of the surface
//! lies above the solid of revolution `B(q) + F_T` around the vertical through `q`, and a ray above `B(q)` can move
//! until it meets that solid; the 2D reduction is exact because the ray's own vertical is the axis. Under `Clamp`
//! the clamped surface is `B(pi(x))`, with `pi` the (1-Lipschitz) projection onto the rectangle of texel centres,
//! which maps any `q` outside the map into the footprint of the texel it is clamped to, so the bound holds there too
//! because `F` is non-decreasing.
//!
//! # Building (sections 3.1 and 4.1)
//! Per texel, `U(r)` bounds `sup { B(x) - B(q) : q in T, |x - q| <= r }` by two facts: `B(x) <= max h_t` over the
//! texels `t` whose bilinear support (the open box of one texel around their centre) comes within `r` of `T`, and
//! `B(q) >= h_lo`, the minimum of `B` on `T` (the least of its 9 corner, edge-midpoint and centre values); and, for
//! `r` up to one texel, `B(x) - B(q) <= L r` with `L` the steepest bilinear gradient of the 4x4 cells around `T`.
//! This disk maximum is the paper's radial function `m_uv`, taken over disks rather than annuli (so it is
//! monotone and the bound needs no outer domain) and over the footprint rather than the centre (so it holds for
//! every point of the texel). Its upper concave hull (the paper's "upper convex bound") comes straight from a max
//! pyramid, without listing `m_uv`: nodes are walked nearest first, a node whose corner point (nearest distance,
//! largest height) lies under the hull is dropped, and one no larger than `ACCEPT_RATIO` of its distance enters as
//! that corner point, which dominates all its texels; each texel starts from the previous one's vertex nodes. So
//! the hull is never below the exact one and never above it stretched by `1 + ACCEPT_RATIO` in `r`. The fit: the cone is the hull's first edge (`a` its end, `b` its
//! height: no cone from the apex can be lower), and `c` is the least value lifting the parabola above every further
//! hull vertex, the paper's `c = max c_j` with `c_j = (r_j + a)/2 + (m_j - b)/(2 (r_j - a))`. The profile is concave
//! and the hull linear between vertices, so clearing the vertices clears the hull. Values are rounded to `f32`
//! upward where that keeps the bound.
//!
//! # Tracing (Algorithm 1)
//! The ray `p(z)` moves `lambda = |(dx, dy)| / dz` uv sideways per unit of depth. At `q = (u(z), v(z))` the gap is
//! `g = s (1 - B(q)) - z`; while `g > eps` (and steps remain) it advances `z += t` with `t` from [`quadric_step`]:
//! the cone if the ray meets it (`lambda g <= a + s b lambda`, then `t = g a / (a + s b lambda)`), else the smaller
//! root of `s lambda^2 t^2 - (1 + 2 s c lambda) t + (g - s (b + a^2 - 2 a c)) = 0` by Algorithm 2 if it lies on the
//! rising part (`lambda t <= c`), else the cap, `t = g - s (b + (c - a)^2)`. The paper needs no refinement; a capped
//! ray gets `refine_steps` of bisection against `B` over one texel of travel past where it stopped, if that
//! brackets a crossing.
//!
//! # Porting to GLSL (where `f32` matters)
//! Store the map as RGBA32F (a 16-bit float would need the same upward rounding as `round_up`). Compute `B(q)`
//! exactly, from four texel fetches and two lerps as [`surface_depth`] does, not with the hardware linear filter,
//! whose 8-bit weights on many GPUs can lift it above the bound; build from `hf.quantized_unorm16()` if heights
//! are R16_UNORM. `g = s (1 - B) - z` cancels near the hit, to about `1e-7 s` in `f32`, hence [`HIT_EPSILON_DEPTH`]. Test
//! the discriminant before `sqrt` (GLSL leaves a negative root undefined); no other branch can see a NaN.
//!
//! # Departures from the paper, all for the guarantee above
//! The apex sits on `B(q)` under the ray, not on the texel's height (the paper's bound is exact only at texel
//! centres); the profile ends in a flat cap where the paper's parabola falls again and a missed parabola means an
//! infinite step (safe only inside a finite domain); the paper's height ratio, which limits the cone on the raw
//! `m_uv`, has no role once the hull is concave (the cone is its first edge).

use std::sync::{Mutex, PoisonError};
use std::thread;

use super::cone_map::footprint_range;
use super::pyramid::{covered_range, MaxPyramid};
use super::reference::{surface_depth, Address, RefRay, SurfaceModel};
use super::stable_quadratic::smaller_root;
use super::Heightfield;

/// Relative slope difference under which hull vertices count as collinear with the cone's edge.
const COLLINEAR: f64 = 1e-9;

/// A pyramid node no larger than this fraction of its distance enters the hull as its corner point instead of
/// being searched: the bound rises by at most this factor there, and the search stops growing with the resolution.
const ACCEPT_RATIO: f64 = 0.5;

/// A ray counts as on the surface once its gap would move it less than this many texels, down or sideways.
pub const HIT_EPSILON_TEXELS: f64 = 1e-3;

/// ... or once its gap is below this fraction of the depth scale, where `f32` can no longer resolve it.
pub const HIT_EPSILON_DEPTH: f64 = 1e-6;

/// Per texel `[a, b, c, h]` (see the module docs), row-major with texel `(i, j)` at `j * width + i`.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadricMap {
    /// Texels along u, the height field's width.
    pub width: u32,
    /// Texels along v, the height field's height.
    pub height: u32,
    /// `[a, b, c, h]` per texel: `a` and `c` in uv, `b` and `h` in normalized height (upward), see the module docs.
    pub texels: Vec<[f32; 4]>,
}

impl QuadricMap {
    /// Builds the map of `hf` for the given addressing (rows in parallel on all cores). For a GPU that stores the
    /// heights as `R16_UNORM`, build from `hf.quantized_unorm16()` so that the bound holds for what it samples.
    pub fn build(hf: &Heightfield, address: Address) -> QuadricMap {
        let builder = Builder::new(hf, address);
        let mut texels = vec![[0.0f32; 4]; hf.texel_count()];
        let threads = thread::available_parallelism().map_or(1, |n| n.get());
        // Rows are handed out one at a time, so threads that draw cheap rows take more of them.
        let rows = Mutex::new((0..).zip(texels.chunks_mut(hf.width() as usize)));
        thread::scope(|scope| {
            for _ in 0..threads {
                scope.spawn(|| loop {
                    let next = rows.lock().unwrap_or_else(PoisonError::into_inner).next();
                    let Some((j, row)) = next else { break };
                    builder.fill_row(j, row);
                });
            }
        });
        QuadricMap {
            width: hf.width(),
            height: hf.height(),
            texels,
        }
    }

    /// Texel `(i, j)`; panics if out of range.
    pub fn get(&self, i: u32, j: u32) -> [f32; 4] {
        assert!(
            i < self.width && j < self.height,
            "texel ({i}, {j}) outside {}x{}",
            self.width,
            self.height
        );
        self.texels[j as usize * self.width as usize + i as usize]
    }

    /// The texel under uv point `(u, v)`, addressed like a nearest-filtered texture fetch.
    fn fetch(&self, u: f64, v: f64, address: Address) -> [f32; 4] {
        let index = |x: f64, n: u32| wrap_or_clamp((x * f64::from(n)).floor() as i64, n, address);
        self.get(index(u, self.width), index(v, self.height))
    }
}

/// `F(r)`, the profile of texel `[a, b, c, h]` at uv distance `r >= 0`, in normalized height above the apex.
pub fn profile_height(texel: [f32; 4], r: f64) -> f64 {
    let [a, b, c] = [texel[0], texel[1], texel[2]].map(f64::from);
    if r <= a {
        b * r / a
    } else {
        let x = r.min(c);
        b + (x - a) * (2.0 * c - x - a)
    }
}

/// One step of Algorithm 1: how far the ray may go down (in depth, uv units) from a point `gap` above the
/// surface, moving `lambda` uv sideways per unit of depth, before it meets the profile of `texel` scaled by `s`.
/// Never more than `gap`. Every quantity is finite for `lambda = 0` (vertical rays take the cone branch).
pub fn quadric_step(gap: f64, lambda: f64, s: f64, texel: [f32; 4]) -> f64 {
    let [a, b, c] = [texel[0], texel[1], texel[2]].map(f64::from);
    // The ray meets the cone iff at r = a it is at or below the rim: lambda gap <= a + s b lambda (times a > 0).
    let rim = a + s * b * lambda;
    if lambda * gap <= rim {
        return (gap * a / rim).min(gap);
    }
    // (gap - t) / s = b + (lambda t - a)(2c - lambda t - a), as A t^2 + B t + C = 0 with A >= 0, B < 0, C > 0.
    let qa = s * lambda * lambda;
    let qb = -(1.0 + 2.0 * s * c * lambda);
    let qc = gap - s * (b + a * a - 2.0 * a * c);
    let t = smaller_root(qa, qb, qc);
    if lambda * t <= c {
        t
    } else {
        // No crossing on the rising part: the ray passes the apex circle above the cap, then meets the cap.
        (gap - s * (b + (c - a) * (c - a))).max(0.0)
    }
}

/// What [`trace_quadric_cpu`] reports: the final depth, the quadric steps taken, and whether the budget ran out
/// before the ray reached the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadricTrace {
    /// Final depth along the ray below the top plane (depth units, `s * (1 - h)` at the surface), after any refinement.
    pub z: f64,
    /// Quadric steps taken (at most `max_steps`; bisection steps are not counted).
    pub steps: u32,
    /// `true` when `max_steps` ran out before the gap fell below the hit epsilons.
    pub capped: bool,
}

/// Traces `ray` with the quadric map: at most `max_steps` steps of Algorithm 1, then, for a capped ray only,
/// `refine_steps` of bisection against the bilinear surface (see the module docs). `map` must be built from `hf`
/// with the same addressing. Converged rays stop at or above the exact bilinear hit.
pub fn trace_quadric_cpu(
    hf: &Heightfield,
    map: &QuadricMap,
    ray: &RefRay,
    depth_scale: f64,
    address: Address,
    max_steps: u32,
    refine_steps: u32,
) -> QuadricTrace {
    let tracer = Tracer::new(hf, map, ray, depth_scale, address);
    tracer.run(max_steps, refine_steps, quadric_step, &mut |_| {})
}

/// The loop of Algorithm 1 with its fixed inputs; the step rule is a parameter so that tests can run cone stepping
/// over the same bound, and `observe` sees every depth the loop reaches.
struct Tracer<'a> {
    hf: &'a Heightfield,
    map: &'a QuadricMap,
    ray: RefRay,
    s: f64,
    address: Address,
    tx: f64,
    ty: f64,
    lambda: f64,
    /// `max(W, H)`: texels per uv along the longer axis.
    texels: f64,
}

impl<'a> Tracer<'a> {
    fn new(
        hf: &'a Heightfield,
        map: &'a QuadricMap,
        ray: &RefRay,
        s: f64,
        address: Address,
    ) -> Self {
        assert_eq!(
            (map.width, map.height),
            (hf.width(), hf.height()),
            "quadric map and height field differ in size"
        );
        assert!(ray.dz > 0.0 && ray.dz.is_finite(), "bad ray {ray:?}");
        assert!(s >= 0.0 && s.is_finite(), "bad depth scale {s}");
        let (tx, ty) = (ray.dx / ray.dz, ray.dy / ray.dz);
        Self {
            hf,
            map,
            ray: *ray,
            s,
            address,
            tx,
            ty,
            lambda: tx.hypot(ty),
            texels: f64::from(hf.width().max(hf.height())),
        }
    }

    fn uv(&self, z: f64) -> (f64, f64) {
        (self.ray.u0 + z * self.tx, self.ray.v0 + z * self.ty)
    }

    /// Surface depth minus ray depth at `z`: positive while the ray is above the bilinear surface.
    fn gap(&self, z: f64) -> f64 {
        let (u, v) = self.uv(z);
        surface_depth(self.hf, u, v, self.s, SurfaceModel::Bilinear, self.address) - z
    }

    fn run(
        &self,
        max_steps: u32,
        refine_steps: u32,
        step: impl Fn(f64, f64, f64, [f32; 4]) -> f64,
        observe: &mut dyn FnMut(f64),
    ) -> QuadricTrace {
        // The gap at which the rest of the way is under HIT_EPSILON_TEXELS down and sideways.
        let eps = (HIT_EPSILON_TEXELS / (self.texels * self.lambda.max(1.0)))
            .max(HIT_EPSILON_DEPTH * self.s);
        let (mut z, mut steps) = (0.0, 0);
        let capped = loop {
            let gap = self.gap(z);
            if gap <= eps {
                break false;
            }
            if steps == max_steps {
                break true;
            }
            let (u, v) = self.uv(z);
            let texel = self.map.fetch(u, v, self.address);
            z = (z + step(gap, self.lambda, self.s, texel)).min(self.s);
            steps += 1;
            observe(z);
        };
        if capped {
            z = self.refine(z, refine_steps);
        }
        QuadricTrace { z, steps, capped }
    }

    /// Bisection between the last safe depth and one texel of travel beyond it (never past `s`), if the far end is
    /// under the surface; otherwise the ray stays where the budget left it.
    fn refine(&self, z: f64, steps: u32) -> f64 {
        if steps == 0 {
            return z;
        }
        let reach = 1.0 / (self.texels * self.lambda.max(1e-12));
        let mut hi = (z + self.gap(z).max(0.0) + reach).min(self.s);
        if self.gap(hi) > 0.0 {
            return z;
        }
        let mut lo = z;
        for _ in 0..steps {
            let mid = 0.5 * (lo + hi);
            if self.gap(mid) <= 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }
}

/// Index `k` mapped into `[0, n)` by the addressing mode.
fn wrap_or_clamp(k: i64, n: u32, address: Address) -> u32 {
    match address {
        Address::Repeat => k.rem_euclid(i64::from(n)) as u32,
        Address::Clamp => k.clamp(0, i64::from(n) - 1) as u32,
    }
}

/// The smallest `f32` at or above `x` (`x` finite, non-negative): rounding that never lowers a bound.
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) >= x {
        f
    } else {
        f32::from_bits(f.to_bits() + 1)
    }
}

/// A max pyramid node: level (0 = the texels) and indices.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Node(usize, u32, u32);

/// A hull vertex: the point `(r, value)` and the node it is the corner point of (none for the anchor).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Vertex {
    r: f64,
    value: f64,
    source: Option<Node>,
}

/// The upper concave, non-decreasing hull of points `(r, value)` with `r > 0`, `value > 0`, anchored at `(0, 0)`
/// and flat beyond its last vertex. Vertices are strictly increasing in both coordinates with strictly falling
/// slopes.
#[derive(Debug, Clone)]
struct Hull {
    vertices: Vec<Vertex>,
}

impl Hull {
    fn new() -> Self {
        let anchor = Vertex {
            r: 0.0,
            value: 0.0,
            source: None,
        };
        Self {
            vertices: vec![anchor],
        }
    }

    /// The hull at `r >= 0`.
    fn eval(&self, r: f64) -> f64 {
        let k = self.vertices.partition_point(|p| p.r <= r);
        let p = self.vertices[k - 1];
        match self.vertices.get(k) {
            None => p.value,
            Some(q) => p.value + (q.value - p.value) * ((r - p.r) / (q.r - p.r)),
        }
    }

    /// Adds a vertex that lies above the hull.
    fn insert(&mut self, vertex: Vertex) {
        debug_assert!(vertex.r > 0.0 && vertex.value > self.eval(vertex.r));
        let pts = &mut self.vertices;
        let mut k = pts.partition_point(|p| p.r < vertex.r);
        if pts.get(k).is_some_and(|p| p.r == vertex.r) {
            pts[k] = vertex;
        } else {
            pts.insert(k, vertex);
        }
        // Vertices to the right no higher than the new one are under its flat continuation.
        let higher = pts[k + 1..].partition_point(|p| p.value <= vertex.value);
        pts.drain(k + 1..k + 1 + higher);
        while k + 2 < pts.len() && !concave(pts[k], pts[k + 1], pts[k + 2]) {
            pts.remove(k + 1);
        }
        while k >= 2 && !concave(pts[k - 2], pts[k - 1], pts[k]) {
            pts.remove(k - 1);
            k -= 1;
        }
    }
}

/// Whether `q` lies strictly above the segment `p`-`w` (with `p.0 < q.0 < w.0`): a strict concave turn.
fn concave(p: Vertex, q: Vertex, w: Vertex) -> bool {
    (q.value - p.value) * (w.r - q.r) > (w.value - q.value) * (q.r - p.r)
}

/// What the radial bound of one texel rests on: its indices, the least bilinear height on its footprint and the
/// steepest bilinear gradient (height per uv) within one texel of it.
struct TexelBound {
    i: u32,
    j: u32,
    h_lo: f64,
    lipschitz: f64,
}

/// One axis of the max pyramid as the search sees it: per level and node index, the level-0 texel range the node
/// covers (for distances) and, from level 1 up, the range of its children one level down.
struct PyramidAxis {
    texels: u32,
    /// The width of one texel in uv.
    texel_uv: f64,
    wrap: bool,
    spans: Vec<Vec<(u32, u32)>>,
    children: Vec<Vec<(u32, u32)>>,
}

impl PyramidAxis {
    /// `lens[level]`: the nodes along this axis at each level, finest first.
    fn new(lens: &[u32], wrap: bool) -> Self {
        let mut spans: Vec<Vec<(u32, u32)>> = vec![(0..lens[0]).map(|k| (k, k)).collect()];
        let mut children = vec![Vec::new()];
        for pair in lens.windows(2) {
            let (fine, coarse) = (pair[0], pair[1]);
            let kids: Vec<(u32, u32)> = (0..coarse)
                .map(|c| covered_range(c, coarse, fine))
                .collect();
            let below = &spans[spans.len() - 1];
            spans.push(
                kids.iter()
                    .map(|&(f, l)| (below[f as usize].0, below[l as usize].1))
                    .collect(),
            );
            children.push(kids);
        }
        Self {
            texels: lens[0],
            texel_uv: 1.0 / f64::from(lens[0]),
            wrap,
            spans,
            children,
        }
    }

    /// The uv gap between footprint `[i, i+1]` and the supports `(k0 - 1/2, k1 + 3/2)` of the texels `k0..=k1`
    /// that node `c` of `level` covers (the shortest way round under `Repeat`).
    fn gap(&self, i: u32, level: usize, c: u32) -> f64 {
        let (k0, k1) = self.spans[level][c as usize];
        let after = f64::from(k0) - 1.5 - f64::from(i);
        let before = f64::from(i) - 1.5 - f64::from(k1);
        let mut gap = after.max(before).max(0.0);
        if self.wrap {
            let n = f64::from(self.texels);
            gap = gap
                .min((after + n).max(before - n).max(0.0))
                .min((after - n).max(before + n).max(0.0));
        }
        gap * self.texel_uv
    }
}

/// Shared state of the build: the map, its max pyramid and the pyramid's axes.
struct Builder<'a> {
    hf: &'a Heightfield,
    address: Address,
    pyramid: MaxPyramid,
    axis_u: PyramidAxis,
    axis_v: PyramidAxis,
    /// The radius up to which the gradient bound holds: one texel along the shorter texel side.
    lip_radius: f64,
}

impl<'a> Builder<'a> {
    fn new(hf: &'a Heightfield, address: Address) -> Self {
        let pyramid = MaxPyramid::build(hf);
        let wrap = address == Address::Repeat;
        let widths: Vec<u32> = pyramid.levels().iter().map(|l| l.width).collect();
        let heights: Vec<u32> = pyramid.levels().iter().map(|l| l.height).collect();
        Self {
            hf,
            address,
            axis_u: PyramidAxis::new(&widths, wrap),
            axis_v: PyramidAxis::new(&heights, wrap),
            pyramid,
            lip_radius: 1.0 / f64::from(hf.width().max(hf.height())),
        }
    }

    /// Height of texel `(i, j)` for any integers, addressed.
    fn at(&self, i: i64, j: i64) -> f64 {
        let i = wrap_or_clamp(i, self.hf.width(), self.address);
        let j = wrap_or_clamp(j, self.hf.height(), self.address);
        f64::from(self.hf.get(i, j))
    }

    fn texel_bound(&self, i: u32, j: u32) -> TexelBound {
        let (ii, jj) = (i64::from(i), i64::from(j));
        let h = |di: i64, dj: i64| self.at(ii + di, jj + dj);
        let (h_lo, _) = footprint_range(h);
        // The 4x4 cells between texel centres i-2..i+2 cover the footprint grown by one texel.
        let (w, ht) = (f64::from(self.hf.width()), f64::from(self.hf.height()));
        let mut lipschitz: f64 = 0.0;
        for k in -2..=1 {
            for l in -2..=1 {
                let [h00, h10, h01, h11] = [h(k, l), h(k + 1, l), h(k, l + 1), h(k + 1, l + 1)];
                let gu = w * (h10 - h00).abs().max((h11 - h01).abs());
                let gv = ht * (h01 - h00).abs().max((h11 - h10).abs());
                lipschitz = lipschitz.max(gu.hypot(gv));
            }
        }
        TexelBound {
            i,
            j,
            h_lo,
            lipschitz,
        }
    }

    /// The uv distance from the texel's footprint to the supports of the node's texels.
    fn distance(&self, tb: &TexelBound, Node(level, ci, cj): Node) -> f64 {
        let du = self.axis_u.gap(tb.i, level, ci);
        let dv = self.axis_v.gap(tb.j, level, cj);
        (du * du + dv * dv).sqrt()
    }

    /// Where `U` can first reach `value` among points at least `distance` away: no nearer than `value / L` while
    /// the gradient bound holds.
    fn corner(&self, tb: &TexelBound, distance: f64, value: f64) -> f64 {
        let gradient_reach = if tb.lipschitz * self.lip_radius <= value {
            self.lip_radius
        } else {
            value / tb.lipschitz
        };
        distance.max(gradient_reach)
    }

    /// The uv diagonal of the texels node covers: how much farther than the node's distance its texels may lie.
    fn extent(&self, Node(level, ci, cj): Node) -> f64 {
        let span = |axis: &PyramidAxis, c: u32| {
            let (k0, k1) = axis.spans[level][c as usize];
            f64::from(k1 - k0 + 1) * axis.texel_uv
        };
        span(&self.axis_u, ci).hypot(span(&self.axis_v, cj))
    }

    /// Fills row `j` of the map. Neighbours have similar hulls, so each texel starts from the vertex nodes of the one
    /// before: a good early hull prunes most of the pyramid.
    fn fill_row(&self, j: u32, row: &mut [[f32; 4]]) {
        let mut seeds = Vec::new();
        for (i, texel) in (0..).zip(row) {
            let hull = self.radial_hull(i, j, &seeds);
            let [a, b, c] = fit_profile(&hull);
            *texel = [a, b, c, self.hf.get(i, j)];
            seeds = hull.vertices.iter().filter_map(|v| v.source).collect();
        }
    }

    /// A concave majorant of texel `(i, j)`'s radial bound `U`, exact but where far nodes stand in for their
    /// texels. The corner points of the `seeds` go in first (a coarse seed too near to stand in for its texels
    /// here is left to the search).
    fn radial_hull(&self, i: u32, j: u32, seeds: &[Node]) -> Hull {
        let tb = self.texel_bound(i, j);
        let mut hull = Hull::new();
        for &node in seeds {
            let dist = self.distance(&tb, node);
            if node.0 == 0 || self.extent(node) <= ACCEPT_RATIO * dist {
                if let Some(vertex) = self.corner_above(&tb, node, dist, &hull) {
                    hull.insert(vertex);
                }
            }
        }
        let root = Node(self.pyramid.level_count() as usize - 1, 0, 0);
        self.visit(&tb, root, self.distance(&tb, root), &mut hull);
        hull
    }

    /// The corner point of `node` (nearest distance, largest value) if it lies above the hull; it dominates the
    /// points of all the node's texels.
    fn corner_above(&self, tb: &TexelBound, node: Node, dist: f64, hull: &Hull) -> Option<Vertex> {
        let Node(level, ci, cj) = node;
        let value = f64::from(self.pyramid.level(level as u32).get(ci, cj)) - tb.h_lo;
        let r = self.corner(tb, dist, value);
        let source = Some(node);
        (value > 0.0 && hull.eval(r) < value).then_some(Vertex { r, value, source })
    }

    /// Adds `node` unless its corner point lies under the hull: as that point if the node is a texel or small for
    /// its distance, else through its children, nearest first.
    fn visit(&self, tb: &TexelBound, node: Node, dist: f64, hull: &mut Hull) {
        let Some(vertex) = self.corner_above(tb, node, dist, hull) else {
            return;
        };
        let Node(level, ci, cj) = node;
        if level == 0 || self.extent(node) <= ACCEPT_RATIO * dist {
            hull.insert(vertex);
            return;
        }
        let (i0, i1) = self.axis_u.children[level][ci as usize];
        let (j0, j1) = self.axis_v.children[level][cj as usize];
        let mut children = [(0.0, node); 9];
        let mut n = 0;
        for cj in j0..=j1 {
            for ci in i0..=i1 {
                let child = Node(level - 1, ci, cj);
                children[n] = (self.distance(tb, child), child);
                n += 1;
            }
        }
        children[..n].sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
        for &(dist, child) in &children[..n] {
            self.visit(tb, child, dist, hull);
        }
    }
}

/// `[a, b, c]` of the lowest profile of the paper's form above `hull`: the cone along the first edge, the parabola
/// through its end clearing every further vertex. A hull with no edge (nothing anywhere rises above the texel's
/// lowest point) gets the flat profile `[1, 0, 1]`.
fn fit_profile(hull: &Hull) -> [f32; 3] {
    let points: Vec<(f64, f64)> = hull.vertices[1..].iter().map(|v| (v.r, v.value)).collect();
    let Some(&(r1, v1)) = points.first() else {
        return [1.0, 0.0, 1.0];
    };
    // Vertices on the first edge's line but for rounding (points on the gradient bound's line L r are) extend the
    // cone; its slope is the steepest of them, so the line stays at or above the first edge, hence above the whole
    // concave hull.
    let (mut r_end, mut slope) = (r1, v1 / r1);
    for &(r, v) in &points[1..] {
        if v / r < slope * (1.0 - COLLINEAR) {
            break;
        }
        (r_end, slope) = (r, slope.max(v / r));
    }
    // Rounding a up keeps the cone's last vertex under the cone: cut short, the parabola would have to climb at
    // the cone's slope.
    let a = round_up(r_end);
    let b = round_up(slope * f64::from(a));
    let (af, bf) = (f64::from(a), f64::from(b));
    let c = points
        .iter()
        .filter(|p| p.0 > af)
        .map(|&(r, v)| 0.5 * (r + af) + (v - bf) / (2.0 * (r - af)))
        .fold(af, f64::max);
    [a, b, round_up(c)]
}

#[cfg(test)]
#[path = "quadric_map_tests.rs"]
mod tests;

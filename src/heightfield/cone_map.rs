//! Cone maps for cone step mapping (Dummer 2006, *conservative*) and relaxed cone stepping (Policarpo and
//! Oliveira 2007, *relaxed*), built exactly on the CPU, and CPU models of both tracers' stepping that the GLSL
//! methods port line for line (the GLSL adds the exact bilinear leaf, shaders/include/cone.glsl). These
//! builders are the reference: `render::cone_map_pass` builds the conservative map on the GPU for frames
//! and benches and is tested against them.
//!
//! # Units
//! A cone map stores per texel `p` a ratio `c >= 0`: horizontal uv per unit of normalised height. Its cone has
//! the apex at the texel centre `p_c` on the surface, height `h(p)`, and opens upward: at height `h' > h(p)`
//! it has radius `c * (h' - h(p))`. The ratio is independent of the depth scale `s`: in depth units the cone
//! widens by `c / s` per unit of depth. Ratios are capped at [`CONE_RATIO_MAX`] (a texel at the global
//! maximum has nothing to limit it) and rounded down to `f32`, so a stored cone is never wider than proven.
//!
//! # Surface model
//! Both maps and both tracers use a *nearest* (box) surface: a height constant over each half-open texel
//! box, extended by `Repeat` tiling or by `Clamp` (border rows and columns extend to infinity). The cones are
//! exact for that surface, so both tracers find its nearest-model reference hit exactly. [`ConeMap::build`]
//! takes as that box surface the *bilinear bound* of the height field ([`bilinear_box_bound`]: per texel the
//! highest point of the bilinear surface over the texel's box), which lies on or above the bilinear surface
//! everywhere; so neither tracer passes the first bilinear hit, and the GPU methods end with an exact
//! ray/bilinear-patch test in the box where the stepping stopped (continuing when it finds nothing there).
//! The height field's own boxes do not bound the bilinear surface (between a low texel and a high
//! neighbour it rises above the low texel's box): cones built on them let grazing rays stop on a box top the
//! bilinear surface passes under, a gross miss. [`ConeMap::build_box`] still builds those, for tests.
//!
//! # Conservative cone
//! `c(p) = min over texels q with h(q) > h(p) of dist(p_c, box(q)) / (h(q) - h(p))`, with `box(q)` closed and
//! distances in uv on the plane (all tiles under `Repeat`; under `Clamp` the border copies are never nearer
//! than the border texels themselves). No point of any box higher than the ray then lies inside the cone.
//!
//! # Relaxed cone
//! A step may now enter the solid but never leave it again, so the step that first lands inside brackets
//! the first hit with a single crossing, which binary search then finds. The *reach* `r(q, S)` of texel `q` in
//! direction sector `S` is the distance from `box(q)` to the nearest region lower than `q` that a straight
//! line leaving `box(q)` with a direction in `S` can enter (capped at 0.25 uv or 16 texels, whichever is
//! less): a ray inside `q`'s solid cannot
//! get out within that distance. Sectors: 16, four per quadrant, cut at slopes 1/3, 1 and 3. Then
//! `c(p) = max(conservative c(p), min over q with h(q) > h(p) of
//! (dist(p_c, box(q)) + min over sectors S from box(p) to box(q) of r(q, S)) / (h(q) - h(p)))`,
//! with reach 0 for the clamp border's copies. Proof sketch: if a step from `x` in `box(p)` entered at `w` in
//! `q` and left at `y`, then `y` is lower than `q` and in the sector of `w - x`, so `|y - x| >= |w - x| +
//! r(q, S)`, while every point of a step obeys `|y - x| + |x - p_c| <= c (h - h(p))` with `h < h(q)`: a
//! contradiction. On the box surface a ray can slip out of a stair sideways into any slightly lower
//! neighbour, so on rough or finely detailed maps reaches are short and relaxed cones are only a little
//! wider than conservative ones (fbm: ratios +5%, steps -4%); plateaus with clean edges relax most.
//! Policarpo's own construction (rays from the top plane only) is wider but guarantees nothing.
//!
//! # Tracing and the ray offset inside a texel
//! The cone of a texel has its apex at the texel centre, but the ray point `x` can be anywhere in the texel.
//! The tracer subtracts the offset: with `delta = |x - p_c|`, horizontal travel `t` per unit depth and the
//! ray at depth `z` above the cell's floor `d = s (1 - h(p))`, the cone step is
//! `dz = max(c (d - z) - s delta, 0) / (t s + c)` (Dummer's `c (d - z) / (t s + c)` when `delta = 0`), which
//! keeps `|y - x| + delta <= c (h - h(p))` along the step. Near the surface that step vanishes, so the tracer
//! also takes the *cell step*: to the cell's exit or floor, whichever comes first (the box is flat, so this is
//! always safe). Each iteration takes the longer of the two, so every iteration leaves the cell or lands on
//! its floor and the walk cannot stall. Under `Clamp`, cells outside the map are merged half-lines (the
//! surface does not change along them); there the conservative cone uses the offset only along axes inside
//! the map (a contraction argument), and the relaxed tracer takes cell steps only.
//!
//! Invariant of [`ConeMap`]: `ratio.len() == width * height`; every ratio is finite, in `[0, CONE_RATIO_MAX]`.

use super::reference::{Address, RefRay};
use super::Heightfield;

#[path = "cone_map_search.rs"]
mod search;
#[path = "cone_map_sectors.rs"]
mod sectors;

use search::{par_rows, Field, ReachPyramid};
pub use search::{REACH_CAP_TEXELS, REACH_CAP_UV};

/// The largest stored ratio (uv per unit height), given to texels nothing limits (the global maximum) and
/// to any wider cone. At depth scale 0.01 it still means a cone 6400 times wider than deep.
pub const CONE_RATIO_MAX: f32 = 64.0;

/// Which cone a [`ConeMap`] holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ConeKind {
    /// Dummer's cone step mapping: cones hold no surface at all.
    Conservative,
    /// Policarpo and Oliveira's relaxed cones: a ray stepping through a cone crosses the surface at most once.
    Relaxed,
}

/// Per-texel cone ratios of one height field (see the module docs for the definitions).
#[derive(Debug, Clone, PartialEq)]
pub struct ConeMap {
    /// Conservative (Dummer) or relaxed (Policarpo and Oliveira) cones.
    pub kind: ConeKind,
    /// Texels along u, the height field's width.
    pub width: u32,
    /// Texels along v, the height field's height.
    pub height: u32,
    /// Row-major like [`Heightfield`]: texel `(i, j)` at `j * width + i`.
    pub ratio: Vec<f32>,
    /// The heights of the box surface the cones are exact for (the cones' apexes and the tracers'
    /// floors), row-major: the bilinear bound for [`ConeMap::build`], the field itself for
    /// [`ConeMap::build_box`].
    pub surface: Vec<f32>,
}

impl ConeMap {
    /// Builds the map of `kind` for the bilinear surface of `hf` under `address`: the cones of the box
    /// surface [`bilinear_box_bound`], which is on or above the bilinear surface everywhere.
    pub fn build(hf: &Heightfield, kind: ConeKind, address: Address) -> ConeMap {
        ConeMap::build_box(&bilinear_box_bound(hf, address), kind, address)
    }

    /// Builds the map of `kind` for the box surface of `hf` itself under `address` on all cores. Both kinds
    /// are exact minima computed by pruned searches over the max pyramid (the tests compare them with brute
    /// force bit for bit).
    pub fn build_box(hf: &Heightfield, kind: ConeKind, address: Address) -> ConeMap {
        let field = Field::new(hf, address);
        let cap = f64::from(CONE_RATIO_MAX);
        let width = hf.width();
        let conservative = par_rows(hf.height(), |j| {
            (0..width)
                .map(|i| search::conservative(&field, i, j, cap))
                .collect()
        });
        let ratio = match kind {
            ConeKind::Conservative => conservative,
            ConeKind::Relaxed => {
                let texels = par_rows(hf.height(), |j| {
                    (0..width)
                        .flat_map(|i| search::reach(&field, i, j))
                        .collect()
                });
                let reach = ReachPyramid::new(&field.main, texels, field.reach_unit());
                par_rows(hf.height(), |j| {
                    (0..width)
                        .map(|i| {
                            let floor = conservative[j as usize * width as usize + i as usize];
                            search::relaxed(&field, &reach, (i, j), floor, cap)
                        })
                        .collect()
                })
            }
        };
        ConeMap {
            kind,
            width,
            height: hf.height(),
            ratio: ratio.into_iter().map(|c| round_down(c.min(cap))).collect(),
            surface: hf.data().to_vec(),
        }
    }

    /// The ratio of texel `(i, j)`. Panics if out of range.
    pub fn get(&self, i: u32, j: u32) -> f32 {
        assert!(
            i < self.width && j < self.height,
            "texel ({i}, {j}) outside {}x{} cone map",
            self.width,
            self.height
        );
        self.ratio[j as usize * self.width as usize + i as usize]
    }
}

/// Per texel, the highest point of the bilinear surface of `hf` (under `address`) over the texel's box,
/// rounded up to `f32`. The box meets the four bilinear cells around the texel centre, in a quarter each;
/// on each quarter (a rectangle) the bilinear function peaks at a corner, so the maximum is the largest of
/// nine values: the texel itself, the means with its four edge neighbours and with each 2x2 block around a
/// box corner. Clamped borders reuse the edge texels, which also bounds the surface beyond the map.
pub fn bilinear_box_bound(hf: &Heightfield, address: Address) -> Heightfield {
    let (w, h) = (i64::from(hf.width()), i64::from(hf.height()));
    let at = |i: i64, j: i64| {
        let (i, j) = match address {
            Address::Repeat => (i.rem_euclid(w), j.rem_euclid(h)),
            Address::Clamp => (i.clamp(0, w - 1), j.clamp(0, h - 1)),
        };
        f64::from(hf.get(i as u32, j as u32))
    };
    let mut data = Vec::with_capacity(hf.data().len());
    for j in 0..h {
        for i in 0..w {
            let (_, top) = footprint_range(|di, dj| at(i + di, j + dj));
            data.push(round_up(top));
        }
    }
    Heightfield::new(hf.width(), hf.height(), data)
        .expect("means of valid heights are valid heights")
}

/// The least and the highest point of the bilinear surface over one texel's box, from the heights `h(di, dj)` of
/// the texel's 3x3 neighbourhood (already addressed): on each quarter of the box the surface is one bilinear
/// patch, extreme at the quarter's corners, so both are among nine values: the texel, the means with its four edge
/// neighbours and the means of the four 2x2 blocks around the box's corners.
pub(crate) fn footprint_range(h: impl Fn(i64, i64) -> f64) -> (f64, f64) {
    let centre = h(0, 0);
    let (mut lo, mut hi) = (centre, centre);
    for (di, dj) in [(-1, -1), (-1, 1), (1, -1), (1, 1)] {
        let (side_u, side_v) = (h(di, 0), h(0, dj));
        for value in [
            0.5 * (centre + side_u),
            0.5 * (centre + side_v),
            0.25 * (centre + side_u + side_v + h(di, dj)),
        ] {
            lo = lo.min(value);
            hi = hi.max(value);
        }
    }
    (lo, hi)
}

/// The smallest `f32` not below `x` in `[0, 1]`.
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x && f < 1.0 {
        f32::from_bits(f.to_bits() + 1)
    } else {
        f
    }
}

/// The largest `f32` not above `x >= 0`.
fn round_down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x && f > 0.0 {
        f32::from_bits(f.to_bits() - 1)
    } else {
        f
    }
}

/// The outcome of [`trace_cone_cpu`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConeTrace {
    /// Depth of the hit (or, when capped, of the last point reached, which is above the surface).
    pub z: f64,
    /// Stepping iterations run (one cone-map and height fetch each), not counting refinement.
    pub steps: u32,
    /// The iteration budget ran out before the ray reached the surface.
    pub capped: bool,
}

/// Traces `ray` with cone stepping over `map` against the map's box surface (`map.surface`; see the module
/// docs), as the GPU methods do with the paper's leaf: at most `max_steps` stepping iterations, then (relaxed
/// maps only) `refine_steps` halvings of the last step, which brackets the first crossing; the reported `z`
/// is the inside end of the final bracket. Conservative tracing ends on the surface itself and ignores
/// `refine_steps`. (With the exact leaf the GPU goes on from there to the bilinear surface of `hf`.)
///
/// Panics if `map` and `hf` differ in size, or on a ray the reference tracer would reject.
pub fn trace_cone_cpu(
    hf: &Heightfield,
    map: &ConeMap,
    ray: &RefRay,
    depth_scale: f64,
    address: Address,
    max_steps: u32,
    refine_steps: u32,
) -> ConeTrace {
    let walk = Walk::new(hf, map, ray, depth_scale, address);
    walk.run(max_steps, refine_steps, |_| {})
}

/// One ray's walk: its fixed quantities, shared by stepping and refinement.
struct Walk<'a> {
    hf: &'a Heightfield,
    map: &'a ConeMap,
    s: f64,
    address: Address,
    /// Texels per uv along u and v.
    nu: f64,
    nv: f64,
    /// Entry point (moved into the first tile under `Repeat`) and uv per unit depth.
    u0: f64,
    v0: f64,
    tu: f64,
    tv: f64,
    /// `|(tu, tv)|`.
    t: f64,
}

/// A cell of the walk. Under `Repeat` indices are unwrapped; under `Clamp` they lie in `-1..=n`, where `-1`
/// and `n` are the merged half-lines outside the map.
type CellIndex = (i64, i64);

impl<'a> Walk<'a> {
    fn new(hf: &'a Heightfield, map: &'a ConeMap, ray: &RefRay, s: f64, address: Address) -> Self {
        assert!(
            map.width == hf.width() && map.height == hf.height(),
            "cone map {}x{} does not match height field {}x{}",
            map.width,
            map.height,
            hf.width(),
            hf.height()
        );
        assert!(
            ray.dz > 0.0 && ray.dz.is_finite() && s >= 0.0 && s.is_finite(),
            "bad ray {ray:?} or depth scale {s}"
        );
        let (tu, tv) = (ray.dx / ray.dz, ray.dy / ray.dz);
        assert!(
            tu.is_finite() && tv.is_finite(),
            "ray too close to horizontal: {ray:?}"
        );
        let (u0, v0) = match address {
            Address::Repeat => (ray.u0 - ray.u0.floor(), ray.v0 - ray.v0.floor()),
            Address::Clamp => (ray.u0, ray.v0),
        };
        Walk {
            hf,
            map,
            s,
            address,
            nu: f64::from(hf.width()),
            nv: f64::from(hf.height()),
            u0,
            v0,
            tu,
            tv,
            t: (tu * tu + tv * tv).sqrt(),
        }
    }

    /// The stepping loop and the refinement. `visit` sees the depth at the start of every iteration.
    fn run(&self, max_steps: u32, refine_steps: u32, mut visit: impl FnMut(f64)) -> ConeTrace {
        let (mut z, mut z_before) = (0.0, 0.0);
        let mut cell = self.cell_at(z);
        for step in 0..max_steps {
            visit(z);
            let floor = self.floor(cell);
            if z >= floor {
                if self.map.kind == ConeKind::Relaxed {
                    z = self.refine(z_before, z, refine_steps);
                }
                return ConeTrace {
                    z,
                    steps: step + 1,
                    capped: false,
                };
            }
            z_before = z;
            (z, cell) = self.advance(z, cell, floor);
        }
        ConeTrace {
            z,
            steps: max_steps,
            capped: true,
        }
    }

    /// One iteration from depth `z` above the floor of `cell`: the longer of the cone step and the cell step.
    fn advance(&self, z: f64, cell: CellIndex, floor: f64) -> (f64, CellIndex) {
        let cone = z + self.cone_step(z, cell, floor);
        let (exit_u, exit_v) = self.exits(z, cell);
        let exit = exit_u.min(exit_v);
        if cone > exit.min(floor) {
            // The cone step never passes the floor; `min` only absorbs rounding.
            let z = cone.min(floor);
            (z, self.cell_at(z))
        } else if floor <= exit {
            (floor, cell)
        } else {
            let (mut ci, mut cj) = cell;
            if exit_u <= exit {
                ci += if self.tu > 0.0 { 1 } else { -1 };
            }
            if exit_v <= exit {
                cj += if self.tv > 0.0 { 1 } else { -1 };
            }
            (exit, (ci, cj))
        }
    }

    /// `max(c (d - z) - s delta, 0) / (t s + c)`, with `delta` the ray's offset from the cell centre.
    fn cone_step(&self, z: f64, (ci, cj): CellIndex, floor: f64) -> f64 {
        let (out_u, out_v) = (self.outside(ci, self.nu), self.outside(cj, self.nv));
        if self.map.kind == ConeKind::Relaxed && (out_u || out_v) {
            return 0.0;
        }
        let (i, j) = self.texel((ci, cj));
        let c = f64::from(self.map.get(i, j));
        let (u, v) = self.point(z);
        // Outside a clamped map the surface is constant along the outward axis, so only the in-map offset counts.
        let du = if out_u {
            0.0
        } else {
            u - (ci as f64 + 0.5) / self.nu
        };
        let dv = if out_v {
            0.0
        } else {
            v - (cj as f64 + 0.5) / self.nv
        };
        let delta = (du * du + dv * dv).sqrt();
        let num = c * (floor - z) - self.s * delta;
        let den = self.t * self.s + c;
        if num > 0.0 && den > 0.0 {
            num / den
        } else {
            0.0
        }
    }

    /// Depths at which the ray leaves `cell` across its u and its v boundaries (infinite if never), not
    /// before `z`.
    fn exits(&self, z: f64, (ci, cj): CellIndex) -> (f64, f64) {
        let exit = |c: i64, n: f64, origin: f64, slope: f64| {
            let (lo, hi) = self.cell_bounds(c, n);
            let bound = if slope > 0.0 { hi } else { lo };
            if slope == 0.0 || bound.is_infinite() {
                f64::INFINITY
            } else {
                ((bound - origin) / slope).max(z)
            }
        };
        (
            exit(ci, self.nu, self.u0, self.tu),
            exit(cj, self.nv, self.v0, self.tv),
        )
    }

    /// The uv interval of cell index `c` along an axis with `n` texels.
    fn cell_bounds(&self, c: i64, n: f64) -> (f64, f64) {
        let (lo, hi) = (c as f64 / n, (c + 1) as f64 / n);
        match self.address {
            Address::Clamp if c < 0 => (f64::NEG_INFINITY, 0.0),
            Address::Clamp if c as f64 >= n => (1.0, f64::INFINITY),
            _ => (lo, hi),
        }
    }

    fn outside(&self, c: i64, n: f64) -> bool {
        self.address == Address::Clamp && (c < 0 || c as f64 >= n)
    }

    fn point(&self, z: f64) -> (f64, f64) {
        (self.u0 + z * self.tu, self.v0 + z * self.tv)
    }

    /// The cell owning the ray point at depth `z` (the nearest model's floor rule).
    fn cell_at(&self, z: f64) -> CellIndex {
        let (u, v) = self.point(z);
        let (ci, cj) = ((u * self.nu).floor(), (v * self.nv).floor());
        match self.address {
            Address::Repeat => (ci as i64, cj as i64),
            Address::Clamp => (
                ci.clamp(-1.0, self.nu) as i64,
                cj.clamp(-1.0, self.nv) as i64,
            ),
        }
    }

    fn texel(&self, (ci, cj): CellIndex) -> (u32, u32) {
        let (w, h) = (i64::from(self.hf.width()), i64::from(self.hf.height()));
        match self.address {
            Address::Repeat => (ci.rem_euclid(w) as u32, cj.rem_euclid(h) as u32),
            Address::Clamp => (ci.clamp(0, w - 1) as u32, cj.clamp(0, h - 1) as u32),
        }
    }

    /// The depth `s (1 - h)` of a cell's box top (of the map's surface).
    fn floor(&self, cell: CellIndex) -> f64 {
        let (i, j) = self.texel(cell);
        let k = j as usize * self.map.width as usize + i as usize;
        self.s * (1.0 - f64::from(self.map.surface[k]))
    }

    /// Binary search between `lo` (above the surface) and `hi` (at or below it); returns the final `hi`.
    fn refine(&self, mut lo: f64, mut hi: f64, steps: u32) -> f64 {
        for _ in 0..steps {
            let mid = 0.5 * (lo + hi);
            if mid >= self.floor(self.cell_at(mid)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }
}

#[cfg(test)]
#[path = "cone_map_tests.rs"]
mod tests;

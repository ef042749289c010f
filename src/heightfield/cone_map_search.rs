//! The searches behind [`super::ConeMap::build`]: exact minima over every texel of the (tiled or clamped)
//! plane, pruned through max / min pyramids so that each texel visits only the nodes that could still lower
//! its answer.
//!
//! Geometry is in uv throughout (boxes and direction sectors are in `cone_map_sectors.rs`). The plane beyond
//! the map is made of *regions*: with `Repeat`, translated copies of the map (tiles `(a, b)`); with `Clamp`,
//! four border strips (each row or column of border texels extended to infinity) and four corner quadrants,
//! which is exactly what clamp-to-edge addressing produces. Regions are visited ring by ring (tile rings, or
//! map then border), and a ring is skipped once a lower bound on its distance already exceeds what it could
//! improve.
//!
//! Every pruned node is skipped only when a lower bound on all of its texels' values is `>=` the current best,
//! and the bound is computed with the same monotone floating-point operations as the texel values
//! themselves, so the results are bit-identical to the brute-force minima (the tests check this).

use std::cell::Cell;
use std::sync::atomic::{AtomicU32, Ordering};
use std::thread;

use super::sectors::{direction_mask, Mask, Rect, SECTORS};
use crate::heightfield::reference::Address;
use crate::heightfield::{covered_range, Heightfield, MaxPyramid};

/// Reaches (see `reach`) are capped at the lesser of this, in uv, and [`REACH_CAP_TEXELS`]: a cap only
/// shortens them, which is always safe.
pub const REACH_CAP_UV: f64 = 0.25;
/// ... and of this many texels along u. The search for a reach visits every node within the cap that
/// holds a lower texel in an open sector, so its cost grows with the cap: with 0.25 uv alone a 256^2
/// step field took 48 s and a 1024^2 one would take about an hour, while on rough fields (fbm) no
/// reach is longer than 16 texels at 1024^2.
pub const REACH_CAP_TEXELS: f64 = 16.0;
/// The uv coordinate standing in for infinity on the open side of a clamp strip.
const FAR: f64 = 1e6;

/// A max pyramid and a pyramid of `max(1 - h)` (so `1 - node` bounds the node's minimum) over one field, with
/// the level-0 texel range behind every node.
pub(super) struct Tree {
    max: MaxPyramid,
    min_inv: MaxPyramid,
    /// Per level, each index's inclusive range of level-0 indices and of level-below indices (its
    /// children), along u and along v.
    span_u: Vec<Vec<(u32, u32)>>,
    span_v: Vec<Vec<(u32, u32)>>,
    kids_u: Vec<Vec<(u32, u32)>>,
    kids_v: Vec<Vec<(u32, u32)>>,
}

impl Tree {
    pub fn new(hf: &Heightfield) -> Tree {
        let inverted = hf.data().iter().map(|&h| 1.0 - h).collect();
        let inverted = Heightfield::from_valid(hf.width(), hf.height(), inverted);
        let max = MaxPyramid::build(hf);
        let sizes: Vec<(u32, u32)> = max.levels().iter().map(|l| (l.width, l.height)).collect();
        let (span_u, kids_u) = level_spans(sizes.iter().map(|s| s.0));
        let (span_v, kids_v) = level_spans(sizes.iter().map(|s| s.1));
        Tree {
            min_inv: MaxPyramid::build(&inverted),
            max,
            span_u,
            span_v,
            kids_u,
            kids_v,
        }
    }

    pub fn top_level(&self) -> u32 {
        self.max.level_count() - 1
    }

    pub fn size(&self, level: u32) -> (u32, u32) {
        let l = self.max.level(level);
        (l.width, l.height)
    }

    pub fn max_at(&self, level: u32, i: u32, j: u32) -> f32 {
        self.max.level(level).get(i, j)
    }

    /// `max(1 - h)` over the node: a node with a texel below `h` has this `>= 1 - h` (in `f32`).
    pub fn min_inv_at(&self, level: u32, i: u32, j: u32) -> f32 {
        self.min_inv.level(level).get(i, j)
    }

    /// The level-below indices under node `(i, j)` of `level >= 1`.
    pub fn children(&self, level: u32, i: u32, j: u32) -> impl Iterator<Item = (u32, u32)> {
        let (i0, i1) = self.kids_u[level as usize][i as usize];
        let (j0, j1) = self.kids_v[level as usize][j as usize];
        (j0..=j1).flat_map(move |cj| (i0..=i1).map(move |ci| (ci, cj)))
    }
}

/// Per level, along one axis: the level-0 range `(first, last)` of every index, and the range of indices it
/// covers on the level below ([`covered_range`]; `(i, i)` on level 0, which has none).
type AxisRanges = Vec<Vec<(u32, u32)>>;

fn level_spans(lens: impl Iterator<Item = u32>) -> (AxisRanges, AxisRanges) {
    let (mut spans, mut kids): (AxisRanges, AxisRanges) = (Vec::new(), Vec::new());
    let mut prev_len = 0;
    for len in lens {
        let (level_spans, level_kids) = match spans.last() {
            None => (
                (0..len).map(|i| (i, i)).collect(),
                (0..len).map(|i| (i, i)).collect(),
            ),
            Some(finer) => (0..len)
                .map(|c| {
                    let (a, b) = covered_range(c, len, prev_len);
                    ((finer[a as usize].0, finer[b as usize].1), (a, b))
                })
                .unzip(),
        };
        spans.push(level_spans);
        kids.push(level_kids);
        prev_len = len;
    }
    (spans, kids)
}

/// How one axis of a region maps level-0 indices to uv.
#[derive(Debug, Clone, Copy)]
enum Span {
    /// Texel `k` covers `[origin + k * step, origin + (k + 1) * step)`.
    Grid { origin: f64, step: f64 },
    /// The whole region covers this interval along the axis (a clamp strip's open side).
    Fixed(f64, f64),
}

impl Span {
    fn range(self, (first, last): (u32, u32)) -> (f64, f64) {
        match self {
            Span::Grid { origin, step } => (
                origin + f64::from(first) * step,
                origin + f64::from(last + 1) * step,
            ),
            Span::Fixed(a, b) => (a, b),
        }
    }
}

/// A tree placed in the plane: a tile of the map, or a clamp strip or corner.
#[derive(Clone, Copy)]
pub(super) struct Placed<'a> {
    pub tree: &'a Tree,
    u: Span,
    v: Span,
    /// Whether its level-0 nodes are texels of the map itself (so per-texel tables apply), not border copies.
    pub real: bool,
}

impl Placed<'_> {
    pub fn rect(&self, level: u32, i: u32, j: u32) -> Rect {
        let (u0, u1) = self.u.range(self.tree.span_u[level as usize][i as usize]);
        let (v0, v1) = self.v.range(self.tree.span_v[level as usize][j as usize]);
        Rect { u0, u1, v0, v1 }
    }
}

/// The clamp border: strips (left, right, bottom, top) and corners (00, 10, 01, 11).
struct Border {
    strips: [Tree; 4],
    corners: [Tree; 4],
}

/// A height field with everything the searches need.
pub(super) struct Field<'a> {
    pub hf: &'a Heightfield,
    pub address: Address,
    pub main: Tree,
    border: Option<Border>,
    pub step_u: f64,
    pub step_v: f64,
    /// The global maximum height.
    pub top: f32,
}

impl<'a> Field<'a> {
    pub fn new(hf: &'a Heightfield, address: Address) -> Field<'a> {
        let main = Tree::new(hf);
        let top = main.max_at(main.top_level(), 0, 0);
        let border = match address {
            Address::Repeat => None,
            Address::Clamp => Some(border_trees(hf)),
        };
        Field {
            hf,
            address,
            main,
            border,
            step_u: 1.0 / f64::from(hf.width()),
            step_v: 1.0 / f64::from(hf.height()),
            top,
        }
    }

    /// The reach cap in uv: [`REACH_CAP_UV`] or [`REACH_CAP_TEXELS`] texels, whichever is less.
    pub fn reach_cap(&self) -> f64 {
        REACH_CAP_UV.min(REACH_CAP_TEXELS * self.step_u)
    }

    /// Reaches are stored as `u16` multiples of this (rounded down, so stored values never exceed true
    /// ones).
    pub fn reach_unit(&self) -> f64 {
        self.reach_cap() / 65535.0
    }

    pub fn texel_rect(&self, i: u32, j: u32) -> Rect {
        self.tile(0, 0).rect(0, i, j)
    }

    pub fn centre(&self, i: u32, j: u32) -> (f64, f64) {
        (
            (f64::from(i) + 0.5) * self.step_u,
            (f64::from(j) + 0.5) * self.step_v,
        )
    }

    pub fn tile(&self, a: i64, b: i64) -> Placed<'_> {
        Placed {
            tree: &self.main,
            u: Span::Grid {
                origin: a as f64,
                step: self.step_u,
            },
            v: Span::Grid {
                origin: b as f64,
                step: self.step_v,
            },
            real: true,
        }
    }

    /// The regions of ring `r` and a lower bound on their distance from any point of the map, or `None` when
    /// there are no more rings. `border` asks for the clamp strips and corners (ring 1 under `Clamp`).
    pub fn ring(&self, r: u32, border: bool) -> Option<(f64, Vec<Placed<'_>>)> {
        let r = i64::from(r);
        match (self.address, &self.border) {
            (_, _) if r == 0 => Some((0.0, vec![self.tile(0, 0)])),
            (Address::Repeat, _) => {
                let tiles = (-r..=r)
                    .flat_map(|b| (-r..=r).map(move |a| (a, b)))
                    .filter(|&(a, b)| a.abs().max(b.abs()) == r)
                    .map(|(a, b)| self.tile(a, b))
                    .collect();
                Some(((r - 1) as f64, tiles))
            }
            (Address::Clamp, Some(bd)) if r == 1 && border => Some((0.0, self.border_regions(bd))),
            (Address::Clamp, _) => None,
        }
    }

    fn border_regions<'b>(&'b self, bd: &'b Border) -> Vec<Placed<'b>> {
        let gu = Span::Grid {
            origin: 0.0,
            step: self.step_u,
        };
        let gv = Span::Grid {
            origin: 0.0,
            step: self.step_v,
        };
        let (lo, hi) = (Span::Fixed(-FAR, 0.0), Span::Fixed(1.0, FAR));
        let place = |tree, u, v| Placed {
            tree,
            u,
            v,
            real: false,
        };
        vec![
            place(&bd.strips[0], lo, gv),
            place(&bd.strips[1], hi, gv),
            place(&bd.strips[2], gu, lo),
            place(&bd.strips[3], gu, hi),
            place(&bd.corners[0], lo, lo),
            place(&bd.corners[1], hi, lo),
            place(&bd.corners[2], lo, hi),
            place(&bd.corners[3], hi, hi),
        ]
    }
}

fn border_trees(hf: &Heightfield) -> Border {
    let (w, h) = (hf.width(), hf.height());
    let column = |i| Heightfield::from_valid(1, h, (0..h).map(|j| hf.get(i, j)).collect());
    let row = |j| Heightfield::from_valid(w, 1, (0..w).map(|i| hf.get(i, j)).collect());
    let corner = |i, j| Tree::new(&Heightfield::from_valid(1, 1, vec![hf.get(i, j)]));
    Border {
        strips: [
            Tree::new(&column(0)),
            Tree::new(&column(w - 1)),
            Tree::new(&row(0)),
            Tree::new(&row(h - 1)),
        ],
        corners: [
            corner(0, 0),
            corner(w - 1, 0),
            corner(0, h - 1),
            corner(w - 1, h - 1),
        ],
    }
}

/// A node waiting on a search stack with its lower bound (and, for reach searches, its sectors).
#[derive(Clone, Copy)]
struct Entry {
    bound: f64,
    mask: Mask,
    region: usize,
    level: u32,
    i: u32,
    j: u32,
}

/// Depth-first search over `regions`, nearest bound first. `bound(region, level, i, j)` returns `None` to
/// drop a node outright, else a lower bound on every texel value under it (the exact value at level 0) and
/// the node's sectors; `keep` is asked again when a node is popped (the best may have improved since it was
/// pushed), and `leaf` receives every level-0 node kept.
fn search(
    regions: &[Placed<'_>],
    mut bound: impl FnMut(&Placed<'_>, u32, u32, u32) -> Option<(f64, Mask)>,
    mut keep: impl FnMut(&Entry) -> bool,
    mut leaf: impl FnMut(&Entry),
) {
    let mut stack: Vec<Entry> = Vec::with_capacity(64);
    let mut kids: Vec<Entry> = Vec::with_capacity(9);
    for (region, placed) in regions.iter().enumerate() {
        let level = placed.tree.top_level();
        if let Some((bound, mask)) = bound(placed, level, 0, 0) {
            stack.push(Entry {
                bound,
                mask,
                region,
                level,
                i: 0,
                j: 0,
            });
        }
        while let Some(e) = stack.pop() {
            if !keep(&e) {
                continue;
            }
            if e.level == 0 {
                leaf(&e);
                continue;
            }
            let p = &regions[e.region];
            kids.clear();
            for (i, j) in p.tree.children(e.level, e.i, e.j) {
                if let Some((bound, mask)) = bound(p, e.level - 1, i, j) {
                    kids.push(Entry {
                        bound,
                        mask,
                        level: e.level - 1,
                        i,
                        j,
                        ..e
                    });
                }
            }
            // Farthest first onto the stack, so the nearest is searched first and tightens the best early.
            kids.sort_unstable_by(|a, b| b.bound.total_cmp(&a.bound));
            stack.extend(kids.iter().filter(|k| keep(k)));
        }
    }
}

/// The conservative ratio of texel `(i, j)` before capping: the minimum over every texel `q` higher than it
/// (all tiles, or the map under `Clamp`, where the border copies are never nearer) of
/// `dist(centre, box(q)) / (h(q) - h)`; `cap` if none is below `cap`.
pub(super) fn conservative(f: &Field<'_>, i: u32, j: u32, cap: f64) -> f64 {
    let hp = f.hf.get(i, j);
    let centre = f.centre(i, j);
    let rise = f64::from(f.top) - f64::from(hp);
    let bound = |p: &Placed<'_>, level, ni, nj| {
        let top = p.tree.max_at(level, ni, nj);
        let rect = p.rect(level, ni, nj);
        (top > hp).then(|| {
            let value = rect.dist_point(centre.0, centre.1) / (f64::from(top) - f64::from(hp));
            (value, 0)
        })
    };
    let best = Cell::new(seed(f, i, j, cap, bound));
    for r in 0.. {
        let Some((gap, regions)) = f.ring(r, false) else {
            break;
        };
        if rise <= 0.0 || gap / rise >= best.get() {
            break;
        }
        search(
            &regions,
            bound,
            |e| e.bound < best.get(),
            |e| best.set(e.bound),
        );
    }
    best.get()
}

/// `cap` lowered to the exact values of the 8 neighbours of `(i, j)`: genuine candidates (computed by the same
/// `bound` as in the search), so the minimum is unchanged, but most of the pyramid is pruned from the start.
fn seed(
    f: &Field<'_>,
    i: u32,
    j: u32,
    cap: f64,
    bound: impl Fn(&Placed<'_>, u32, u32, u32) -> Option<(f64, Mask)>,
) -> f64 {
    let (w, h) = (i64::from(f.hf.width()), i64::from(f.hf.height()));
    let mut best = cap;
    for (di, dj) in (-1..=1).flat_map(|dj| (-1..=1).map(move |di| (di, dj))) {
        let (ni, nj) = (i64::from(i) + di, i64::from(j) + dj);
        let (a, b) = (ni.div_euclid(w), nj.div_euclid(h));
        // Repeat: the neighbour in its tile (ring 1 at most, which every search visits); Clamp: in-map only.
        if (di, dj) == (0, 0) || (f.address == Address::Clamp && (a, b) != (0, 0)) {
            continue;
        }
        let texel = (ni.rem_euclid(w) as u32, nj.rem_euclid(h) as u32);
        if let Some((value, _)) = bound(&f.tile(a, b), 0, texel.0, texel.1) {
            best = best.min(value);
        }
    }
    best
}

/// The reach of texel `q` per sector (see the module docs of `cone_map`): for each sector `S`, the distance
/// from `box(q)` to the nearest region lower than `q` that a ray leaving `q` in a direction of `S` can enter,
/// capped at [`Field::reach_cap`] and stored as a `u16` multiple of [`Field::reach_unit`] (rounded down).
pub(super) fn reach(f: &Field<'_>, i: u32, j: u32) -> [u16; SECTORS] {
    let hq = f.hf.get(i, j);
    let g = 1.0 - hq;
    let q = f.texel_rect(i, j);
    let reach = Cell::new([f.reach_cap(); SECTORS]);
    let live = |mask: Mask, d: f64| {
        let e = reach.get();
        (0..SECTORS).any(|k| mask & (1 << k) != 0 && e[k] > d)
    };
    for r in 0.. {
        let Some((gap, regions)) = f.ring(r, true) else {
            break;
        };
        if gap >= reach.get().iter().fold(0.0f64, |m, &e| m.max(e)) {
            break;
        }
        search(
            &regions,
            |p, level, ni, nj| {
                // A node with no texel below `hq` holds nothing a ray could drop into.
                if p.tree.min_inv_at(level, ni, nj) < g {
                    return None;
                }
                let rect = p.rect(level, ni, nj);
                let d = q.dist_rect(&rect);
                let mask = direction_mask(&q, &rect, level == 0);
                live(mask, d).then_some((d, mask))
            },
            |e| live(e.mask, e.bound),
            |e| {
                if regions[e.region].tree.max_at(0, e.i, e.j) < hq {
                    let mut all = reach.get();
                    for (k, ek) in all.iter_mut().enumerate() {
                        if e.mask & (1 << k) != 0 && e.bound < *ek {
                            *ek = e.bound;
                        }
                    }
                    reach.set(all);
                }
            },
        );
    }
    reach
        .get()
        .map(|x| (x / f.reach_unit()).floor().min(65535.0) as u16)
}

/// Per-sector reaches of every texel (level 0) and their per-node minima (levels above), laid out like
/// the main tree's levels with [`SECTORS`] values per node.
pub(super) struct ReachPyramid {
    levels: Vec<Vec<u16>>,
    widths: Vec<u32>,
    /// uv per stored unit ([`Field::reach_unit`]).
    unit: f64,
}

impl ReachPyramid {
    pub fn new(main: &Tree, texels: Vec<u16>, unit: f64) -> ReachPyramid {
        let mut levels = vec![texels];
        let mut widths = vec![main.size(0).0];
        for level in 1..=main.top_level() {
            let (w, h) = main.size(level);
            let fine = &levels[levels.len() - 1];
            let fw = widths[widths.len() - 1] as usize;
            let mut out = vec![u16::MAX; w as usize * h as usize * SECTORS];
            for j in 0..h {
                for i in 0..w {
                    let at = (j as usize * w as usize + i as usize) * SECTORS;
                    for (ci, cj) in main.children(level, i, j) {
                        let from = (cj as usize * fw + ci as usize) * SECTORS;
                        for k in 0..SECTORS {
                            out[at + k] = out[at + k].min(fine[from + k]);
                        }
                    }
                }
            }
            levels.push(out);
            widths.push(w);
        }
        ReachPyramid {
            levels,
            widths,
            unit,
        }
    }

    /// The smallest reach (uv) over the sectors in `mask` at node `(i, j)` of `level`.
    pub fn min_over(&self, level: u32, i: u32, j: u32, mask: Mask) -> f64 {
        let w = self.widths[level as usize] as usize;
        let at = (j as usize * w + i as usize) * SECTORS;
        let row = &self.levels[level as usize][at..at + SECTORS];
        let q = (0..SECTORS)
            .filter(|k| mask & (1 << k) != 0)
            .map(|k| row[k])
            .min()
            .unwrap_or(0);
        f64::from(q) * self.unit
    }
}

/// The relaxed ratio of texel `(i, j)`: `max(floor, m)` with `m` the minimum over every region `q` higher
/// than `p` of `(dist(centre, box(q)) + reach(q, sectors from box(p) to box(q))) / (h(q) - h(p))`, border
/// copies counting with reach 0; `cap` if nothing is below it.
pub(super) fn relaxed(
    f: &Field<'_>,
    reach: &ReachPyramid,
    (i, j): (u32, u32),
    floor: f64,
    cap: f64,
) -> f64 {
    let hp = f.hf.get(i, j);
    let centre = f.centre(i, j);
    let prect = f.texel_rect(i, j);
    let rise = f64::from(f.top) - f64::from(hp);
    let bound = |p: &Placed<'_>, level, ni, nj| {
        let top = p.tree.max_at(level, ni, nj);
        if top <= hp {
            return None;
        }
        let rect = p.rect(level, ni, nj);
        let extra = if p.real {
            let mask = direction_mask(&prect, &rect, level == 0);
            reach.min_over(level, ni, nj, mask)
        } else {
            0.0
        };
        let dist = rect.dist_point(centre.0, centre.1);
        Some(((dist + extra) / (f64::from(top) - f64::from(hp)), 0))
    };
    let best = Cell::new(seed(f, i, j, cap, bound));
    for r in 0.. {
        let Some((gap, regions)) = f.ring(r, true) else {
            break;
        };
        // At or below the floor the answer is the floor, whatever else is found.
        if rise <= 0.0 || best.get() <= floor || gap / rise >= best.get() {
            break;
        }
        search(
            &regions,
            bound,
            |e| best.get() > floor && e.bound < best.get(),
            |e| best.set(e.bound),
        );
    }
    best.get().max(floor)
}

/// Runs `row(j)` for every `j < height` on all available cores (rows handed out one at a time, so uneven
/// rows balance), returning the rows' outputs concatenated in order.
pub(super) fn par_rows<T: Send>(height: u32, row: impl Fn(u32) -> Vec<T> + Sync) -> Vec<T> {
    let next = AtomicU32::new(0);
    let threads = thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(height as usize)
        .max(1);
    let mut parts: Vec<(u32, Vec<T>)> = thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut out = Vec::new();
                    loop {
                        let j = next.fetch_add(1, Ordering::Relaxed);
                        if j >= height {
                            break out;
                        }
                        out.push((j, row(j)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    parts.sort_unstable_by_key(|p| p.0);
    parts.into_iter().flat_map(|p| p.1).collect()
}

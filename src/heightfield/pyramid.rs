//! The conservative max pyramid: mip level `L + 1` holds, per texel, the maximum of every texel of level `L`
//! that it overlaps in uv, so a coarse texel is an upper bound on the heights under it and empty-space
//! skipping against it never steps over the surface.
//!
//! Works for any size, including 1x1 and non-powers of two. Level sizes follow Vulkan's mip rule
//! (`max(1, floor(n / 2))` per level, down to 1x1), so the levels upload as the mips of one image. With odd
//! sizes a coarse texel does not line up with whole finer texels; [`covered_range`] then includes every finer
//! texel it touches, and a finer texel on a shared border feeds both neighbours. That overlap is what keeps the
//! bound conservative, and the GPU builder (`pyramid.comp`) computes the same formula,
//! and the tests compare the two.
//!
//! Invariants: `levels[0]` is the height field itself; `levels.len() == mip_level_count(w, h)`; the last level
//! is 1x1 and holds the global maximum; every level's `data.len() == width * height`, row-major.

use super::Heightfield;

/// One level of the pyramid, row-major like [`Heightfield`].
#[derive(Debug, Clone, PartialEq)]
pub struct PyramidLevel {
    /// Texels along u.
    pub width: u32,
    /// Texels along v.
    pub height: u32,
    /// `width * height` maxima; texel `(i, j)` at `j * width + i`.
    pub data: Vec<f32>,
}

impl PyramidLevel {
    /// The value of texel `(i, j)`. Panics if out of range.
    pub fn get(&self, i: u32, j: u32) -> f32 {
        assert!(
            i < self.width && j < self.height,
            "texel ({i}, {j}) outside level"
        );
        self.data[j as usize * self.width as usize + i as usize]
    }
}

/// A max pyramid from the full-resolution map (level 0) down to 1x1.
#[derive(Debug, Clone, PartialEq)]
pub struct MaxPyramid {
    levels: Vec<PyramidLevel>,
}

/// Number of mip levels of a `width x height` image down to 1x1: `floor(log2(max(width, height))) + 1`.
/// A zero dimension is treated as 1.
pub fn mip_level_count(width: u32, height: u32) -> u32 {
    let largest = width.max(height).max(1);
    u32::BITS - largest.leading_zeros()
}

/// The inclusive range `(first, last)` of finer texels that coarse texel `coarse_index` overlaps in uv,
/// along one axis where the coarse level has `coarse_len` texels and the finer level `fine_len`
/// (`1 <= coarse_len <= fine_len`, `coarse_index < coarse_len`):
///
/// `first = floor(coarse_index * fine_len / coarse_len)`,
/// `last = ceil((coarse_index + 1) * fine_len / coarse_len) - 1`, in exact integer arithmetic.
///
/// These are exactly the finer texels `k` with `[k, k+1) / fine_len` intersecting
/// `[c, c+1) / coarse_len`. For `fine_len = 2 * coarse_len` it is `(2c, 2c + 1)`; for odd `fine_len` the
/// ranges of neighbouring coarse texels share one finer texel.
pub fn covered_range(coarse_index: u32, coarse_len: u32, fine_len: u32) -> (u32, u32) {
    let (c, nc, nf) = (
        u64::from(coarse_index),
        u64::from(coarse_len),
        u64::from(fine_len),
    );
    // u64 products cannot overflow for u32 inputs; the results are < fine_len, so they fit in u32.
    let first = c * nf / nc;
    let last = ((c + 1) * nf).div_ceil(nc) - 1;
    (first as u32, last as u32)
}

impl MaxPyramid {
    /// Builds every level from `hf`. Separable: the maximum over a rectangle is the maximum over its rows of
    /// each row's maximum, so each level is one pass along u, then one along v (linear time, cache-friendly).
    pub fn build(hf: &Heightfield) -> MaxPyramid {
        let count = mip_level_count(hf.width(), hf.height()) as usize;
        let mut levels = Vec::with_capacity(count);
        levels.push(PyramidLevel {
            width: hf.width(),
            height: hf.height(),
            data: hf.data().to_vec(),
        });
        while levels.len() < count {
            let finer = &levels[levels.len() - 1];
            let coarser = reduce(finer);
            levels.push(coarser);
        }
        MaxPyramid { levels }
    }

    /// The pyramid the hierarchical methods traverse: level 0 is the map itself, and level 1
    /// takes the max over every texel its cell overlaps *and their neighbours* (one texel wider on
    /// each side, wrapping when `wrap`, else clamped), then levels 2.. as in [`MaxPyramid::build`].
    /// The bilinear surface over a cell interpolates texel centres up to half a texel outside it,
    /// so without that margin a node could sit below the bilinear surface near its edges; with
    /// it every node from level 1 up bounds the bilinear surface (and the box surface) from above.
    pub fn build_bilinear_bound(hf: &Heightfield, wrap: bool) -> MaxPyramid {
        let count = mip_level_count(hf.width(), hf.height()) as usize;
        let base = PyramidLevel {
            width: hf.width(),
            height: hf.height(),
            data: hf.data().to_vec(),
        };
        let mut levels = Vec::with_capacity(count);
        if count > 1 {
            levels.push(reduce(&dilate(&base, wrap)));
        }
        while levels.len() + 1 < count {
            let coarser = reduce(&levels[levels.len() - 1]);
            levels.push(coarser);
        }
        levels.insert(0, base);
        MaxPyramid { levels }
    }

    /// A pyramid of levels made elsewhere (a blended terrain's bound): sizes must follow the mip
    /// rule from `levels[0]` down to 1x1.
    pub fn from_levels(levels: Vec<PyramidLevel>) -> MaxPyramid {
        let first = &levels[0];
        debug_assert_eq!(
            levels.len() as u32,
            mip_level_count(first.width, first.height)
        );
        debug_assert!(levels
            .iter()
            .all(|l| l.data.len() == l.width as usize * l.height as usize));
        MaxPyramid { levels }
    }

    /// All levels, finest (level 0, the map itself) first.
    pub fn levels(&self) -> &[PyramidLevel] {
        &self.levels
    }

    /// Level `n`; panics if `n >= level_count()` (use [`MaxPyramid::levels`] for a fallible lookup).
    pub fn level(&self, n: u32) -> &PyramidLevel {
        &self.levels[n as usize]
    }

    /// Number of levels: `mip_level_count(width, height)` of the source map.
    pub fn level_count(&self) -> u32 {
        self.levels.len() as u32
    }
}

/// Each texel replaced by the max of its 3x3 neighbourhood (wrapping or clamping at the borders).
fn dilate(level: &PyramidLevel, wrap: bool) -> PyramidLevel {
    let (w, h) = (level.width as i64, level.height as i64);
    let index = |k: i64, n: i64| {
        if wrap {
            k.rem_euclid(n)
        } else {
            k.clamp(0, n - 1)
        }
    };
    let mut data = Vec::with_capacity(level.data.len());
    for j in 0..h {
        for i in 0..w {
            let mut m = f32::MIN;
            for dj in -1..=1 {
                for di in -1..=1 {
                    let k = index(j + dj, h) * w + index(i + di, w);
                    m = m.max(level.data[k as usize]);
                }
            }
            data.push(m);
        }
    }
    PyramidLevel {
        width: level.width,
        height: level.height,
        data,
    }
}

/// The next coarser level of `fine` by Vulkan's size rule.
fn reduce(fine: &PyramidLevel) -> PyramidLevel {
    let width = (fine.width / 2).max(1);
    let height = (fine.height / 2).max(1);
    let rows = reduce_along_u(fine, width);
    let data = reduce_along_v(&rows, width as usize, fine.height, height);
    PyramidLevel {
        width,
        height,
        data,
    }
}

/// Per fine row, the maximum over each coarse texel's u range: `coarse_width x fine.height` values.
fn reduce_along_u(fine: &PyramidLevel, coarse_width: u32) -> Vec<f32> {
    let ranges: Vec<(usize, usize)> = (0..coarse_width)
        .map(|c| {
            let (a, b) = covered_range(c, coarse_width, fine.width);
            (a as usize, b as usize)
        })
        .collect();
    let mut out = Vec::with_capacity(ranges.len() * fine.height as usize);
    for row in fine.data.chunks_exact(fine.width as usize) {
        out.extend(
            ranges
                .iter()
                .map(|&(a, b)| row[a..=b].iter().fold(f32::MIN, |m, &h| m.max(h))),
        );
    }
    out
}

/// Per coarse row, the element-wise maximum of the rows (already reduced along u) in its v range.
fn reduce_along_v(rows: &[f32], width: usize, fine_height: u32, coarse_height: u32) -> Vec<f32> {
    let mut out = Vec::with_capacity(width * coarse_height as usize);
    for c in 0..coarse_height {
        let (a, b) = covered_range(c, coarse_height, fine_height);
        let start = out.len();
        out.extend_from_slice(&rows[a as usize * width..(a as usize + 1) * width]);
        for r in a as usize + 1..=b as usize {
            let src = &rows[r * width..(r + 1) * width];
            for (m, &h) in out[start..].iter_mut().zip(src) {
                *m = m.max(h);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::rng::SplitMix64;

    fn random_field(w: u32, h: u32, seed: u64) -> Heightfield {
        let mut rng = SplitMix64::new(seed);
        let data = (0..w * h).map(|_| rng.next_f32()).collect();
        Heightfield::new(w, h, data).expect("valid")
    }

    /// Independent overlap test by cross-multiplication: fine texel `k` covers `[k, k+1)/nf`, coarse texel
    /// `c` covers `[c, c+1)/nc`; they overlap iff `k/nf < (c+1)/nc` and `(k+1)/nf > c/nc`.
    fn overlaps(k: u32, nf: u32, c: u32, nc: u32) -> bool {
        let (k, nf, c, nc) = (k as u64, nf as u64, c as u64, nc as u64);
        k * nc < (c + 1) * nf && (k + 1) * nc > c * nf
    }

    /// A superset of the fine texels coarse texel `c` can overlap, padded by two so the overlap test, not
    /// this window, decides; it only keeps the brute force affordable on 257x129.
    fn search_window(c: u32, nc: u32, nf: u32) -> std::ops::RangeInclusive<u32> {
        let (c, nc, nf) = (c as u64, nc as u64, nf as u64);
        let lo = (c * nf / nc).saturating_sub(2);
        let hi = ((c + 1) * nf / nc + 2).min(nf - 1);
        lo as u32..=hi as u32
    }

    /// Straightforward max of all fine texels overlapping coarse texel `(ci, cj)`; also checks the bound.
    fn brute_max(fine: &PyramidLevel, coarse: &PyramidLevel, ci: u32, cj: u32) -> f32 {
        let mut m = f32::MIN;
        for j in search_window(cj, coarse.height, fine.height) {
            for i in search_window(ci, coarse.width, fine.width) {
                if overlaps(i, fine.width, ci, coarse.width)
                    && overlaps(j, fine.height, cj, coarse.height)
                {
                    let v = fine.get(i, j);
                    assert!(
                        coarse.get(ci, cj) >= v,
                        "coarse ({ci}, {cj}) below fine ({i}, {j})"
                    );
                    m = m.max(v);
                }
            }
        }
        m
    }

    fn check_pyramid(w: u32, h: u32) {
        let hf = random_field(w, h, u64::from(w) * 1000 + u64::from(h));
        let pyr = MaxPyramid::build(&hf);
        assert_eq!(pyr.level_count(), mip_level_count(w, h));
        assert_eq!(pyr.level(0).data, hf.data());
        for n in 1..pyr.level_count() {
            let (fine, coarse) = (pyr.level(n - 1), pyr.level(n));
            assert_eq!(coarse.width, (fine.width / 2).max(1), "{w}x{h} level {n}");
            assert_eq!(coarse.height, (fine.height / 2).max(1), "{w}x{h} level {n}");
            assert_eq!(coarse.data.len(), (coarse.width * coarse.height) as usize);
            for cj in 0..coarse.height {
                for ci in 0..coarse.width {
                    let want = brute_max(fine, coarse, ci, cj);
                    assert_eq!(
                        coarse.get(ci, cj),
                        want,
                        "{w}x{h} level {n} texel ({ci}, {cj})"
                    );
                }
            }
        }
        let top = pyr.level(pyr.level_count() - 1);
        assert_eq!((top.width, top.height), (1, 1));
        let global = hf.data().iter().fold(f32::MIN, |m, &v| m.max(v));
        assert_eq!(top.data[0], global);
    }

    #[test]
    fn bilinear_bound_levels_bound_the_bilinear_surface() {
        use crate::heightfield::reference::{surface_depth, Address, SurfaceModel};
        for (w, h, wrap) in [
            (13, 7, true),
            (16, 16, false),
            (5, 3, true),
            (33, 17, false),
        ] {
            let hf = random_field(w, h, 7 + u64::from(w));
            let pyr = MaxPyramid::build_bilinear_bound(&hf, wrap);
            assert_eq!(pyr.level(0).data, hf.data(), "level 0 is the map itself");
            let address = if wrap {
                Address::Repeat
            } else {
                Address::Clamp
            };
            for level in pyr.levels().iter().skip(1) {
                for j in 0..level.height {
                    for i in 0..level.width {
                        // Sample the cell densely, edges included.
                        for sj in 0..=8 {
                            for si in 0..=8 {
                                let u =
                                    (f64::from(i) + f64::from(si) / 8.0) / f64::from(level.width);
                                let v =
                                    (f64::from(j) + f64::from(sj) / 8.0) / f64::from(level.height);
                                let d =
                                    surface_depth(&hf, u, v, 1.0, SurfaceModel::Bilinear, address);
                                let surface = 1.0 - d;
                                assert!(
                                    f64::from(level.get(i, j)) >= surface - 1e-6,
                                    "{w}x{h} level {}x{} node ({i},{j}) {} below bilinear {surface} at ({u},{v})",
                                    level.width, level.height, level.get(i, j)
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn pyramid_matches_brute_force_for_awkward_sizes() {
        for (w, h) in [
            (1, 1),
            (2, 2),
            (3, 5),
            (64, 64),
            (257, 129),
            (7, 1),
            (1, 6),
            (5, 3),
        ] {
            check_pyramid(w, h);
        }
    }

    #[test]
    fn every_level_bounds_the_full_resolution_map() {
        // Conservative against level 0 directly, not only against the level below.
        let hf = random_field(13, 7, 99);
        let pyr = MaxPyramid::build(&hf);
        let base = pyr.level(0);
        for level in &pyr.levels()[1..] {
            for cj in 0..level.height {
                for ci in 0..level.width {
                    brute_max(base, level, ci, cj);
                }
            }
        }
    }

    #[test]
    fn level_counts_and_sizes_follow_vulkan() {
        assert_eq!(mip_level_count(1, 1), 1);
        assert_eq!(mip_level_count(2, 1), 2);
        assert_eq!(mip_level_count(3, 5), 3);
        assert_eq!(mip_level_count(256, 256), 9);
        assert_eq!(mip_level_count(257, 129), 9);
        assert_eq!(mip_level_count(4096, 16), 13);
        let pyr = MaxPyramid::build(&random_field(257, 129, 1));
        let sizes: Vec<(u32, u32)> = pyr.levels().iter().map(|l| (l.width, l.height)).collect();
        let expected = [
            (257, 129),
            (128, 64),
            (64, 32),
            (32, 16),
            (16, 8),
            (8, 4),
            (4, 2),
            (2, 1),
            (1, 1),
        ];
        assert_eq!(sizes, expected);
    }

    #[test]
    fn covered_range_examples() {
        assert_eq!(covered_range(3, 8, 16), (6, 7));
        assert_eq!(covered_range(0, 1, 1), (0, 0));
        assert_eq!(covered_range(0, 1, 3), (0, 2));
        // 5 -> 2: texel 2 of the finer level straddles both coarse texels and feeds both.
        assert_eq!(covered_range(0, 2, 5), (0, 2));
        assert_eq!(covered_range(1, 2, 5), (2, 4));
        assert_eq!(
            covered_range(u32::MAX - 1, u32::MAX, u32::MAX),
            (u32::MAX - 1, u32::MAX - 1)
        );
    }
}

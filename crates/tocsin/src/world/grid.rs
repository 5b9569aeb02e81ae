//! Broad phase without a sweep: a grid of cells on all three axes, as wide as the widest
//! "regular" box ([`SweepAxis::Grid3`](super::broad::SweepAxis::Grid3), and the GPU's plan,
//! `world::gpu` with the feature `cuda`).
//!
//! Two boxes that overlap have low corners at most the wider one's width apart on every axis.
//! With cells at least as wide as every regular box, the low corners of two overlapping
//! regular boxes lie in cells at most one apart on each axis, so each box tests only the boxes
//! whose low corner lies in the 27 cells around its own: a counting sort by cell replaces the
//! sorting the sweep needs. The widest boxes (the "oversize" ones, below) are kept out of the
//! cell size; each is tested against the boxes whose low corners lie in the cells its own range
//! covers (one more below).
//!
//! The cell size is the largest regular width times `1 + 1e-6` plus a few units in the last
//! place of the largest coordinate, so rounding in `(x - origin) / size` never puts two low
//! corners a width apart two cells apart; the grid has at most about four cells per box (the
//! cells grow where the boxes' extent would need more).
//!
//! Where the boxes' extent would need more than that many cells of that size (a far outlier, a
//! sparse world, boxes that are points), cells grown to fit would hold clusters whole; the
//! CPU then answers with the sweep in the coordinate frame, which sorts inside its cells.
//!
//! On the CPU the regular boxes are those at most twice the median width wide, as the sweep's
//! cells are twice the median width (the cells as wide as the widest of them): an oversize box
//! costs the cells its range covers, so many may be; the oversize boxes against each other are
//! the same search on them alone (their own median), so a world of plates, bins and small parts
//! stays a grid at every size. On the GPU an oversize box costs a pass over every box, so only
//! `64 + n / 16384` are allowed (`world::gpu`).
//!
//! The boxes are visited in cell order (the neighbours' boxes are near in memory), each
//! reporting the partners after it, and the pairs are sorted at the end: the same answer as
//! [`super::broad::sweep_and_prune`]'s in the other frames.

use super::swept::Aabb;
use rayon::prelude::*;

/// The cells: `n` per axis of side `size` from `origin` (the smallest low corner).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CellGrid {
    pub origin: [f64; 3],
    pub size: f64,
    pub n: [u32; 3],
    /// Whether the cells had to grow to more than twice the width asked for (the extent would
    /// have needed too many).
    pub coarse: bool,
}

impl CellGrid {
    /// Cells over the low corners' extent `lo..hi` (of `valid` boxes), wider than `wmax` by the
    /// rounding margin (module docs), grown until there are at most `4 valid + 64` of them (and
    /// under 2^31: cell numbers are 32-bit).
    pub(crate) fn new(valid: u64, lo: [f64; 3], hi: [f64; 3], wmax: f64) -> Self {
        let span = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        let largest = lo
            .iter()
            .chain(hi.iter())
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let slack = 8.0 * f64::EPSILON * largest;
        let base = (wmax * (1.0 + 1e-6) + slack).max(f64::MIN_POSITIVE);
        let mut size = base;
        let most = (4.0 * valid as f64 + 64.0).min(f64::from(1u32 << 31));
        let count = |size: f64| span.map(|s| (s / size).floor() + 1.0);
        let cells = |c: [f64; 3]| c[0] * c[1] * c[2];
        if cells(count(size)) > most {
            // From the size that would give `most` cells over the non-flat axes, grown.
            let (prod, dims) = span
                .iter()
                .filter(|&&s| s > 0.0)
                .fold((1.0, 0i32), |(p, d), &s| (p * s, d + 1));
            if dims > 0 {
                size = size.max((prod / most).powf(1.0 / f64::from(dims)));
            }
            while cells(count(size)) > most {
                size *= 1.25;
            }
        }
        Self {
            origin: lo,
            size,
            n: count(size).map(|v| v as u32),
            coarse: size > 2.0 * base,
        }
    }

    /// How many cells.
    pub(crate) fn cells(&self) -> usize {
        self.n.iter().map(|&c| c as usize).product()
    }

    /// The cell coordinate of `v` on axis `k`, clamped to the grid.
    #[inline]
    pub(crate) fn coord(&self, v: f64, k: usize) -> u32 {
        let q = ((v - self.origin[k]) / self.size).floor();
        // NaN (never for a valid box) and below the origin: the first cell.
        if q.is_nan() || q <= 0.0 {
            0
        } else if q >= f64::from(self.n[k] - 1) {
            self.n[k] - 1
        } else {
            q as u32
        }
    }

    #[inline]
    fn cell(&self, c: [u32; 3]) -> usize {
        (c[0] as usize * self.n[1] as usize + c[1] as usize) * self.n[2] as usize + c[2] as usize
    }
}

/// A box with finite coordinates and `min <= max` on every axis.
#[inline]
pub(crate) fn holds_something(b: &Aabb) -> bool {
    b.min.is_finite() && b.max.is_finite() && b.min.cmple(b.max).all()
}

/// A box as six numbers: min x y z, max x y z (the layout the grid and the GPU's kernels read).
#[inline]
pub(crate) fn flat(b: &Aabb) -> [f64; 6] {
    [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z]
}

/// A box's largest side.
#[inline]
fn width(b: &Aabb) -> f64 {
    (b.max - b.min).max_element()
}

/// Every pair `(i, j)`, `i < j`, of boxes that overlap (touching counts), sorted (module docs);
/// boxes with a NaN or infinite coordinate, or empty, overlap nothing.
pub(crate) fn grid_pairs(boxes: &[Aabb]) -> Vec<(u32, u32)> {
    let n = boxes.len();
    let widths: Vec<f64> = boxes
        .par_iter()
        .map(|b| if holds_something(b) { width(b) } else { -1.0 })
        .collect();
    let mut valid_widths: Vec<f64> = widths.par_iter().copied().filter(|&w| w >= 0.0).collect();
    let valid = valid_widths.len() as u64;
    if valid < 2 {
        return Vec::new();
    }
    // Cells as wide as the widest box at most twice the median width; wider boxes are oversize.
    let half = valid_widths.len() / 2;
    let median = *valid_widths.select_nth_unstable_by(half, f64::total_cmp).1;
    let wmax = valid_widths
        .iter()
        .copied()
        .filter(|&w| w <= 2.0 * median)
        .fold(0.0, f64::max);
    drop(valid_widths);
    let (lo, hi) = boxes
        .par_iter()
        .zip(widths.par_iter())
        .filter(|(_, &w)| w >= 0.0)
        .map(|(b, _)| (b.min.to_array(), b.min.to_array()))
        .reduce(
            || ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
            |a, b| {
                (
                    std::array::from_fn(|k| a.0[k].min(b.0[k])),
                    std::array::from_fn(|k| a.1[k].max(b.1[k])),
                )
            },
        );
    let grid = CellGrid::new(valid, lo, hi, wmax);
    if grid.size
        > 2.0 * (wmax * (1.0 + 1e-6))
            + 16.0 * f64::EPSILON * lo.iter().fold(0.0f64, |m, v| m.max(v.abs()))
    {
        // The boxes' extent needs more cells than the grid may have (a far outlier, a sparse
        // world, boxes that are points): cells that coarse would hold clusters whole, which
        // the sweep's sorted cells take in their stride.
        return super::broad::sweep_and_prune(boxes, super::broad::SweepAxis::LargestVariance);
    }
    let regular = |i: usize| widths[i] >= 0.0 && widths[i] <= wmax;
    let corner = |b: &Aabb| [0, 1, 2].map(|k| grid.coord(b.min[k], k));
    // The counting sort: each regular box in its low corner's cell, cells in order, boxes in
    // index order inside a cell.
    let cells = grid.cells();
    let cell_of: Vec<u32> = (0..n)
        .into_par_iter()
        .map(|i| {
            if regular(i) {
                grid.cell(corner(&boxes[i])) as u32
            } else {
                u32::MAX
            }
        })
        .collect();
    let mut start = vec![0u32; cells + 1];
    for &c in &cell_of {
        if c != u32::MAX {
            start[c as usize + 1] += 1;
        }
    }
    for c in 0..cells {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut sorted = vec![(0u32, [0.0f64; 6]); start[cells] as usize];
    for (i, &c) in cell_of.iter().enumerate() {
        if c != u32::MAX {
            let b = &boxes[i];
            let at = &mut fill[c as usize];
            sorted[*at as usize] = (i as u32, flat(b));
            *at += 1;
        }
    }
    drop(fill);
    let meets = |a: &[f64; 6], b: &[f64; 6]| {
        a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5]
    };
    // The boxes whose low corner lies in cells `from..=to` (per axis), each given to `f`.
    let scan = |from: [u32; 3], to: [u32; 3], f: &mut dyn FnMut(u32, &[f64; 6])| {
        for x in from[0]..=to[0] {
            for y in from[1]..=to[1] {
                let row = grid.cell([x, y, 0]);
                let q0 = start[row + from[2] as usize] as usize;
                let q1 = start[row + to[2] as usize + 1] as usize;
                for (j, b) in &sorted[q0..q1] {
                    f(*j, b);
                }
            }
        }
    };
    let below = |c: [u32; 3]| c.map(|v| v.saturating_sub(1));
    let above = |c: [u32; 3]| [0, 1, 2].map(|k| (c[k] + 1).min(grid.n[k] - 1));
    // Regular boxes against the 27 cells around their own, in cell order (neighbours are read
    // from memory nearby); all pairs are sorted at the end.
    let chunk = 2048;
    let mut pairs: Vec<(u32, u32)> = (0..sorted.len().div_ceil(chunk))
        .into_par_iter()
        .flat_map_iter(|c| {
            let mut out = Vec::new();
            for (i, a) in &sorted[c * chunk..((c + 1) * chunk).min(sorted.len())] {
                let home = [0, 1, 2].map(|k| grid.coord(a[k], k));
                scan(below(home), above(home), &mut |j, other| {
                    if j > *i && meets(a, other) {
                        out.push((*i, j));
                    }
                });
            }
            out
        })
        .collect();
    let oversize: Vec<usize> = (0..n)
        .filter(|&i| widths[i] >= 0.0 && !regular(i))
        .collect();
    // Oversize boxes against the regular boxes whose low corners lie in the cells of their own
    // range (one more below).
    let extra: Vec<(u32, u32)> = oversize
        .par_iter()
        .flat_map_iter(|&o| {
            let b = &boxes[o];
            let a = flat(b);
            let to = [0, 1, 2].map(|k| grid.coord(b.max[k], k));
            let mut out = Vec::new();
            scan(below(corner(b)), to, &mut |j, other| {
                if meets(&a, other) {
                    out.push((j.min(o as u32), j.max(o as u32)));
                }
            });
            out
        })
        .collect();
    pairs.extend(extra);
    // Oversize boxes against each other: the same search on them alone (their own median).
    if oversize.len() >= 2 {
        let wide: Vec<Aabb> = oversize.iter().map(|&o| boxes[o]).collect();
        pairs.extend(
            grid_pairs(&wide)
                .into_iter()
                .map(|(a, b)| (oversize[a as usize] as u32, oversize[b as usize] as u32)),
        );
    }
    pairs.par_sort_unstable();
    pairs
}

//! Broad phase: every pair of overlapping boxes, by sort and sweep in cells.
//!
//! A sweep along one axis alone prunes in one dimension only: for a million boxes in a unit
//! cube sized for two overlaps each, every box still meets 16,000 others along the axis (7 s
//! on 2 cores, measured). So, as gSaP does (Liu, Harada, Lee, Kim, "Real-time collision
//! culling of a million bodies on graphics processing units", 2010), the sweep runs along one
//! axis `d1` of a frame, inside the cells of a grid on the frame's two other axes:
//! 1. each box is projected on the frame `d1, d2, d3` (the interval `c . d +- h . |d|`, exact
//!    for a box, and overlapping projections are necessary for overlapping boxes; on coordinate
//!    axes the box's own interval);
//! 2. the plane `d2, d3` is cut into square cells twice the median box width (measured: 1x and
//!    1.5x are slower at a million boxes, 3x at ten thousand); each box is copied into every cell
//!    its projection covers (a counting sort), and each cell is sorted by the low end on `d1`,
//!    cells in parallel; a box covering more than [`MAX_CELLS`] cells is "oversize" and kept
//!    out of the cells;
//! 3. each cell is swept in parallel: a box is tested against the boxes after it whose low end
//!    on `d1` is not past its high end; a pair found in several cells is reported only in the
//!    cell holding the low corner of the overlap of its two `d2, d3` rectangles (one cell);
//! 4. each oversize box is tested against every box whose `d1` interval meets its own (by
//!    binary search in the boxes sorted along `d1`).
//!
//! The exact test of a candidate is the boxes' own overlap (touching counts), so no pair is
//! missed and none is invented whatever the axes; the frame only decides the work.
//! [`SweepAxis::Principal`] uses the principal axes of the box centres (gSaP's choice),
//! [`SweepAxis::LargestVariance`] the coordinate axes, the one of largest variance first: on
//! coordinate axes the projections are the boxes themselves (no rotated box grows, and the
//! overlap test needs no second read of the boxes), which measured 1.4 to 2.4 times faster on
//! random boxes (docs/BENCHMARKS.md): the default. [`SweepAxis::Grid3`] does not sweep: a
//! counting sort into cells on all three axes (`world::grid`), faster again on dense sets of
//! boxes, level on a world's. The pairs come back sorted, so the result does not depend on the
//! thread count or the method.

use super::grid::holds_something;
use super::swept::Aabb;
use crate::math::Vec3;
use rayon::prelude::*;

/// The frame the boxes are sorted and binned in (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum SweepAxis {
    /// The principal axes of the box centres.
    Principal,
    /// The coordinate axes, the one with the largest variance of the box centres first (the
    /// default: measured 1.4 to 2.4 times faster than the principal axes, docs/BENCHMARKS.md).
    #[default]
    LargestVariance,
    /// No sweep: a grid of cells on all three axes as wide as the widest regular box, each box
    /// against the 27 cells around its own (the GPU's plan; `world::grid`'s module docs). On
    /// dense sets of boxes (two pairs each), 14 to 36% faster than the sweep from 500 to a
    /// million boxes; on the 10,000-body world's swept boxes level with it or up to 10% slower
    /// (docs/BENCHMARKS.md, twenty-fifth session), so not the default.
    Grid3,
}

/// A box covering more cells than this is swept against all boxes instead.
pub const MAX_CELLS: usize = 64;

/// A box projected on the sweep frame.
#[derive(Clone, Copy)]
struct Projected {
    lo: [f64; 3],
    hi: [f64; 3],
    id: u32,
}

impl Projected {
    #[inline]
    fn meets(&self, other: &Projected, axis: usize) -> bool {
        self.lo[axis] <= other.hi[axis] && other.lo[axis] <= self.hi[axis]
    }
}

/// The cell grid on the frame's second and third axes.
struct Grid {
    origin: [f64; 2],
    size: f64,
    n: [usize; 2],
}

impl Grid {
    #[inline]
    fn index(&self, v: f64, k: usize) -> usize {
        let i = ((v - self.origin[k]) / self.size).floor();
        if i >= 0.0 {
            (i as usize).min(self.n[k] - 1)
        } else {
            0
        }
    }

    /// The cells a projected box covers: `[i0, i1] x [j0, j1]`.
    #[inline]
    fn cover(&self, p: &Projected) -> ([usize; 2], [usize; 2]) {
        (
            [self.index(p.lo[1], 0), self.index(p.lo[2], 1)],
            [self.index(p.hi[1], 0), self.index(p.hi[2], 1)],
        )
    }
}

/// Every pair `(i, j)`, `i < j`, of boxes that overlap (touching counts), sorted. Boxes with a
/// NaN or infinite coordinate, or `min > max` on an axis (empty), overlap nothing.
pub fn sweep_and_prune(boxes: &[Aabb], axis: SweepAxis) -> Vec<(u32, u32)> {
    assert!(
        u32::try_from(boxes.len()).is_ok(),
        "sweep_and_prune: more than u32::MAX boxes"
    );
    if boxes.len() < 2 {
        return Vec::new();
    }
    if axis == SweepAxis::Grid3 {
        return super::grid::grid_pairs(boxes);
    }
    let frame = sweep_frame(boxes, axis);
    // On coordinate axes a box's projection is its own interval, taken as stored: the overlap
    // of the three projections is then the exact test, and the boxes need not be read again.
    let coordinate = frame.map(|d| [Vec3::X, Vec3::Y, Vec3::Z].iter().position(|e| *e == d));
    let exact = coordinate.iter().all(Option::is_some);
    let project = |b: &Aabb| {
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for k in 0..3 {
            if let Some(axis) = coordinate[k] {
                lo[k] = b.min[axis];
                hi[k] = b.max[axis];
            } else {
                let (c, h) = (b.center(), b.half_extents());
                let d = frame[k].abs();
                let (m, r) = (c.dot(frame[k]), h.dot(d));
                // Widened by a bound on the rounding of the centre, the half extents and the
                // dot products, so that the projection holds the box's own (a point touching a
                // box's corner was missed without it); the exact test of the boxes decides.
                let slack = 8.0 * f64::EPSILON * (c.abs().dot(d) + r);
                lo[k] = m - r - slack;
                hi[k] = m + r + slack;
            }
        }
        (lo, hi)
    };
    let projected: Vec<Projected> = boxes
        .par_iter()
        .enumerate()
        .filter(|(_, b)| holds_something(b))
        .map(|(i, b)| {
            let (lo, hi) = project(b);
            Projected {
                lo,
                hi,
                id: i as u32,
            }
        })
        .collect();
    let grid = grid(&projected);
    // Cells: a counting sort of (cell, box) entries, then each cell sorted along d1.
    let cells = grid.n[0] * grid.n[1];
    let covers: Vec<([usize; 2], [usize; 2])> =
        projected.par_iter().map(|p| grid.cover(p)).collect();
    let mut start = vec![0u32; cells + 1];
    let mut is_oversize = vec![false; projected.len()];
    for (k, (a, b)) in covers.iter().enumerate() {
        if (b[0] - a[0] + 1) * (b[1] - a[1] + 1) > MAX_CELLS {
            is_oversize[k] = true;
            continue;
        }
        for i in a[0]..=b[0] {
            for j in a[1]..=b[1] {
                start[i * grid.n[1] + j + 1] += 1;
            }
        }
    }
    for c in 0..cells {
        start[c + 1] += start[c];
    }
    // Each cell's boxes are copied next to each other: the sweep reads memory in order.
    let placeholder = Projected {
        lo: [0.0; 3],
        hi: [0.0; 3],
        id: 0,
    };
    let mut entries = vec![placeholder; start[cells] as usize];
    let mut fill = start.clone();
    for (k, (a, b)) in covers.iter().enumerate() {
        if is_oversize[k] {
            continue;
        }
        for i in a[0]..=b[0] {
            for j in a[1]..=b[1] {
                let c = i * grid.n[1] + j;
                entries[fill[c] as usize] = projected[k];
                fill[c] += 1;
            }
        }
    }
    let mut slices = Vec::with_capacity(cells);
    let mut rest = entries.as_mut_slice();
    for c in 0..cells {
        let (cell, tail) = rest.split_at_mut((start[c + 1] - start[c]) as usize);
        slices.push(cell);
        rest = tail;
    }
    slices.par_iter_mut().for_each(|cell| {
        cell.sort_unstable_by(|a, b| a.lo[0].total_cmp(&b.lo[0]).then(a.id.cmp(&b.id)));
    });
    let found = |pairs: &mut Vec<(u32, u32)>, p: &Projected, q: &Projected| {
        if exact || boxes[p.id as usize].overlaps(&boxes[q.id as usize]) {
            pairs.push((p.id.min(q.id), p.id.max(q.id)));
        }
    };
    let mut pairs: Vec<(u32, u32)> = (0..cells)
        .into_par_iter()
        .flat_map_iter(|c| {
            let cell = &entries[start[c] as usize..start[c + 1] as usize];
            let home = [c / grid.n[1], c % grid.n[1]];
            let mut out = Vec::new();
            for (x, p) in cell.iter().enumerate() {
                for q in &cell[x + 1..] {
                    if q.lo[0] > p.hi[0] {
                        break;
                    }
                    if !(p.meets(q, 1) && p.meets(q, 2)) {
                        continue;
                    }
                    let corner = [
                        grid.index(p.lo[1].max(q.lo[1]), 0),
                        grid.index(p.lo[2].max(q.lo[2]), 1),
                    ];
                    if corner == home {
                        found(&mut out, p, q);
                    }
                }
            }
            out
        })
        .collect();
    // Oversize boxes against every box whose d1 interval meets theirs, found by binary search
    // in the order along d1; a pair of two oversize boxes is reported by the one first there.
    let oversize: Vec<usize> = (0..projected.len()).filter(|&k| is_oversize[k]).collect();
    let extra: Vec<(u32, u32)> = if oversize.is_empty() {
        Vec::new()
    } else {
        let mut order: Vec<(f64, u32)> = projected
            .iter()
            .enumerate()
            .map(|(k, p)| (p.lo[0], k as u32))
            .collect();
        order.par_sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let widest = projected
            .iter()
            .map(|p| p.hi[0] - p.lo[0])
            .fold(0.0, f64::max);
        oversize
            .par_iter()
            .flat_map_iter(|&k| {
                let p = &projected[k];
                // A box meeting `p` along d1 starts at most its width, so at most `widest`,
                // below `p.lo`. Both the widths and this subtraction round: lowered by a bound
                // on both (a box touching `p`'s low end exactly, as wide as `widest`, was
                // skipped when `p.lo - widest` rounded up by one unit in the last place).
                let reach = widest + 4.0 * f64::EPSILON * (p.lo[0].abs() + widest);
                let first = order.partition_point(|q| q.0 < p.lo[0] - reach);
                let mut out = Vec::new();
                for &(lo, m) in &order[first..] {
                    if lo > p.hi[0] {
                        break;
                    }
                    let m = m as usize;
                    if m == k || (is_oversize[m] && m < k) {
                        continue;
                    }
                    let q = &projected[m];
                    if p.meets(q, 0) && p.meets(q, 1) && p.meets(q, 2) {
                        found(&mut out, p, q);
                    }
                }
                out
            })
            .collect()
    };
    pairs.extend(extra);
    pairs.par_sort_unstable();
    pairs
}

/// Cells twice the median width of the boxes on the frame's second and third axes, no more
/// than about four per box.
fn grid(sorted: &[Projected]) -> Grid {
    let stride = (sorted.len() / 4096).max(1);
    let mut widths: Vec<f64> = sorted
        .iter()
        .step_by(stride)
        .map(|p| (p.hi[1] - p.lo[1]).max(p.hi[2] - p.lo[2]))
        .filter(|w| w.is_finite())
        .collect();
    widths.sort_by(f64::total_cmp);
    let median = widths.get(widths.len() / 2).copied().unwrap_or(0.0);
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in sorted {
        for k in 0..2 {
            if p.lo[k + 1].is_finite() {
                lo[k] = lo[k].min(p.lo[k + 1]);
            }
            if p.hi[k + 1].is_finite() {
                hi[k] = hi[k].max(p.hi[k + 1]);
            }
        }
    }
    let span = [(hi[0] - lo[0]).max(0.0), (hi[1] - lo[1]).max(0.0)];
    let most = (4.0 * sorted.len() as f64).max(1.0);
    // The smallest cell that keeps the count under `most`.
    let floor = (span[0] * span[1] / most)
        .sqrt()
        .max(span[0].max(span[1]) / most);
    let size = (2.0 * median).max(floor);
    if !(size.is_finite() && size > 0.0 && lo[0].is_finite() && lo[1].is_finite()) {
        return Grid {
            origin: [0.0; 2],
            size: 1.0,
            n: [1, 1],
        };
    }
    let count = |k: usize| ((span[k] / size).floor() as usize + 1).clamp(1, 1 << 16);
    Grid {
        origin: lo,
        size,
        n: [count(0), count(1)],
    }
}

/// The same pairs by testing every pair of boxes (the reference the sweep is tested and
/// benchmarked against), in parallel over the first box; boxes with a NaN or infinite
/// coordinate, or empty, overlap nothing here too.
pub fn all_pairs(boxes: &[Aabb]) -> Vec<(u32, u32)> {
    assert!(
        u32::try_from(boxes.len()).is_ok(),
        "all_pairs: more than u32::MAX boxes"
    );
    (0..boxes.len())
        .into_par_iter()
        .flat_map_iter(|i| {
            let bi = boxes[i];
            let keep = holds_something(&bi);
            boxes[i + 1..]
                .iter()
                .enumerate()
                .filter(move |(_, bj)| keep && holds_something(bj) && bi.overlaps(bj))
                .map(move |(k, _)| (i as u32, (i + 1 + k) as u32))
        })
        .collect()
}

/// The orthonormal frame the sweep works in: the sweep axis first.
fn sweep_frame(boxes: &[Aabb], axis: SweepAxis) -> [Vec3; 3] {
    let finite = |b: &&Aabb| holds_something(b);
    let (count, sum) = boxes
        .par_iter()
        .filter(finite)
        .map(|b| (1usize, b.center()))
        .reduce(|| (0, Vec3::ZERO), |a, b| (a.0 + b.0, a.1 + b.1));
    if count < 2 {
        return [Vec3::X, Vec3::Y, Vec3::Z];
    }
    let mean = sum / count as f64;
    let cov = boxes
        .par_iter()
        .filter(finite)
        .map(|b| {
            let c = b.center() - mean;
            [
                [c.x * c.x, c.x * c.y, c.x * c.z],
                [c.y * c.x, c.y * c.y, c.y * c.z],
                [c.z * c.x, c.z * c.y, c.z * c.z],
            ]
        })
        .reduce(
            || [[0.0; 3]; 3],
            |a, b| std::array::from_fn(|r| std::array::from_fn(|c| a[r][c] + b[r][c])),
        );
    match axis {
        SweepAxis::Principal => {
            let m = crate::bvh::eigen::principal_axes(cov);
            let frame = [m.x_axis, m.y_axis, m.z_axis];
            if frame
                .iter()
                .all(|d| d.is_finite() && (d.length() - 1.0).abs() < 1e-6)
            {
                frame
            } else {
                [Vec3::X, Vec3::Y, Vec3::Z]
            }
        }
        SweepAxis::LargestVariance | SweepAxis::Grid3 => {
            let v = [cov[0][0], cov[1][1], cov[2][2]];
            let mut order = [0usize, 1, 2];
            order.sort_by(|&a, &b| v[b].total_cmp(&v[a]));
            order.map(|k| [Vec3::X, Vec3::Y, Vec3::Z][k])
        }
    }
}

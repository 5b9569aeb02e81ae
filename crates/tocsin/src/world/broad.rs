//! Broad phase: every pair of overlapping boxes, by sort and sweep along one axis.
//!
//! Each box is projected on a unit axis `d` (the interval `c . d +- h . |d|`, exact for a box);
//! the intervals are sorted by their low end (in parallel), and each box is tested in full (all
//! three coordinates) against the boxes after it whose low end is not past its high end. Every
//! overlapping pair has overlapping projections, so none is missed, whatever the axis; the axis
//! only decides how many projections overlap for nothing. [`SweepAxis::Principal`] is the
//! principal axis of the box centres (the largest-variance direction, as in gSaP: Liu et al.,
//! "Real-time collision culling of a million bodies on graphics processing units", 2010);
//! [`SweepAxis::LargestVariance`] the coordinate axis with the largest variance. The sweep is
//! split in chunks of sorted boxes run on rayon's threads; the pairs come back sorted, so the
//! result does not depend on the thread count or the axis.

use super::swept::Aabb;
use crate::math::Vec3;
use rayon::prelude::*;

/// The axis the boxes are sorted along (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum SweepAxis {
    /// The principal axis of the box centres.
    #[default]
    Principal,
    /// The x, y or z axis, whichever has the largest variance of the box centres.
    LargestVariance,
}

/// Boxes per parallel chunk of the sweep.
const CHUNK: usize = 2048;

/// Every pair `(i, j)`, `i < j`, of boxes that overlap (touching counts), sorted. Boxes with a
/// NaN coordinate overlap nothing.
pub fn sweep_and_prune(boxes: &[Aabb], axis: SweepAxis) -> Vec<(u32, u32)> {
    let n = boxes.len();
    assert!(
        u32::try_from(n).is_ok(),
        "sweep_and_prune: more than u32::MAX boxes"
    );
    if n < 2 {
        return Vec::new();
    }
    let d = sweep_direction(boxes, axis);
    let dabs = d.abs();
    let mut order: Vec<(f64, u32)> = boxes
        .par_iter()
        .enumerate()
        .filter(|(_, b)| !(b.min.is_nan() || b.max.is_nan()))
        .map(|(i, b)| (b.center().dot(d) - b.half_extents().dot(dabs), i as u32))
        .collect();
    order.par_sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let lo: Vec<f64> = order.iter().map(|o| o.0).collect();
    let sorted: Vec<(Aabb, u32, f64)> = order
        .par_iter()
        .map(|&(_, i)| {
            let b = boxes[i as usize];
            (b, i, b.center().dot(d) + b.half_extents().dot(dabs))
        })
        .collect();
    let m = sorted.len();
    let mut pairs: Vec<(u32, u32)> = (0..m.div_ceil(CHUNK))
        .into_par_iter()
        .flat_map_iter(|c| {
            let mut out = Vec::new();
            for i in c * CHUNK..((c + 1) * CHUNK).min(m) {
                let (bi, id_i, hi) = sorted[i];
                for j in i + 1..m {
                    if lo[j] > hi {
                        break;
                    }
                    let (bj, id_j, _) = sorted[j];
                    if bi.overlaps(&bj) {
                        out.push((id_i.min(id_j), id_i.max(id_j)));
                    }
                }
            }
            out
        })
        .collect();
    pairs.par_sort_unstable();
    pairs
}

/// The same pairs by testing every pair of boxes (the reference the sweep is tested and
/// benchmarked against), in parallel over the first box.
pub fn all_pairs(boxes: &[Aabb]) -> Vec<(u32, u32)> {
    assert!(
        u32::try_from(boxes.len()).is_ok(),
        "all_pairs: more than u32::MAX boxes"
    );
    (0..boxes.len())
        .into_par_iter()
        .flat_map_iter(|i| {
            let bi = boxes[i];
            boxes[i + 1..]
                .iter()
                .enumerate()
                .filter(move |(_, bj)| bi.overlaps(bj))
                .map(move |(k, _)| (i as u32, (i + 1 + k) as u32))
        })
        .collect()
}

/// The unit axis the sweep sorts along.
fn sweep_direction(boxes: &[Aabb], axis: SweepAxis) -> Vec3 {
    let finite = |b: &&Aabb| b.min.is_finite() && b.max.is_finite();
    let (count, sum) = boxes
        .par_iter()
        .filter(finite)
        .map(|b| (1usize, b.center()))
        .reduce(|| (0, Vec3::ZERO), |a, b| (a.0 + b.0, a.1 + b.1));
    if count < 2 {
        return Vec3::X;
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
            let d = crate::bvh::eigen::principal_axes(cov).x_axis;
            if d.is_finite() && d.length() > 0.5 {
                d.normalize()
            } else {
                Vec3::X
            }
        }
        SweepAxis::LargestVariance => {
            let v = [cov[0][0], cov[1][1], cov[2][2]];
            let k = (0..3).fold(0, |k, i| if v[i] > v[k] { i } else { k });
            [Vec3::X, Vec3::Y, Vec3::Z][k]
        }
    }
}

//! Rectangle swept sphere volumes (RSS, Larsen et al., "Fast proximity queries with swept sphere
//! volumes", 1999): the set of points within `radius` of a rectangle.
//!
//! Fitting follows the principal axes (largest spread first, the third axis is the rectangle's
//! normal). The radius is half the spread along the normal; the rectangle is then shrunk so
//! that the spherical ends still cover every point (each point keeps `dx, dy <= s/sqrt(2)` of
//! the rectangle where `s^2 = r^2 - dz^2`, so it is within `r`). The radius is inflated by a
//! relative 1e-12 so that rounding in the projection can never leave a point outside.

use crate::math::{Mat3, Vec3};

/// A rectangle swept sphere, in the frame of its mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rss {
    /// Columns: the rectangle's two edge directions and its normal (right-handed, orthonormal).
    pub axes: Mat3,
    /// Centre of the rectangle, mesh frame.
    pub center: Vec3,
    /// Half lengths of the rectangle along `axes.x_axis` and `axes.y_axis` (model units).
    pub half_lengths: [f64; 2],
    /// Radius of the swept sphere (model units).
    pub radius: f64,
}

impl Rss {
    /// Fits an RSS with the given axes around `points` (mesh frame). `points` must not be empty.
    pub(crate) fn fit(axes: Mat3, points: impl Iterator<Item = Vec3> + Clone) -> Rss {
        let rt = axes.transpose();
        let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
        let mut magnitude: f64 = 0.0;
        for p in points.clone() {
            let q = rt * p;
            lo = lo.min(q);
            hi = hi.max(q);
            magnitude = magnitude.max(q.abs().max_element());
        }
        // Fit with the exact half spread, then inflate: the margin must cover rounding only.
        let radius = 0.5 * (hi.z - lo.z);
        let cz = 0.5 * (hi.z + lo.z);
        // Shrink the rectangle in x and y while every point stays covered by the round ends.
        let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY);
        for p in points {
            let q = rt * p;
            let dz = q.z - cz;
            let s = (radius * radius - dz * dz).max(0.0).sqrt() * std::f64::consts::FRAC_1_SQRT_2;
            x0 = x0.min(q.x + s);
            x1 = x1.max(q.x - s);
            y0 = y0.min(q.y + s);
            y1 = y1.max(q.y - s);
        }
        if x0 > x1 {
            let m = 0.5 * (x0 + x1);
            (x0, x1) = (m, m);
        }
        if y0 > y1 {
            let m = 0.5 * (y0 + y1);
            (y0, y1) = (m, m);
        }
        let local_center = Vec3::new(0.5 * (x0 + x1), 0.5 * (y0 + y1), cz);
        Rss {
            axes,
            center: axes * local_center,
            half_lengths: [0.5 * (x1 - x0), 0.5 * (y1 - y0)],
            radius: radius + 1e-12 * magnitude + f64::MIN_POSITIVE,
        }
    }

    /// Radius of a ball about `center` that contains the volume.
    pub fn bounding_radius(&self) -> f64 {
        self.half_lengths[0].hypot(self.half_lengths[1]) + self.radius
    }

    /// A size used to choose which of two volumes to split first during traversal.
    #[inline]
    pub(crate) fn size(&self) -> f64 {
        self.half_lengths[0] + self.half_lengths[1] + self.radius
    }
}

/// `b` expressed in the frame of `a` (`a` is then the rectangle `[-l0,l0] x [-l1,l1] x {0}`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RelativeRss {
    /// Columns: `b`'s axes in `a`'s frame.
    pub r: Mat3,
    /// `b`'s centre in `a`'s frame.
    pub t: Vec3,
}

impl RelativeRss {
    /// `b`'s frame in `a`'s frame, where `rot12`, `trans12` map `b`'s mesh frame into `a`'s.
    #[inline]
    pub(crate) fn new(a: &Rss, b: &Rss, rot12: &Mat3, trans12: Vec3) -> Self {
        let at = a.axes.transpose();
        Self { r: at * (*rot12 * b.axes), t: at * (*rot12 * b.center + trans12 - a.center) }
    }
}

/// A lower bound on the distance between two RSS (0 when they may overlap) and the unit
/// direction, in `a`'s frame, along which it was found (pointing from `a` towards `b`).
///
/// The bound is the largest gap `|n.t| - extent_a(n) - extent_b(n)` over 13 candidate
/// separating axes (both normals, the four rectangle edges, the six edge cross products and
/// the centre line). By convex duality the exact distance is the largest gap over all unit
/// directions, so any candidate gives a valid lower bound, and the face and edge-edge cases are
/// exact. Returns as soon as a gap reaches `cutoff` (the caller can prune).
#[inline]
pub(crate) fn rss_separation(a: &Rss, b: &Rss, rel: &RelativeRss, cutoff: f64) -> (f64, Vec3) {
    let (la0, la1) = (a.half_lengths[0], a.half_lengths[1]);
    let (lb0, lb1) = (b.half_lengths[0], b.half_lengths[1]);
    let radii = a.radius + b.radius;
    let (r0, r1, r2) = (rel.r.x_axis, rel.r.y_axis, rel.r.z_axis);
    let t = rel.t;
    let mut best = f64::NEG_INFINITY;
    let mut best_axis = Vec3::Z;
    // Gap along a direction `n` of length `len` (> 0), given the dot products it needs.
    let mut consider = |n: Vec3, len: f64, n_r0: f64, n_r1: f64| -> bool {
        if len <= 1e-12 {
            return false;
        }
        let nt = n.dot(t);
        let gap = (nt.abs() - la0 * n.x.abs() - la1 * n.y.abs() - lb0 * n_r0.abs() - lb1 * n_r1.abs())
            / len
            - radii;
        if gap > best {
            best = gap;
            best_axis = n * (nt.signum() / len);
        }
        best >= cutoff
    };
    let tl = t.length();
    if consider(t, tl, t.dot(r0), t.dot(r1))
        || consider(Vec3::Z, 1.0, r0.z, r1.z)
        || consider(r2, 1.0, 0.0, 0.0)
        || consider(Vec3::X, 1.0, r0.x, r1.x)
        || consider(Vec3::Y, 1.0, r0.y, r1.y)
        || consider(Vec3::new(r0.x, r0.y, r0.z), 1.0, 1.0, 0.0)
        || consider(Vec3::new(r1.x, r1.y, r1.z), 1.0, 0.0, 1.0)
    {
        return (best.max(0.0), best_axis);
    }
    // Cross products of the rectangle edges: e_i x r_j, with (e_i x r_j).r_k = e_i.(r_j x r_k).
    for (j, rj) in [(0, r0), (1, r1)] {
        let sign = if j == 0 { 1.0 } else { -1.0 };
        let candidates = [
            (Vec3::new(0.0, -rj.z, rj.y), sign * r2.x),
            (Vec3::new(rj.z, 0.0, -rj.x), sign * r2.y),
            (Vec3::new(-rj.y, rj.x, 0.0), sign * r2.z),
        ];
        for (n, n_other) in candidates {
            let (n_r0, n_r1) = if j == 0 { (0.0, n_other) } else { (n_other, 0.0) };
            if consider(n, n.length(), n_r0, n_r1) {
                return (best.max(0.0), best_axis);
            }
        }
    }
    (best.max(0.0), best_axis)
}

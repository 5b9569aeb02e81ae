//! Rectangle swept sphere volumes (RSS, Larsen et al., "Fast proximity queries with swept sphere
//! volumes", 1999): the set of points within `radius` of a rectangle.
//!
//! Fitting follows the principal axes (largest spread first, the third axis is the rectangle's
//! normal). The radius is half the spread along the normal; the rectangle is then shrunk so
//! that the spherical ends still cover every point (each point keeps `dx, dy <= s/sqrt(2)` of
//! the rectangle where `s^2 = r^2 - dz^2`, so it is within `r`). The radius is inflated by
//! [`RADIUS_MARGIN`] of the points' magnitude so that rounding in the fit can never leave a
//! point outside.

use crate::math::{Mat3, Vec3};
use crate::motion::Spread;

/// Relative margin added to every radius. The fit's rounding (a rotated coordinate, a half
/// spread, the square root that shrinks the rectangle) is a few units in the last place of the
/// points' magnitude, about 1e-15 of it; 1e-14 covers it ten times over. It must stay well
/// below the distance search's tie slack (1e-13 of the scene scale, two volumes' margins
/// together): with the earlier 1e-12, parallel faces tied with the best pair were all visited
/// (two parallel 180K-triangle plates took 0.6 s).
pub const RADIUS_MARGIN: f64 = 1e-14;

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

/// How a node's triangles spread along the three axes of its volume: how far their centroids
/// spread, and the most any one triangle reaches. Where the triangles reach farther than their
/// centroids spread (slivers spanning a tube segment), a split along that axis leaves both
/// halves as long as the parent.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SplitSpread {
    /// Largest minus smallest centroid coordinate, per axis.
    pub centroids: Vec3,
    /// Largest extent of one triangle, per axis.
    pub reach: Vec3,
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
        Self::fit_from_bounds(axes, points, lo, hi, magnitude)
    }

    /// [`Rss::fit`] around the corners of `triangles`, with the [`SplitSpread`] of the
    /// triangles along the three axes gathered in the same pass (the hierarchy build chooses
    /// its split axis from it).
    pub(crate) fn fit_triangles(axes: Mat3, triangles: &[[Vec3; 3]]) -> (Rss, SplitSpread) {
        let rt = axes.transpose();
        let (mut lo, mut hi) = (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY));
        let (mut c_lo, mut c_hi) = (lo, hi);
        let mut reach = Vec3::ZERO;
        let mut magnitude: f64 = 0.0;
        for t in triangles {
            let q = t.map(|p| rt * p);
            let (t_lo, t_hi) = (q[0].min(q[1]).min(q[2]), q[0].max(q[1]).max(q[2]));
            lo = lo.min(t_lo);
            hi = hi.max(t_hi);
            reach = reach.max(t_hi - t_lo);
            let sum = q[0] + q[1] + q[2];
            c_lo = c_lo.min(sum);
            c_hi = c_hi.max(sum);
            magnitude = magnitude.max(t_lo.abs().max(t_hi.abs()).max_element());
        }
        let rss =
            Self::fit_from_bounds(axes, triangles.iter().flatten().copied(), lo, hi, magnitude);
        let spread = SplitSpread {
            centroids: (c_hi - c_lo) / 3.0,
            reach,
        };
        (rss, spread)
    }

    /// The rest of a fit, given the points' bounds `lo..hi` in the frame of `axes` and their
    /// largest coordinate magnitude in it.
    fn fit_from_bounds(
        axes: Mat3,
        points: impl Iterator<Item = Vec3>,
        lo: Vec3,
        hi: Vec3,
        magnitude: f64,
    ) -> Rss {
        let rt = axes.transpose();
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
            radius: radius + RADIUS_MARGIN * magnitude + f64::MIN_POSITIVE,
        }
    }

    /// Radius of a ball about `center` that contains the volume.
    pub fn bounding_radius(&self) -> f64 {
        self.half_lengths[0] + self.half_lengths[1] + self.radius
    }

    /// The farthest a point of the volume lies from `center`: the rectangle's corner plus the
    /// radius, `sqrt(h1^2 + h2^2) + r` (at most [`Self::bounding_radius`]).
    #[inline]
    pub(crate) fn corner_radius(&self) -> f64 {
        let [h1, h2] = self.half_lengths;
        (h1 * h1 + h2 * h2).sqrt() + self.radius
    }

    /// Half the width of the volume's projection on the unit `u` (the volume's frame): the
    /// rectangle's reach along `u` plus the radius.
    #[inline]
    pub(crate) fn support(&self, u: Vec3) -> f64 {
        self.half_lengths[0] * self.axes.x_axis.dot(u).abs()
            + self.half_lengths[1] * self.axes.y_axis.dot(u).abs()
            + self.radius
    }

    /// The volume's reach about its centre by direction, for directions of any length (the
    /// volume's frame): [`Spread::support`] is [`Self::support`] scaled by the direction's
    /// length.
    #[inline]
    pub(crate) fn spread(&self) -> Spread {
        Spread::rss(
            self.axes.x_axis,
            self.axes.y_axis,
            self.half_lengths[0],
            self.half_lengths[1],
            self.radius,
        )
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
        Self::from_a_side(&ASide::new(a, rot12, trans12), b)
    }

    /// `b` in `a`'s frame from `a`'s precomputed side (one matrix product).
    #[inline]
    pub(crate) fn from_a_side(a: &ASide, b: &Rss) -> Self {
        Self {
            r: a.q * b.axes,
            t: a.q * b.center + a.q0,
        }
    }

    /// `b` in `a`'s frame when both volumes are given in one frame (one matrix product).
    #[inline]
    pub(crate) fn in_common_frame(a: &Rss, b: &Rss) -> Self {
        Self::from_axes(a, &b.axes, b.center)
    }

    /// `b` in `a`'s frame from `b`'s precomputed side (one matrix product).
    #[inline]
    pub(crate) fn from_b_side(a: &Rss, b: &BSide) -> Self {
        Self::from_axes(a, &b.axes, b.center)
    }

    /// Axes and a centre given in the frame `a` is given in, seen from `a`'s own frame.
    #[inline]
    fn from_axes(a: &Rss, axes: &Mat3, center: Vec3) -> Self {
        let at = a.axes.transpose();
        Self {
            r: at * *axes,
            t: at * (center - a.center),
        }
    }
}

/// What a pair `(a, b)` shares for all `b`: `q = Ra^T R12`, `q0 = Ra^T (t12 - ca)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ASide {
    q: Mat3,
    q0: Vec3,
}

impl ASide {
    #[inline]
    pub(crate) fn new(a: &Rss, rot12: &Mat3, trans12: Vec3) -> Self {
        let at = a.axes.transpose();
        Self {
            q: at * *rot12,
            q0: at * (trans12 - a.center),
        }
    }
}

/// What a pair `(a, b)` shares for all `a`: `b`'s axes and centre in mesh 1's frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BSide {
    axes: Mat3,
    center: Vec3,
}

impl BSide {
    #[inline]
    pub(crate) fn new(b: &Rss, rot12: &Mat3, trans12: Vec3) -> Self {
        Self {
            axes: *rot12 * b.axes,
            center: *rot12 * b.center + trans12,
        }
    }
}

/// A lower bound on the distance between two RSS (0 when they may overlap) and the unit
/// direction, in `a`'s frame, along which it was found (pointing from `a` towards `b`).
///
/// The bound is the largest gap `|n.t| - extent_a(n) - extent_b(n)` over four candidate
/// separating axes: the two normals; the near-points axis (`b`'s centre clamped to `a`'s
/// rectangle, that point clamped to `b`'s rectangle, and that one clamped back to `a`'s; the
/// axis runs between the last two points: two and a half steps of alternating projection
/// towards the closest points of the two rectangles, so the axis approaches the direction of
/// the exact distance, exact for two balls and for a rectangle and a ball); and the common
/// perpendicular of the two long edges (`a_x x b_x`), which gives the exact distance of two
/// slivers that cross far from their centres, where the first three fail (ARCHITECTURE.md).
/// By convex duality every unit direction gives a valid lower bound.
///
/// Measured on the knot34k distance workload (`examples/profile_distance.rs`) against the 13
/// axes used before (normals, rectangle edges, edge cross products, the line between the
/// centres): 1%, 28% and 10% fewer node pairs at 0.01, 0.1 and 1 R, and 28% fewer
/// instructions. Adding back the edge crosses or the edge directions prunes under 5% more
/// pairs and costs more than it saves.
/// Returns as soon as a normal's gap reaches `cutoff` (the caller can prune).
#[inline]
pub(crate) fn rss_separation(a: &Rss, b: &Rss, rel: &RelativeRss, cutoff: f64) -> (f64, Vec3) {
    let (la0, la1) = (a.half_lengths[0], a.half_lengths[1]);
    let (lb0, lb1) = (b.half_lengths[0], b.half_lengths[1]);
    let rr = a.radius + b.radius;
    // b's axes in a's frame, and b's centre.
    let (b0, b1, b2) = (rel.r.x_axis, rel.r.y_axis, rel.r.z_axis);
    let t = rel.t;
    let normal_a = t.z.abs() - lb0 * b0.z.abs() - lb1 * b1.z.abs();
    if normal_a - rr >= cutoff {
        return ((normal_a - rr).max(0.0), Vec3::Z * t.z.signum());
    }
    let bt2 = b2.dot(t);
    let normal_b = bt2.abs() - la0 * b2.x.abs() - la1 * b2.y.abs();
    if normal_b - rr >= cutoff {
        return ((normal_b - rr).max(0.0), b2 * bt2.signum());
    }
    let pa = Vec3::new(t.x.max(-la0).min(la0), t.y.max(-la1).min(la1), 0.0);
    let q = pa - t;
    let pb = t + b0 * b0.dot(q).max(-lb0).min(lb0) + b1 * b1.dot(q).max(-lb1).min(lb1);
    let u = Vec3::new(
        pb.x - pb.x.max(-la0).min(la0),
        pb.y - pb.y.max(-la1).min(la1),
        pb.z,
    );
    let ut = u.dot(t);
    let gap_u = ut.abs()
        - la0 * u.x.abs()
        - la1 * u.y.abs()
        - lb0 * u.dot(b0).abs()
        - lb1 * u.dot(b1).abs();
    let ul = u.length_squared().max(f64::MIN_POSITIVE).sqrt();
    let near = gap_u / ul;
    // The common perpendicular of the two long edges (`a`'s x axis cross `b`'s).
    let e = Vec3::new(0.0, -b0.z, b0.y);
    let et = e.dot(t);
    let el = e.length_squared().max(f64::MIN_POSITIVE).sqrt();
    let cross = (et.abs() - la1 * b0.z.abs() - lb1 * e.dot(b1).abs()) / el;
    let (gap, axis) = if cross > near.max(normal_a).max(normal_b) && e != Vec3::ZERO {
        (cross, e / el * et.signum())
    } else if near > normal_a.max(normal_b) && u != Vec3::ZERO {
        (near, u / ul * ut.signum())
    } else if normal_a >= normal_b {
        (normal_a, Vec3::Z * t.z.signum())
    } else {
        (normal_b, b2 * bt2.signum())
    };
    ((gap - rr).max(0.0), axis)
}

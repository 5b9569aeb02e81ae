//! Exact distance between two triangles, robust for degenerate triangles (points, segments),
//! parallel and coplanar pairs.
//!
//! For disjoint triangles the closest pair is either edge-edge or vertex-interior, so the
//! distance is the minimum of the 9 edge-edge distances and of the vertices that project
//! inside the other triangle. The triangles intersect exactly when that minimum is 0 or an
//! edge of one crosses the plane of the other strictly inside it; then the distance is 0 and
//! both witnesses are the crossing point.

use super::distance_point_triangle::{inside_triangle, project_inside_triangle, triangle_normal};
use super::distance_segment_segment::closest_points_segment_segment;
use crate::math::Vec3;

/// Distance between two triangles and the closest point on each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrianglePairDistance {
    /// Distance (model units, >= 0; 0 when the triangles touch or intersect).
    pub distance: f64,
    /// Closest point on the first triangle.
    pub point1: Vec3,
    /// Closest point on the second triangle.
    pub point2: Vec3,
}

/// Exact distance between triangles `a` and `b` (both in the same frame).
pub fn distance_triangle_triangle(a: &[Vec3; 3], b: &[Vec3; 3]) -> TrianglePairDistance {
    let mut best = TrianglePairDistance {
        distance: f64::INFINITY,
        point1: a[0],
        point2: b[0],
    };
    let mut best_sq = f64::INFINITY;
    let mut consider = |x: Vec3, y: Vec3, best: &mut TrianglePairDistance| {
        let d = (x - y).length_squared();
        if d < best_sq {
            best_sq = d;
            best.point1 = x;
            best.point2 = y;
        }
    };
    for i in 0..3 {
        let (p0, p1) = (a[i], a[(i + 1) % 3]);
        for j in 0..3 {
            let (x, y) = closest_points_segment_segment(p0, p1, b[j], b[(j + 1) % 3]);
            // Certificate: x and y are closest on their edges, so v = y - x separates the
            // triangles when the third vertex of each lies behind its witness along v; then no
            // pair of points is closer than |v| and (x, y) is the answer. Trusted only when |v|
            // is well above rounding at these coordinates (else the pair may intersect).
            let v = y - x;
            let vv = v.length_squared();
            let noise = 1e-12 * (x.abs().max_element() + y.abs().max_element());
            if vv > noise * noise
                && (a[(i + 2) % 3] - x).dot(v) <= 0.0
                && (b[(j + 2) % 3] - y).dot(v) >= 0.0
            {
                return TrianglePairDistance {
                    distance: vv.sqrt(),
                    point1: x,
                    point2: y,
                };
            }
            consider(x, y, &mut best);
        }
    }
    let na = triangle_normal(a);
    let nb = triangle_normal(b);
    if let Some(n) = nb {
        for &p in a {
            if let Some(x) = project_inside_triangle(p, b, n) {
                consider(p, x, &mut best);
            }
        }
    }
    if let Some(n) = na {
        for &q in b {
            if let Some(x) = project_inside_triangle(q, a, n) {
                consider(x, q, &mut best);
            }
        }
    }
    if best_sq > 0.0 {
        if let Some(x) = edge_crossing(a, b, nb).or_else(|| edge_crossing(b, a, na)) {
            return TrianglePairDistance {
                distance: 0.0,
                point1: x,
                point2: x,
            };
        }
    }
    best.distance = best_sq.sqrt();
    best
}

/// A point where an edge of `e` crosses triangle `t` (normal `n`) with its endpoints strictly on
/// opposite sides of `t`'s plane.
fn edge_crossing(e: &[Vec3; 3], t: &[Vec3; 3], n: Option<Vec3>) -> Option<Vec3> {
    let n = n?;
    let d = e.map(|p| n.dot(p - t[0]));
    for i in 0..3 {
        let j = (i + 1) % 3;
        if (d[i] > 0.0 && d[j] < 0.0) || (d[i] < 0.0 && d[j] > 0.0) {
            let x = e[i] + (e[j] - e[i]) * (d[i] / (d[i] - d[j]));
            if inside_triangle(x, t, n) {
                return Some(x);
            }
        }
    }
    None
}

/// Whether two triangles intersect (touching counts). Rejects quickly when one triangle lies
/// on one side of the other's plane by more than rounding; when each plane cuts the other
/// triangle, compares the two segments where each triangle meets the other's plane along the
/// planes' common line (`crossing_intervals`); defers to the exact distance (`distance ==
/// 0`) whenever either test is within its rounding bound (a vertex near the other plane, a
/// shared vertex, nearly parallel planes, degenerate triangles, touching within rounding), so
/// the verdict is the distance's wherever the two could differ (the tests compare them).
pub fn intersect_triangle_triangle(a: &[Vec3; 3], b: &[Vec3; 3]) -> bool {
    let Some((na, db, noise_b)) = plane_sides(a, b) else {
        return false;
    };
    let Some((nb, da, noise_a)) = plane_sides(b, a) else {
        return false;
    };
    match crossing_intervals(a, b, (na, nb), (da, db), (noise_a, noise_b)) {
        Some(verdict) => verdict,
        None => distance_triangle_triangle(a, b).distance == 0.0,
    }
}

/// The larger of two numbers (plain comparison: the callers' NaNs end in the distance).
#[inline(always)]
fn larger(x: f64, y: f64) -> f64 {
    if x > y {
        x
    } else {
        y
    }
}

/// The largest absolute coordinate of `p`.
#[inline(always)]
fn reach(p: Vec3) -> f64 {
    larger(larger(p.x.abs(), p.y.abs()), p.z.abs())
}

/// Triangle `t`'s normal, the other triangle's vertices' signed distances to its plane (times
/// the normal's length), and their rounding bound: the normal's is about the product of its
/// edges' sizes, the differences' the coordinates' magnitude. `None`: all on one side by more
/// than that (apart).
#[inline(always)]
fn plane_sides(t: &[Vec3; 3], o: &[Vec3; 3]) -> Option<(Vec3, [f64; 3], f64)> {
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let n = e1.cross(e2);
    let d = [n.dot(o[0] - t[0]), n.dot(o[1] - t[0]), n.dot(o[2] - t[0])];
    let edge = larger(reach(e1), reach(e2));
    let noise = ROUNDING
        * edge
        * edge
        * (larger(larger(reach(o[0]), reach(o[1])), reach(o[2])) + reach(t[0]));
    if (d[0] > noise && d[1] > noise && d[2] > noise)
        || (d[0] < -noise && d[1] < -noise && d[2] < -noise)
    {
        return None;
    }
    Some((n, d, noise))
}

/// Relative rounding bound of the intersection test's quantities (a wide margin over the
/// few units of 2^-52 that each accumulates).
const ROUNDING: f64 = 1e-12;

/// The interval test of two triangles whose planes each cut the other triangle (Moller's,
/// 1997): each triangle meets the other's plane in a segment on the planes' common line `L`;
/// they intersect exactly when the two segments overlap. `n`: the (unnormalised) normals;
/// `d`: each triangle's vertices' signed distances to the other's plane (times its normal's
/// length), `noise` their rounding bounds. `None` when
/// the answer is not certain in floating point: a vertex within rounding of the other plane
/// (its side unsure), planes parallel within rounding, or segments overlapping or apart by
/// less than the endpoints' rounding bound.
fn crossing_intervals(
    a: &[Vec3; 3],
    b: &[Vec3; 3],
    (na, nb): (Vec3, Vec3),
    (da, db): ([f64; 3], [f64; 3]),
    (noise_a, noise_b): (f64, f64),
) -> Option<bool> {
    let far = larger(
        larger(larger(reach(a[0]), reach(a[1])), reach(a[2])),
        larger(larger(reach(b[0]), reach(b[1])), reach(b[2])),
    );
    let line = na.cross(nb);
    let lalb_sq = na.length_squared() * nb.length_squared();
    // Planes at an angle whose sine is below 1e-6 (or a degenerate triangle, or coordinates
    // that are not finite): the distance.
    let sine_sq = line.length_squared();
    if sine_sq.is_nan() || sine_sq <= 1e-12 * lalb_sq {
        return None;
    }
    // The projections' rounding (|line| <= |na| |nb|).
    let projection_err = 4.0 * ROUNDING * lalb_sq.sqrt() * far;
    // Each triangle's segment on L, as [lo, hi] of `line . x`, with its rounding bound.
    let segment = |t: &[Vec3; 3], d: [f64; 3], noise: f64| -> Option<(f64, f64, f64)> {
        if d[0].abs() <= noise || d[1].abs() <= noise || d[2].abs() <= noise {
            return None;
        }
        let p = [line.dot(t[0]), line.dot(t[1]), line.dot(t[2])];
        let (mut lo, mut hi, mut err) = (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64);
        for (i, j) in [(0, 1), (1, 2), (2, 0)] {
            if (d[i] > 0.0) != (d[j] > 0.0) {
                let x = p[i] + (p[j] - p[i]) * (d[i] / (d[i] - d[j]));
                lo = if x < lo { x } else { lo };
                hi = larger(hi, x);
                // The crossing's shift along the edge by the distances' rounding.
                err = larger(
                    err,
                    projection_err + (p[j] - p[i]).abs() * 2.0 * noise / (d[i] - d[j]).abs(),
                );
            }
        }
        (lo <= hi).then_some((lo, hi, err))
    };
    let (lo_a, hi_a, err_a) = segment(a, da, noise_a)?;
    let (lo_b, hi_b, err_b) = segment(b, db, noise_b)?;
    // Apart by `gap` > 0, overlapping by -gap.
    let gap = larger(lo_a, lo_b) - if hi_a < hi_b { hi_a } else { hi_b };
    let bound = 2.0 * (err_a + err_b);
    if gap > bound {
        Some(false)
    } else if gap < -bound {
        Some(true)
    } else {
        None
    }
}

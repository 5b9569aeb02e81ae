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
/// strictly on one side of the other's plane, else defers to the exact distance.
pub fn intersect_triangle_triangle(a: &[Vec3; 3], b: &[Vec3; 3]) -> bool {
    let one_side = |t: &[Vec3; 3], other: &[Vec3; 3]| {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        let d = other.map(|p| n.dot(p - t[0]));
        (d[0] > 0.0 && d[1] > 0.0 && d[2] > 0.0) || (d[0] < 0.0 && d[1] < 0.0 && d[2] < 0.0)
    };
    if one_side(a, b) || one_side(b, a) {
        return false;
    }
    distance_triangle_triangle(a, b).distance == 0.0
}

//! Point against triangle: the closest point when the point projects inside the triangle.
//! Outside projections are handled by the callers' edge tests (the closest point is then on
//! the boundary), so this kernel never has to classify Voronoi regions. Degenerate triangles
//! (sin of every angle below 1e-10) have no interior and return `None`.

use crate::math::Vec3;

/// Unnormalised normal of a triangle, or `None` when the triangle is degenerate.
#[inline]
pub fn triangle_normal(t: &[Vec3; 3]) -> Option<Vec3> {
    let e0 = t[1] - t[0];
    let e1 = t[2] - t[0];
    let n = e0.cross(e1);
    let nn = n.length_squared();
    (nn > 1e-20 * e0.length_squared() * e1.length_squared() && nn > 0.0).then_some(n)
}

/// Whether `x` (assumed in the plane of `t`) lies inside or on the boundary of `t`, whose
/// unnormalised normal is `n`.
#[inline]
pub fn inside_triangle(x: Vec3, t: &[Vec3; 3], n: Vec3) -> bool {
    (t[1] - t[0]).cross(x - t[0]).dot(n) >= 0.0
        && (t[2] - t[1]).cross(x - t[1]).dot(n) >= 0.0
        && (t[0] - t[2]).cross(x - t[2]).dot(n) >= 0.0
}

/// If `p` projects inside the (non-degenerate, normal `n`) triangle `t`, its projection.
#[inline]
pub fn project_inside_triangle(p: Vec3, t: &[Vec3; 3], n: Vec3) -> Option<Vec3> {
    let x = p - n * (n.dot(p - t[0]) / n.length_squared());
    inside_triangle(x, t, n).then_some(x)
}

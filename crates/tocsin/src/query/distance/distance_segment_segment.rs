//! Closest points between two segments (possibly degenerate to points), by minimising
//! `|p0 + s d1 - q0 - t d2|^2` over the unit square: the unconstrained minimum clamped in `s`,
//! then `t` solved and clamped, then `s` re-solved for the clamped `t`. Parallel segments
//! (the system is singular) start from `s = 0`; any minimiser gives the same distance.

use crate::math::Vec3;

/// Closest points `(x, y)` with `x` on segment `[p0, p1]` and `y` on `[q0, q1]`.
#[inline]
pub fn closest_points_segment_segment(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> (Vec3, Vec3) {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let a = d1.dot(d1);
    let e = d2.dot(d2);
    let f = d2.dot(r);
    if a == 0.0 && e == 0.0 {
        return (p0, q0);
    }
    let (s, t);
    if a == 0.0 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(r);
        if e == 0.0 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b;
            let s0 = if denom > 1e-14 * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            } else {
                t = t0;
                s = s0;
            }
        }
    }
    (p0 + d1 * s, q0 + d2 * t)
}

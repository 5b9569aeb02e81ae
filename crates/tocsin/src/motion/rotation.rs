//! Rotation logarithm and exponential (rotation vectors), accurate to rounding at every angle.
//!
//! The logarithm goes through a unit quaternion (Shepperd's choice of the largest of the four
//! squared components, so no component is recovered from a small difference): the angle is
//! `2 atan2(|v|, w)` with `w >= 0`, which keeps full relative precision near 0 and near pi. The
//! earlier closed form (`acos` of the trace, then the skew part over `2 sin`) lost digits near
//! pi: 5.5e-10 at 1e-5 from pi, against about 1e-16 now (tested).

use crate::math::{Mat3, Vec3};

/// `exp([w]x)`: the rotation by `|w|` radians about `w` (Rodrigues).
pub fn rotation_exp(w: Vec3) -> Mat3 {
    let theta = w.length();
    if theta < 1e-300 {
        return Mat3::IDENTITY;
    }
    Mat3::from_axis_angle(w / theta, theta)
}

/// The unit quaternion `(v, w)` of `r` with `w >= 0` (Shepperd's method). `r` should be a
/// rotation; for a matrix a little off one (rounded input) the result is normalised.
fn quaternion(r: &Mat3) -> (Vec3, f64) {
    let c = r.to_cols_array_2d(); // c[col][row]
    let m = |row: usize, col: usize| c[col][row];
    let trace = m(0, 0) + m(1, 1) + m(2, 2);
    // Four times the squares of w, x, y, z; the largest is recovered first.
    let sq = [
        1.0 + trace,
        1.0 + m(0, 0) - m(1, 1) - m(2, 2),
        1.0 - m(0, 0) + m(1, 1) - m(2, 2),
        1.0 - m(0, 0) - m(1, 1) + m(2, 2),
    ];
    let k = (0..4).max_by(|&i, &j| sq[i].total_cmp(&sq[j])).unwrap_or(0);
    let s = 2.0 * sq[k].max(0.0).sqrt(); // 4 times the largest component
    let (x, y, z, w) = match k {
        0 => (
            (m(2, 1) - m(1, 2)) / s,
            (m(0, 2) - m(2, 0)) / s,
            (m(1, 0) - m(0, 1)) / s,
            0.25 * s,
        ),
        1 => (
            0.25 * s,
            (m(0, 1) + m(1, 0)) / s,
            (m(0, 2) + m(2, 0)) / s,
            (m(2, 1) - m(1, 2)) / s,
        ),
        2 => (
            (m(0, 1) + m(1, 0)) / s,
            0.25 * s,
            (m(1, 2) + m(2, 1)) / s,
            (m(0, 2) - m(2, 0)) / s,
        ),
        _ => (
            (m(0, 2) + m(2, 0)) / s,
            (m(1, 2) + m(2, 1)) / s,
            0.25 * s,
            (m(1, 0) - m(0, 1)) / s,
        ),
    };
    let norm = (x * x + y * y + z * z + w * w).sqrt();
    let (v, w) = (Vec3::new(x, y, z) / norm, w / norm);
    if w < 0.0 {
        (-v, -w)
    } else {
        (v, w)
    }
}

/// The rotation vector of `r` (axis times angle, angle in `[0, pi]`). At exactly `pi` the axis
/// sign is ambiguous; the one whose largest component is positive is returned.
pub fn rotation_log(r: &Mat3) -> Vec3 {
    let (v, w) = quaternion(r);
    let sin_half = v.length();
    if sin_half == 0.0 {
        return Vec3::ZERO;
    }
    let theta = 2.0 * sin_half.atan2(w);
    let axis = v / sin_half;
    if w == 0.0 && axis[axis.abs().max_position()] < 0.0 {
        return -axis * theta;
    }
    axis * theta
}

/// `V(phi) x`, where `V(phi) = I + (1 - cos t)/t^2 [phi]x + (t - sin t)/t^3 [phi]x^2` (`t = |phi|`)
/// is the left Jacobian of SO(3): the translation of `exp` of the twist `(phi, x)` is `V(phi) x`.
/// Each coefficient is taken without cancellation (a half-angle form, or its series below 0.05).
pub(crate) fn jacobian_apply(phi: Vec3, x: Vec3) -> Vec3 {
    let t2 = phi.length_squared();
    let t = t2.sqrt();
    let (a, b) = if t < 0.05 {
        (
            0.5 - t2 / 24.0 + t2 * t2 / 720.0,
            1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0 - t2 * t2 * t2 / 362_880.0,
        )
    } else {
        let s = (0.5 * t).sin();
        (2.0 * s * s / t2, (t - t.sin()) / (t2 * t))
    };
    let px = phi.cross(x);
    x + a * px + b * phi.cross(px)
}

/// `V(phi)^-1 x = x - [phi]x x / 2 + (1 - (t/2) cot(t/2)) / t^2 [phi]x^2 x` for `|phi| <= pi`
/// (series below 0.05, where the closed form cancels).
pub(crate) fn jacobian_inverse_apply(phi: Vec3, x: Vec3) -> Vec3 {
    let t2 = phi.length_squared();
    let t = t2.sqrt();
    let c = if t < 0.05 {
        1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30_240.0 + t2 * t2 * t2 / 1_209_600.0
    } else {
        let h = 0.5 * t;
        (1.0 - h * h.cos() / h.sin()) / t2
    };
    let px = phi.cross(x);
    x - 0.5 * px + c * phi.cross(px)
}

/// `(exp([phi]x) - I) x`, the displacement of `x` by the rotation `phi`, without forming
/// `exp(phi) x - x` (which cancels when `x` is large and the turn small):
/// `sin t (k x x) + 2 sin^2(t/2) k x (k x x)`, `k = phi / t`.
pub(crate) fn turn_displacement(phi: Vec3, x: Vec3) -> Vec3 {
    let t = phi.length();
    if t == 0.0 {
        return Vec3::ZERO;
    }
    let k = phi / t;
    let kx = k.cross(x);
    let h = (0.5 * t).sin();
    t.sin() * kx + 2.0 * h * h * k.cross(kx)
}

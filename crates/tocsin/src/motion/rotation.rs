//! Rotation logarithm and exponential (rotation vectors), robust near 0 and at pi.

use crate::math::{Mat3, Vec3};

/// `exp([w]x)`: the rotation by `|w|` radians about `w` (Rodrigues).
pub fn rotation_exp(w: Vec3) -> Mat3 {
    let theta = w.length();
    if theta < 1e-300 {
        return Mat3::IDENTITY;
    }
    Mat3::from_axis_angle(w / theta, theta)
}

/// The rotation vector of `r` (axis times angle, angle in `[0, pi]`). At exactly `pi` the axis
/// sign is ambiguous; the one whose largest component is positive is returned.
pub fn rotation_log(r: &Mat3) -> Vec3 {
    let c = r.to_cols_array_2d(); // c[col][row]
    let m = |row: usize, col: usize| c[col][row];
    let trace = m(0, 0) + m(1, 1) + m(2, 2);
    let cos = ((trace - 1.0) * 0.5).clamp(-1.0, 1.0);
    // Twice sin(theta) times the axis.
    let s = Vec3::new(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
    let sin2 = s.length();
    let theta = (0.5 * sin2).atan2(cos);
    if theta < 1e-8 {
        // First order: r ~ I + [w]x.
        return 0.5 * s;
    }
    if std::f64::consts::PI - theta > 1e-6 {
        return s * (theta / sin2);
    }
    // Near pi: ((R + R^T) / 2 + I) / 2 = a a^T + O((pi - theta)^2); its largest column is the axis.
    let sym = |i: usize, j: usize| 0.25 * (m(i, j) + m(j, i)) + if i == j { 0.5 } else { 0.0 };
    let k = (0..3)
        .max_by(|&i, &j| sym(i, i).total_cmp(&sym(j, j)))
        .unwrap_or(0);
    let mut axis = Vec3::new(sym(0, k), sym(1, k), sym(2, k)).normalize_or(Vec3::X);
    if sin2 > 0.0 && axis.dot(s) < 0.0 {
        axis = -axis; // not exactly pi: keep the sense that the skew part shows
    } else if sin2 == 0.0 && axis[axis.abs().max_position()] < 0.0 {
        axis = -axis;
    }
    axis * theta
}

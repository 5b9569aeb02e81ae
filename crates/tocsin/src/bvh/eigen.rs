//! Principal axes of a symmetric 3x3 matrix (covariance fitting).
//!
//! Closed form: the largest eigenvalue by the trigonometric formula, its eigenvector as the
//! longest cross product of two rows of `A - l I`, then the 2x2 problem in the orthogonal plane
//! by one exact rotation. When the largest eigenvalue is repeated (no unique axis), cyclic
//! Jacobi rotations decide. Any orthonormal frame gives a valid volume; accuracy only buys
//! tightness, so the hierarchy stays correct whatever this returns.

use crate::math::{Mat3, Vec3};

/// Eigen-decomposition of the symmetric matrix `m`: returns a right-handed orthonormal frame whose
/// columns are eigenvectors sorted by decreasing eigenvalue. A zero or isotropic matrix gives
/// the identity frame.
pub(crate) fn principal_axes(m: [[f64; 3]; 3]) -> Mat3 {
    let scale = m.iter().flatten().fold(0.0_f64, |s, v| s.max(v.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return Mat3::IDENTITY;
    }
    let a = m.map(|row| row.map(|v| v / scale));
    let (a00, a01, a02, a11, a12, a22) = (a[0][0], a[0][1], a[0][2], a[1][1], a[1][2], a[2][2]);
    let q = (a00 + a11 + a22) / 3.0;
    let off = a01 * a01 + a02 * a02 + a12 * a12;
    let p = (((a00 - q).powi(2) + (a11 - q).powi(2) + (a22 - q).powi(2) + 2.0 * off) / 6.0).sqrt();
    if p <= 1e-12 {
        return Mat3::IDENTITY; // isotropic: every frame is principal
    }
    let b = Mat3::from_cols_array_2d(&a.map(|row| row.map(|v| v / p)))
        - Mat3::from_diagonal(Vec3::splat(q / p));
    let phi = (0.5 * b.determinant()).clamp(-1.0, 1.0).acos() / 3.0;
    let largest = q + 2.0 * p * phi.cos();
    let rows = [
        Vec3::new(a00 - largest, a01, a02),
        Vec3::new(a01, a11 - largest, a12),
        Vec3::new(a02, a12, a22 - largest),
    ];
    let crosses = [
        rows[0].cross(rows[1]),
        rows[0].cross(rows[2]),
        rows[1].cross(rows[2]),
    ];
    let c = crosses.into_iter().fold(Vec3::ZERO, |m, c| {
        if c.length_squared() > m.length_squared() {
            c
        } else {
            m
        }
    });
    if c.length_squared() <= 1e-16 * p.powi(4) {
        return jacobi_axes(a); // repeated largest eigenvalue
    }
    let am = Mat3::from_cols_array_2d(&a);
    let x = c.normalize();
    let u = x.any_orthonormal_vector();
    let v = x.cross(u);
    let (cuu, cuv, cvv) = (u.dot(am * u), u.dot(am * v), v.dot(am * v));
    let theta = 0.5 * (2.0 * cuv).atan2(cuu - cvv);
    let y = u * theta.cos() + v * theta.sin();
    Mat3::from_cols(x, y, x.cross(y))
}

/// Cyclic Jacobi rotations: the fallback when the largest eigenvalue is repeated.
pub(crate) fn jacobi_axes(m: [[f64; 3]; 3]) -> Mat3 {
    let mut a = m;
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]; // v[row][col]
                                                                     // Any orthonormal frame gives a valid volume; accuracy only buys tightness.
    for _sweep in 0..12 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-10 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // Rotation angle that zeroes a[p][q].
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (row_p, row_q) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * row_p[k] - s * row_q[k];
                a[q][k] = s * row_p[k] + c * row_q[k];
            }
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let col = |j: usize| Vec3::new(v[0][j], v[1][j], v[2][j]).normalize_or(Vec3::X);
    let x = col(order[0]);
    let y0 = col(order[1]);
    // Re-orthonormalise and force a right-handed frame.
    let y = (y0 - x * x.dot(y0)).normalize_or(x.any_orthonormal_vector());
    Mat3::from_cols(x, y, x.cross(y))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form agrees with Jacobi on the axes (up to sign) for distinct eigenvalues.
    #[test]
    fn closed_form_matches_jacobi() {
        let mut g = crate::bvh::TestRng(7);
        let mut next = || g.next() - 0.5;
        for _ in 0..1000 {
            let pts: Vec<Vec3> = (0..5)
                .map(|_| Vec3::new(next(), 0.3 * next(), 0.05 * next()))
                .collect();
            let mean = pts.iter().copied().sum::<Vec3>() / 5.0;
            let mut m = [[0.0; 3]; 3];
            for p in &pts {
                let d = *p - mean;
                for r in 0..3 {
                    for c in 0..3 {
                        m[r][c] += d[r] * d[c];
                    }
                }
            }
            let a = principal_axes(m);
            let b = jacobi_axes(m);
            for k in 0..2 {
                let dot = a.col(k).dot(b.col(k)).abs();
                assert!(dot > 1.0 - 1e-6, "axis {k}: {a:?} vs {b:?} for {m:?}");
            }
        }
    }
}

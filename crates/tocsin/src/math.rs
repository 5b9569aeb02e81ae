//! The one place that names the math types: glam's `f64` types and a rigid [`Pose`].
//!
//! A [`Pose`] maps body-frame points to the world frame: `x_world = rotation * x_body + translation`.
//! Poses built from user input are checked to be rigid (orthonormal rotation with determinant +1).

use crate::error::PoseError;

/// A 3-vector of `f64` (points, directions, translations).
pub type Vec3 = glam::DVec3;
/// A 3x3 matrix of `f64`, column-major (rotations).
pub type Mat3 = glam::DMat3;
/// A 4x4 matrix of `f64`, column-major (homogeneous transforms).
pub type Mat4 = glam::DMat4;

/// Default tolerance used to accept a matrix as a rotation: `|R^T R - I|` and `|det R - 1|`
/// must be below it, entry-wise.
pub const ROTATION_TOLERANCE: f64 = 1e-6;

/// Largest coordinate magnitude accepted anywhere (mesh vertices, translations, centres). The
/// kernels form products of up to eight lengths (a triangle pair's normals' squared lengths
/// multiplied, the square of their cross product), which stay finite and normal for lengths
/// from about 1e-38 to 1e38; 1e30 leaves a margin. The range was 1e-150 to 1e150, where only
/// squared distances were sure: at 1e70 a screw motion's collisions were missed, at 1e80 two
/// triangles 1e80 apart were reported touching and at 1e120 a point over a face was taken to be
/// nearest an edge (the twenty-seventh session's sweep, docs/BENCHMARKS.md).
pub const MAX_COORDINATE: f64 = 1e30;

/// Smallest scale of a mesh (its largest coordinate magnitude, unless all are zero): see
/// [`MAX_COORDINATE`].
pub const MIN_SCALE: f64 = 1e-30;

/// Checks a translation: finite and within [`MAX_COORDINATE`].
pub fn check_translation(t: Vec3) -> Result<(), PoseError> {
    if !t.is_finite() {
        return Err(PoseError::NonFinite);
    }
    match t.to_array().into_iter().find(|v| v.abs() > MAX_COORDINATE) {
        Some(value) => Err(PoseError::OutOfRange { value }),
        None => Ok(()),
    }
}

/// A rigid transform (rotation then translation), mapping body-frame points to the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Rotation part: columns are the body axes expressed in the world frame.
    pub rotation: Mat3,
    /// Translation part: the body origin in the world frame, in model units.
    pub translation: Vec3,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// The identity transform.
    pub const IDENTITY: Pose = Pose {
        rotation: Mat3::IDENTITY,
        translation: Vec3::ZERO,
    };

    /// A pure translation.
    pub fn from_translation(translation: Vec3) -> Self {
        Self {
            rotation: Mat3::IDENTITY,
            translation,
        }
    }

    /// A pose from a rotation and a translation, checking that `rotation` is a proper rotation
    /// within [`ROTATION_TOLERANCE`] and that every entry is finite.
    pub fn new(rotation: Mat3, translation: Vec3) -> Result<Self, PoseError> {
        check_rotation(&rotation, ROTATION_TOLERANCE)?;
        check_translation(translation)?;
        Ok(Self {
            rotation,
            translation,
        })
    }

    /// A pose from a rotation about `axis` (need not be unit) by `angle` radians, and a translation.
    pub fn from_axis_angle(axis: Vec3, angle: f64, translation: Vec3) -> Self {
        let axis = axis.normalize_or(Vec3::Z);
        Self {
            rotation: Mat3::from_axis_angle(axis, angle),
            translation,
        }
    }

    /// A pose from a 4x4 homogeneous matrix (the convention of trimesh and robotics: the last
    /// row is `0 0 0 1`), checked to be rigid within `tolerance`.
    pub fn from_matrix(m: &Mat4, tolerance: f64) -> Result<Self, PoseError> {
        let cols = m.to_cols_array_2d();
        if cols.iter().flatten().any(|v| !v.is_finite()) {
            return Err(PoseError::NonFinite);
        }
        let last_row = [cols[0][3], cols[1][3], cols[2][3], cols[3][3]];
        let expected = [0.0, 0.0, 0.0, 1.0];
        if last_row
            .iter()
            .zip(expected)
            .any(|(a, b)| (a - b).abs() > tolerance)
        {
            return Err(PoseError::NotHomogeneous { last_row });
        }
        let rotation = Mat3::from_mat4(*m);
        check_rotation(&rotation, tolerance)?;
        check_translation(m.w_axis.truncate())?;
        Ok(Self {
            rotation,
            translation: m.w_axis.truncate(),
        })
    }

    /// A pose from a 4x4 matrix whose rotation block is a rotation only up to rounding in its
    /// input (values written to six digits, say): the block is replaced by the nearest rotation
    /// (the orthogonal factor of its polar decomposition, Frobenius norm), provided
    /// `|R^T R - I|` is at most `max_error` entry-wise and the determinant is positive. The
    /// translation and the last row are checked as in [`Pose::from_matrix`] (the last row within
    /// `max_error`). Use this explicitly for rounded input; [`Pose::from_matrix`] never corrects.
    pub fn from_matrix_orthonormalized(m: &Mat4, max_error: f64) -> Result<Self, PoseError> {
        let cols = m.to_cols_array_2d();
        if cols.iter().flatten().any(|v| !v.is_finite()) {
            return Err(PoseError::NonFinite);
        }
        let rotation = Mat3::from_mat4(*m);
        let err = orthonormality_error(&rotation);
        if err > max_error {
            return Err(PoseError::NotOrthonormal { error: err });
        }
        let det = rotation.determinant();
        if det <= 0.0 {
            return Err(PoseError::NotProperRotation { determinant: det });
        }
        // Newton's iteration for the polar factor, X <- (X + X^-T) / 2: quadratic convergence
        // from a matrix this close to orthonormal; a few steps reach rounding.
        let mut x = rotation;
        for _ in 0..8 {
            let next = 0.5 * (x + x.inverse().transpose());
            let change = (next - x)
                .to_cols_array()
                .iter()
                .fold(0.0_f64, |a, v| a.max(v.abs()));
            x = next;
            if change < 1e-16 {
                break;
            }
        }
        let mut fixed = *m;
        fixed.x_axis = x.x_axis.extend(cols[0][3]);
        fixed.y_axis = x.y_axis.extend(cols[1][3]);
        fixed.z_axis = x.z_axis.extend(cols[2][3]);
        Self::from_matrix(&fixed, max_error.max(ROTATION_TOLERANCE))
    }

    /// The pose as a 4x4 homogeneous matrix.
    pub fn to_matrix(&self) -> Mat4 {
        Mat4::from_cols(
            self.rotation.x_axis.extend(0.0),
            self.rotation.y_axis.extend(0.0),
            self.rotation.z_axis.extend(0.0),
            self.translation.extend(1.0),
        )
    }

    /// Applies the pose to a point.
    #[inline]
    pub fn transform_point(&self, p: Vec3) -> Vec3 {
        self.rotation * p + self.translation
    }

    /// Applies the rotation only (directions, normals).
    #[inline]
    pub fn transform_vector(&self, v: Vec3) -> Vec3 {
        self.rotation * v
    }

    /// The inverse transform (uses the transpose of the rotation).
    #[inline]
    pub fn inverse(&self) -> Self {
        let rt = self.rotation.transpose();
        Self {
            rotation: rt,
            translation: -(rt * self.translation),
        }
    }

    /// Composition `self * other`: first `other`, then `self`.
    #[inline]
    pub fn mul(&self, other: &Pose) -> Self {
        Self {
            rotation: self.rotation * other.rotation,
            translation: self.rotation * other.translation + self.translation,
        }
    }

    /// `self^-1 * other`: the pose of `other`'s frame seen from `self`'s frame (`pos12`).
    #[inline]
    pub fn inv_mul(&self, other: &Pose) -> Self {
        self.inverse().mul(other)
    }
}

/// Checks that `r` is a proper rotation (orthonormal, determinant +1) within `tolerance`.
pub fn check_rotation(r: &Mat3, tolerance: f64) -> Result<(), PoseError> {
    let cols = r.to_cols_array();
    if cols.iter().any(|v| !v.is_finite()) {
        return Err(PoseError::NonFinite);
    }
    let err = orthonormality_error(r);
    if err > tolerance {
        return Err(PoseError::NotOrthonormal { error: err });
    }
    let det = r.determinant();
    if (det - 1.0).abs() > tolerance {
        return Err(PoseError::NotProperRotation { determinant: det });
    }
    Ok(())
}

/// The largest entry of `|R^T R - I|`.
fn orthonormality_error(r: &Mat3) -> f64 {
    (r.transpose() * *r - Mat3::IDENTITY)
        .to_cols_array()
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
}

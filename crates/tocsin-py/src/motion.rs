//! `tocsin.Motion` and `tocsin.orthonormalize`.

use crate::convert::{matrix4_from, pose_from, pose_to_numpy, vec3_from};
use crate::errors::{error, motion_error};
use numpy::PyArray2;
use pyo3::prelude::*;
use tocsin::{Pose, Vec3};

/// A rigid motion over t in [0, 1] from a start to an end pose (4x4 rigid transforms, world
/// frame). Build one with Motion.translation, Motion.interp, Motion.screw, Motion.turn or
/// Motion.stationary; pose_at(t) gives the pose along the way, within rounding of start at
/// t = 0 and of end at t = 1 for every rotation angle in [0, pi].
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct Motion {
    pub(crate) inner: tocsin::Motion,
}

#[pymethods]
impl Motion {
    /// Pure translation: X(t) = R0 x + (1 - t) p0 + t p1. The rotations of start and end must
    /// agree within 1e-9, else MotionError.
    #[staticmethod]
    fn translation(start: &Bound<'_, PyAny>, end: &Bound<'_, PyAny>) -> PyResult<Self> {
        let py = start.py();
        let (a, b) = (pose_from(start, "start")?, pose_from(end, "end")?);
        let inner = tocsin::Motion::translation(a, b).map_err(|e| motion_error(py, e))?;
        Ok(Self { inner })
    }

    /// The body point `center` (body frame, three numbers; default: the origin) moves on a
    /// straight line; the body turns about it at constant angular velocity,
    /// R(t) = exp(t log(R1 R0^T)) R0 (angle in [0, pi]). With center = 0 this is FCL's
    /// InterpMotion.
    #[staticmethod]
    #[pyo3(signature = (start, end, center=None))]
    fn interp(
        start: &Bound<'_, PyAny>,
        end: &Bound<'_, PyAny>,
        center: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let py = start.py();
        let (a, b) = (pose_from(start, "start")?, pose_from(end, "end")?);
        let c = match center {
            Some(c) => vec3_from(c, "center", "MotionError")?,
            None => Vec3::ZERO,
        };
        let inner = tocsin::Motion::interp(a, b, c).map_err(|e| motion_error(py, e))?;
        Ok(Self { inner })
    }

    /// The SE(3) geodesic T(t) = exp(t log(T1 T0^-1)) T0: rotation about a fixed world axis
    /// with translation along it. A relative rotation below 1e-15 rad is a translation.
    #[staticmethod]
    fn screw(start: &Bound<'_, PyAny>, end: &Bound<'_, PyAny>) -> PyResult<Self> {
        let py = start.py();
        let (a, b) = (pose_from(start, "start")?, pose_from(end, "end")?);
        let inner = tocsin::Motion::screw(a, b).map_err(|e| motion_error(py, e))?;
        Ok(Self { inner })
    }

    /// A turn by `angle` radians (any size; its sign gives the sense about `axis`, right-hand
    /// rule) about the world line through `point` along `axis`, from the pose `start`:
    /// pose_at(t) is start turned by t * angle about that line. A screw between two poses
    /// stops at pi; a turn may go round several times (a wheel on its axle, a turntable). The
    /// rotation certificates serve a body symmetric about the line in a close fit. MotionError
    /// for a zero or non-finite axis, a non-finite point or angle, or a start that is not rigid.
    #[staticmethod]
    fn turn(
        start: &Bound<'_, PyAny>,
        point: &Bound<'_, PyAny>,
        axis: &Bound<'_, PyAny>,
        angle: f64,
    ) -> PyResult<Self> {
        let py = start.py();
        let a = pose_from(start, "start")?;
        let p = vec3_from(point, "point", "MotionError")?;
        let dir = vec3_from(axis, "axis", "MotionError")?;
        let length = dir.length();
        if !(length.is_finite() && length > 0.0 && angle.is_finite()) {
            return Err(error(
                py,
                "MotionError",
                format!("axis must be a finite nonzero vector and angle finite, got {dir:?} and {angle}"),
            ));
        }
        let inner =
            tocsin::Motion::turn(a, p, dir / length * angle).map_err(|e| motion_error(py, e))?;
        Ok(Self { inner })
    }

    /// A body that stays at `pose`.
    #[staticmethod]
    fn stationary(pose: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(Self {
            inner: tocsin::Motion::stationary(pose_from(pose, "pose")?),
        })
    }

    /// The pose at time t (a finite real; the motion is defined on [0, 1]) as a 4x4 array.
    fn pose_at<'py>(&self, py: Python<'py>, t: f64) -> PyResult<Bound<'py, PyArray2<f64>>> {
        if !t.is_finite() {
            return Err(error(
                py,
                "OptionsError",
                format!("t must be finite, got {t}"),
            ));
        }
        pose_to_numpy(py, &self.inner.pose_at(t))
    }

    /// "translation", "interp", "screw" or "turn".
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner.kind() {
            tocsin::MotionKind::Translation => "translation",
            tocsin::MotionKind::Interp => "interp",
            tocsin::MotionKind::Turn => "turn",
            _ => "screw",
        }
    }

    /// Pickling: the kind, the end poses and the centre (interp) or the axis point and
    /// rotation vector (turn); rebuilt exactly.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let f = py.import("tocsin._core")?.getattr("_motion_from_parts")?;
        let m = &self.inner;
        let kind = match self.kind() {
            "translation" if m.is_stationary() => "stationary",
            k => k,
        };
        let (center, angular) = match m.fixed_axis() {
            Some(axis) if kind == "turn" => (axis.world_point, m.angular_velocity()),
            _ => (m.axis_point(), Vec3::ZERO),
        };
        let args = (
            kind,
            pose_to_numpy(py, &m.start())?,
            pose_to_numpy(py, &m.end())?,
            center.to_array(),
            angular.to_array(),
        );
        Ok((f, args).into_pyobject(py)?.into_any())
    }

    fn __repr__(&self) -> String {
        format!("Motion.{}(...)", self.kind())
    }
}

/// Unpickles a Motion (`Motion.__reduce__`): `center` is a turn's axis point, `angular` its
/// rotation vector.
#[pyfunction]
#[pyo3(signature = (kind, start, end, center, angular=[0.0; 3]))]
pub(crate) fn _motion_from_parts(
    py: Python<'_>,
    kind: &str,
    start: &Bound<'_, PyAny>,
    end: &Bound<'_, PyAny>,
    center: [f64; 3],
    angular: [f64; 3],
) -> PyResult<Motion> {
    let (a, b) = (pose_from(start, "start")?, pose_from(end, "end")?);
    let inner = match kind {
        "stationary" => Ok(tocsin::Motion::stationary(a)),
        "translation" => tocsin::Motion::translation(a, b),
        "interp" => tocsin::Motion::interp(a, b, Vec3::from_array(center)),
        "screw" => tocsin::Motion::screw(a, b),
        "turn" => tocsin::Motion::turn(a, Vec3::from_array(center), Vec3::from_array(angular)),
        other => {
            return Err(error(
                py,
                "MotionError",
                format!("unknown motion kind {other:?}"),
            ))
        }
    }
    .map_err(|e| motion_error(py, e))?;
    Ok(Motion { inner })
}

/// A copy of the 4x4 pose with its rotation block replaced by the nearest rotation, for input
/// whose rotations were rounded (written to six digits, say), which the 1e-6 rigidity check of
/// every query rejects. Raises PoseError when the block is farther than `max_error` from
/// orthonormal (entry-wise |R^T R - I|) or is a reflection. Never called implicitly.
#[pyfunction]
#[pyo3(signature = (pose, max_error=1e-3))]
pub(crate) fn orthonormalize<'py>(
    py: Python<'py>,
    pose: &Bound<'_, PyAny>,
    max_error: f64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    if !(max_error.is_finite() && max_error >= 0.0) {
        return Err(error(
            py,
            "OptionsError",
            format!("max_error must be finite and non-negative, got {max_error:?}"),
        ));
    }
    let m = matrix4_from(pose, "pose")?;
    let fixed = Pose::from_matrix_orthonormalized(&m, max_error)
        .map_err(|e| error(py, "PoseError", format!("pose: {e}")))?;
    pose_to_numpy(py, &fixed)
}

//! The static queries: distance, collide, collide_pairs, within_distance.

use crate::convert::{pose_from, vec3};
use crate::errors::options_error;
use crate::mesh::Mesh;
use crate::pool;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use std::sync::Arc;
use tocsin::{Pose, TriMesh, Vec3};

/// A query's two meshes (shared, for use without the GIL) and their checked poses.
fn scene(
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
) -> PyResult<(Arc<TriMesh>, Pose, Arc<TriMesh>, Pose)> {
    let (p1, p2) = (pose_from(pose1, "pose1")?, pose_from(pose2, "pose2")?);
    Ok((mesh1.inner.clone(), p1, mesh2.inner.clone(), p2))
}

/// The closest pair of points between two meshes (world frame).
///
/// The distance is exact up to about 2e-13 of the scene's scale (the meshes' sizes and
/// positions): two meshes one rounding step apart may get distance 0.0 while collide() says
/// False. Ask collide() whether they touch.
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct DistanceResult {
    /// Minimum distance, model units, >= 0 (0 when the meshes touch or intersect).
    #[pyo3(get)]
    distance: f64,
    p1: Vec3,
    p2: Vec3,
    /// Index of the triangle of mesh 1 holding point1.
    #[pyo3(get)]
    triangle1: usize,
    /// Index of the triangle of mesh 2 holding point2.
    #[pyo3(get)]
    triangle2: usize,
}

#[pymethods]
impl DistanceResult {
    /// Closest point on mesh 1, world frame, shape (3,).
    #[getter]
    fn point1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p1)
    }

    /// Closest point on mesh 2, world frame, shape (3,).
    #[getter]
    fn point2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p2)
    }

    fn __repr__(&self) -> String {
        format!(
            "DistanceResult(distance={}, point1={:?}, point2={:?}, triangle1={}, triangle2={})",
            self.distance,
            self.p1.to_array(),
            self.p2.to_array(),
            self.triangle1,
            self.triangle2
        )
    }
}

/// Minimum distance between mesh1 at pose1 and mesh2 at pose2 (4x4 rigid transforms, world
/// frame). Exact by default (to about 2e-13 of the scene's scale); with error bounds the
/// distance d returned satisfies true <= d <= true * (1 + relative_error) + absolute_error.
/// The GIL is released.
#[pyfunction]
#[pyo3(signature = (mesh1, pose1, mesh2, pose2, relative_error=0.0, absolute_error=0.0))]
pub(crate) fn distance(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
    relative_error: f64,
    absolute_error: f64,
) -> PyResult<DistanceResult> {
    let opts = tocsin::DistanceOptions {
        relative_error,
        absolute_error,
    };
    let (m1, p1, m2, p2) = scene(mesh1, pose1, mesh2, pose2)?;
    let r = py
        .detach(|| tocsin::distance(&m1, &p1, &m2, &p2, &opts))
        .map_err(|e| options_error(py, e))?;
    Ok(DistanceResult {
        distance: r.distance,
        p1: r.point1,
        p2: r.point2,
        triangle1: r.triangle1,
        triangle2: r.triangle2,
    })
}

/// Whether mesh1 at pose1 and mesh2 at pose2 intersect or touch (coplanar overlaps included).
#[pyfunction]
pub(crate) fn collide(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
) -> PyResult<bool> {
    let (m1, p1, m2, p2) = scene(mesh1, pose1, mesh2, pose2)?;
    Ok(py.detach(|| tocsin::collide(&m1, &p1, &m2, &p2)))
}

/// All intersecting triangle pairs, a sorted (K, 2) array [triangle of mesh1, of mesh2].
#[pyfunction]
pub(crate) fn collide_pairs<'py>(
    py: Python<'py>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let (m1, p1, m2, p2) = scene(mesh1, pose1, mesh2, pose2)?;
    let pairs = pool::run(py, || tocsin::collide_pairs(&m1, &p1, &m2, &p2))?;
    let flat: Vec<i64> = pairs
        .iter()
        .flat_map(|p| [p[0] as i64, p[1] as i64])
        .collect();
    PyArray1::from_vec(py, flat).reshape([pairs.len(), 2])
}

/// Whether the distance is at most `threshold` (model units); stops at the first pair within it.
#[pyfunction]
pub(crate) fn within_distance(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
    threshold: f64,
) -> PyResult<bool> {
    let (m1, p1, m2, p2) = scene(mesh1, pose1, mesh2, pose2)?;
    py.detach(|| tocsin::within_distance(&m1, &p1, &m2, &p2, threshold))
        .map_err(|e| options_error(py, e))
}

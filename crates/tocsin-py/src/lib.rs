//! PyO3 binding of tocsin: type conversions, GIL release around queries, and errors mapped to
//! the package's own exception classes (defined in `tocsin/_errors.py`). No geometry here.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyType;
use std::sync::Arc;
use tocsin::{math::ROTATION_TOLERANCE, Mat4, Pose, TriMesh, Vec3};
use tocsin::{ContactOptions, ContactStatus};

/// Raises `tocsin.<class>` with `message`.
fn error(py: Python<'_>, class: &str, message: impl Into<String>) -> PyErr {
    let cls = py
        .import("tocsin._errors")
        .and_then(|m| m.getattr(class))
        .and_then(|c| c.cast_into::<PyType>().map_err(PyErr::from));
    match cls {
        Ok(cls) => PyErr::from_type(cls, message.into()),
        Err(e) => e,
    }
}

fn mesh_error(py: Python<'_>, e: tocsin::MeshError) -> PyErr {
    match e {
        tocsin::MeshError::Io { .. } => error(py, "MeshFileError", e.to_string()),
        _ => error(py, "MeshError", e.to_string()),
    }
}

/// `np.ascontiguousarray(obj, dtype=dtype)` with a 2-D shape check.
fn as_array<'py, T: numpy::Element>(
    obj: &Bound<'py, PyAny>,
    dtype: &str,
    cols: usize,
    what: &str,
    class: &str,
) -> PyResult<PyReadonlyArray2<'py, T>> {
    let py = obj.py();
    let np = py.import("numpy")?;
    let arr = np
        .call_method1("ascontiguousarray", (obj, dtype))
        .map_err(|e| {
            error(
                py,
                class,
                format!("{what}: cannot convert to a {dtype} array ({e})"),
            )
        })?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    if shape.len() != 2 || shape[1] != cols {
        return Err(error(
            py,
            class,
            format!("{what} must have shape (N, {cols}), got {shape:?}"),
        ));
    }
    let arr = arr
        .cast_into::<PyArray2<T>>()
        .map_err(|_| error(py, class, format!("{what}: not a {dtype} array")))?;
    Ok(arr.readonly())
}

fn pose_from(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Pose> {
    let py = obj.py();
    // Fast path: already a float64 array (the common case); anything else goes through numpy.
    let arr = match obj.cast::<PyArray2<f64>>() {
        Ok(a) if a.shape() == [4, 4] => a.readonly(),
        _ => as_array::<f64>(obj, "float64", 4, name, "PoseError")?,
    };
    if arr.shape()[0] != 4 {
        return Err(error(
            py,
            "PoseError",
            format!("{name} must have shape (4, 4), got {:?}", arr.shape()),
        ));
    }
    let a = arr.as_array();
    let mut rows = [0.0; 16];
    for (k, v) in rows.iter_mut().enumerate() {
        *v = a[[k / 4, k % 4]];
    }
    let m = Mat4::from_cols_slice(&rows).transpose(); // rows were read row-major
    Pose::from_matrix(&m, ROTATION_TOLERANCE)
        .map_err(|e| error(py, "PoseError", format!("{name}: {e}")))
}

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

fn vec3<'py>(py: Python<'py>, v: Vec3) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, &v.to_array())
}

/// A triangle mesh (polygon soup) with its bounding volume hierarchy. Immutable.
#[pyclass(frozen, module = "tocsin._core")]
struct Mesh {
    inner: Arc<TriMesh>,
}

#[pymethods]
impl Mesh {
    #[new]
    fn new(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        triangles: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let v = as_array::<f64>(vertices, "float64", 3, "vertices", "MeshError")?;
        let kind: String = triangles
            .py()
            .import("numpy")?
            .call_method1("asarray", (triangles,))?
            .getattr("dtype")?
            .getattr("kind")?
            .extract()?;
        if kind != "i" && kind != "u" {
            return Err(error(
                py,
                "MeshError",
                format!("triangles must be an integer array, got dtype kind '{kind}'"),
            ));
        }
        let t = as_array::<i64>(triangles, "int64", 3, "triangles", "MeshError")?;
        let (vs, ts) = (
            v.as_slice()
                .map_err(|e| error(py, "MeshError", e.to_string()))?,
            t.as_slice()
                .map_err(|e| error(py, "MeshError", e.to_string()))?,
        );
        let verts: Vec<[f64; 3]> = vs.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let tris: Vec<[i64; 3]> = ts.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let mesh = py
            .detach(|| TriMesh::from_arrays(&verts, &tris))
            .map_err(|e| mesh_error(py, e))?;
        Ok(Self {
            inner: Arc::new(mesh),
        })
    }

    #[staticmethod]
    fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        let mesh = py
            .detach(|| TriMesh::load(&path))
            .map_err(|e| mesh_error(py, e))?;
        Ok(Self {
            inner: Arc::new(mesh),
        })
    }

    #[staticmethod]
    fn torus_knot(py: Python<'_>, n_u: usize, n_v: usize) -> PyResult<Self> {
        Self::generated(py, tocsin::mesh::torus_knot(n_u, n_v))
    }

    #[staticmethod]
    fn sphere(py: Python<'_>, radius: f64, n_lat: usize, n_lon: usize) -> PyResult<Self> {
        Self::generated(py, tocsin::mesh::sphere(radius, n_lat, n_lon))
    }

    #[staticmethod]
    #[pyo3(name = "box")]
    fn box_(py: Python<'_>, half_extents: [f64; 3]) -> PyResult<Self> {
        Self::generated(py, tocsin::mesh::box_mesh(Vec3::from_array(half_extents)))
    }

    #[staticmethod]
    fn plate(py: Python<'_>, size: f64, n: usize) -> PyResult<Self> {
        Self::generated(py, tocsin::mesh::plate(size, n))
    }

    #[getter]
    fn num_vertices(&self) -> usize {
        self.inner.num_vertices()
    }

    #[getter]
    fn num_triangles(&self) -> usize {
        self.inner.num_triangles()
    }

    #[getter]
    fn bounding_radius(&self) -> f64 {
        self.inner.bounding_radius()
    }

    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self
            .inner
            .vertices()
            .iter()
            .map(|v| v.to_array().to_vec())
            .collect();
        Ok(PyArray2::from_vec2(py, &rows)?)
    }

    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let rows: Vec<Vec<i64>> = self
            .inner
            .triangles()
            .iter()
            .map(|t| t.iter().map(|&i| i64::from(i)).collect())
            .collect();
        Ok(PyArray2::from_vec2(py, &rows)?)
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh(num_vertices={}, num_triangles={})",
            self.inner.num_vertices(),
            self.inner.num_triangles()
        )
    }
}

impl Mesh {
    fn generated(py: Python<'_>, m: Result<TriMesh, tocsin::MeshError>) -> PyResult<Self> {
        Ok(Self {
            inner: Arc::new(m.map_err(|e| mesh_error(py, e))?),
        })
    }
}

/// The closest pair of points between two meshes (world frame).
#[pyclass(frozen, module = "tocsin._core")]
struct DistanceResult {
    #[pyo3(get)]
    distance: f64,
    p1: Vec3,
    p2: Vec3,
    #[pyo3(get)]
    triangle1: usize,
    #[pyo3(get)]
    triangle2: usize,
}

#[pymethods]
impl DistanceResult {
    #[getter]
    fn point1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p1)
    }

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

#[pyfunction]
#[pyo3(signature = (mesh1, pose1, mesh2, pose2, relative_error=0.0, absolute_error=0.0))]
fn distance(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
    relative_error: f64,
    absolute_error: f64,
) -> PyResult<DistanceResult> {
    let (m1, p1, m2, p2) = scene(mesh1, pose1, mesh2, pose2)?;
    let opts = tocsin::DistanceOptions {
        relative_error,
        absolute_error,
    };
    let r = py
        .detach(|| tocsin::distance(&m1, &p1, &m2, &p2, &opts))
        .map_err(|e| error(py, "OptionsError", e.to_string()))?;
    Ok(DistanceResult {
        distance: r.distance,
        p1: r.point1,
        p2: r.point2,
        triangle1: r.triangle1,
        triangle2: r.triangle2,
    })
}

#[pyfunction]
fn collide(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
) -> PyResult<bool> {
    let (m1, p1, m2, p2) = scene(mesh1, pose1, mesh2, pose2)?;
    Ok(py.detach(|| tocsin::collide(&m1, &p1, &m2, &p2)))
}

#[pyfunction]
fn collide_pairs<'py>(
    py: Python<'py>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let (m1, p1, m2, p2) = scene(mesh1, pose1, mesh2, pose2)?;
    let pairs = py.detach(|| tocsin::collide_pairs(&m1, &p1, &m2, &p2));
    let flat: Vec<i64> = pairs
        .iter()
        .flat_map(|p| [p[0] as i64, p[1] as i64])
        .collect();
    PyArray1::from_vec(py, flat).reshape([pairs.len(), 2])
}

#[pyfunction]
fn within_distance(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
    threshold: f64,
) -> PyResult<bool> {
    let (m1, p1, m2, p2) = scene(mesh1, pose1, mesh2, pose2)?;
    py.detach(|| tocsin::within_distance(&m1, &p1, &m2, &p2, threshold))
        .map_err(|e| error(py, "OptionsError", e.to_string()))
}

fn pose_to_numpy<'py>(py: Python<'py>, p: &Pose) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let m = p.to_matrix().transpose().to_cols_array(); // row-major
    PyArray1::from_slice(py, &m).reshape([4, 4])
}

fn motion_error(py: Python<'_>, e: tocsin::MotionError) -> PyErr {
    error(py, "MotionError", e.to_string())
}

/// A rigid motion over t in [0, 1] from a start to an end pose (4x4, world frame).
#[pyclass(frozen, module = "tocsin._core")]
struct Motion {
    inner: tocsin::Motion,
}

#[pymethods]
impl Motion {
    /// Pure translation; `end` must have the rotation of `start` (within 1e-9).
    #[staticmethod]
    fn translation(start: &Bound<'_, PyAny>, end: &Bound<'_, PyAny>) -> PyResult<Self> {
        let py = start.py();
        let (a, b) = (pose_from(start, "start")?, pose_from(end, "end")?);
        let inner = tocsin::Motion::translation(a, b).map_err(|e| motion_error(py, e))?;
        Ok(Self { inner })
    }

    /// The body-frame point `center` (default: the origin) moves on a straight line while the
    /// body turns about it at constant angular velocity.
    #[staticmethod]
    #[pyo3(signature = (start, end, center=None))]
    fn interp(
        start: &Bound<'_, PyAny>,
        end: &Bound<'_, PyAny>,
        center: Option<[f64; 3]>,
    ) -> PyResult<Self> {
        let py = start.py();
        let (a, b) = (pose_from(start, "start")?, pose_from(end, "end")?);
        let c = Vec3::from_array(center.unwrap_or([0.0; 3]));
        let inner = tocsin::Motion::interp(a, b, c).map_err(|e| motion_error(py, e))?;
        Ok(Self { inner })
    }

    /// The SE(3) geodesic: rotation about a fixed axis with translation along it.
    #[staticmethod]
    fn screw(start: &Bound<'_, PyAny>, end: &Bound<'_, PyAny>) -> PyResult<Self> {
        let py = start.py();
        let (a, b) = (pose_from(start, "start")?, pose_from(end, "end")?);
        let inner = tocsin::Motion::screw(a, b).map_err(|e| motion_error(py, e))?;
        Ok(Self { inner })
    }

    /// A body that stays at `pose`.
    #[staticmethod]
    fn stationary(pose: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(Self {
            inner: tocsin::Motion::stationary(pose_from(pose, "pose")?),
        })
    }

    /// The pose at time t as a 4x4 array.
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

    /// "translation", "interp" or "screw".
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner.kind() {
            tocsin::MotionKind::Translation => "translation",
            tocsin::MotionKind::Interp => "interp",
            _ => "screw",
        }
    }

    fn __repr__(&self) -> String {
        format!("Motion.{}(...)", self.kind())
    }
}

/// When and where two moving meshes first come within the tolerance.
#[pyclass(frozen, module = "tocsin._core")]
struct ContactResult {
    #[pyo3(get)]
    time: f64,
    p1: Vec3,
    p2: Vec3,
    n: Vec3,
    #[pyo3(get)]
    distance: f64,
    #[pyo3(get)]
    triangle1: usize,
    #[pyo3(get)]
    triangle2: usize,
    #[pyo3(get)]
    iterations: usize,
    #[pyo3(get)]
    status: &'static str,
}

#[pymethods]
impl ContactResult {
    /// Closest point on mesh 1 at `time`, world frame, shape (3,).
    #[getter]
    fn point1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p1)
    }

    /// Closest point on mesh 2 at `time`, world frame, shape (3,).
    #[getter]
    fn point2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p2)
    }

    /// Unit normal from body 1 to body 2, world frame, shape (3,).
    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.n)
    }

    fn __repr__(&self) -> String {
        format!(
            "ContactResult(time={}, distance={}, status='{}', iterations={})",
            self.time, self.distance, self.status, self.iterations
        )
    }
}

/// First time of contact, or None when the meshes stay farther apart than the tolerance.
#[pyfunction]
#[pyo3(signature = (mesh1, motion1, mesh2, motion2, tolerance=None, max_iterations=None))]
fn time_of_contact(
    py: Python<'_>,
    mesh1: &Mesh,
    motion1: &Motion,
    mesh2: &Mesh,
    motion2: &Motion,
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
) -> PyResult<Option<ContactResult>> {
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    let (mo1, mo2) = (motion1.inner, motion2.inner);
    let opts = ContactOptions {
        tolerance,
        max_iterations: max_iterations.unwrap_or(ContactOptions::default().max_iterations),
    };
    let r = py
        .detach(|| tocsin::time_of_contact(&m1, &mo1, &m2, &mo2, &opts))
        .map_err(|e| error(py, "OptionsError", e.to_string()))?;
    Ok(r.map(|c| ContactResult {
        time: c.time,
        p1: c.point1,
        p2: c.point2,
        n: c.normal,
        distance: c.distance,
        triangle1: c.triangle1,
        triangle2: c.triangle2,
        iterations: c.iterations,
        status: match c.status {
            ContactStatus::Converged => "converged",
            ContactStatus::StartedInContact => "started_in_contact",
            _ => "iteration_limit",
        },
    }))
}

/// The compiled core of the `tocsin` package.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Mesh>()?;
    m.add_class::<DistanceResult>()?;
    m.add_function(wrap_pyfunction!(distance, m)?)?;
    m.add_function(wrap_pyfunction!(collide, m)?)?;
    m.add_function(wrap_pyfunction!(collide_pairs, m)?)?;
    m.add_function(wrap_pyfunction!(within_distance, m)?)?;
    m.add_class::<Motion>()?;
    m.add_class::<ContactResult>()?;
    m.add_function(wrap_pyfunction!(time_of_contact, m)?)?;
    Ok(())
}

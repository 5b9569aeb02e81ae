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

    /// A mesh from a `trimesh.Trimesh` (or anything with `.vertices` and `.faces` arrays).
    #[staticmethod]
    fn from_trimesh(py: Python<'_>, mesh: &Bound<'_, PyAny>) -> PyResult<Self> {
        let get = |name: &str| {
            mesh.getattr(name).map_err(|_| {
                error(
                    py,
                    "MeshError",
                    format!("expected a trimesh.Trimesh: the object has no `{name}`"),
                )
            })
        };
        Self::new(py, &get("vertices")?, &get("faces")?)
    }

    /// Loads an OBJ, STL (ASCII or binary) or PLY file; polygons are triangulated.
    #[staticmethod]
    fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        let mesh = py
            .detach(|| TriMesh::load(&path))
            .map_err(|e| mesh_error(py, e))?;
        Ok(Self {
            inner: Arc::new(mesh),
        })
    }

    /// A (2,3) torus-knot tube with 2 * n_u * n_v triangles (knot radius ~3, tube radius 0.4).
    #[staticmethod]
    fn torus_knot(py: Python<'_>, n_u: usize, n_v: usize) -> PyResult<Self> {
        Self::generated(py, tocsin::mesh::torus_knot(n_u, n_v))
    }

    /// A UV sphere of the given radius centred at the origin.
    #[staticmethod]
    fn sphere(py: Python<'_>, radius: f64, n_lat: usize, n_lon: usize) -> PyResult<Self> {
        Self::generated(py, tocsin::mesh::sphere(radius, n_lat, n_lon))
    }

    /// An axis-aligned box centred at the origin with the given half extents (12 triangles).
    #[staticmethod]
    #[pyo3(name = "box")]
    fn box_(py: Python<'_>, half_extents: [f64; 3]) -> PyResult<Self> {
        Self::generated(py, tocsin::mesh::box_mesh(Vec3::from_array(half_extents)))
    }

    /// A zero-thickness square plate in z = 0, `size` wide, 2 * n * n triangles.
    #[staticmethod]
    fn plate(py: Python<'_>, size: f64, n: usize) -> PyResult<Self> {
        Self::generated(py, tocsin::mesh::plate(size, n))
    }

    /// Number of vertices.
    #[getter]
    fn num_vertices(&self) -> usize {
        self.inner.num_vertices()
    }

    /// Number of triangles.
    #[getter]
    fn num_triangles(&self) -> usize {
        self.inner.num_triangles()
    }

    /// Radius of a ball containing the mesh, model units (scale of default tolerances).
    #[getter]
    fn bounding_radius(&self) -> f64 {
        self.inner.bounding_radius()
    }

    /// A copy of the (N, 3) vertex coordinates, body frame.
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

    /// A copy of the (M, 3) triangle vertex indices.
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
/// frame). Exact by default; with error bounds the distance d returned satisfies
/// true <= d <= true * (1 + relative_error) + absolute_error. The GIL is released.
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

/// Whether mesh1 at pose1 and mesh2 at pose2 intersect or touch (coplanar overlaps included).
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

/// All intersecting triangle pairs, a sorted (K, 2) array [triangle of mesh1, of mesh2].
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

/// Whether the distance is at most `threshold` (model units); stops at the first pair within it.
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
    /// Time of contact in [0, 1], no later than the first collision.
    #[pyo3(get)]
    time: f64,
    p1: Vec3,
    p2: Vec3,
    n: Vec3,
    /// Distance at `time`, model units (at most the tolerance unless status is 'iteration_limit').
    #[pyo3(get)]
    distance: f64,
    /// Triangle of mesh 1 holding point1.
    #[pyo3(get)]
    triangle1: usize,
    /// Triangle of mesh 2 holding point2.
    #[pyo3(get)]
    triangle2: usize,
    /// Conservative-advancement iterations taken.
    #[pyo3(get)]
    iterations: usize,
    /// 'converged', 'started_in_contact' or 'iteration_limit'.
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

/// (K, 4, 4) poses (a single (4, 4) pose is repeated `k` times when `k` is given), each checked.
fn poses_from(obj: &Bound<'_, PyAny>, name: &str, k: Option<usize>) -> PyResult<Vec<Pose>> {
    let py = obj.py();
    let arr = py
        .import("numpy")?
        .call_method1("ascontiguousarray", (obj, "float64"))
        .map_err(|e| {
            error(
                py,
                "PoseError",
                format!("{name}: cannot convert to a float64 array ({e})"),
            )
        })?;
    let shape: Vec<usize> = arr.getattr("shape")?.extract()?;
    let (count, single) = match (shape.as_slice(), k) {
        ([n, 4, 4], _) => (*n, false),
        ([4, 4], Some(k)) => (k, true),
        _ => {
            return Err(error(
                py,
                "PoseError",
                format!("{name} must have shape (K, 4, 4), got {shape:?}"),
            ))
        }
    };
    if let Some(k) = k.filter(|&k| k != count) {
        return Err(error(
            py,
            "PoseError",
            format!("{name} has {count} poses, expected {k}"),
        ));
    }
    let flat = arr
        .call_method1("reshape", (-1,))?
        .cast_into::<PyArray1<f64>>()?;
    let ro = flat.readonly();
    let v = ro
        .as_slice()
        .map_err(|e| error(py, "PoseError", e.to_string()))?;
    let poses: Vec<Pose> = v
        .chunks_exact(16)
        .enumerate()
        .map(|(i, m)| {
            Pose::from_matrix(&Mat4::from_cols_slice(m).transpose(), ROTATION_TOLERANCE)
                .map_err(|e| error(py, "PoseError", format!("{name}[{i}]: {e}")))
        })
        .collect::<PyResult<_>>()?;
    Ok(if single { vec![poses[0]; count] } else { poses })
}

fn array2<'py>(py: Python<'py>, rows: Vec<[f64; 3]>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = rows.len();
    PyArray1::from_vec(py, rows.into_iter().flatten().collect()).reshape([n, 3])
}

type Arrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
);

/// Distances for K pose pairs: (distance, point1, point2, triangle1, triangle2) arrays.
#[pyfunction]
#[pyo3(signature = (mesh1, poses1, mesh2, poses2, relative_error=0.0, absolute_error=0.0))]
fn _distance_batch<'py>(
    py: Python<'py>,
    mesh1: &Mesh,
    poses1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    poses2: &Bound<'_, PyAny>,
    relative_error: f64,
    absolute_error: f64,
) -> PyResult<Arrays<'py>> {
    let p1 = poses_from(poses1, "poses1", None)?;
    let p2 = poses_from(poses2, "poses2", Some(p1.len()))?;
    let pairs: Vec<(Pose, Pose)> = p1.into_iter().zip(p2).collect();
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    let opts = tocsin::DistanceOptions {
        relative_error,
        absolute_error,
    };
    let r = py
        .detach(|| tocsin::distance_batch(&m1, &m2, &pairs, &opts))
        .map_err(|e| error(py, "OptionsError", e.to_string()))?;
    Ok((
        PyArray1::from_vec(py, r.iter().map(|d| d.distance).collect()),
        array2(py, r.iter().map(|d| d.point1.to_array()).collect())?,
        array2(py, r.iter().map(|d| d.point2.to_array()).collect())?,
        PyArray1::from_vec(py, r.iter().map(|d| d.triangle1 as i64).collect()),
        PyArray1::from_vec(py, r.iter().map(|d| d.triangle2 as i64).collect()),
    ))
}

/// Collision flags for K pose pairs.
#[pyfunction]
fn _collide_batch<'py>(
    py: Python<'py>,
    mesh1: &Mesh,
    poses1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    poses2: &Bound<'_, PyAny>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let p1 = poses_from(poses1, "poses1", None)?;
    let p2 = poses_from(poses2, "poses2", Some(p1.len()))?;
    let pairs: Vec<(Pose, Pose)> = p1.into_iter().zip(p2).collect();
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    Ok(PyArray1::from_vec(
        py,
        py.detach(|| tocsin::collide_batch(&m1, &m2, &pairs)),
    ))
}

fn motions_from(
    kind: &str,
    starts: &[Pose],
    ends: &[Pose],
    py: Python<'_>,
    name: &str,
) -> PyResult<Vec<tocsin::Motion>> {
    starts
        .iter()
        .zip(ends)
        .enumerate()
        .map(|(i, (a, b))| {
            let m = match kind {
                "translation" => tocsin::Motion::translation(*a, *b),
                "interp" => tocsin::Motion::interp(*a, *b, Vec3::ZERO),
                "screw" => tocsin::Motion::screw(*a, *b),
                other => {
                    return Err(error(
                        py,
                        "MotionError",
                        format!("unknown motion kind '{other}' (translation, interp, screw)"),
                    ))
                }
            };
            m.map_err(|e| error(py, "MotionError", format!("{name}[{i}]: {e}")))
        })
        .collect()
}

type ContactArrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
);

/// Times of contact for K motions: arrays, NaN / -1 where there is no contact; status codes
/// 0 none, 1 converged, 2 started in contact, 3 iteration limit.
#[pyfunction]
#[pyo3(signature = (mesh1, starts1, ends1, mesh2, starts2, ends2, kind, tolerance=None, max_iterations=None))]
#[allow(clippy::too_many_arguments)]
fn _time_of_contact_batch<'py>(
    py: Python<'py>,
    mesh1: &Mesh,
    starts1: &Bound<'_, PyAny>,
    ends1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    starts2: &Bound<'_, PyAny>,
    ends2: &Bound<'_, PyAny>,
    kind: &str,
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
) -> PyResult<ContactArrays<'py>> {
    let s1 = poses_from(starts1, "starts1", None)?;
    let k = Some(s1.len());
    let (e1, s2, e2) = (
        poses_from(ends1, "ends1", k)?,
        poses_from(starts2, "starts2", k)?,
        poses_from(ends2, "ends2", k)?,
    );
    let m1 = motions_from(kind, &s1, &e1, py, "motions1")?;
    let m2 = motions_from(kind, &s2, &e2, py, "motions2")?;
    let pairs: Vec<(tocsin::Motion, tocsin::Motion)> = m1.into_iter().zip(m2).collect();
    let (a, b) = (mesh1.inner.clone(), mesh2.inner.clone());
    let opts = ContactOptions {
        tolerance,
        max_iterations: max_iterations.unwrap_or(ContactOptions::default().max_iterations),
    };
    let r = py
        .detach(|| tocsin::time_of_contact_batch(&a, &b, &pairs, &opts))
        .map_err(|e| error(py, "OptionsError", e.to_string()))?;
    let nan3 = [f64::NAN; 3];
    let f = |g: &dyn Fn(&tocsin::ContactTime) -> f64| -> Vec<f64> {
        r.iter().map(|c| c.as_ref().map_or(f64::NAN, g)).collect()
    };
    let v = |g: &dyn Fn(&tocsin::ContactTime) -> Vec3| -> Vec<[f64; 3]> {
        r.iter()
            .map(|c| c.as_ref().map_or(nan3, |c| g(c).to_array()))
            .collect()
    };
    let i = |g: &dyn Fn(&tocsin::ContactTime) -> i64, none: i64| -> Vec<i64> {
        r.iter().map(|c| c.as_ref().map_or(none, g)).collect()
    };
    let status = |c: &tocsin::ContactTime| match c.status {
        ContactStatus::Converged => 1,
        ContactStatus::StartedInContact => 2,
        _ => 3,
    };
    Ok((
        PyArray1::from_vec(py, f(&|c| c.time)),
        array2(py, v(&|c| c.point1))?,
        array2(py, v(&|c| c.point2))?,
        array2(py, v(&|c| c.normal))?,
        PyArray1::from_vec(py, f(&|c| c.distance)),
        PyArray1::from_vec(py, i(&|c| c.triangle1 as i64, -1)),
        PyArray1::from_vec(py, i(&|c| c.triangle2 as i64, -1)),
        PyArray1::from_vec(py, i(&|c| c.iterations as i64, 0)),
        PyArray1::from_vec(py, i(&status, 0)),
    ))
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
    m.add_function(wrap_pyfunction!(_distance_batch, m)?)?;
    m.add_function(wrap_pyfunction!(_collide_batch, m)?)?;
    m.add_function(wrap_pyfunction!(_time_of_contact_batch, m)?)?;
    Ok(())
}

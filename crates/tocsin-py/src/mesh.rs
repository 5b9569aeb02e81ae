//! `tocsin.Mesh`: construction from arrays, files and generators; read-only views.

use crate::convert::{as_array, vec3_from};
use crate::errors::{count, error, mesh_error};
use crate::pool;
use numpy::{PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::sync::Arc;
use tocsin::TriMesh;

/// A triangle mesh (polygon soup) with its bounding volume hierarchy; immutable.
///
/// Mesh(vertices, triangles): vertices is an (N, 3) array of float coordinates (body frame,
/// model units, each of magnitude at most 1e30), triangles an (M, 3) array of integer vertex
/// indices. No closedness, orientation or connectivity is assumed: duplicated and degenerate
/// triangles and isolated vertices are accepted. The arrays are copied, never modified.
/// Raises MeshError on bad shapes, dtypes, indices or coordinates, OutOfMemoryError when the
/// mesh and its hierarchy do not fit in memory.
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct Mesh {
    pub(crate) inner: Arc<TriMesh>,
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
        let kind: String = py
            .import("numpy")?
            .call_method1("asarray", (triangles,))
            .map_err(|e| error(py, "MeshError", format!("triangles: {e}")))?
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
        tocsin::mesh::reserve(v.shape()[0], t.shape()[0]).map_err(|e| mesh_error(py, e))?;
        let (vs, ts) = (
            v.as_slice()
                .map_err(|e| error(py, "MeshError", e.to_string()))?,
            t.as_slice()
                .map_err(|e| error(py, "MeshError", e.to_string()))?,
        );
        let verts: Vec<[f64; 3]> = vs.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let tris: Vec<[i64; 3]> = ts.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        Self::built(py, pool::run(py, || TriMesh::from_arrays(&verts, &tris))?)
    }

    /// A mesh from a trimesh.Trimesh (anything with .vertices (N, 3) and .faces (M, 3)).
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

    /// Loads an OBJ, STL (ASCII or binary, one or more solids), PLY or COLLADA file;
    /// polygons are triangulated, points and lines skipped (a COLLADA file: every geometry
    /// its visual scene places, with the nodes' transforms and the unit; up_axis ignored, as
    /// ROS and coal do). Raises MeshFileError if the file cannot be
    /// read, MeshError if its content is bad.
    #[staticmethod]
    fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        Self::built(py, pool::run(py, || TriMesh::load(&path))?)
    }

    /// A (2,3) torus-knot tube with 2 * n_u * n_v triangles (knot radius ~3, tube radius 0.4);
    /// n_u and n_v are positive integers, raised to at least 3.
    #[staticmethod]
    fn torus_knot(
        py: Python<'_>,
        n_u: &Bound<'_, PyAny>,
        n_v: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let n_u = count(py, n_u, "n_u", 1, "MeshError")?;
        let n_v = count(py, n_v, "n_v", 1, "MeshError")?;
        Self::built(py, pool::run(py, || tocsin::mesh::torus_knot(n_u, n_v))?)
    }

    /// A UV sphere of the given radius centred at the origin, n_lat bands of latitude and
    /// n_lon of longitude (positive integers, raised to at least 2 and 3).
    #[staticmethod]
    fn sphere(
        py: Python<'_>,
        radius: f64,
        n_lat: &Bound<'_, PyAny>,
        n_lon: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let n_lat = count(py, n_lat, "n_lat", 1, "MeshError")?;
        let n_lon = count(py, n_lon, "n_lon", 1, "MeshError")?;
        Self::built(
            py,
            pool::run(py, || tocsin::mesh::sphere(radius, n_lat, n_lon))?,
        )
    }

    /// A cylinder along z centred at the origin (radius, full length), tessellated so that it
    /// contains the true cylinder (the radial slack is below 0.5%).
    #[staticmethod]
    fn cylinder(py: Python<'_>, radius: f64, length: f64) -> PyResult<Self> {
        Self::built(
            py,
            pool::run(py, || tocsin::mesh::cylinder(radius, length))?,
        )
    }

    /// A capsule along z (radius, length of its cylinder part; the URDF convention), tessellated
    /// so that it contains the true capsule (slack about 2% of the radius).
    #[staticmethod]
    fn capsule(py: Python<'_>, radius: f64, length: f64) -> PyResult<Self> {
        Self::built(py, pool::run(py, || tocsin::mesh::capsule(radius, length))?)
    }

    /// An axis-aligned box centred at the origin with the given three half extents (12
    /// triangles).
    #[staticmethod]
    #[pyo3(name = "box")]
    fn box_(py: Python<'_>, half_extents: &Bound<'_, PyAny>) -> PyResult<Self> {
        let h = vec3_from(half_extents, "half_extents", "MeshError")?;
        Self::built(py, pool::run(py, || tocsin::mesh::box_mesh(h))?)
    }

    /// A zero-thickness square plate in z = 0, `size` wide, 2 * n * n triangles.
    #[staticmethod]
    fn plate(py: Python<'_>, size: f64, n: &Bound<'_, PyAny>) -> PyResult<Self> {
        let n = count(py, n, "n", 1, "MeshError")?;
        Self::built(py, pool::run(py, || tocsin::mesh::plate(size, n))?)
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

    /// Whether the mesh is a closed convex polytope (to 1e-12 of its size; no degenerate
    /// triangle). Two such meshes take the GJK path of distance, within_distance and
    /// time_of_contact (certified against a triangle pair, the same answers). The test runs on
    /// first use and is kept (about the cost of building the mesh); the queries run it
    /// themselves only on meshes of at most 4,096 vertices, so reading this property once lets
    /// a larger convex mesh take the path too.
    #[getter]
    fn is_convex(&self, py: Python<'_>) -> bool {
        let inner = &self.inner;
        py.detach(|| inner.is_convex())
    }

    /// A copy of the (N, 3) vertex coordinates, body frame.
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = self
            .inner
            .vertices()
            .iter()
            .flat_map(|v| v.to_array())
            .collect();
        numpy::PyArray1::from_vec(py, flat).reshape([self.inner.num_vertices(), 3])
    }

    /// A copy of the (M, 3) triangle vertex indices.
    #[getter]
    fn triangles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let flat: Vec<i64> = self
            .inner
            .triangles()
            .iter()
            .flat_map(|t| t.map(i64::from))
            .collect();
        numpy::PyArray1::from_vec(py, flat).reshape([self.inner.num_triangles(), 3])
    }

    /// Pickling: the vertices and triangles; unpickling rebuilds the hierarchy (deterministic:
    /// every query answers bit for bit as on the original).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let cls = py.import("tocsin._core")?.getattr("Mesh")?;
        let args = (self.vertices(py)?, self.triangles(py)?);
        Ok((cls, args).into_pyobject(py)?.into_any())
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
    fn built(py: Python<'_>, m: Result<TriMesh, tocsin::MeshError>) -> PyResult<Self> {
        Ok(Self {
            inner: Arc::new(m.map_err(|e| mesh_error(py, e))?),
        })
    }
}

//! Inside and outside of a polygon soup (`winding_number`, `contains`) and the Hausdorff
//! distance between two (`hausdorff_distance`, `HausdorffResult`).

use crate::convert::{as_array, pose_from, vec3};
use crate::errors::{contact_error, count, options_error};
use crate::mesh::Mesh;
use crate::pool;
use numpy::PyArray1;
use pyo3::prelude::*;
use tocsin::query::penetration::default_max_error;
use tocsin::{DepthOptions, DepthStatus, Vec3, WindingOptions};

fn points(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Vec3>> {
    let a = as_array::<f64>(obj, "float64", 3, "points", "OptionsError")?;
    let s = a
        .as_slice()
        .map_err(|e| crate::errors::error(obj.py(), "OptionsError", e.to_string()))?;
    // A NaN point had a winding number of NaN and an infinite one was "outside": bad input,
    // said so, as for the meshes' vertices and the poses.
    let max = tocsin::math::MAX_COORDINATE;
    if let Some(k) = s.iter().position(|v| !v.is_finite() || v.abs() > max) {
        return Err(crate::errors::error(
            obj.py(),
            "OptionsError",
            format!(
                "points row {}, coordinate {}: {:e} is not finite or outside the supported \
                 range (magnitude at most {max:e})",
                k / 3,
                k % 3,
                s[k]
            ),
        ));
    }
    Ok(s.chunks_exact(3)
        .map(|c| Vec3::new(c[0], c[1], c[2]))
        .collect())
}

/// The generalized winding number of `mesh` placed by `pose` (4x4) at each world point of
/// `points` (N, 3): 1 inside and 0 outside a closed mesh oriented outwards, -1 inside an
/// inside-out one, fractional near holes (Jacobson et al. 2013). Clusters of triangles seen
/// from farther than `beta` times their radius are summed as dipoles (Barill et al. 2018;
/// beta=2: median error 2.7e-3 on a torus knot, worst 0.024); `exact=True` sums every
/// triangle's solid angle. On all cores; the GIL is released. Raises OptionsError for a point
/// that is not finite or beyond 1e30 in magnitude.
#[pyfunction]
#[pyo3(signature = (mesh, pose, points, beta=2.0, exact=false))]
pub(crate) fn winding_number<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    pose: &Bound<'py, PyAny>,
    points: &Bound<'py, PyAny>,
    beta: f64,
    exact: bool,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let pose = pose_from(pose, "pose")?;
    let pts = self::points(points)?;
    let options = WindingOptions {
        beta: if exact { f64::INFINITY } else { beta },
    };
    let m = mesh.inner.clone();
    let w = pool::run(py, || tocsin::winding_number(&m, &pose, &pts, &options))?
        .map_err(|e| options_error(py, e))?;
    Ok(PyArray1::from_vec(py, w))
}

/// Whether each world point (N, 3) is inside `mesh` placed by `pose`: the magnitude of its
/// generalized winding number exceeds 1/2 (exactly evaluated wherever the fast one is near 1/2;
/// the magnitude, as a soup has no reliable orientation: inside-out meshes have the same
/// inside). A polygon soup has no inside for distance and collide; this is the inside the
/// penetration queries use. Raises OptionsError for a point that is not finite or beyond 1e30
/// in magnitude.
#[pyfunction]
pub(crate) fn contains<'py>(
    py: Python<'py>,
    mesh: &Mesh,
    pose: &Bound<'py, PyAny>,
    points: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<bool>>> {
    let pose = pose_from(pose, "pose")?;
    let pts = self::points(points)?;
    let m = mesh.inner.clone();
    let inside = pool::run(py, || tocsin::contains(&m, &pose, &pts))?;
    Ok(PyArray1::from_vec(py, inside))
}

/// The Hausdorff distance found, within the error bound, and where.
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct HausdorffResult {
    /// A value attained by a surface point (model units, >= 0): at most the true distance, at
    /// least it minus max_error.
    #[pyo3(get)]
    distance: f64,
    /// An upper bound on the true distance (model units; upper_bound - distance <= max_error).
    #[pyo3(get)]
    upper_bound: f64,
    /// Whether point1 is on mesh1 (False: the symmetric distance is realised from mesh2).
    #[pyo3(get)]
    from_first: bool,
    p1: Vec3,
    p2: Vec3,
}

#[pymethods]
impl HausdorffResult {
    /// The point realising `distance`, on the mesh it is measured from, world frame, (3,).
    #[getter]
    fn point1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p1)
    }

    /// Its closest point on the other mesh, world frame, (3,).
    #[getter]
    fn point2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p2)
    }

    fn __repr__(&self) -> String {
        format!(
            "HausdorffResult(distance={}, upper_bound={}, from_first={})",
            self.distance,
            self.upper_bound,
            if self.from_first { "True" } else { "False" }
        )
    }
}

/// The Hausdorff distance between the surfaces of mesh1 and mesh2 (placed by 4x4 poses):
/// one-sided from mesh1 (max over points a of mesh1 of their distance to mesh2), or with
/// symmetric=True the larger of both directions; exact within max_error (model units, > 0;
/// default 1e-4 of the smaller bounding radius; one below the distances' accuracy, 2e-13 of
/// the radii plus the poses' distances from the origin, is raised to it). Returns a
/// HausdorffResult with the attained value, an upper bound and the witness points. A mesh
/// against itself at another pose (a pose error), or against a copy with the same triangle
/// list, is bounded by how far corresponding points moved and answered quickly. The GIL is
/// released.
#[pyfunction]
#[pyo3(signature = (mesh1, pose1, mesh2, pose2, max_error=None, symmetric=false))]
pub(crate) fn hausdorff_distance(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
    max_error: Option<f64>,
    symmetric: bool,
) -> PyResult<HausdorffResult> {
    let (p1, p2) = (pose_from(pose1, "pose1")?, pose_from(pose2, "pose2")?);
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    let e = max_error.unwrap_or_else(|| default_max_error(&m1, &m2));
    // The two directions of a symmetric distance run in parallel: this process's pool.
    let r = pool::run(py, || {
        tocsin::hausdorff_distance(&m1, &p1, &m2, &p2, e, symmetric)
    })?
    .map_err(|e| options_error(py, e))?;
    Ok(HausdorffResult {
        distance: r.distance,
        upper_bound: r.upper_bound,
        from_first: r.from_first,
        p1: r.point1,
        p2: r.point2,
    })
}

/// A translational penetration depth and the translation that realises it.
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct PenetrationResult {
    /// Length of the translation (model units, >= 0; 0 when separated).
    #[pyo3(get)]
    depth: f64,
    /// Refinement iterations taken.
    #[pyo3(get)]
    iterations: usize,
    /// 'separated', 'converged' or 'iteration_limit'.
    #[pyo3(get)]
    status: &'static str,
    /// Whether depth is exact (both meshes closed convex polytopes; then the translation is
    /// depth + tolerance / 2 long, so the bodies end apart).
    #[pyo3(get)]
    exact: bool,
    t: Vec3,
    dir: Vec3,
    p1: Vec3,
    p2: Vec3,
}

#[pymethods]
impl PenetrationResult {
    /// Translation to apply to body 2 (world frame), shape (3,): after it the meshes touch
    /// within the tolerance and do not intersect.
    #[getter]
    fn translation<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.t)
    }

    /// Unit direction of the translation, shape (3,).
    #[getter]
    fn direction<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.dir)
    }

    /// Closest point on body 1 at the touching configuration, world frame, (3,).
    #[getter]
    fn point1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p1)
    }

    /// Closest point on body 2 there (body 2 translated), world frame, (3,).
    #[getter]
    fn point2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p2)
    }

    fn __repr__(&self) -> String {
        format!(
            "PenetrationResult(depth={}, status='{}', iterations={})",
            self.depth, self.status, self.iterations
        )
    }
}

/// Translational penetration depth of mesh2 (placed by pose2) into mesh1, after PolyDepth,
/// when they penetrate (their surfaces intersect, or one lies inside the other by the winding
/// number): the shortest translation of body 2 found after which the two do not intersect and
/// are apart by at most min(tolerance, 1e-3 depth) (tolerance: default 1e-3 of the smaller
/// radius; below twice the distances' accuracy, 2e-13 of the radii plus the poses' distances
/// from the origin, it is raised to that, so that the bodies end apart). Seeds are
/// out-projected with the exact continuous collision query, then refined on the local contact
/// space; the result is a local optimum and always a valid separating
/// translation (on random overlapping boxes within 0.05% of the exact depth at the median,
/// 3% at worst). Two closed convex meshes get the exact global depth instead (result.exact;
/// exact_convex=False runs the local search on them too). `cached_direction` (3,) is tried first
/// (coherence between frames). `starts` (default 2, at least 1): how many of the seeds' shortest
/// touching translations are refined at deep penetrations; 3 found a 0-6% shorter depth on 9 of
/// 81 deep queries at about 1.2-1.4x the time. `directions` (default 32): seed directions
/// spread over the sphere, at most 1,000,000. Status 'separated' (depth 0) when they do not
/// penetrate.
#[pyfunction]
#[pyo3(signature = (mesh1, pose1, mesh2, pose2, tolerance=None, max_iterations=None, directions=None, cached_direction=None, exact_convex=true, starts=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn penetration_depth(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<&Bound<'_, PyAny>>,
    directions: Option<&Bound<'_, PyAny>>,
    cached_direction: Option<&Bound<'_, PyAny>>,
    exact_convex: bool,
    starts: Option<&Bound<'_, PyAny>>,
) -> PyResult<PenetrationResult> {
    let (p1, p2) = (pose_from(pose1, "pose1")?, pose_from(pose2, "pose2")?);
    let defaults = DepthOptions::default();
    let options = DepthOptions {
        tolerance,
        max_iterations: match max_iterations {
            Some(m) => count(py, m, "max_iterations", 0, "OptionsError")?,
            None => defaults.max_iterations,
        },
        directions: match directions {
            Some(m) => count(py, m, "directions", 0, "OptionsError")?,
            None => defaults.directions,
        },
        cached_direction: match cached_direction {
            Some(d) => Some(crate::convert::vec3_from(
                d,
                "cached_direction",
                "OptionsError",
            )?),
            None => None,
        },
        exact_convex,
        starts: match starts {
            Some(m) => count(py, m, "starts", 1, "OptionsError")?,
            None => defaults.starts,
        },
    };
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    let r = py
        .detach(|| tocsin::penetration_depth(&m1, &p1, &m2, &p2, &options))
        .map_err(|e| contact_error(py, e))?;
    Ok(PenetrationResult {
        depth: r.depth,
        iterations: r.iterations,
        status: match r.status {
            DepthStatus::Separated => "separated",
            DepthStatus::Converged => "converged",
            _ => "iteration_limit",
        },
        exact: r.exact,
        t: r.translation,
        dir: r.direction,
        p1: r.point1,
        p2: r.point2,
    })
}

/// The deepest interpenetrating points found (pointwise penetration depth).
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct PointwiseResult {
    /// Depth attained (model units, >= 0): distance from point1 (inside the other body) to
    /// the other surface.
    #[pyo3(get)]
    depth: f64,
    /// Upper bound on the true pointwise depth (model units).
    #[pyo3(get)]
    upper_bound: f64,
    /// Whether point1 is on mesh1 (inside mesh2); False: on mesh2 inside mesh1.
    #[pyo3(get)]
    from_first: bool,
    p1: Vec3,
    p2: Vec3,
}

#[pymethods]
impl PointwiseResult {
    /// The deepest point found, on its own surface, world frame, (3,).
    #[getter]
    fn point1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p1)
    }

    /// Its closest point on the other surface, world frame, (3,).
    #[getter]
    fn point2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p2)
    }

    fn __repr__(&self) -> String {
        format!(
            "PointwiseResult(depth={}, upper_bound={})",
            self.depth, self.upper_bound
        )
    }
}

/// Pointwise penetration depth (Tang, Lee, Kim 2009): the largest distance from a point of one
/// surface that lies inside the other body (winding number magnitude above 1/2) to the other surface,
/// within max_error (default 1e-4 of the smaller bounding radius; one below the distances'
/// accuracy, 2e-13 of the radii plus the poses' distances from the origin, is raised to it),
/// with the two points. Depth 0 when neither surface enters the other. Exact inside/outside
/// for closed meshes; on soups with holes a piece not crossing the other surface is classified
/// at a point joined to it without crossing that surface (its centroid or a neighbour's).
/// Against itself at another pose, or a copy with the same triangle list, pieces are also
/// bounded by how far their corresponding points moved.
#[pyfunction]
#[pyo3(signature = (mesh1, pose1, mesh2, pose2, max_error=None))]
pub(crate) fn pointwise_penetration(
    py: Python<'_>,
    mesh1: &Mesh,
    pose1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    pose2: &Bound<'_, PyAny>,
    max_error: Option<f64>,
) -> PyResult<PointwiseResult> {
    let (p1, p2) = (pose_from(pose1, "pose1")?, pose_from(pose2, "pose2")?);
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    let e = max_error.unwrap_or_else(|| default_max_error(&m1, &m2));
    // Both directions run in parallel: this process's pool.
    let r = pool::run(py, || tocsin::pointwise_penetration(&m1, &p1, &m2, &p2, e))?
        .map_err(|e| options_error(py, e))?;
    Ok(PointwiseResult {
        depth: r.depth,
        upper_bound: r.upper_bound,
        from_first: r.from_first,
        p1: r.point1,
        p2: r.point2,
    })
}

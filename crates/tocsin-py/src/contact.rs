//! Continuous collision: `ContactResult` and `time_of_contact`.

use crate::convert::vec3;
use crate::errors::{contact_error, count};
use crate::mesh::Mesh;
use crate::motion::Motion;
use numpy::PyArray1;
use pyo3::prelude::*;
use tocsin::{ContactOptions, ContactStatus, Vec3, Witnesses};

/// When and where two moving meshes first come within the tolerance.
///
/// `time` is no later than the first collision, and the distance there is at most the
/// tolerance. point1 and point2 are the meshes' closest points there, or with
/// time_of_contact(..., contact_pair=True) the closest points of the triangle pair that ended
/// the advancement (within the tolerance; the meshes' distance is at most `distance`). The normal
/// points from body 1 to body 2: the direction between the points where that is determined;
/// at a distance below rounding (1e-12 of the scene scale), the direction at the last
/// advancement step where the meshes were clearly apart; when the meshes start in contact, the
/// normal of triangle1 turned towards triangle2 (a convention).
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct ContactResult {
    /// Time of contact in [0, 1], no later than the first collision.
    #[pyo3(get)]
    pub(crate) time: f64,
    p1: Vec3,
    p2: Vec3,
    n: Vec3,
    /// Distance between point1 and point2, model units, at most the tolerance: the meshes'
    /// distance at `time` (with contact_pair=True, at least it).
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
    /// 'converged' or 'started_in_contact'.
    #[pyo3(get)]
    status: &'static str,
}

#[pymethods]
impl ContactResult {
    /// Point of mesh 1 at `time` (the closest, or the contact pair's), world frame, shape (3,).
    #[getter]
    fn point1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p1)
    }

    /// Point of mesh 2 at `time` (the closest, or the contact pair's), world frame, shape (3,).
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

impl ContactResult {
    pub(crate) fn from_core(c: &tocsin::ContactTime) -> Self {
        Self {
            time: c.time,
            p1: c.point1,
            p2: c.point2,
            n: c.normal,
            distance: c.distance,
            triangle1: c.triangle1,
            triangle2: c.triangle2,
            iterations: c.iterations,
            status: status_name(c.status),
        }
    }
}

pub(crate) fn status_name(s: ContactStatus) -> &'static str {
    match s {
        ContactStatus::StartedInContact => "started_in_contact",
        _ => "converged",
    }
}

/// The options of a time-of-contact call, checked for type (ranges are the core's).
pub(crate) fn contact_options(
    py: Python<'_>,
    tolerance: Option<f64>,
    max_iterations: Option<&Bound<'_, PyAny>>,
) -> PyResult<ContactOptions> {
    Ok(ContactOptions {
        tolerance,
        max_iterations: match max_iterations {
            Some(m) => count(py, m, "max_iterations", 1, "OptionsError")?,
            None => ContactOptions::default().max_iterations,
        },
        ..ContactOptions::default()
    })
}

/// The witnesses a time of contact reports: the contact pair's when `contact_pair`, else the
/// closest points.
pub(crate) fn witnesses(contact_pair: bool) -> Witnesses {
    if contact_pair {
        Witnesses::Contact
    } else {
        Witnesses::Closest
    }
}

/// First time of contact of mesh1 moving by motion1 and mesh2 moving by motion2 over t in
/// [0, 1]. Returns a ContactResult whenever the meshes come within tolerance / 2 of each other
/// (always when they collide), None when they stay farther apart than the tolerance, and
/// either in between. The tolerance defaults to 1e-3 of the smaller bounding radius (raised
/// for degenerate meshes); below the distances' own accuracy (2e-13 of the scene's scale, radii
/// plus the farthest start or end position) a pair within that accuracy counts as a contact,
/// and the distance returned is at most it. Raises IterationLimitError when max_iterations
/// (default 1000) runs out first: that is no contact, and the motion is only known free up to
/// its time_reached.
/// The points reported are the meshes' closest at that time, with their exact distance;
/// contact_pair=True reports those of the triangle pair that ended the advancement instead
/// (within the tolerance; their distance is at least the meshes', by up to the tolerance: a
/// caller that sets a next tolerance from it needs the default), which saves the final exact
/// distance query (15 to 25% of a knot's time of contact).
#[pyfunction]
#[pyo3(signature = (mesh1, motion1, mesh2, motion2, tolerance=None, max_iterations=None, contact_pair=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn time_of_contact(
    py: Python<'_>,
    mesh1: &Mesh,
    motion1: &Motion,
    mesh2: &Mesh,
    motion2: &Motion,
    tolerance: Option<f64>,
    max_iterations: Option<&Bound<'_, PyAny>>,
    contact_pair: bool,
) -> PyResult<Option<ContactResult>> {
    let opts = ContactOptions {
        witnesses: witnesses(contact_pair),
        ..contact_options(py, tolerance, max_iterations)?
    };
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    let (mo1, mo2) = (motion1.inner, motion2.inner);
    let r = py
        .detach(|| tocsin::time_of_contact(&m1, &mo1, &m2, &mo2, &opts))
        .map_err(|e| contact_error(py, e))?;
    Ok(r.as_ref().map(ContactResult::from_core))
}

/// Whether mesh1 moving by motion1 and mesh2 moving by motion2 stay free of contact over t in
/// [0, 1]: True when they stay farther apart than the tolerance, False whenever they come
/// within tolerance / 2 (always when they collide), either in between; the same answer as
/// `time_of_contact(...) is None`, but it stops at the first step within the tolerance,
/// computes no witnesses, and settles colliding motions by exact collision tests at a few times
/// (the end, the middle, then evenly spaced times of the rest when the advancement is slow)
/// before the advancement converges to the contact: the question a path planner asks. Raises
/// IterationLimitError when max_iterations runs out before the answer is known. The GIL is
/// released.
#[pyfunction]
#[pyo3(signature = (mesh1, motion1, mesh2, motion2, tolerance=None, max_iterations=None))]
pub(crate) fn motion_is_free(
    py: Python<'_>,
    mesh1: &Mesh,
    motion1: &Motion,
    mesh2: &Mesh,
    motion2: &Motion,
    tolerance: Option<f64>,
    max_iterations: Option<&Bound<'_, PyAny>>,
) -> PyResult<bool> {
    let opts = contact_options(py, tolerance, max_iterations)?;
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    let (mo1, mo2) = (motion1.inner, motion2.inner);
    py.detach(|| tocsin::motion_is_free(&m1, &mo1, &m2, &mo2, &opts))
        .map_err(|e| contact_error(py, e))
}

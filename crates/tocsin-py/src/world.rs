//! `tocsin.World` and `tocsin.WorldContact`: many bodies and the queries over all of them.

use crate::contact::{contact_options, ContactResult};
use crate::convert::{pose_from, pose_to_numpy, poses_from};
use crate::errors::{contact_error, error, motion_error, options_error};
use crate::mesh::Mesh;
use crate::motion::Motion;
use crate::pool;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use std::sync::{Arc, RwLock};
use tocsin::world::{self as core, WorldError};
use tocsin::{Pose, Vec3};

/// A body index given from Python: an int (or anything with `__index__`) in `0..len`. Any other int (negative, or beyond
/// what an index holds) is a WorldError like an index past the end, not the OverflowError of
/// converting it; a non-int is a TypeError.
fn body_index(py: Python<'_>, index: &Bound<'_, PyAny>, len: usize) -> PyResult<usize> {
    // `__index__`: ints, bools and numpy's integers, as a list index takes them.
    let Ok(int) = index.call_method0("__index__") else {
        let given = index.get_type().name()?;
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "a body index must be an int, got {given}"
        )));
    };
    match int.extract::<usize>() {
        Ok(i) if i < len => Ok(i),
        Ok(i) => Err(world_error(py, WorldError::UnknownBody { index: i, len })),
        Err(_) => Err(error(
            py,
            "WorldError",
            format!("body {index} does not exist: the world has {len} bodies"),
        )),
    }
}

fn world_error(py: Python<'_>, e: WorldError) -> PyErr {
    match e {
        WorldError::Options(o) => options_error(py, o),
        WorldError::Contact {
            body1,
            body2,
            source,
        } => {
            let err = contact_error(py, source);
            let note = format!("bodies {body1} and {body2}");
            let _ = err.value(py).call_method1("add_note", (note,));
            err
        }
        other => error(py, "WorldError", other.to_string()),
    }
}

/// Bodies, each a Mesh moving by a rigid Motion over the step t in [0, 1], or static; and the
/// queries over all of them at once (first_contacts, earliest_contact, colliding_pairs,
/// pairs_within). Bodies given the same Mesh object share its hierarchy. A query works on a
/// snapshot: editing the world from another thread never changes a query already running.
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct World {
    inner: RwLock<Arc<core::World>>,
}

impl World {
    fn snapshot(&self) -> Arc<core::World> {
        self.inner.read().unwrap_or_else(|p| p.into_inner()).clone()
    }

    fn edit<R>(&self, f: impl FnOnce(&mut core::World) -> R) -> R {
        let mut guard = self.inner.write().unwrap_or_else(|p| p.into_inner());
        f(Arc::make_mut(&mut guard))
    }

    /// Poses given, or every body's pose at `t`.
    fn poses(world: &core::World, poses: Option<&Bound<'_, PyAny>>, t: f64) -> PyResult<Vec<Pose>> {
        match poses {
            Some(p) => poses_from(p, "poses", Some(world.len())),
            None => Ok(world.poses_at(t)),
        }
    }
}

fn options(
    py: Python<'_>,
    tolerance: Option<f64>,
    max_iterations: Option<&Bound<'_, PyAny>>,
) -> PyResult<core::WorldOptions> {
    Ok(core::WorldOptions {
        contact: contact_options(py, tolerance, max_iterations)?,
        ..Default::default()
    })
}

fn pairs_array<'py>(
    py: Python<'py>,
    pairs: impl ExactSizeIterator<Item = (usize, usize)>,
) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let n = pairs.len();
    let flat: Vec<i64> = pairs.flat_map(|(i, j)| [i as i64, j as i64]).collect();
    PyArray1::from_vec(py, flat).reshape([n, 2])
}

#[pymethods]
impl World {
    #[new]
    fn new() -> Self {
        Self {
            inner: RwLock::new(Arc::new(core::World::new())),
        }
    }

    /// Adds a moving body: `motion` is a Motion, or a 4x4 pose for a body at rest (it is still
    /// checked against static bodies). Returns the body's index.
    fn add_body(&self, mesh: &Mesh, motion: &Bound<'_, PyAny>) -> PyResult<usize> {
        let motion = match motion.cast::<Motion>() {
            Ok(m) => m.get().inner,
            Err(_) => tocsin::Motion::stationary(pose_from(motion, "motion")?),
        };
        Ok(self.edit(|w| w.add_body(&mesh.inner, motion)))
    }

    /// Adds a static body at `pose` (4x4); static bodies are never checked against each other.
    /// Returns the body's index.
    fn add_static(&self, mesh: &Mesh, pose: &Bound<'_, PyAny>) -> PyResult<usize> {
        let pose = pose_from(pose, "pose")?;
        Ok(self.edit(|w| w.add_static(&mesh.inner, pose)))
    }

    /// Sets body `index`'s Motion over the next step (WorldError for an unknown index).
    fn set_motion(
        &self,
        py: Python<'_>,
        index: &Bound<'_, PyAny>,
        motion: &Motion,
    ) -> PyResult<()> {
        let index = body_index(py, index, self.snapshot().len())?;
        self.edit(|w| w.set_motion(index, motion.inner))
            .map_err(|e| world_error(py, e))
    }

    /// Sets the motions of the bodies `bodies` (K indices) from `starts` to `ends` ((K, 4, 4)
    /// each), all of one kind: "screw" (default), "interp" (about each body's origin) or
    /// "translation". Nothing changes when any of them is invalid.
    #[pyo3(signature = (bodies, starts, ends, kind="screw"))]
    fn set_motions(
        &self,
        py: Python<'_>,
        bodies: Vec<Bound<'_, PyAny>>,
        starts: &Bound<'_, PyAny>,
        ends: &Bound<'_, PyAny>,
        kind: &str,
    ) -> PyResult<()> {
        let len = self.snapshot().len();
        let bodies = bodies
            .iter()
            .map(|i| body_index(py, i, len))
            .collect::<PyResult<Vec<usize>>>()?;
        let k = bodies.len();
        let (a, b) = (
            poses_from(starts, "starts", Some(k))?,
            poses_from(ends, "ends", Some(k))?,
        );
        let make = match kind {
            "screw" => tocsin::Motion::screw,
            "translation" => tocsin::Motion::translation,
            "interp" => |s, e| tocsin::Motion::interp(s, e, Vec3::ZERO),
            other => {
                return Err(error(
                    py,
                    "MotionError",
                    format!("kind must be 'screw', 'interp' or 'translation', got {other:?}"),
                ))
            }
        };
        let motions = a
            .iter()
            .zip(&b)
            .map(|(s, e)| make(*s, *e))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| motion_error(py, e))?;
        self.edit(|w| {
            for (&i, m) in bodies.iter().zip(motions) {
                // Indices were checked above.
                let _ = w.set_motion(i, m);
            }
        });
        Ok(())
    }

    fn __len__(&self) -> usize {
        self.snapshot().len()
    }

    /// Number of distinct meshes (hierarchies) the bodies share.
    #[getter]
    fn num_meshes(&self) -> usize {
        self.snapshot().num_meshes()
    }

    /// Whether body `index` is static.
    fn is_static(&self, py: Python<'_>, index: &Bound<'_, PyAny>) -> PyResult<bool> {
        let w = self.snapshot();
        let index = body_index(py, index, w.len())?;
        Ok(w.is_static(index))
    }

    /// Every body's pose at time t of the step, shape (N, 4, 4).
    fn poses_at<'py>(&self, py: Python<'py>, t: f64) -> PyResult<Bound<'py, PyAny>> {
        let w = self.snapshot();
        let list = w
            .poses_at(t)
            .iter()
            .map(|p| pose_to_numpy(py, p))
            .collect::<PyResult<Vec<_>>>()?;
        let np = py.import("numpy")?;
        if list.is_empty() {
            return np.call_method1("zeros", ((0, 4, 4),));
        }
        np.call_method1("stack", (list,))
    }

    /// The broad phase over the step: every pair (i, j), i < j, not both static, whose swept
    /// boxes (grown by half the largest tolerance either can use) meet, shape (K, 2).
    #[pyo3(signature = (tolerance=None))]
    fn candidate_pairs<'py>(
        &self,
        py: Python<'py>,
        tolerance: Option<f64>,
    ) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let w = self.snapshot();
        let opts = options(py, tolerance, None)?;
        let pairs = pool::run(py, || w.candidate_pairs(&opts))?.map_err(|e| world_error(py, e))?;
        pairs_array(py, pairs.into_iter().map(|(i, j)| (i as usize, j as usize)))
    }

    /// Every pair of bodies that comes within its tolerance during the step, each with the
    /// answer time_of_contact gives for the pair alone (body1 < body2 is mesh 1), sorted by
    /// time then body indices. With `bodies`, only the pairs with at least one of them (what a
    /// simulation asks again after changing a few bodies' motions). Raises IterationLimitError
    /// (with the bodies in a note) when a pair's max_iterations runs out.
    #[pyo3(signature = (tolerance=None, max_iterations=None, bodies=None))]
    fn first_contacts(
        &self,
        py: Python<'_>,
        tolerance: Option<f64>,
        max_iterations: Option<&Bound<'_, PyAny>>,
        bodies: Option<Vec<usize>>,
    ) -> PyResult<Vec<WorldContact>> {
        let w = self.snapshot();
        let opts = options(py, tolerance, max_iterations)?;
        let r = pool::run(py, || match &bodies {
            Some(b) => core::first_contacts_among(&w, &opts, b),
            None => core::first_contacts(&w, &opts),
        })?
        .map_err(|e| world_error(py, e))?;
        r.contacts
            .iter()
            .map(|c| WorldContact::from_core(py, c))
            .collect()
    }

    /// The earliest of first_contacts (ties by body indices), or None; pairs that cannot beat
    /// the best time found are not run.
    #[pyo3(signature = (tolerance=None, max_iterations=None))]
    fn earliest_contact(
        &self,
        py: Python<'_>,
        tolerance: Option<f64>,
        max_iterations: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Option<WorldContact>> {
        let w = self.snapshot();
        let opts = options(py, tolerance, max_iterations)?;
        let r =
            pool::run(py, || core::earliest_contact(&w, &opts))?.map_err(|e| world_error(py, e))?;
        r.as_ref()
            .map(|c| WorldContact::from_core(py, c))
            .transpose()
    }

    /// Pairs (i, j), i < j, not both static, whose meshes touch or intersect at `poses`
    /// ((N, 4, 4); default: the poses at time t), shape (K, 2), sorted.
    #[pyo3(signature = (poses=None, t=0.0))]
    fn colliding_pairs<'py>(
        &self,
        py: Python<'py>,
        poses: Option<&Bound<'_, PyAny>>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let w = self.snapshot();
        let poses = Self::poses(&w, poses, t)?;
        let r =
            pool::run(py, || core::colliding_pairs(&w, &poses))?.map_err(|e| world_error(py, e))?;
        pairs_array(py, r.into_iter())
    }

    /// Pairs (i, j), i < j, not both static, whose meshes are at most `distance` apart at
    /// `poses` ((N, 4, 4); default: the poses at time t), shape (K, 2), sorted.
    #[pyo3(signature = (distance, poses=None, t=0.0))]
    fn pairs_within<'py>(
        &self,
        py: Python<'py>,
        distance: f64,
        poses: Option<&Bound<'_, PyAny>>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let w = self.snapshot();
        let poses = Self::poses(&w, poses, t)?;
        let r = pool::run(py, || core::pairs_within(&w, &poses, distance))?
            .map_err(|e| world_error(py, e))?;
        pairs_array(py, r.into_iter())
    }

    /// Pickling: each distinct mesh once, then every body's mesh index, motion and whether it
    /// is static; the copy shares its meshes between bodies as the original does.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.snapshot();
        let f = py.import("tocsin._core")?.getattr("_world_from_parts")?;
        let mut meshes: Vec<Py<Mesh>> = Vec::new();
        let mut seen: Vec<*const tocsin::TriMesh> = Vec::new();
        let mut bodies = Vec::with_capacity(w.len());
        for i in 0..w.len() {
            let m = w.mesh(i);
            let k = match seen.iter().position(|p| std::ptr::eq(*p, Arc::as_ptr(m))) {
                Some(k) => k,
                None => {
                    seen.push(Arc::as_ptr(m));
                    meshes.push(Py::new(py, Mesh { inner: m.clone() })?);
                    seen.len() - 1
                }
            };
            let motion = Py::new(
                py,
                Motion {
                    inner: *w.motion(i),
                },
            )?;
            bodies.push((k, motion, w.is_static(i)));
        }
        Ok((f, (meshes, bodies)).into_pyobject(py)?.into_any())
    }

    fn __repr__(&self) -> String {
        let w = self.snapshot();
        format!("World(bodies={}, meshes={})", w.len(), w.num_meshes())
    }
}

/// Unpickles a World (`World.__reduce__`).
#[pyfunction]
pub(crate) fn _world_from_parts(
    py: Python<'_>,
    meshes: Vec<Bound<'_, Mesh>>,
    bodies: Vec<(Bound<'_, PyAny>, Bound<'_, Motion>, bool)>,
) -> PyResult<World> {
    let mut w = core::World::new();
    for (k, motion, fixed) in bodies {
        // The index is read here rather than as a `usize` argument, so that a corrupted
        // pickle's negative or huge index is this error and not an OverflowError.
        let mesh = k
            .extract::<usize>()
            .ok()
            .and_then(|k| meshes.get(k))
            .ok_or_else(|| error(py, "WorldError", "a pickled world names a mesh it lacks"))?;
        let inner = mesh.borrow().inner.clone();
        let m = motion.borrow().inner;
        if fixed {
            w.add_static(&inner, m.start());
        } else {
            w.add_body(&inner, m);
        }
    }
    Ok(World {
        inner: RwLock::new(Arc::new(w)),
    })
}

/// A pair of bodies that comes within its tolerance during the step: body1 < body2 and the
/// pair's ContactResult (body1 is mesh 1: the normal points from body1 to body2).
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct WorldContact {
    /// The smaller body index.
    #[pyo3(get)]
    body1: usize,
    /// The larger body index.
    #[pyo3(get)]
    body2: usize,
    /// The pair's first contact (time, world-frame points, normal from body1 to body2).
    #[pyo3(get)]
    contact: Py<ContactResult>,
}

#[pymethods]
impl WorldContact {
    /// The contact's time in [0, 1] (contact.time).
    #[getter]
    fn time(&self) -> f64 {
        self.contact.get().time
    }

    fn __repr__(&self) -> String {
        format!(
            "WorldContact(body1={}, body2={}, time={})",
            self.body1,
            self.body2,
            self.time()
        )
    }
}

impl WorldContact {
    fn from_core(py: Python<'_>, c: &core::WorldContact) -> PyResult<Self> {
        Ok(Self {
            body1: c.body1,
            body2: c.body2,
            contact: Py::new(py, ContactResult::from_core(&c.contact))?,
        })
    }
}

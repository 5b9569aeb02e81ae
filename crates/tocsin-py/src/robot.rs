//! Robots: `Robot` (URDF, SRDF, attachments, forward kinematics), `Scene` (static obstacles),
//! `RobotContact`, and the segment queries (time of contact, path checks, configuration checks,
//! batches). Every query releases the GIL; batches run in the binding's fork-safe pool.

use crate::contact::{status_name, witnesses};
use crate::convert::{as_array, pose_from, pose_to_numpy, vec3};
use crate::errors::{contact_error, count, error, mesh_error};
use crate::mesh::Mesh;
use crate::pool;
use numpy::{PyArray1, PyArray3, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, RwLock};
use tocsin::robot::query as rq;
use tocsin::robot::{RobotOptions, Scene as CoreScene};
use tocsin::{RobotError, Vec3};

pub(crate) fn robot_error(py: Python<'_>, e: RobotError) -> PyErr {
    match e {
        RobotError::Contact(c) => contact_error(py, c),
        RobotError::Mesh { link, source } => {
            let inner = mesh_error(py, source);
            error(py, "RobotError", format!("link {link}: {inner}"))
        }
        RobotError::MissingMesh { .. } | RobotError::Parse { .. } => {
            error(py, "RobotFileError", e.to_string())
        }
        RobotError::Configuration { .. } => error(py, "ConfigurationError", e.to_string()),
        other => error(py, "RobotError", other.to_string()),
    }
}

/// An articulated robot from URDF: bodies (links merged over fixed joints), moving joints
/// (revolute, continuous, prismatic, mimic), each link's collision geometry as one polygon soup
/// (OBJ, STL, PLY or COLLADA meshes with their scale; boxes exactly; spheres, cylinders and
/// capsules as tessellations that contain the true shape), and the link pairs checked for self-collision (all but
/// adjacent bodies, SRDF-disabled pairs, pairs you allow, attachments and their touch links).
///
/// Configurations are float arrays of shape (dof,) in the order of `joint_names` (the actuated
/// joints as the URDF lists them, mimics excluded). Build one with Robot.from_urdf.
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct Robot {
    /// Queries take a snapshot (the `Arc`) and release the lock at once; edits copy on write,
    /// so a query running in another thread keeps the robot it started with, and no borrow
    /// error can reach Python.
    inner: RwLock<Arc<tocsin::Robot>>,
    /// How the robot was made and edited, replayed on unpickling: the URDF and SRDF texts (read
    /// once), absolute mesh folders, then every successful edit in order. The lock is held
    /// across each edit, so the order is the order the edits were applied in.
    recipe: Mutex<Vec<Py<PyAny>>>,
    /// The URDF's meshes a pickle brought (filename: (vertices, triangles)), pickled again as
    /// they are: the files may not exist here.
    carried: Option<Py<PyAny>>,
}

/// A path made absolute (a Ray worker runs in another folder), unchanged when that fails.
fn absolute(p: &std::path::Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}

/// Reads a snapshot out of a lock (a poisoned lock still holds a whole value: edits replace it
/// only once they succeeded).
fn snapshot<T>(lock: &RwLock<Arc<T>>) -> Arc<T> {
    lock.read().unwrap_or_else(|p| p.into_inner()).clone()
}

/// Edits the value in a lock, copying it first if a query still holds the old one.
fn edit<T: Clone, R>(lock: &RwLock<Arc<T>>, f: impl FnOnce(&mut T) -> R) -> R {
    let mut guard = lock.write().unwrap_or_else(|p| p.into_inner());
    f(Arc::make_mut(&mut guard))
}

impl Robot {
    /// Applies an edit and, when it succeeds, appends `op` to the recipe (under one lock).
    fn recorded<R>(
        &self,
        py: Python<'_>,
        op: Py<PyAny>,
        f: impl FnOnce(&mut tocsin::Robot) -> Result<R, RobotError>,
    ) -> PyResult<R> {
        let mut recipe = self.recipe.lock().unwrap_or_else(|p| p.into_inner());
        let out = edit(&self.inner, f).map_err(|e| robot_error(py, e))?;
        recipe.push(op);
        Ok(out)
    }
}

/// A mesh file's contents as a robot's pickle carries them: vertices and triangles.
type PickledMesh = (Vec<[f64; 3]>, Vec<[u32; 3]>);

/// Unpickles a Robot (`Robot.__reduce__`): replays its recipe, the URDF's meshes taken from
/// `meshes` (filename as written in the URDF: (vertices, triangles)) rather than from files.
#[pyfunction]
#[pyo3(signature = (recipe, meshes=None))]
pub(crate) fn _robot_from_recipe(
    py: Python<'_>,
    recipe: Vec<Bound<'_, PyAny>>,
    meshes: Option<Bound<'_, PyAny>>,
) -> PyResult<Robot> {
    let bad = || error(py, "RobotError", "a pickled robot's recipe is malformed");
    let first = recipe.first().ok_or_else(bad)?;
    let (tag, xml, base, dirs): (String, String, Option<PathBuf>, Vec<PathBuf>) =
        first.extract().map_err(|_| bad())?;
    if tag != "urdf" {
        return Err(bad());
    }
    let given: HashMap<String, PickledMesh> = match &meshes {
        Some(m) => m.extract().map_err(|_| bad())?,
        None => HashMap::new(),
    };
    let provided: HashMap<String, tocsin::robot::urdf::RawMesh> = given
        .into_iter()
        .map(|(k, (v, t))| (k, (v.into_iter().map(Vec3::from_array).collect(), t)))
        .collect();
    // The meshes are built in this process's pool (fork-safe, like every mesh build).
    let core = pool::run(py, || {
        tocsin::Robot::from_urdf_str_with_meshes(&xml, base.as_deref(), &dirs, &provided)
    })?
    .map_err(|e| robot_error(py, e))?;
    let robot = Robot {
        inner: RwLock::new(Arc::new(core)),
        recipe: Mutex::new(vec![first.clone().unbind()]),
        carried: meshes.map(Bound::unbind),
    };
    for op in &recipe[1..] {
        let tag: String = op.get_item(0)?.extract()?;
        match tag.as_str() {
            "srdf" => {
                robot.apply_srdf_string(py, &op.get_item(1)?.extract::<String>()?)?;
            }
            "allow" => robot.allow_collision(
                py,
                &op.get_item(1)?.extract::<String>()?,
                &op.get_item(2)?.extract::<String>()?,
            )?,
            "attach" => {
                let mesh = op.get_item(2)?;
                let mesh = mesh.cast::<Mesh>().map_err(|_| bad())?;
                robot.attach(
                    py,
                    &op.get_item(1)?.extract::<String>()?,
                    &mesh.borrow(),
                    &op.get_item(3)?.extract::<String>()?,
                    Some(&op.get_item(4)?),
                    op.get_item(5)?.extract()?,
                )?
            }
            "detach" => robot.detach(py, &op.get_item(1)?.extract::<String>()?)?,
            "base" => robot.set_base(&op.get_item(1)?)?,
            _ => return Err(bad()),
        }
    }
    Ok(robot)
}

/// A configuration array of shape (dof,).
fn config(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let py = obj.py();
    let arr = py
        .import("numpy")?
        .call_method1("asarray", (obj, "float64"))
        .map_err(|e| error(py, "ConfigurationError", format!("{what}: {e}")))?;
    let ndim: usize = arr.getattr("ndim")?.extract()?;
    if ndim != 1 {
        return Err(error(
            py,
            "ConfigurationError",
            format!("{what} must have shape (dof,), got {ndim} dimensions"),
        ));
    }
    arr.call_method0("tolist")?.extract()
}

/// A configuration batch of shape (N, dof).
fn configs(obj: &Bound<'_, PyAny>, dof: usize, what: &str) -> PyResult<Vec<Vec<f64>>> {
    let a = as_array::<f64>(obj, "float64", dof, what, "ConfigurationError")?;
    let s = a
        .as_slice()
        .map_err(|e| error(obj.py(), "ConfigurationError", e.to_string()))?;
    Ok(if dof == 0 {
        // Rows of nothing: the count comes from the shape.
        vec![Vec::new(); a.shape()[0]]
    } else {
        s.chunks_exact(dof).map(<[f64]>::to_vec).collect()
    })
}

fn options(
    py: Python<'_>,
    tolerance: Option<f64>,
    max_iterations: Option<&Bound<'_, PyAny>>,
) -> PyResult<RobotOptions> {
    Ok(RobotOptions {
        tolerance,
        max_iterations: match max_iterations {
            Some(m) => count(py, m, "max_iterations", 1, "OptionsError")?,
            None => RobotOptions::default().max_iterations,
        },
        ..RobotOptions::default()
    })
}

fn scene_of(scene: Option<&Scene>) -> Arc<CoreScene> {
    scene.map_or_else(|| Arc::new(CoreScene::new()), |s| snapshot(&s.inner))
}

#[pymethods]
impl Robot {
    /// Loads a URDF file. Mesh filenames (`package://name/rest`, `file://`, relative, absolute)
    /// are looked for in `package_dirs` (as dir/name/rest, and dir/rest when dir is named
    /// `name`), then in the URDF's folder and its ancestors, then as rest next to the URDF
    /// (pybullet's convention); a missing mesh raises RobotFileError listing every path tried.
    /// `srdf`: a MoveIt SRDF file whose <disable_collisions> pairs are allowed to touch.
    /// Raises RobotFileError (unreadable file, missing mesh), RobotError (bad model:
    /// unsupported joint type, cycles, several roots, bad axes or mimics, a bad mesh).
    #[staticmethod]
    #[pyo3(signature = (path, package_dirs=Vec::new(), srdf=None))]
    fn from_urdf(
        py: Python<'_>,
        path: PathBuf,
        package_dirs: Vec<PathBuf>,
        srdf: Option<PathBuf>,
    ) -> PyResult<Self> {
        let dirs: Vec<PathBuf> = package_dirs.iter().map(|d| absolute(d)).collect();
        let read = |p: &PathBuf| {
            std::fs::read_to_string(p).map_err(|e| {
                robot_error(
                    py,
                    RobotError::Parse {
                        path: p.clone(),
                        message: e.to_string(),
                    },
                )
            })
        };
        let xml = read(&path)?;
        let srdf_xml = srdf.as_ref().map(read).transpose()?;
        let base = path.parent().map(absolute);
        // The meshes are built in this process's pool (fork-safe, like every mesh build).
        let robot = pool::run(py, || -> Result<tocsin::Robot, RobotError> {
            let mut r = tocsin::Robot::from_urdf_file(&path, &dirs)?;
            if let Some(s) = &srdf {
                r.apply_srdf_file(s)?;
            }
            Ok(r)
        })?
        .map_err(|e| robot_error(py, e))?;
        let mut recipe = vec![("urdf", xml, base, dirs)
            .into_pyobject(py)?
            .into_any()
            .unbind()];
        if let Some(text) = srdf_xml {
            recipe.push(("srdf", text).into_pyobject(py)?.into_any().unbind());
        }
        Ok(Self {
            inner: RwLock::new(Arc::new(robot)),
            recipe: Mutex::new(recipe),
            carried: None,
        })
    }

    /// A robot from URDF text; relative mesh paths resolve against `base_dir` (see from_urdf).
    #[staticmethod]
    #[pyo3(signature = (xml, base_dir=None, package_dirs=Vec::new()))]
    fn from_urdf_string(
        py: Python<'_>,
        xml: &str,
        base_dir: Option<PathBuf>,
        package_dirs: Vec<PathBuf>,
    ) -> PyResult<Self> {
        let robot = pool::run(py, || {
            tocsin::Robot::from_urdf_str(xml, base_dir.as_deref(), &package_dirs)
        })?
        .map_err(|e| robot_error(py, e))?;
        let base = base_dir.as_deref().map(absolute);
        let dirs: Vec<PathBuf> = package_dirs.iter().map(|d| absolute(d)).collect();
        let first = ("urdf", xml, base, dirs)
            .into_pyobject(py)?
            .into_any()
            .unbind();
        Ok(Self {
            inner: RwLock::new(Arc::new(robot)),
            recipe: Mutex::new(vec![first]),
            carried: None,
        })
    }

    /// Allows the link pairs an SRDF file disables (<disable_collisions>); returns how many
    /// collision-object pairs that removed from the checks.
    fn apply_srdf(&self, py: Python<'_>, path: PathBuf) -> PyResult<usize> {
        let xml = std::fs::read_to_string(&path).map_err(|e| {
            robot_error(
                py,
                RobotError::Parse {
                    path: path.clone(),
                    message: e.to_string(),
                },
            )
        })?;
        self.apply_srdf_string(py, &xml)
    }

    /// As apply_srdf, from SRDF text.
    fn apply_srdf_string(&self, py: Python<'_>, xml: &str) -> PyResult<usize> {
        let op = ("srdf", xml).into_pyobject(py)?.into_any().unbind();
        self.recorded(py, op, |r| r.apply_srdf_str(xml))
    }

    /// Allows two links (or attached objects) to touch: their pair is not checked.
    fn allow_collision(&self, py: Python<'_>, link1: &str, link2: &str) -> PyResult<()> {
        let op = ("allow", link1, link2)
            .into_pyobject(py)?
            .into_any()
            .unbind();
        self.recorded(py, op, |r| r.allow_collision(link1, link2))
    }

    /// Attaches `mesh` to `link` (a grasped part): `pose` (4x4) places the mesh in the link's
    /// frame. The object may touch its own link's body and `touch_links`; every other robot
    /// link and every obstacle is checked against it.
    #[pyo3(signature = (name, mesh, link, pose=None, touch_links=Vec::new()))]
    fn attach(
        &self,
        py: Python<'_>,
        name: &str,
        mesh: &Mesh,
        link: &str,
        pose: Option<&Bound<'_, PyAny>>,
        touch_links: Vec<String>,
    ) -> PyResult<()> {
        let pose = match pose {
            Some(p) => pose_from(p, "pose")?,
            None => tocsin::Pose::IDENTITY,
        };
        let touch: Vec<&str> = touch_links.iter().map(String::as_str).collect();
        let m = Mesh {
            inner: mesh.inner.clone(),
        };
        let op = (
            "attach",
            name,
            m,
            link,
            pose_to_numpy(py, &pose)?,
            touch_links.clone(),
        )
            .into_pyobject(py)?
            .into_any()
            .unbind();
        self.recorded(py, op, |r| r.attach(name, &mesh.inner, link, &pose, &touch))
    }

    /// Removes an attached object.
    fn detach(&self, py: Python<'_>, name: &str) -> PyResult<()> {
        let op = ("detach", name).into_pyobject(py)?.into_any().unbind();
        self.recorded(py, op, |r| r.detach(name))
    }

    /// Pickling: the recipe (URDF and SRDF texts, absolute mesh folders, edits in order) and
    /// the URDF's collision mesh files as read at pickling time, replayed on unpickling: the
    /// copy needs no file (a cluster's nodes need not share a disk).
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let f = py.import("tocsin._core")?.getattr("_robot_from_recipe")?;
        let ops: Vec<Py<PyAny>> = self
            .recipe
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .iter()
            .map(|o| o.clone_ref(py))
            .collect();
        if let Some(carried) = &self.carried {
            return Ok((f, (ops, carried.clone_ref(py)))
                .into_pyobject(py)?
                .into_any());
        }
        // The URDF's mesh files travel with the pickle, as read now.
        let first = ops.first().map(|o| o.bind(py).clone());
        let meshes = pyo3::types::PyDict::new(py);
        if let Some(first) = first {
            let (_, xml, base, dirs): (String, String, Option<PathBuf>, Vec<PathBuf>) =
                first.extract()?;
            let files = tocsin::Robot::urdf_mesh_files(&xml, base.as_deref(), &dirs)
                .map_err(|e| robot_error(py, e))?;
            for (name, path) in files {
                let (v, t) = tocsin::TriMesh::load_raw(&path).map_err(|e| {
                    robot_error(
                        py,
                        RobotError::Mesh {
                            link: name.clone(),
                            source: e,
                        },
                    )
                })?;
                let n = v.len();
                let verts = numpy::PyArray1::from_vec(
                    py,
                    v.iter().flat_map(|p| p.to_array()).collect::<Vec<f64>>(),
                )
                .reshape([n, 3])?;
                let m = t.len();
                let tris = numpy::PyArray1::from_vec(
                    py,
                    t.iter().flatten().copied().collect::<Vec<u32>>(),
                )
                .reshape([m, 3])?;
                meshes.set_item(name, (verts, tris))?;
            }
        }
        Ok((f, (ops, meshes)).into_pyobject(py)?.into_any())
    }

    /// The robot's name (from the URDF).
    #[getter]
    fn name(&self) -> String {
        snapshot(&self.inner).name().to_string()
    }

    /// Number of configuration entries.
    #[getter]
    fn dof(&self) -> usize {
        snapshot(&self.inner).dof()
    }

    /// Names of the configuration entries, in order.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        snapshot(&self.inner).joint_names().to_vec()
    }

    /// Joint limits, shape (dof, 2): lower and upper (infinite for continuous joints).
    #[getter]
    fn joint_limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let robot = snapshot(&self.inner);
        let flat: Vec<f64> = robot
            .joint_limits()
            .iter()
            .flat_map(|(a, b)| [*a, *b])
            .collect();
        PyArray1::from_vec(py, flat).reshape([robot.dof(), 2])
    }

    /// Every URDF link's name, in the order of link_poses.
    #[getter]
    fn link_names(&self) -> Vec<String> {
        snapshot(&self.inner)
            .link_names()
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    /// Names of the collision objects (links with geometry, attached objects).
    #[getter]
    fn object_names(&self) -> Vec<String> {
        snapshot(&self.inner)
            .objects()
            .iter()
            .map(|o| o.name.clone())
            .collect()
    }

    /// The object name pairs checked for self-collision.
    #[getter]
    fn self_pairs(&self) -> Vec<(String, String)> {
        let robot = snapshot(&self.inner);
        let o = robot.objects();
        robot
            .self_pairs()
            .iter()
            .map(|&(i, j)| (o[i].name.clone(), o[j].name.clone()))
            .collect()
    }

    /// The root link's world pose (4x4); settable.
    #[getter]
    fn get_base<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        pose_to_numpy(py, &snapshot(&self.inner).base())
    }

    #[setter]
    fn set_base(&self, pose: &Bound<'_, PyAny>) -> PyResult<()> {
        let py = pose.py();
        let p = pose_from(pose, "base")?;
        let op = ("base", pose_to_numpy(py, &p)?)
            .into_pyobject(py)?
            .into_any()
            .unbind();
        self.recorded(py, op, |r| {
            r.set_base(p);
            Ok(())
        })
    }

    /// The collision mesh of an object (vertices in its body's frame: the frame of the link
    /// at the head of its merged body).
    fn object_mesh(&self, py: Python<'_>, name: &str) -> PyResult<Mesh> {
        snapshot(&self.inner)
            .objects()
            .iter()
            .find(|o| o.name == name)
            .map(|o| Mesh {
                inner: o.mesh.clone(),
            })
            .ok_or_else(|| error(py, "RobotError", format!("unknown object {name:?}")))
    }

    /// World pose of every URDF link at configuration q, shape (L, 4, 4), in link_names order.
    fn link_poses<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.poses_array(py, q, false)
    }

    /// World pose of every collision object at q, shape (K, 4, 4), in object_names order.
    fn object_poses<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.poses_array(py, q, true)
    }

    /// Whether q lies within the joint limits (inclusive, with `tolerance`).
    #[pyo3(signature = (q, tolerance=0.0))]
    fn within_limits(&self, q: &Bound<'_, PyAny>, tolerance: f64) -> PyResult<bool> {
        Ok(snapshot(&self.inner).within_limits(&config(q, "q")?, tolerance))
    }

    /// First time of contact along the straight joint-space segment q(t) = q0 + t (q1 - q0),
    /// t in [0, 1], of the robot with itself (pairs not allowed to touch) or with the scene's
    /// obstacles: a RobotContact whenever some checked pair comes within tolerance / 2 (always
    /// when one collides), no later than the first collision; None when every pair stays
    /// farther apart than the tolerance. The tolerance defaults to 1e-3 of the smallest
    /// bounding radius among the robot's collision objects. Exact: no sampling. The points are
    /// the two objects' closest, with their exact distance; contact_pair=True reports those of
    /// the triangle pair that ended the pair's advancement (within the tolerance) instead,
    /// without the final exact distance query.
    #[pyo3(signature = (q0, q1, scene=None, tolerance=None, max_iterations=None, cache=None, contact_pair=false))]
    #[allow(clippy::too_many_arguments)]
    fn time_of_contact(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        q1: &Bound<'_, PyAny>,
        scene: Option<&Scene>,
        tolerance: Option<f64>,
        max_iterations: Option<&Bound<'_, PyAny>>,
        cache: Option<&RobotCache>,
        contact_pair: bool,
    ) -> PyResult<Option<RobotContact>> {
        let SegmentCall {
            a,
            b,
            mut opts,
            robot,
            scene,
        } = self.segment_call(py, q0, q1, scene, tolerance, max_iterations)?;
        opts.witnesses = witnesses(contact_pair);
        let r = py
            .detach(|| match cache {
                Some(c) => {
                    let mut guard = c.inner.lock().unwrap_or_else(|p| p.into_inner());
                    rq::time_of_contact_with_cache(&robot, &a, &b, &scene, &opts, &mut guard)
                }
                None => rq::time_of_contact(&robot, &a, &b, &scene, &opts),
            })
            .map_err(|e| robot_error(py, e))?;
        Ok(r.map(RobotContact::from_core))
    }

    /// Whether the segment q0 -> q1 is free (the question OMPL's checkMotion asks): True when
    /// every checked pair stays farther apart than the tolerance, False as soon as one is
    /// known to come within tolerance / 2 (it stops there); the same answer as
    /// `time_of_contact(...) is None`. For the last free time, use last_valid.
    #[pyo3(signature = (q0, q1, scene=None, tolerance=None, max_iterations=None, cache=None))]
    #[allow(clippy::too_many_arguments)]
    fn path_is_free(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        q1: &Bound<'_, PyAny>,
        scene: Option<&Scene>,
        tolerance: Option<f64>,
        max_iterations: Option<&Bound<'_, PyAny>>,
        cache: Option<&RobotCache>,
    ) -> PyResult<bool> {
        let SegmentCall {
            a,
            b,
            opts,
            robot,
            scene,
        } = self.segment_call(py, q0, q1, scene, tolerance, max_iterations)?;
        py.detach(|| match cache {
            Some(c) => {
                let mut guard = c.inner.lock().unwrap_or_else(|p| p.into_inner());
                rq::path_is_free_with_cache(&robot, &a, &b, &scene, &opts, &mut guard)
            }
            None => rq::path_is_free(&robot, &a, &b, &scene, &opts),
        })
        .map_err(|e| robot_error(py, e))
    }

    /// The last time of the segment q0 -> q1 known free (what OMPL's checkMotion(s1, s2,
    /// lastValid) reports): 1.0 when path_is_free, else the time of contact, before which
    /// every checked pair stays farther apart than tolerance / 2. A free segment costs one
    /// path_is_free; a blocked one also a time_of_contact.
    #[pyo3(signature = (q0, q1, scene=None, tolerance=None, max_iterations=None))]
    fn last_valid(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        q1: &Bound<'_, PyAny>,
        scene: Option<&Scene>,
        tolerance: Option<f64>,
        max_iterations: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<f64> {
        let SegmentCall {
            a,
            b,
            opts,
            robot,
            scene,
        } = self.segment_call(py, q0, q1, scene, tolerance, max_iterations)?;
        py.detach(|| -> Result<f64, RobotError> {
            if rq::path_is_free(&robot, &a, &b, &scene, &opts)? {
                return Ok(1.0);
            }
            // Only the time is wanted: the contact pair's witnesses skip the final exact
            // distance query (the time is the same with either).
            let time_only = RobotOptions {
                witnesses: tocsin::Witnesses::Contact,
                ..opts
            };
            Ok(rq::time_of_contact(&robot, &a, &b, &scene, &time_only)?.map_or(1.0, |c| c.time))
        })
        .map_err(|e| robot_error(py, e))
    }

    /// Whether the robot at q collides with itself or the scene (exact; touching counts).
    #[pyo3(signature = (q, scene=None))]
    fn in_collision(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        scene: Option<&Scene>,
    ) -> PyResult<bool> {
        let q = config(q, "q")?;
        let (robot, scene) = (snapshot(&self.inner), scene_of(scene));
        py.detach(|| rq::in_collision(&robot, &q, &scene))
            .map_err(|e| robot_error(py, e))
    }

    /// in_collision for every row of Q (N, dof), on all cores; a bool array of shape (N,).
    #[pyo3(signature = (qs, scene=None))]
    fn check_configurations<'py>(
        &self,
        py: Python<'py>,
        qs: &Bound<'py, PyAny>,
        scene: Option<&Scene>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let qs = configs(qs, snapshot(&self.inner).dof(), "configurations")?;
        let (robot, scene) = (snapshot(&self.inner), scene_of(scene));
        let r = pool::run(py, || rq::check_configurations(&robot, &qs, &scene))?
            .map_err(|e| robot_error(py, e))?;
        Ok(PyArray1::from_vec(py, r))
    }

    /// path_is_free for every segment (Q0[i], Q1[i]) (two (N, dof) arrays), on all cores;
    /// a bool array of shape (N,), identical to the single calls. The first failing segment
    /// (an iteration cap) raises, naming its index.
    #[pyo3(signature = (q0s, q1s, scene=None, tolerance=None, max_iterations=None))]
    fn paths_are_free<'py>(
        &self,
        py: Python<'py>,
        q0s: &Bound<'py, PyAny>,
        q1s: &Bound<'py, PyAny>,
        scene: Option<&Scene>,
        tolerance: Option<f64>,
        max_iterations: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<bool>>> {
        let segments = self.segments(q0s, q1s)?;
        let opts = options(py, tolerance, max_iterations)?;
        let (robot, scene) = (snapshot(&self.inner), scene_of(scene));
        let r = pool::run(py, || {
            rq::path_is_free_batch(&robot, &segments, &scene, &opts)
        })?
        .map_err(|e| robot_error(py, e))?;
        let mut out = Vec::with_capacity(r.len());
        for (i, x) in r.into_iter().enumerate() {
            out.push(x.map_err(|e| {
                let err = robot_error(py, e);
                error(py, "TocsinError", format!("segment {i}: {err}"))
            })?);
        }
        Ok(PyArray1::from_vec(py, out))
    }

    /// time_of_contact for every segment (Q0[i], Q1[i]), on all cores: a list of RobotContact
    /// or None, identical to the single calls. The first failing segment raises, naming it.
    /// `contact_pair` as in time_of_contact.
    #[pyo3(signature = (q0s, q1s, scene=None, tolerance=None, max_iterations=None, contact_pair=false))]
    #[allow(clippy::too_many_arguments)]
    fn time_of_contact_batch(
        &self,
        py: Python<'_>,
        q0s: &Bound<'_, PyAny>,
        q1s: &Bound<'_, PyAny>,
        scene: Option<&Scene>,
        tolerance: Option<f64>,
        max_iterations: Option<&Bound<'_, PyAny>>,
        contact_pair: bool,
    ) -> PyResult<Vec<Option<RobotContact>>> {
        let segments = self.segments(q0s, q1s)?;
        let opts = RobotOptions {
            witnesses: witnesses(contact_pair),
            ..options(py, tolerance, max_iterations)?
        };
        let (robot, scene) = (snapshot(&self.inner), scene_of(scene));
        let r = pool::run(py, || {
            rq::time_of_contact_batch(&robot, &segments, &scene, &opts)
        })?
        .map_err(|e| robot_error(py, e))?;
        let mut out = Vec::with_capacity(r.len());
        for (i, x) in r.into_iter().enumerate() {
            let c = x.map_err(|e| {
                let err = robot_error(py, e);
                error(py, "TocsinError", format!("segment {i}: {err}"))
            })?;
            out.push(c.map(RobotContact::from_core));
        }
        Ok(out)
    }

    fn __repr__(&self) -> String {
        let robot = snapshot(&self.inner);
        format!(
            "Robot(name={:?}, dof={}, objects={}, self_pairs={})",
            robot.name(),
            robot.dof(),
            robot.objects().len(),
            robot.self_pairs().len()
        )
    }
}

/// What every single-segment query parses first: both configurations, the options, and
/// snapshots of the robot and scene (taken before the GIL is released).
struct SegmentCall {
    a: Vec<f64>,
    b: Vec<f64>,
    opts: RobotOptions,
    robot: Arc<tocsin::Robot>,
    scene: Arc<CoreScene>,
}

impl Robot {
    fn segment_call(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        q1: &Bound<'_, PyAny>,
        scene: Option<&Scene>,
        tolerance: Option<f64>,
        max_iterations: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<SegmentCall> {
        Ok(SegmentCall {
            a: config(q0, "q0")?,
            b: config(q1, "q1")?,
            opts: options(py, tolerance, max_iterations)?,
            robot: snapshot(&self.inner),
            scene: scene_of(scene),
        })
    }

    fn poses_array<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        objects: bool,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let q = config(q, "q")?;
        let poses = if objects {
            snapshot(&self.inner).object_poses(&q)
        } else {
            snapshot(&self.inner).link_poses(&q)
        }
        .map_err(|e| robot_error(py, e))?;
        let n = poses.len();
        let flat: Vec<f64> = poses
            .iter()
            .flat_map(|p| p.to_matrix().transpose().to_cols_array())
            .collect();
        PyArray1::from_vec(py, flat).reshape([n, 4, 4])
    }

    fn segments(
        &self,
        q0s: &Bound<'_, PyAny>,
        q1s: &Bound<'_, PyAny>,
    ) -> PyResult<Vec<(Vec<f64>, Vec<f64>)>> {
        let dof = snapshot(&self.inner).dof();
        let (a, b) = (configs(q0s, dof, "q0s")?, configs(q1s, dof, "q1s")?);
        if a.len() != b.len() {
            return Err(error(
                q0s.py(),
                "ConfigurationError",
                format!("q0s has {} rows, q1s {}", a.len(), b.len()),
            ));
        }
        Ok(a.into_iter().zip(b).collect())
    }
}

/// The closest triangle pair of every robot pair seen by earlier segment checks, for warm
/// starts: pass the same cache to the checks of the many edges a planner tries from one node
/// (cache=...). The answers do not depend on it. Use one cache per robot and scene.
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct RobotCache {
    inner: std::sync::Mutex<rq::RobotCache>,
}

#[pymethods]
impl RobotCache {
    #[new]
    fn new() -> Self {
        Self {
            inner: std::sync::Mutex::new(rq::RobotCache::default()),
        }
    }
}

/// Static obstacles for the robot queries: named meshes at world poses. Scene() is empty;
/// add obstacles with add(name, mesh, pose).
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct Scene {
    /// As `Robot::inner`.
    inner: RwLock<Arc<CoreScene>>,
}

#[pymethods]
impl Scene {
    #[new]
    fn new() -> Self {
        Self {
            inner: RwLock::new(Arc::new(CoreScene::new())),
        }
    }

    /// Adds an obstacle: `mesh` placed by `pose` (4x4, body to world; identity by default).
    #[pyo3(signature = (name, mesh, pose=None))]
    fn add(&self, name: &str, mesh: &Mesh, pose: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let pose = match pose {
            Some(p) => pose_from(p, "pose")?,
            None => tocsin::Pose::IDENTITY,
        };
        edit(&self.inner, |r| r.add(name, mesh.inner.clone(), pose));
        Ok(())
    }

    /// The obstacles' names, in the order added.
    #[getter]
    fn names(&self) -> Vec<String> {
        snapshot(&self.inner)
            .obstacles()
            .iter()
            .map(|o| o.name.clone())
            .collect()
    }

    fn __len__(&self) -> usize {
        snapshot(&self.inner).obstacles().len()
    }

    /// Pickling: the obstacles' names, meshes and poses.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let f = py.import("tocsin._core")?.getattr("_scene_from_parts")?;
        let items = snapshot(&self.inner)
            .obstacles()
            .iter()
            .map(|o| {
                let mesh = Py::new(
                    py,
                    Mesh {
                        inner: o.mesh.clone(),
                    },
                )?;
                Ok((o.name.clone(), mesh, pose_to_numpy(py, &o.pose)?))
            })
            .collect::<PyResult<Vec<_>>>()?;
        Ok((f, (items,)).into_pyobject(py)?.into_any())
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({} obstacles)",
            snapshot(&self.inner).obstacles().len()
        )
    }
}

/// Unpickles a Scene (`Scene.__reduce__`).
#[pyfunction]
pub(crate) fn _scene_from_parts(
    items: Vec<(String, Bound<'_, Mesh>, Bound<'_, PyAny>)>,
) -> PyResult<Scene> {
    let scene = Scene::new();
    for (name, mesh, pose) in &items {
        scene.add(name, &mesh.borrow(), Some(pose))?;
    }
    Ok(scene)
}

/// When and where the robot first comes within the tolerance of itself or an obstacle along a
/// joint-space segment. `object1` is a robot link (or attached object); `object2` another one
/// (self_collision True) or an obstacle. Points and normal are world-frame; the normal points
/// from object1 to object2.
#[pyclass(frozen, module = "tocsin._core")]
pub(crate) struct RobotContact {
    /// Time in [0, 1] along the segment, no later than the first collision.
    #[pyo3(get)]
    time: f64,
    /// The robot object of the pair.
    #[pyo3(get)]
    object1: String,
    /// The other object: a robot link or an obstacle.
    #[pyo3(get)]
    object2: String,
    /// Whether object2 is part of the robot.
    #[pyo3(get)]
    self_collision: bool,
    /// Distance between point1 and point2 (model units, >= 0, at most the tolerance): the
    /// objects' distance at `time` (with contact_pair=True, at least it).
    #[pyo3(get)]
    distance: f64,
    /// Advancement iterations of the pair that made the contact.
    #[pyo3(get)]
    iterations: usize,
    /// 'converged' or 'started_in_contact'.
    #[pyo3(get)]
    status: &'static str,
    p1: Vec3,
    p2: Vec3,
    n: Vec3,
}

#[pymethods]
impl RobotContact {
    /// Point of object1 at `time` (the closest, or the contact pair's), world frame, shape (3,).
    #[getter]
    fn point1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p1)
    }

    /// Point of object2 at `time` (the closest, or the contact pair's), world frame, shape (3,).
    #[getter]
    fn point2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.p2)
    }

    /// Unit normal from object1 to object2, world frame, shape (3,).
    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vec3(py, self.n)
    }

    fn __repr__(&self) -> String {
        format!(
            "RobotContact(time={}, object1={:?}, object2={:?}, distance={}, status='{}')",
            self.time, self.object1, self.object2, self.distance, self.status
        )
    }
}

impl RobotContact {
    fn from_core(c: rq::RobotContact) -> Self {
        Self {
            time: c.time,
            object1: c.object1,
            object2: c.object2,
            self_collision: c.self_collision,
            distance: c.distance,
            iterations: c.iterations,
            status: status_name(c.status),
            p1: c.point1,
            p2: c.point2,
            n: c.normal,
        }
    }
}

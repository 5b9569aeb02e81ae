//! Batch queries for one mesh pair (the Python wrappers in `tocsin/_batch.py` name the fields).

use crate::contact::{contact_options, witnesses};
use crate::convert::{array2, poses_from};
use crate::errors::{error, motion_error, options_error};
use crate::mesh::Mesh;
use crate::pool;
use numpy::PyArray1;
use pyo3::prelude::*;
use tocsin::{ContactError, ContactStatus, Pose, Vec3};

type Arrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<i64>>,
    Bound<'py, PyArray1<i64>>,
);
use numpy::PyArray2;

/// Distances for K pose pairs: (distance, point1, point2, triangle1, triangle2) arrays.
#[pyfunction]
#[pyo3(signature = (mesh1, poses1, mesh2, poses2, relative_error=0.0, absolute_error=0.0))]
pub(crate) fn _distance_batch<'py>(
    py: Python<'py>,
    mesh1: &Mesh,
    poses1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    poses2: &Bound<'_, PyAny>,
    relative_error: f64,
    absolute_error: f64,
) -> PyResult<Arrays<'py>> {
    let opts = tocsin::DistanceOptions {
        relative_error,
        absolute_error,
    };
    let p1 = poses_from(poses1, "poses1", None)?;
    let p2 = poses_from(poses2, "poses2", Some(p1.len()))?;
    let pairs: Vec<(Pose, Pose)> = p1.into_iter().zip(p2).collect();
    let (m1, m2) = (mesh1.inner.clone(), mesh2.inner.clone());
    let r = pool::run(py, || tocsin::distance_batch(&m1, &m2, &pairs, &opts))?
        .map_err(|e| options_error(py, e))?;
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
pub(crate) fn _collide_batch<'py>(
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
    let hits = pool::run(py, || tocsin::collide_batch(&m1, &m2, &pairs))?;
    Ok(PyArray1::from_vec(py, hits))
}

fn motions_from(
    kind: &str,
    starts: &[Pose],
    ends: &[Pose],
    py: Python<'_>,
    name: &str,
) -> PyResult<Vec<tocsin::Motion>> {
    let make = match kind {
        "translation" => tocsin::Motion::translation,
        "interp" => |a, b| tocsin::Motion::interp(a, b, Vec3::ZERO),
        "screw" => tocsin::Motion::screw,
        other => {
            return Err(error(
                py,
                "MotionError",
                format!("unknown motion kind '{other}' (translation, interp, screw)"),
            ))
        }
    };
    starts
        .iter()
        .zip(ends)
        .enumerate()
        .map(|(i, (a, b))| {
            make(*a, *b).map_err(|e| {
                let inner = motion_error(py, e);
                error(py, "MotionError", format!("{name}[{i}]: {inner}"))
            })
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
    Bound<'py, PyArray1<f64>>,
);

/// The K motion pairs of a batch: body 1 from `starts1[k]` to `ends1[k]`, body 2 from
/// `starts2[k]` to `ends2[k]` (a single pose is used for every row), both of `kind`.
fn motion_pairs(
    py: Python<'_>,
    (starts1, ends1): (&Bound<'_, PyAny>, &Bound<'_, PyAny>),
    (starts2, ends2): (&Bound<'_, PyAny>, &Bound<'_, PyAny>),
    kind: &str,
) -> PyResult<Vec<(tocsin::Motion, tocsin::Motion)>> {
    let s1 = poses_from(starts1, "starts1", None)?;
    let k = Some(s1.len());
    let (e1, s2, e2) = (
        poses_from(ends1, "ends1", k)?,
        poses_from(starts2, "starts2", k)?,
        poses_from(ends2, "ends2", k)?,
    );
    let m1 = motions_from(kind, &s1, &e1, py, "motions1")?;
    let m2 = motions_from(kind, &s2, &e2, py, "motions2")?;
    Ok(m1.into_iter().zip(m2).collect())
}

/// The options and the (motion1, motion2) pairs of a motion batch read from Python, and `batch`
/// (a Rust motion batch) run on them with the GIL released: the motion batches' common part.
#[allow(clippy::type_complexity)]
fn run_motions<T: Send>(
    py: Python<'_>,
    (mesh1, mesh2): (&Mesh, &Mesh),
    body1: (&Bound<'_, PyAny>, &Bound<'_, PyAny>),
    body2: (&Bound<'_, PyAny>, &Bound<'_, PyAny>),
    (kind, tolerance, max_iterations, contact_pair): (
        &str,
        Option<f64>,
        Option<&Bound<'_, PyAny>>,
        bool,
    ),
    batch: fn(
        &tocsin::TriMesh,
        &tocsin::TriMesh,
        &[(tocsin::Motion, tocsin::Motion)],
        &tocsin::ContactOptions,
    ) -> Result<Vec<Result<T, ContactError>>, tocsin::OptionsError>,
) -> PyResult<Vec<Result<T, ContactError>>> {
    let opts = tocsin::ContactOptions {
        witnesses: witnesses(contact_pair),
        ..contact_options(py, tolerance, max_iterations)?
    };
    let pairs = motion_pairs(py, body1, body2, kind)?;
    let (a, b) = (mesh1.inner.clone(), mesh2.inner.clone());
    pool::run(py, || batch(&a, &b, &pairs, &opts))?.map_err(|e| options_error(py, e))
}

type FreeArrays<'py> = (Bound<'py, PyArray1<bool>>, Bound<'py, PyArray1<bool>>);

/// Whether K motions are free of contact: (free, decided) boolean arrays; a row that reached
/// the iteration cap first is undecided and not free.
#[pyfunction]
#[pyo3(signature = (mesh1, starts1, ends1, mesh2, starts2, ends2, kind, tolerance=None, max_iterations=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _motion_is_free_batch<'py>(
    py: Python<'py>,
    mesh1: &Mesh,
    starts1: &Bound<'_, PyAny>,
    ends1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    starts2: &Bound<'_, PyAny>,
    ends2: &Bound<'_, PyAny>,
    kind: &str,
    tolerance: Option<f64>,
    max_iterations: Option<&Bound<'_, PyAny>>,
) -> PyResult<FreeArrays<'py>> {
    let r = run_motions(
        py,
        (mesh1, mesh2),
        (starts1, ends1),
        (starts2, ends2),
        (kind, tolerance, max_iterations, false),
        tocsin::motion_is_free_batch,
    )?;
    let free = r.iter().map(|x| matches!(x, Ok(true))).collect();
    let decided = r.iter().map(Result::is_ok).collect();
    Ok((
        PyArray1::from_vec(py, free),
        PyArray1::from_vec(py, decided),
    ))
}

/// Times of contact for K motions: arrays, NaN / -1 where there is no contact; status codes
/// 0 none, 1 converged, 2 started in contact, 3 iteration limit (no contact, undecided), and
/// the time up to which each motion is known free of contact.
#[pyfunction]
#[pyo3(signature = (mesh1, starts1, ends1, mesh2, starts2, ends2, kind, tolerance=None, max_iterations=None, contact_pair=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _time_of_contact_batch<'py>(
    py: Python<'py>,
    mesh1: &Mesh,
    starts1: &Bound<'_, PyAny>,
    ends1: &Bound<'_, PyAny>,
    mesh2: &Mesh,
    starts2: &Bound<'_, PyAny>,
    ends2: &Bound<'_, PyAny>,
    kind: &str,
    tolerance: Option<f64>,
    max_iterations: Option<&Bound<'_, PyAny>>,
    contact_pair: bool,
) -> PyResult<ContactArrays<'py>> {
    let r = run_motions(
        py,
        (mesh1, mesh2),
        (starts1, ends1),
        (starts2, ends2),
        (kind, tolerance, max_iterations, contact_pair),
        tocsin::time_of_contact_batch,
    )?;
    let contact = |x: &Result<Option<tocsin::ContactTime>, ContactError>| match x {
        Ok(Some(c)) => Some(*c),
        _ => None,
    };
    let nan3 = [f64::NAN; 3];
    let f = |g: &dyn Fn(&tocsin::ContactTime) -> f64| -> Vec<f64> {
        r.iter()
            .map(|c| contact(c).map_or(f64::NAN, |c| g(&c)))
            .collect()
    };
    let v = |g: &dyn Fn(&tocsin::ContactTime) -> Vec3| -> Vec<[f64; 3]> {
        r.iter()
            .map(|c| contact(c).map_or(nan3, |c| g(&c).to_array()))
            .collect()
    };
    let i = |g: &dyn Fn(&tocsin::ContactTime) -> i64| -> Vec<i64> {
        r.iter().map(|c| contact(c).map_or(-1, |c| g(&c))).collect()
    };
    let status: Vec<i64> = r
        .iter()
        .map(|c| match c {
            Ok(None) => 0,
            Ok(Some(c)) if c.status == ContactStatus::StartedInContact => 2,
            Ok(Some(_)) => 1,
            Err(_) => 3,
        })
        .collect();
    let iterations: Vec<i64> = r
        .iter()
        .map(|c| match c {
            Ok(Some(c)) => c.iterations as i64,
            Err(ContactError::IterationLimit { iterations, .. }) => *iterations as i64,
            _ => 0,
        })
        .collect();
    let free_until: Vec<f64> = r
        .iter()
        .map(|c| match c {
            Ok(None) => 1.0,
            Ok(Some(c)) => c.time,
            Err(ContactError::IterationLimit { time_reached, .. }) => *time_reached,
            Err(_) => 0.0,
        })
        .collect();
    Ok((
        PyArray1::from_vec(py, f(&|c| c.time)),
        array2(py, v(&|c| c.point1))?,
        array2(py, v(&|c| c.point2))?,
        array2(py, v(&|c| c.normal))?,
        PyArray1::from_vec(py, f(&|c| c.distance)),
        PyArray1::from_vec(py, i(&|c| c.triangle1 as i64)),
        PyArray1::from_vec(py, i(&|c| c.triangle2 as i64)),
        PyArray1::from_vec(py, iterations),
        PyArray1::from_vec(py, status),
        PyArray1::from_vec(py, free_until),
    ))
}

//! Conversions between numpy arrays (or anything array-like) and the core's types. Inputs are
//! copied, never modified; shapes and dtypes are checked with messages that name the argument.

use crate::errors::error;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use tocsin::{math::ROTATION_TOLERANCE, Mat4, Pose, Vec3};

/// `np.ascontiguousarray(obj, dtype)`, with conversion failures raised as `class`.
fn contiguous<'py>(
    obj: &Bound<'py, PyAny>,
    dtype: &str,
    what: &str,
    class: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let py = obj.py();
    py.import("numpy")?
        .call_method1("ascontiguousarray", (obj, dtype))
        .map_err(|e| {
            error(
                py,
                class,
                format!("{what}: cannot convert to a {dtype} array ({e})"),
            )
        })
}

fn shape_of(arr: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
    arr.getattr("shape")?.extract()
}

/// A contiguous (N, cols) array of `T`.
pub(crate) fn as_array<'py, T: numpy::Element>(
    obj: &Bound<'py, PyAny>,
    dtype: &str,
    cols: usize,
    what: &str,
    class: &str,
) -> PyResult<PyReadonlyArray2<'py, T>> {
    let py = obj.py();
    let arr = contiguous(obj, dtype, what, class)?;
    let shape = shape_of(&arr)?;
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

/// A 3-vector (a list, tuple or array of three real numbers), raised as `class` otherwise.
pub(crate) fn vec3_from(obj: &Bound<'_, PyAny>, what: &str, class: &str) -> PyResult<Vec3> {
    let py = obj.py();
    let arr = contiguous(obj, "float64", what, class)?;
    let shape = shape_of(&arr)?;
    if shape != [3] {
        return Err(error(
            py,
            class,
            format!("{what} must have 3 elements (shape (3,)), got shape {shape:?}"),
        ));
    }
    let v: Vec<f64> = arr.call_method0("tolist")?.extract()?;
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// A 4x4 matrix (row-major in Python), shape checked, rigidity not.
pub(crate) fn matrix4_from(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Mat4> {
    let py = obj.py();
    // Fast path: already a float64 array (the common case); anything else goes through numpy.
    let arr = match obj.cast::<PyArray2<f64>>() {
        Ok(a) if a.shape() == [4, 4] => a.readonly(),
        _ => {
            let arr = contiguous(obj, "float64", name, "PoseError")?;
            let shape = shape_of(&arr)?;
            if shape != [4, 4] {
                return Err(error(
                    py,
                    "PoseError",
                    format!("{name} must have shape (4, 4), got {shape:?}"),
                ));
            }
            arr.cast_into::<PyArray2<f64>>()
                .map_err(|_| error(py, "PoseError", format!("{name}: not a float64 array")))?
                .readonly()
        }
    };
    let a = arr.as_array();
    let mut rows = [0.0; 16];
    for (k, v) in rows.iter_mut().enumerate() {
        *v = a[[k / 4, k % 4]];
    }
    Ok(Mat4::from_cols_slice(&rows).transpose()) // rows were read row-major
}

/// A 4x4 rigid transform, checked (within 1e-6).
pub(crate) fn pose_from(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Pose> {
    let m = matrix4_from(obj, name)?;
    Pose::from_matrix(&m, ROTATION_TOLERANCE)
        .map_err(|e| error(obj.py(), "PoseError", format!("{name}: {e}")))
}

/// (K, 4, 4) poses (a single (4, 4) pose is repeated `k` times when `k` is given), each checked.
pub(crate) fn poses_from(
    obj: &Bound<'_, PyAny>,
    name: &str,
    k: Option<usize>,
) -> PyResult<Vec<Pose>> {
    let py = obj.py();
    let arr = contiguous(obj, "float64", name, "PoseError")?;
    let shape = shape_of(&arr)?;
    let (count, single) = match (shape.as_slice(), k) {
        ([n, 4, 4], _) => (*n, false),
        ([4, 4], Some(k)) => (k, true),
        _ => {
            let expected = if k.is_some() {
                "(K, 4, 4) or (4, 4)"
            } else {
                "(K, 4, 4)"
            };
            return Err(error(
                py,
                "PoseError",
                format!("{name} must have shape {expected}, got {shape:?}"),
            ));
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
    Ok(if single {
        poses.first().map_or_else(Vec::new, |p| vec![*p; count])
    } else {
        poses
    })
}

pub(crate) fn vec3<'py>(py: Python<'py>, v: Vec3) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, &v.to_array())
}

pub(crate) fn array2<'py>(
    py: Python<'py>,
    rows: Vec<[f64; 3]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let n = rows.len();
    PyArray1::from_vec(py, rows.into_iter().flatten().collect()).reshape([n, 3])
}

pub(crate) fn pose_to_numpy<'py>(py: Python<'py>, p: &Pose) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let m = p.to_matrix().transpose().to_cols_array(); // row-major
    PyArray1::from_slice(py, &m).reshape([4, 4])
}

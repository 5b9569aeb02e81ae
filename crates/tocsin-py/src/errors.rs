//! Errors mapped to the package's own exception classes (`tocsin/_errors.py`), all under
//! `tocsin.TocsinError`. Nothing else crosses into Python: no panic, no bare ValueError.

use pyo3::prelude::*;
use pyo3::types::PyType;

/// The class `tocsin._errors.<class>`.
fn class<'py>(py: Python<'py>, class: &str) -> PyResult<Bound<'py, PyType>> {
    py.import("tocsin._errors")?
        .getattr(class)?
        .cast_into::<PyType>()
        .map_err(PyErr::from)
}

/// Raises `tocsin.<class>` with `message`.
pub(crate) fn error(py: Python<'_>, class_name: &str, message: impl Into<String>) -> PyErr {
    match class(py, class_name) {
        Ok(cls) => PyErr::from_type(cls, message.into()),
        Err(e) => e,
    }
}

pub(crate) fn mesh_error(py: Python<'_>, e: tocsin::MeshError) -> PyErr {
    match e {
        tocsin::MeshError::Io { .. } => error(py, "MeshFileError", e.to_string()),
        tocsin::MeshError::OutOfMemory { .. } => error(py, "OutOfMemoryError", e.to_string()),
        _ => error(py, "MeshError", e.to_string()),
    }
}

pub(crate) fn motion_error(py: Python<'_>, e: tocsin::MotionError) -> PyErr {
    error(py, "MotionError", e.to_string())
}

pub(crate) fn options_error(py: Python<'_>, e: tocsin::OptionsError) -> PyErr {
    error(py, "OptionsError", e.to_string())
}

/// `IterationLimitError` carries `iterations` and `time_reached` as attributes.
pub(crate) fn contact_error(py: Python<'_>, e: tocsin::ContactError) -> PyErr {
    match e {
        tocsin::ContactError::IterationLimit {
            iterations,
            time_reached,
        } => {
            let made = class(py, "IterationLimitError").and_then(|cls| {
                let value = cls.call1((e.to_string(),))?;
                value.setattr("iterations", iterations)?;
                value.setattr("time_reached", time_reached)?;
                Ok(PyErr::from_value(value))
            });
            made.unwrap_or_else(|err| err)
        }
        tocsin::ContactError::Options(o) => options_error(py, o),
        other => error(py, "TocsinError", other.to_string()),
    }
}

/// An integer option that must be at least `min`, taken as any Python int (a negative or huge
/// value is an `OptionsError`, not an `OverflowError`).
pub(crate) fn count(
    py: Python<'_>,
    value: &Bound<'_, PyAny>,
    name: &str,
    min: usize,
    class_name: &str,
) -> PyResult<usize> {
    let as_int: Option<i128> = value.extract().ok();
    if let Some(v) = as_int.filter(|&v| v >= min as i128 && v <= usize::MAX as i128) {
        return Ok(v as usize);
    }
    let message = match as_int {
        Some(v) if v < min as i128 => {
            format!("{name} must be an integer of at least {min}, got {v}")
        }
        // Above the machine's range, or an int too large even for i128.
        _ if as_int.is_some() || value.is_instance_of::<pyo3::types::PyInt>() => format!(
            "{name} must be an integer of at most {}, got {value}",
            usize::MAX
        ),
        _ => format!(
            "{name} must be an integer, got {}",
            value
                .get_type()
                .name()
                .map_or("?".into(), |n| n.to_string())
        ),
    };
    Err(error(py, class_name, message))
}

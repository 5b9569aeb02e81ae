//! PyO3 binding of tocsin: type conversions, GIL release around queries, and errors mapped to
//! the package's own exception classes (defined in `tocsin/_errors.py`). No geometry here.
//!
//! One file per concern: `convert` (arrays and poses), `errors`, `pool` (the fork-safe thread
//! pool), `mesh`, `queries` (static queries), `motion`, `contact` (time of contact), `batch`, `robot` (robots, scenes, segment checks), `penetration` (winding number, depth,
//! Hausdorff), `world` (many bodies).

mod batch;
mod contact;
mod convert;
mod errors;
mod mesh;
mod motion;
mod penetration;
mod pool;
mod queries;
mod robot;
mod world;

use pyo3::prelude::*;

/// The compiled core of the `tocsin` package.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<mesh::Mesh>()?;
    m.add_class::<queries::DistanceResult>()?;
    m.add_function(wrap_pyfunction!(queries::distance, m)?)?;
    m.add_function(wrap_pyfunction!(queries::collide, m)?)?;
    m.add_function(wrap_pyfunction!(queries::collide_pairs, m)?)?;
    m.add_function(wrap_pyfunction!(queries::within_distance, m)?)?;
    m.add_class::<motion::Motion>()?;
    m.add_function(wrap_pyfunction!(motion::orthonormalize, m)?)?;
    m.add_function(wrap_pyfunction!(motion::_motion_from_parts, m)?)?;
    m.add_function(wrap_pyfunction!(robot::_robot_from_recipe, m)?)?;
    m.add_function(wrap_pyfunction!(robot::_scene_from_parts, m)?)?;
    m.add_class::<contact::ContactResult>()?;
    m.add_function(wrap_pyfunction!(contact::time_of_contact, m)?)?;
    m.add_function(wrap_pyfunction!(contact::motion_is_free, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_distance_batch, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_collide_batch, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_time_of_contact_batch, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_motion_is_free_batch, m)?)?;
    m.add_function(wrap_pyfunction!(penetration::winding_number, m)?)?;
    m.add_function(wrap_pyfunction!(penetration::contains, m)?)?;
    m.add_function(wrap_pyfunction!(penetration::hausdorff_distance, m)?)?;
    m.add_class::<penetration::HausdorffResult>()?;
    m.add_function(wrap_pyfunction!(penetration::penetration_depth, m)?)?;
    m.add_class::<penetration::PenetrationResult>()?;
    m.add_function(wrap_pyfunction!(penetration::pointwise_penetration, m)?)?;
    m.add_class::<penetration::PointwiseResult>()?;
    m.add_class::<robot::Robot>()?;
    m.add_class::<robot::Scene>()?;
    m.add_class::<robot::RobotContact>()?;
    m.add_class::<robot::RobotCache>()?;
    m.add_class::<world::World>()?;
    m.add_class::<world::WorldContact>()?;
    m.add_function(wrap_pyfunction!(world::_world_from_parts, m)?)?;
    Ok(())
}

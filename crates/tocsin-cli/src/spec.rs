//! What the command line and scene files share: built-in or file meshes, poses and motions
//! from numbers, and results as JSON. Errors are one-line strings for the user.

use serde_json::{json, Value};
use tocsin::{
    mesh, ContactStatus, ContactTime, DepthOptions, DepthStatus, DistanceResult, HausdorffResult,
    Mat3, Mat4, Motion, PenetrationDepth, PointwisePenetration, Pose, TriMesh, Vec3,
};

/// A mesh from a path (.obj, .stl, .ply; a relative path is taken from `base`, the scene
/// file's folder, or the working directory when `None`) or `builtin:NAME`.
pub fn load_mesh(spec: &str, base: Option<&std::path::Path>) -> Result<TriMesh, String> {
    let built = match spec.strip_prefix("builtin:") {
        None => {
            let path = std::path::Path::new(spec);
            let path = match base {
                Some(dir) if path.is_relative() => dir.join(path),
                _ => path.to_path_buf(),
            };
            return TriMesh::load(&path).map_err(|e| e.to_string());
        }
        Some("knot2.8k") => mesh::torus_knot(175, 8),
        Some("knot11k") => mesh::torus_knot(344, 16),
        Some("knot34k") => mesh::torus_knot(680, 25),
        Some("sphere") => mesh::sphere(1.0, 32, 64),
        Some("box") => mesh::box_mesh(Vec3::splat(0.5)),
        Some("plate") => mesh::plate(2.0, 8),
        Some(other) => {
            return Err(format!(
                "unknown built-in model `{other}` (knot2.8k, knot11k, knot34k, sphere, box, plate)"
            ))
        }
    };
    built.map_err(|e| e.to_string())
}

/// A pose from 3 numbers (translation), 6 (translation, rotation vector in radians) or 16
/// (a 4x4 matrix, row-major), checked to be rigid.
pub fn pose_from_values(values: &[f64], what: &str) -> Result<Pose, String> {
    if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
        return Err(format!("{what}: {bad} is not a finite number"));
    }
    let pose = match values.len() {
        3 => Pose::new(Mat3::IDENTITY, Vec3::from_slice(values)),
        6 => {
            let rv = Vec3::from_slice(&values[3..]);
            let rotation = rv.try_normalize().map_or(Mat3::IDENTITY, |axis| {
                Mat3::from_axis_angle(axis, rv.length())
            });
            Pose::new(rotation, Vec3::from_slice(&values[..3]))
        }
        16 => Pose::from_matrix(
            &Mat4::from_cols_slice(values).transpose(),
            tocsin::math::ROTATION_TOLERANCE,
        ),
        n => return Err(format!("{what}: expected 3, 6 or 16 numbers, got {n}")),
    };
    pose.map_err(|e| format!("{what}: {e}"))
}

/// Comma-separated finite numbers (NaN and infinities are refused: a NaN rotation vector was
/// once read as no rotation).
pub fn numbers(text: &str, what: &str) -> Result<Vec<f64>, String> {
    text.split(',')
        .map(|s| match s.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(format!("{what}: `{s}` is not a finite number")),
            Err(_) => Err(format!("{what}: `{s}` is not a number")),
        })
        .collect()
}

/// A motion of the given kind (`translation`, `interp`, `screw`); only `interp` takes a centre.
pub fn motion_from(
    kind: &str,
    start: Pose,
    end: Pose,
    center: Option<Vec3>,
    what: &str,
) -> Result<Motion, String> {
    let motion = match (kind, center) {
        ("translation", None) => Motion::translation(start, end),
        ("screw", None) => Motion::screw(start, end),
        ("interp", c) => Motion::interp(start, end, c.unwrap_or(Vec3::ZERO)),
        (kind, _) => {
            return Err(format!(
                "{what}: unknown motion `{kind}` (translation, interp, screw; only interp takes a centre)"
            ))
        }
    };
    motion.map_err(|e| format!("{what}: {e}"))
}

/// A motion from `KIND:START:END[:CENTER]`, each pose as comma-separated numbers.
pub fn parse_motion(text: &str, what: &str) -> Result<Motion, String> {
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() < 3 || parts.len() > 4 {
        return Err(format!(
            "{what}: expected KIND:START:END[:CENTER], got `{text}`"
        ));
    }
    let start = pose_from_values(&numbers(parts[1], what)?, what)?;
    let end = pose_from_values(&numbers(parts[2], what)?, what)?;
    let center = match parts.get(3) {
        None => None,
        Some(c) => match numbers(c, what)?.as_slice() {
            [x, y, z] => Some(Vec3::new(*x, *y, *z)),
            _ => return Err(format!("{what}: the centre needs 3 numbers")),
        },
    };
    motion_from(parts[0], start, end, center, what)
}

fn vec(v: Vec3) -> Value {
    json!([v.x, v.y, v.z])
}

/// A distance result as JSON (world frame).
pub fn distance_json(r: &DistanceResult) -> Value {
    json!({
        "distance": r.distance, "point1": vec(r.point1), "point2": vec(r.point2),
        "triangle1": r.triangle1, "triangle2": r.triangle2,
    })
}

/// A time-of-contact result as JSON (`contact: false` when there is none).
pub fn contact_json(r: &Option<ContactTime>) -> Value {
    match r {
        None => json!({ "contact": false }),
        Some(c) => json!({
            "contact": true, "time": c.time, "point1": vec(c.point1), "point2": vec(c.point2),
            "normal": vec(c.normal), "distance": c.distance, "triangle1": c.triangle1,
            "triangle2": c.triangle2, "iterations": c.iterations,
            "status": match c.status {
                ContactStatus::Converged => "converged",
                ContactStatus::StartedInContact => "started_in_contact",
                _ => "other",
            },
        }),
    }
}

/// The penetration depth's options from the command line or a scene: the library's defaults
/// where a value is not given.
pub fn depth_options(tolerance: Option<f64>, starts: Option<usize>) -> DepthOptions {
    let defaults = DepthOptions::default();
    DepthOptions {
        tolerance,
        starts: starts.unwrap_or(defaults.starts),
        ..defaults
    }
}

/// A translational penetration depth as JSON (world frame; the translation is body 2's).
pub fn depth_json(r: &PenetrationDepth) -> Value {
    json!({
        "depth": r.depth, "translation": vec(r.translation), "direction": vec(r.direction),
        "point1": vec(r.point1), "point2": vec(r.point2), "iterations": r.iterations,
        "status": match r.status {
            DepthStatus::Separated => "separated",
            DepthStatus::Converged => "converged",
            _ => "iteration_limit",
        },
    })
}

/// A Hausdorff distance as JSON (world frame).
pub fn hausdorff_json(r: &HausdorffResult) -> Value {
    json!({
        "distance": r.distance, "upper_bound": r.upper_bound, "point1": vec(r.point1),
        "point2": vec(r.point2), "from_first": r.from_first,
    })
}

/// A pointwise penetration depth as JSON (world frame).
pub fn pointwise_json(r: &PointwisePenetration) -> Value {
    json!({
        "depth": r.depth, "upper_bound": r.upper_bound, "point1": vec(r.point1),
        "point2": vec(r.point2), "from_first": r.from_first,
    })
}

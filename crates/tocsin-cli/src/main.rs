//! The `tocsin` command: distance and collision between two meshes, printed as JSON.
//!
//! Meshes are file paths (OBJ, STL, PLY) or built-in models (`builtin:knot2.8k`,
//! `builtin:knot11k`, `builtin:knot34k`, `builtin:sphere`, `builtin:box`, `builtin:plate`).
//! Poses are 3 numbers (a translation), 6 (translation then rotation vector in radians) or 16
//! (a 4x4 matrix, row-major), comma-separated. Motions are `KIND:START:END` with KIND one of
//! `translation`, `interp`, `screw` and START, END poses (`interp` takes an optional fourth
//! field, the centre `x,y,z` in the body frame). Errors print one line and exit with status 2.

use clap::{Parser, Subcommand};
use serde_json::json;
use std::process::ExitCode;
use tocsin::{
    collide, collide_pairs, distance, mesh, time_of_contact, within_distance, ContactOptions,
    ContactStatus, DistanceOptions, Mat4, Motion, Pose, TriMesh, Vec3,
};

#[derive(Parser)]
#[command(
    name = "tocsin",
    version,
    about = "Exact distance, collision and continuous collision between polygon soups"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct PairArgs {
    /// First mesh: a path (.obj, .stl, .ply) or builtin:NAME.
    mesh1: String,
    /// Second mesh: a path or builtin:NAME.
    mesh2: String,
    /// Pose of mesh 1: "x,y,z", "x,y,z,rx,ry,rz" (rotation vector, radians) or 16 numbers
    /// (row-major 4x4).
    #[arg(long, allow_hyphen_values = true)]
    pose1: Option<String>,
    /// Pose of mesh 2, same forms as --pose1.
    #[arg(long, allow_hyphen_values = true)]
    pose2: Option<String>,
}

#[derive(Subcommand)]
enum Command {
    /// Minimum distance with witness points (world frame) and triangle indices.
    Distance {
        #[command(flatten)]
        pair: PairArgs,
        /// Allowed relative error of the distance (0 = exact).
        #[arg(long, default_value_t = 0.0)]
        relative_error: f64,
        /// Allowed absolute error of the distance, model units (0 = exact).
        #[arg(long, default_value_t = 0.0)]
        absolute_error: f64,
    },
    /// Whether the meshes intersect; with --pairs, every intersecting triangle pair.
    Collide {
        #[command(flatten)]
        pair: PairArgs,
        /// List all intersecting triangle pairs.
        #[arg(long)]
        pairs: bool,
    },
    /// First time of contact of two moving meshes over t in [0, 1].
    ContactTime {
        /// First mesh: a path or builtin:NAME.
        mesh1: String,
        /// Second mesh: a path or builtin:NAME.
        mesh2: String,
        /// Motion of mesh 1, KIND:START:END[:CENTER] (default: stays at the identity).
        #[arg(long, allow_hyphen_values = true)]
        motion1: Option<String>,
        /// Motion of mesh 2, same form (default: stays at the identity).
        #[arg(long, allow_hyphen_values = true)]
        motion2: Option<String>,
        /// Distance tolerance (model units; default 1e-3 of the smaller bounding radius).
        #[arg(long)]
        tolerance: Option<f64>,
        /// Iteration cap.
        #[arg(long, default_value_t = 1000)]
        max_iterations: usize,
    },
    /// Whether the distance is at most THRESHOLD (model units).
    Within {
        #[command(flatten)]
        pair: PairArgs,
        /// The distance threshold, model units.
        threshold: f64,
    },
}

fn load_mesh(spec: &str) -> Result<TriMesh, String> {
    let built = match spec.strip_prefix("builtin:") {
        None => return TriMesh::load(spec).map_err(|e| e.to_string()),
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

fn parse_pose(text: Option<&str>, which: &str) -> Result<Pose, String> {
    let Some(text) = text else {
        return Ok(Pose::IDENTITY);
    };
    let values: Vec<f64> = text
        .split(',')
        .map(|s| {
            s.trim()
                .parse::<f64>()
                .map_err(|_| format!("--{which}: `{s}` is not a number"))
        })
        .collect::<Result<_, _>>()?;
    let pose = match values.len() {
        3 => Pose::new(tocsin::Mat3::IDENTITY, Vec3::from_slice(&values)),
        6 => {
            let rv = Vec3::from_slice(&values[3..]);
            let rotation = if rv.length() > 0.0 {
                tocsin::Mat3::from_axis_angle(rv.normalize(), rv.length())
            } else {
                tocsin::Mat3::IDENTITY
            };
            Pose::new(rotation, Vec3::from_slice(&values[..3]))
        }
        16 => Pose::from_matrix(
            &Mat4::from_cols_slice(&values).transpose(),
            tocsin::math::ROTATION_TOLERANCE,
        ),
        n => return Err(format!("--{which}: expected 3, 6 or 16 numbers, got {n}")),
    };
    pose.map_err(|e| format!("--{which}: {e}"))
}

fn parse_motion(text: Option<&str>, which: &str) -> Result<Motion, String> {
    let Some(text) = text else {
        return Ok(Motion::stationary(Pose::IDENTITY));
    };
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() < 3 || parts.len() > 4 {
        return Err(format!(
            "--{which}: expected KIND:START:END[:CENTER], got `{text}`"
        ));
    }
    let (start, end) = (
        parse_pose(Some(parts[1]), which)?,
        parse_pose(Some(parts[2]), which)?,
    );
    let motion = match (parts[0], parts.get(3)) {
        ("translation", None) => Motion::translation(start, end),
        ("screw", None) => Motion::screw(start, end),
        ("interp", centre) => {
            let c = match centre {
                None => Vec3::ZERO,
                Some(c) => {
                    let v: Vec<f64> = c.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| format!("--{which}: bad centre `{c}`"))?;
                    if v.len() != 3 {
                        return Err(format!("--{which}: the centre needs 3 numbers"));
                    }
                    Vec3::from_slice(&v)
                }
            };
            Motion::interp(start, end, c)
        }
        (kind, _) => return Err(format!("--{which}: unknown motion `{kind}` (translation, interp, screw; only interp takes a centre)")),
    };
    motion.map_err(|e| format!("--{which}: {e}"))
}

fn vec(v: Vec3) -> serde_json::Value {
    json!([v.x, v.y, v.z])
}

fn run(cli: Cli) -> Result<serde_json::Value, String> {
    let setup = |p: &PairArgs| -> Result<_, String> {
        Ok((
            load_mesh(&p.mesh1)?,
            parse_pose(p.pose1.as_deref(), "pose1")?,
            load_mesh(&p.mesh2)?,
            parse_pose(p.pose2.as_deref(), "pose2")?,
        ))
    };
    match cli.command {
        Command::Distance {
            pair,
            relative_error,
            absolute_error,
        } => {
            let (m1, p1, m2, p2) = setup(&pair)?;
            let opts = DistanceOptions {
                relative_error,
                absolute_error,
            };
            let start = std::time::Instant::now();
            let r = distance(&m1, &p1, &m2, &p2, &opts).map_err(|e| e.to_string())?;
            Ok(json!({
                "distance": r.distance, "point1": vec(r.point1), "point2": vec(r.point2),
                "triangle1": r.triangle1, "triangle2": r.triangle2,
                "seconds": start.elapsed().as_secs_f64(),
            }))
        }
        Command::Collide { pair, pairs } => {
            let (m1, p1, m2, p2) = setup(&pair)?;
            if pairs {
                let list = collide_pairs(&m1, &p1, &m2, &p2);
                Ok(json!({ "collide": !list.is_empty(), "pairs": list }))
            } else {
                Ok(json!({ "collide": collide(&m1, &p1, &m2, &p2) }))
            }
        }
        Command::ContactTime {
            mesh1,
            mesh2,
            motion1,
            motion2,
            tolerance,
            max_iterations,
        } => {
            let (m1, m2) = (load_mesh(&mesh1)?, load_mesh(&mesh2)?);
            let (mo1, mo2) = (
                parse_motion(motion1.as_deref(), "motion1")?,
                parse_motion(motion2.as_deref(), "motion2")?,
            );
            let opts = ContactOptions {
                tolerance,
                max_iterations,
            };
            let start = std::time::Instant::now();
            let r = time_of_contact(&m1, &mo1, &m2, &mo2, &opts).map_err(|e| e.to_string())?;
            let seconds = start.elapsed().as_secs_f64();
            Ok(match r {
                None => json!({ "contact": false, "seconds": seconds }),
                Some(c) => json!({
                    "contact": true, "time": c.time, "point1": vec(c.point1), "point2": vec(c.point2),
                    "normal": vec(c.normal), "distance": c.distance, "triangle1": c.triangle1,
                    "triangle2": c.triangle2, "iterations": c.iterations,
                    "status": match c.status { ContactStatus::Converged => "converged", ContactStatus::StartedInContact => "started_in_contact", _ => "iteration_limit" },
                    "seconds": seconds,
                }),
            })
        }
        Command::Within { pair, threshold } => {
            let (m1, p1, m2, p2) = setup(&pair)?;
            let w = within_distance(&m1, &p1, &m2, &p2, threshold).map_err(|e| e.to_string())?;
            Ok(json!({ "within": w, "threshold": threshold }))
        }
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(v) => {
            println!("{v}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("tocsin: {e}");
            ExitCode::from(2)
        }
    }
}

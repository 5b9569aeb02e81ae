//! `tocsin robot-path robot.urdf --q0 .. --q1 .. [--scene obstacles.toml]`: the exact check of
//! a straight joint-space segment (time of contact, or with `--free-only` the yes/no answer).
//!
//! Obstacle files (`.toml` or `.json`) list named meshes with poses; relative mesh paths are
//! taken from the file's folder:
//!
//! ```toml
//! [[obstacles]]
//! name = "table"
//! mesh = "builtin:box"
//! pose = [0.5, 0, 0.3]          # 3, 6 or 16 numbers, as on the command line
//! ```

use crate::spec::{load_mesh, numbers, pose_from_values};
use serde::Deserialize;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use tocsin::robot::{query, RobotOptions, Scene};
use tocsin::Robot;

/// The arguments of `robot-path`.
#[derive(clap::Args)]
pub struct RobotPathArgs {
    /// The robot's URDF file.
    urdf: PathBuf,
    /// Start configuration: comma-separated joint values in the URDF's order of actuated joints.
    #[arg(long, allow_hyphen_values = true)]
    q0: String,
    /// End configuration, same form.
    #[arg(long, allow_hyphen_values = true)]
    q1: String,
    /// Obstacles: a .toml or .json file (see the module docs).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// A MoveIt SRDF whose <disable_collisions> pairs are allowed to touch.
    #[arg(long)]
    srdf: Option<PathBuf>,
    /// Folders where package:// mesh paths are looked for (repeatable).
    #[arg(long = "package-dir")]
    package_dirs: Vec<PathBuf>,
    /// Distance tolerance (model units; default 1e-3 of the smallest link's bounding radius).
    #[arg(long)]
    tolerance: Option<f64>,
    /// Only whether the segment is free (stops at the first contact found; no witnesses).
    #[arg(long)]
    free_only: bool,
    /// Report the points of the triangle pair that ended the advancement (within the
    /// tolerance) instead of the two objects' closest points, which take one exact distance
    /// query more.
    #[arg(long)]
    contact_pair: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObstacleFile {
    obstacles: Vec<ObstacleSpec>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObstacleSpec {
    name: String,
    mesh: String,
    #[serde(default)]
    pose: Option<Vec<f64>>,
}

fn load_scene(path: &Path) -> Result<Scene, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let file: ObstacleFile = if path.extension().is_some_and(|e| e == "json") {
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?
    } else {
        toml::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?
    };
    let base = path.parent();
    let mut scene = Scene::new();
    for o in file.obstacles {
        if scene.obstacles().iter().any(|x| x.name == o.name) {
            return Err(format!("obstacle `{}` is defined twice", o.name));
        }
        let mesh = load_mesh(&o.mesh, base).map_err(|e| format!("obstacle `{}`: {e}", o.name))?;
        let pose = match &o.pose {
            Some(v) => pose_from_values(v, &format!("obstacle `{}` pose", o.name))?,
            None => tocsin::Pose::IDENTITY,
        };
        scene.add(&o.name, Arc::new(mesh), pose);
    }
    Ok(scene)
}

/// Runs `robot-path` and returns its JSON result.
pub fn run(args: &RobotPathArgs) -> Result<Value, String> {
    let mut robot =
        Robot::from_urdf_file(&args.urdf, &args.package_dirs).map_err(|e| e.to_string())?;
    if let Some(srdf) = &args.srdf {
        robot.apply_srdf_file(srdf).map_err(|e| e.to_string())?;
    }
    let scene = match &args.scene {
        Some(p) => load_scene(p)?,
        None => Scene::new(),
    };
    let (q0, q1) = (numbers(&args.q0, "--q0")?, numbers(&args.q1, "--q1")?);
    let opts = RobotOptions {
        tolerance: args.tolerance,
        witnesses: if args.contact_pair {
            tocsin::Witnesses::Contact
        } else {
            tocsin::Witnesses::Closest
        },
        ..RobotOptions::default()
    };
    let start = std::time::Instant::now();
    if args.free_only {
        let free =
            query::path_is_free(&robot, &q0, &q1, &scene, &opts).map_err(|e| e.to_string())?;
        return Ok(json!({ "free": free, "seconds": start.elapsed().as_secs_f64() }));
    }
    let r = query::time_of_contact(&robot, &q0, &q1, &scene, &opts).map_err(|e| e.to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    Ok(match r {
        None => json!({ "free": true, "contact": null, "seconds": seconds }),
        Some(c) => json!({
            "free": false,
            "contact": {
                "time": c.time,
                "object1": c.object1,
                "object2": c.object2,
                "self_collision": c.self_collision,
                "point1": c.point1.to_array(),
                "point2": c.point2.to_array(),
                "normal": c.normal.to_array(),
                "distance": c.distance,
                "status": match c.status {
                    tocsin::ContactStatus::StartedInContact => "started_in_contact",
                    _ => "converged",
                },
            },
            "seconds": seconds,
        }),
    })
}

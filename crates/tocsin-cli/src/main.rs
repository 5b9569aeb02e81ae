//! The `tocsin` command: distance and collision between two meshes, printed as JSON.
//!
//! Meshes are file paths (OBJ, STL, PLY) or built-in models (`builtin:knot2.8k`,
//! `builtin:knot11k`, `builtin:knot34k`, `builtin:sphere`, `builtin:box`, `builtin:plate`).
//! Poses are 3 numbers (a translation), 6 (translation then rotation vector in radians) or 16
//! (a 4x4 matrix, row-major), comma-separated. Motions are `KIND:START:END` with KIND one of
//! `translation`, `interp`, `screw` and START, END poses (`interp` takes an optional fourth
//! field, the centre `x,y,z` in the body frame). `tocsin run scene.json` (or `.toml`) runs a
//! scene file (see `scene.rs`); `tocsin robot-path robot.urdf --q0 .. --q1 ..` checks a robot's
//! joint-space segment (see `robot.rs`); `penetration`, `pointwise` and `hausdorff` give the
//! translational and pointwise penetration depths and the Hausdorff distance of two placed
//! meshes. Errors print one line and exit with
//! status 2.

mod rain;
mod render;
mod robot;
mod scene;
mod spec;

use clap::{Parser, Subcommand};
use serde_json::json;
use std::process::ExitCode;
use tocsin::{
    collide, collide_pairs, distance, motion_is_free, time_of_contact, within_distance,
    ContactOptions, ContactTime, DistanceOptions, Motion, Pose, TriMesh, Witnesses,
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

#[derive(clap::Args)]
struct MotionArgs {
    /// First mesh: a path (.obj, .stl, .ply) or builtin:NAME.
    mesh1: String,
    /// Second mesh: a path or builtin:NAME.
    mesh2: String,
    /// Motion of mesh 1, KIND:START:END or KIND:START:END:CENTER (default: stays at the
    /// identity).
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
    /// Report the points of the triangle pair that ended the advancement (within the
    /// tolerance; their distance is at least the meshes') instead of the meshes' closest points,
    /// which take one exact distance query more.
    #[arg(long)]
    contact_pair: bool,
}

impl MotionArgs {
    /// Loads the meshes and parses the motions and the options.
    fn load(&self) -> Result<(TriMesh, Motion, TriMesh, Motion, ContactOptions), String> {
        let (m1, m2) = (
            spec::load_mesh(&self.mesh1, None)?,
            spec::load_mesh(&self.mesh2, None)?,
        );
        let mo1 = motion_arg(self.motion1.as_deref(), "motion1")?;
        let mo2 = motion_arg(self.motion2.as_deref(), "motion2")?;
        let opts = ContactOptions {
            tolerance: self.tolerance,
            max_iterations: self.max_iterations,
            witnesses: if self.contact_pair {
                Witnesses::Contact
            } else {
                Witnesses::Closest
            },
        };
        Ok((m1, mo1, m2, mo2, opts))
    }

    /// Loads the meshes, parses the motions and runs the time-of-contact query.
    fn run(&self) -> Result<(TriMesh, Motion, TriMesh, Motion, Option<ContactTime>), String> {
        let (m1, mo1, m2, mo2, opts) = self.load()?;
        let r = time_of_contact(&m1, &mo1, &m2, &mo2, &opts).map_err(|e| e.to_string())?;
        Ok((m1, mo1, m2, mo2, r))
    }
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
    /// First time of contact of two moving meshes over t in [0, 1]; with --free-only, whether
    /// the motions are free of contact.
    ContactTime {
        #[command(flatten)]
        motions: MotionArgs,
        /// Only whether the motions are free of contact (`motion_is_free`: stops as soon as the
        /// answer is known, no witnesses).
        #[arg(long)]
        free_only: bool,
    },
    /// Like contact-time, and writes a PNG of the two meshes at the time of contact (at t = 1
    /// when there is none) with the witness points and the normal marked.
    RenderContact {
        #[command(flatten)]
        motions: MotionArgs,
        /// Where to write the PNG.
        #[arg(long, default_value = "contact.png")]
        out: String,
        /// Image width and height in pixels.
        #[arg(long, num_args = 2, default_values_t = [800, 600])]
        size: Vec<usize>,
    },
    /// Runs the queries of a scene file (.json or .toml) and prints their results as JSON.
    Run {
        /// The scene file.
        scene: String,
    },
    /// Exact check of a robot's straight joint-space segment q0 -> q1 against itself and the
    /// obstacles of --scene: the first time of contact, or with --free-only whether it is free.
    RobotPath {
        #[command(flatten)]
        args: robot::RobotPathArgs,
    },
    /// A simulation that never tunnels: rods and cubes thrown through a rack of 1 mm plates
    /// into a bin, stepped from earliest contact to earliest contact; checks every step that no
    /// meshes intersect and no body crossed a plate (JSON out; --frames for pictures).
    Rain {
        #[command(flatten)]
        args: rain::RainArgs,
    },
    /// Translational penetration depth of mesh 2 into mesh 1 (after PolyDepth): the translation
    /// of mesh 2 (world frame) that leaves them touching without intersecting.
    Penetration {
        #[command(flatten)]
        pair: PairArgs,
        /// Distance tolerance of the touching configuration (default 1e-3 of the smaller
        /// bounding radius).
        #[arg(long)]
        tolerance: Option<f64>,
        /// Seeds refined at deep penetrations (at least 1; default 2, 3 is sometimes a few
        /// percent shallower and slower).
        #[arg(long)]
        starts: Option<usize>,
    },
    /// Hausdorff distance from mesh 1's surface to mesh 2's (with --symmetric, both ways),
    /// exact within --max-error.
    Hausdorff {
        #[command(flatten)]
        pair: PairArgs,
        /// Error bound, model units (default 1e-4 of the smaller bounding radius).
        #[arg(long)]
        max_error: Option<f64>,
        /// The larger of both directions.
        #[arg(long)]
        symmetric: bool,
    },
    /// Pointwise penetration depth: the deepest point of either surface inside the other body
    /// (generalized winding number) and its distance to the other surface, exact within
    /// --max-error.
    Pointwise {
        #[command(flatten)]
        pair: PairArgs,
        /// Error bound, model units (default 1e-4 of the smaller bounding radius).
        #[arg(long)]
        max_error: Option<f64>,
    },
    /// Whether the distance is at most THRESHOLD (model units).
    Within {
        #[command(flatten)]
        pair: PairArgs,
        /// The distance threshold, model units.
        threshold: f64,
    },
}

fn pose_arg(text: Option<&str>, which: &str) -> Result<Pose, String> {
    let what = format!("--{which}");
    text.map_or(Ok(Pose::IDENTITY), |t| {
        spec::pose_from_values(&spec::numbers(t, &what)?, &what)
    })
}

fn motion_arg(text: Option<&str>, which: &str) -> Result<Motion, String> {
    text.map_or(Ok(Motion::stationary(Pose::IDENTITY)), |t| {
        spec::parse_motion(t, &format!("--{which}"))
    })
}

fn run(cli: Cli) -> Result<serde_json::Value, String> {
    let setup = |p: &PairArgs| -> Result<_, String> {
        Ok((
            spec::load_mesh(&p.mesh1, None)?,
            pose_arg(p.pose1.as_deref(), "pose1")?,
            spec::load_mesh(&p.mesh2, None)?,
            pose_arg(p.pose2.as_deref(), "pose2")?,
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
            let mut out = spec::distance_json(&r);
            out["seconds"] = json!(start.elapsed().as_secs_f64());
            Ok(out)
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
            motions,
            free_only: true,
        } => {
            let (m1, mo1, m2, mo2, opts) = motions.load()?;
            let start = std::time::Instant::now();
            let free = motion_is_free(&m1, &mo1, &m2, &mo2, &opts).map_err(|e| e.to_string())?;
            Ok(timed(json!({ "free": free }), start))
        }
        Command::ContactTime { motions, .. } => {
            let (m1, mo1, m2, mo2, opts) = motions.load()?;
            let start = std::time::Instant::now();
            let r = time_of_contact(&m1, &mo1, &m2, &mo2, &opts).map_err(|e| e.to_string())?;
            Ok(timed(spec::contact_json(&r), start))
        }
        Command::RenderContact { motions, out, size } => {
            let (m1, mo1, m2, mo2, r) = motions.run()?;
            let t = r.map_or(1.0, |c| c.time);
            let (p1, p2) = (mo1.pose_at(t), mo2.pose_at(t));
            let marks = match &r {
                Some(c) => render::Marks {
                    point1: c.point1,
                    point2: c.point2,
                    normal: c.normal,
                },
                None => {
                    let d = distance(&m1, &p1, &m2, &p2, &DistanceOptions::default())
                        .map_err(|e| e.to_string())?;
                    let normal = (d.point2 - d.point1)
                        .try_normalize()
                        .unwrap_or(tocsin::Vec3::Z);
                    render::Marks {
                        point1: d.point1,
                        point2: d.point2,
                        normal,
                    }
                }
            };
            let (w, h) = (size[0].clamp(16, 8192), size[1].clamp(16, 8192));
            render::render(&out, (&m1, &p1), (&m2, &p2), &marks, (w, h))?;
            let mut json_out = spec::contact_json(&r);
            json_out["image"] = json!(out);
            json_out["rendered_at"] = json!(t);
            Ok(json_out)
        }
        Command::Run { scene } => scene::run(&scene),
        Command::RobotPath { args } => robot::run(&args),
        Command::Rain { args } => rain::run(&args),
        Command::Penetration {
            pair,
            tolerance,
            starts,
        } => {
            let (m1, p1, m2, p2) = setup(&pair)?;
            let opts = spec::depth_options(tolerance, starts);
            let start = std::time::Instant::now();
            let r =
                tocsin::penetration_depth(&m1, &p1, &m2, &p2, &opts).map_err(|e| e.to_string())?;
            Ok(timed(spec::depth_json(&r), start))
        }
        Command::Hausdorff {
            pair,
            max_error,
            symmetric,
        } => {
            let (m1, p1, m2, p2) = setup(&pair)?;
            let e = max_error
                .unwrap_or_else(|| tocsin::query::penetration::default_max_error(&m1, &m2));
            let start = std::time::Instant::now();
            let r = tocsin::hausdorff_distance(&m1, &p1, &m2, &p2, e, symmetric)
                .map_err(|e| e.to_string())?;
            Ok(timed(spec::hausdorff_json(&r), start))
        }
        Command::Pointwise { pair, max_error } => {
            let (m1, p1, m2, p2) = setup(&pair)?;
            let e = max_error
                .unwrap_or_else(|| tocsin::query::penetration::default_max_error(&m1, &m2));
            let start = std::time::Instant::now();
            let r =
                tocsin::pointwise_penetration(&m1, &p1, &m2, &p2, e).map_err(|e| e.to_string())?;
            Ok(timed(spec::pointwise_json(&r), start))
        }
        Command::Within { pair, threshold } => {
            let (m1, p1, m2, p2) = setup(&pair)?;
            let w = within_distance(&m1, &p1, &m2, &p2, threshold).map_err(|e| e.to_string())?;
            Ok(json!({ "within": w, "threshold": threshold }))
        }
    }
}

/// `v` with the seconds since `start` added (the query's own time, after loading).
fn timed(mut v: serde_json::Value, start: std::time::Instant) -> serde_json::Value {
    v["seconds"] = json!(start.elapsed().as_secs_f64());
    v
}

/// Writes the result line. A reader that closed the pipe early (`tocsin ... | head -c 10`)
/// ends the program quietly and successfully, as with other Unix filters; any other write
/// failure (a full disk) is an error. `println!` panicked on both (exit 101).
fn emit(v: &serde_json::Value) -> Result<(), String> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{v}").and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(format!("cannot write the result: {e}"))
        }
        _ => Ok(()),
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()).and_then(|v| emit(&v)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // stderr may be closed too; nothing more can be said then.
            use std::io::Write;
            let _ = writeln!(std::io::stderr(), "tocsin: {e}");
            ExitCode::from(2)
        }
    }
}

//! Scene files (`tocsin run scene.json` or `scene.toml`): named meshes (a path or a built-in),
//! then queries on them, each with poses or motions; the results come out as JSON, in order.
//!
//! ```json
//! { "meshes": { "a": "builtin:knot34k", "b": "parts/b.stl" },
//!   "queries": [
//!     { "query": "distance", "mesh1": "a", "mesh2": "b", "pose2": [7, 0.2, 0.1] },
//!     { "query": "collide", "mesh1": "a", "mesh2": "b", "pose2": [0.5, 0, 0, 0, 0, 0.3] },
//!     { "query": "within", "mesh1": "a", "mesh2": "b", "pose2": [9, 0, 0], "threshold": 0.5 },
//!     { "query": "contact_time", "mesh1": "a", "mesh2": "b",
//!       "motion1": { "kind": "screw", "start": [-14, 1, 0.5], "end": [14, 0, 0, 0, 0, 1.2] },
//!       "tolerance": 0.001 },
//!     { "query": "motion_is_free", "mesh1": "a", "mesh2": "b",
//!       "motion1": { "kind": "translation", "start": [-14, 1, 0.5], "end": [14, 1, 0.5] } },
//!     { "query": "penetration", "mesh1": "a", "mesh2": "a", "pose2": [0.3, 0, 0] },
//!     { "query": "pointwise", "mesh1": "a", "mesh2": "a", "pose2": [0.3, 0, 0], "max_error": 1e-3 },
//!     { "query": "hausdorff", "mesh1": "a", "mesh2": "b", "symmetric": true } ] }
//! ```
//! Poses are 3, 6 or 16 numbers as on the command line; a missing pose is the identity and a
//! missing motion keeps the body at the identity. `contact_time` takes `"contact_pair": true`
//! to report the points of the triangle pair that ended the advancement (within the
//! tolerance) instead of the meshes' closest points, which take one exact distance query more;
//! `penetration` takes `"tolerance"` and `"starts"` (the seeds refined at deep penetrations,
//! default 2). Relative mesh paths are taken from the scene file's folder. A key given twice
//! (a mesh name, a query field) is an error, not "the last one wins".

use crate::spec::{
    contact_json, depth_json, depth_options, distance_json, hausdorff_json, load_mesh, motion_from,
    pointwise_json, pose_from_values,
};
use serde::Deserialize;
use serde_json::{json, Value};
use std::collections::BTreeMap;
use std::io::IsTerminal;
use tocsin::query::penetration::default_max_error;
use tocsin::{
    collide, distance, hausdorff_distance, motion_is_free, penetration_depth,
    pointwise_penetration, time_of_contact, within_distance, ContactOptions, DistanceOptions,
    Motion, Pose, TriMesh, Vec3, Witnesses,
};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Scene {
    meshes: UniqueMap,
    queries: Vec<Query>,
}

/// Mesh names to specs; a name given twice is an error (serde's maps keep the last silently).
struct UniqueMap(BTreeMap<String, String>);

impl<'de> Deserialize<'de> for UniqueMap {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = UniqueMap;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a map of mesh names to paths or builtin:NAME")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<UniqueMap, A::Error> {
                let mut out = BTreeMap::new();
                while let Some((k, v)) = map.next_entry::<String, String>()? {
                    if out.contains_key(&k) {
                        return Err(serde::de::Error::custom(format!(
                            "mesh `{k}` is defined twice"
                        )));
                    }
                    out.insert(k, v);
                }
                Ok(UniqueMap(out))
            }
        }
        d.deserialize_map(Visitor)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MotionSpec {
    kind: String,
    start: Vec<f64>,
    end: Vec<f64>,
    center: Option<[f64; 3]>,
}

/// The fields of a query on two moving meshes (`contact_time`, `motion_is_free`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Motions {
    mesh1: String,
    mesh2: String,
    motion1: Option<MotionSpec>,
    motion2: Option<MotionSpec>,
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
    /// `contact_time` reports the contact pair's points rather than the closest points at the
    /// time (which take one exact distance query more).
    #[serde(default)]
    contact_pair: bool,
}

#[derive(Deserialize)]
#[serde(tag = "query", rename_all = "snake_case", deny_unknown_fields)]
enum Query {
    Distance {
        mesh1: String,
        mesh2: String,
        pose1: Option<Vec<f64>>,
        pose2: Option<Vec<f64>>,
        #[serde(default)]
        relative_error: f64,
        #[serde(default)]
        absolute_error: f64,
    },
    Collide {
        mesh1: String,
        mesh2: String,
        pose1: Option<Vec<f64>>,
        pose2: Option<Vec<f64>>,
    },
    Within {
        mesh1: String,
        mesh2: String,
        pose1: Option<Vec<f64>>,
        pose2: Option<Vec<f64>>,
        threshold: f64,
    },
    ContactTime(Motions),
    MotionIsFree(Motions),
    Penetration {
        mesh1: String,
        mesh2: String,
        pose1: Option<Vec<f64>>,
        pose2: Option<Vec<f64>>,
        tolerance: Option<f64>,
        starts: Option<usize>,
    },
    Pointwise {
        mesh1: String,
        mesh2: String,
        pose1: Option<Vec<f64>>,
        pose2: Option<Vec<f64>>,
        max_error: Option<f64>,
    },
    Hausdorff {
        mesh1: String,
        mesh2: String,
        pose1: Option<Vec<f64>>,
        pose2: Option<Vec<f64>>,
        max_error: Option<f64>,
        #[serde(default)]
        symmetric: bool,
    },
}

fn pose(values: &Option<Vec<f64>>, what: &str) -> Result<Pose, String> {
    values
        .as_deref()
        .map_or(Ok(Pose::IDENTITY), |v| pose_from_values(v, what))
}

fn motion(spec: &Option<MotionSpec>, what: &str) -> Result<Motion, String> {
    let Some(m) = spec else {
        return Ok(Motion::stationary(Pose::IDENTITY));
    };
    let (start, end) = (
        pose_from_values(&m.start, what)?,
        pose_from_values(&m.end, what)?,
    );
    let center = m.center.map(Vec3::from_array);
    if center.is_some_and(|c| !c.is_finite()) {
        return Err(format!("{what}: the centre is not finite"));
    }
    motion_from(&m.kind, start, end, center, what)
}

/// Reads and runs a scene file; returns `{"results": [...]}` in the order of the queries.
pub fn run(path: &str) -> Result<Value, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {path}: {e}"))?;
    let scene: Scene = if path.ends_with(".toml") {
        toml::from_str(&text).map_err(|e| {
            format!(
                "{path}: {}",
                e.to_string().lines().collect::<Vec<_>>().join(" ")
            )
        })?
    } else {
        serde_json::from_str(&text).map_err(|e| format!("{path}: {e}"))?
    };
    let base = std::path::Path::new(path).parent();
    let meshes: BTreeMap<&str, TriMesh> = scene
        .meshes
        .0
        .iter()
        .map(|(name, spec)| {
            Ok((
                name.as_str(),
                load_mesh(spec, base).map_err(|e| format!("mesh `{name}`: {e}"))?,
            ))
        })
        .collect::<Result<_, String>>()?;
    let get = |name: &str, i: usize| {
        meshes
            .get(name)
            .ok_or_else(|| format!("query {i}: no mesh named `{name}`"))
    };
    let progress = (std::io::stderr().is_terminal() && scene.queries.len() > 1)
        .then(|| indicatif::ProgressBar::new(scene.queries.len() as u64));
    let mut results = Vec::with_capacity(scene.queries.len());
    for (i, q) in scene.queries.iter().enumerate() {
        let at = |what: &str| format!("query {i} {what}");
        // The two named meshes and their poses, checked in that order.
        let placed =
            |mesh1: &str, pose1: &Option<Vec<f64>>, mesh2: &str, pose2: &Option<Vec<f64>>| {
                Ok::<_, String>((
                    get(mesh1, i)?,
                    pose(pose1, &at("pose1"))?,
                    get(mesh2, i)?,
                    pose(pose2, &at("pose2"))?,
                ))
            };
        let result = match q {
            Query::Distance {
                mesh1,
                mesh2,
                pose1,
                pose2,
                relative_error,
                absolute_error,
            } => {
                let opts = DistanceOptions {
                    relative_error: *relative_error,
                    absolute_error: *absolute_error,
                };
                let (m1, p1, m2, p2) = placed(mesh1, pose1, mesh2, pose2)?;
                let r = distance(m1, &p1, m2, &p2, &opts).map_err(|e| format!("query {i}: {e}"))?;
                distance_json(&r)
            }
            Query::Collide {
                mesh1,
                mesh2,
                pose1,
                pose2,
            } => {
                let (m1, p1, m2, p2) = placed(mesh1, pose1, mesh2, pose2)?;
                json!({ "collide": collide(m1, &p1, m2, &p2) })
            }
            Query::Within {
                mesh1,
                mesh2,
                pose1,
                pose2,
                threshold,
            } => {
                let (m1, p1, m2, p2) = placed(mesh1, pose1, mesh2, pose2)?;
                let w = within_distance(m1, &p1, m2, &p2, *threshold)
                    .map_err(|e| format!("query {i}: {e}"))?;
                json!({ "within": w })
            }
            Query::ContactTime(m) | Query::MotionIsFree(m) => {
                let opts = ContactOptions {
                    tolerance: m.tolerance,
                    max_iterations: m
                        .max_iterations
                        .unwrap_or(ContactOptions::default().max_iterations),
                    witnesses: if m.contact_pair {
                        Witnesses::Contact
                    } else {
                        Witnesses::Closest
                    },
                };
                let (m1, mo1, m2, mo2) = (
                    get(&m.mesh1, i)?,
                    motion(&m.motion1, &at("motion1"))?,
                    get(&m.mesh2, i)?,
                    motion(&m.motion2, &at("motion2"))?,
                );
                if matches!(q, Query::MotionIsFree(_)) {
                    let free = motion_is_free(m1, &mo1, m2, &mo2, &opts)
                        .map_err(|e| format!("query {i}: {e}"))?;
                    json!({ "free": free })
                } else {
                    let r = time_of_contact(m1, &mo1, m2, &mo2, &opts)
                        .map_err(|e| format!("query {i}: {e}"))?;
                    contact_json(&r)
                }
            }
            Query::Penetration {
                mesh1,
                mesh2,
                pose1,
                pose2,
                tolerance,
                starts,
            } => {
                let opts = depth_options(*tolerance, *starts);
                let (m1, p1, m2, p2) = placed(mesh1, pose1, mesh2, pose2)?;
                let r = penetration_depth(m1, &p1, m2, &p2, &opts)
                    .map_err(|e| format!("query {i}: {e}"))?;
                depth_json(&r)
            }
            Query::Pointwise {
                mesh1,
                mesh2,
                pose1,
                pose2,
                max_error,
            } => {
                let (m1, p1, m2, p2) = placed(mesh1, pose1, mesh2, pose2)?;
                let e = max_error.unwrap_or_else(|| default_max_error(m1, m2));
                let r = pointwise_penetration(m1, &p1, m2, &p2, e)
                    .map_err(|e| format!("query {i}: {e}"))?;
                pointwise_json(&r)
            }
            Query::Hausdorff {
                mesh1,
                mesh2,
                pose1,
                pose2,
                max_error,
                symmetric,
            } => {
                let (m1, p1, m2, p2) = placed(mesh1, pose1, mesh2, pose2)?;
                let e = max_error.unwrap_or_else(|| default_max_error(m1, m2));
                let r = hausdorff_distance(m1, &p1, m2, &p2, e, *symmetric)
                    .map_err(|e| format!("query {i}: {e}"))?;
                hausdorff_json(&r)
            }
        };
        results.push(result);
        if let Some(p) = &progress {
            p.inc(1);
        }
    }
    if let Some(p) = progress {
        p.finish_and_clear();
    }
    Ok(json!({ "results": results }))
}

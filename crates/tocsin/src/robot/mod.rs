//! Articulated robots: a kinematic tree from URDF, its collision geometry as polygon soups,
//! forward kinematics, allowed-collision pairs, and the queries a motion planner asks along a
//! straight joint-space segment (module [`query`]).
//!
//! # The model
//!
//! URDF links joined by fixed joints move together: they are merged into one *body*, whose
//! frame is the frame of the link at its head (the child of a moving joint, or the root). The
//! moving joints (revolute, continuous, prismatic) connect bodies; a joint's `origin` is
//! re-expressed in its parent body's frame, so forward kinematics is one pass over the moving
//! joints in tree order: `pose(child) = pose(parent) * origin * J(q)`. Mimic joints follow
//! their source, `q = multiplier * q_source + offset` (mimics of mimics are resolved; cycles
//! are refused). Floating, planar and spherical joints are refused with a clear error.
//!
//! Each URDF link with collision geometry is one *collision object*: all its `<collision>`
//! elements (meshes with their scale, and primitives as conservative meshes, see
//! [`primitives`]) merged into one polygon soup with its vertices in the body's frame, so an
//! object's pose is its body's pose. Attached objects (a grasped part) are objects too.
//!
//! # Allowed collisions
//!
//! Object pairs never checked: two objects on the same body (rigidly joined); objects on
//! bodies joined directly by a moving joint ("adjacent", decided per body: an object on a link
//! merged into a body counts as on that body); pairs disabled by an SRDF's
//! `<disable_collisions>`; pairs the user allows; an attached object and the objects of its
//! body and of the links it is declared to touch. Every other pair of robot objects is checked
//! for self-collision, and every robot object against every obstacle of the scene.

pub(crate) mod chain;
pub mod primitives;
pub mod query;
mod srdf;
pub mod urdf;

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::Arc;

use crate::math::{Pose, Vec3};
use crate::TriMesh;
pub use query::{RobotContact, RobotOptions, Scene};

/// A robot could not be built, or a robot query was given bad input.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RobotError {
    /// The URDF or SRDF file could not be read or parsed.
    #[error("{path}: {message}")]
    Parse {
        /// The file (or `<string>`).
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The kinematic description is not a supported tree: unknown links, several roots, a
    /// cycle, an unsupported joint type, a bad axis or mimic.
    #[error("{0}")]
    Model(String),
    /// A collision mesh file could not be found in any of the places tried.
    #[error("link {link}: mesh {filename} not found (tried: {tried})")]
    MissingMesh {
        /// The link whose collision element names the mesh.
        link: String,
        /// The filename as written in the URDF.
        filename: String,
        /// The paths tried, in order, separated by ", ".
        tried: String,
    },
    /// A collision mesh could not be loaded or built.
    #[error("link {link}: {source}")]
    Mesh {
        /// The link.
        link: String,
        /// The mesh error.
        source: crate::MeshError,
    },
    /// A name (link, joint, object) is not part of the robot.
    #[error("unknown {what} {name:?}")]
    UnknownName {
        /// What kind of name ("link", "joint", "object").
        what: &'static str,
        /// The name.
        name: String,
    },
    /// A configuration has the wrong length or a non-finite value.
    #[error("configuration {which}: {message}")]
    Configuration {
        /// Which configuration (`q0`, `q1`, or an index).
        which: String,
        /// What is wrong.
        message: String,
    },
    /// A contact query failed (bad options, iteration cap).
    #[error(transparent)]
    Contact(#[from] crate::ContactError),
}

/// The kind of a moving joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about the axis (radians); URDF `revolute` and `continuous`.
    Revolute,
    /// Translation along the axis (model units).
    Prismatic,
}

/// Where a moving joint's value comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointSource {
    /// The configuration's entry with this index.
    Dof(usize),
    /// `multiplier * q[dof] + offset`.
    Mimic {
        /// Index of the source configuration entry.
        dof: usize,
        /// Multiplier.
        multiplier: f64,
        /// Offset.
        offset: f64,
    },
}

/// A moving joint.
#[derive(Clone, Debug)]
pub struct Joint {
    /// URDF name.
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Unit axis in the joint frame.
    pub axis: Vec3,
    /// The joint frame in the parent body's frame (at `q = 0`).
    pub origin: Pose,
    /// The body it moves (index into the bodies).
    pub child: usize,
    /// The body it hangs from.
    pub parent: usize,
    /// Lower and upper limits (infinite for continuous joints).
    pub limits: (f64, f64),
    /// Its value's source.
    pub source: JointSource,
    /// Origin and axis in the form forward kinematics evaluates.
    pub(crate) frame: chain::JointFrame,
}

/// A set of URDF links moving together.
#[derive(Clone, Debug)]
pub struct Body {
    /// The head link's name (the body's frame is this link's frame).
    pub name: String,
    /// The moving joint above it (`None` for the root).
    pub joint: Option<usize>,
    /// Moving joints from the root to this body, root first.
    pub chain: Vec<usize>,
}

/// One collision object: a link's collision geometry, or an attached object.
#[derive(Clone, Debug)]
pub struct CollisionObject {
    /// The URDF link name, or the attached object's name.
    pub name: String,
    /// The body it rides on.
    pub body: usize,
    /// Its soup, vertices in the body's frame.
    pub mesh: Arc<TriMesh>,
    /// Largest distance of a vertex from the body's origin.
    pub reach: f64,
}

/// An articulated robot: bodies, moving joints, collision objects and the pairs to check.
#[derive(Clone, Debug)]
pub struct Robot {
    name: String,
    base: Pose,
    bodies: Vec<Body>,
    /// Moving joints in tree order (a parent's joint before its children's).
    joints: Vec<Joint>,
    /// Names of the configuration entries (the actuated joints, in URDF order).
    dof_names: Vec<String>,
    dof_limits: Vec<(f64, f64)>,
    /// Every URDF link: its name, its body, its pose in the body's frame.
    links: Vec<(String, usize, Pose)>,
    objects: Vec<CollisionObject>,
    /// Object pairs allowed to touch (unordered, stored low index first).
    allowed: HashSet<(usize, usize)>,
    /// For each attached object, the bodies whose objects it may touch.
    touch: Vec<(usize, Vec<usize>)>,
    /// Object pairs checked for self-collision, derived from the rest.
    self_pairs: Vec<(usize, usize)>,
}

impl Robot {
    /// Loads a URDF file. Mesh filenames (`package://name/rest`, `file://`, relative or absolute)
    /// are resolved against `package_dirs` and the URDF's own folder (see
    /// [`Robot::from_urdf_str`]).
    ///
    /// # Errors
    /// [`RobotError`] for an unreadable or invalid file, a missing or invalid mesh, or an
    /// unsupported model.
    pub fn from_urdf_file(
        path: impl AsRef<std::path::Path>,
        package_dirs: &[PathBuf],
    ) -> Result<Self, RobotError> {
        urdf::from_file(path.as_ref(), package_dirs)
    }

    /// Builds a robot from URDF text. Relative mesh paths resolve against `base_dir`; a
    /// `package://name/rest` filename is looked for as `dir/name/rest` and, when `dir` is itself
    /// named `name`, as `dir/rest`, for each `dir` in `package_dirs`, then `base_dir` and each
    /// of its ancestors (the ROS layout), then as `base_dir/rest` (pybullet's convention). The
    /// error lists every path tried (or says there was nowhere to look: a package mesh with
    /// neither `base_dir` nor `package_dirs`).
    ///
    /// # Errors
    /// As [`Robot::from_urdf_file`].
    pub fn from_urdf_str(
        xml: &str,
        base_dir: Option<&std::path::Path>,
        package_dirs: &[PathBuf],
    ) -> Result<Self, RobotError> {
        urdf::from_str(xml, base_dir, package_dirs, PathBuf::from("<string>"))
    }

    /// As [`Robot::from_urdf_str`], with every mesh whose URDF filename (as written in the
    /// URDF) is a key of `meshes` taken from it instead of from a file: a robot rebuilt where
    /// its mesh files are not (the Python binding's pickles carry them).
    ///
    /// # Errors
    /// As [`Robot::from_urdf_file`].
    pub fn from_urdf_str_with_meshes(
        xml: &str,
        base_dir: Option<&std::path::Path>,
        package_dirs: &[PathBuf],
        meshes: &std::collections::HashMap<String, urdf::RawMesh>,
    ) -> Result<Self, RobotError> {
        urdf::from_str_with(xml, base_dir, package_dirs, meshes)
    }

    /// Every collision mesh filename the URDF text names (each once, in order of the links)
    /// and the file it resolves to, as [`Robot::from_urdf_str`] resolves it.
    ///
    /// # Errors
    /// [`RobotError::Parse`] for bad XML, [`RobotError::MissingMesh`] for a file not found.
    pub fn urdf_mesh_files(
        xml: &str,
        base_dir: Option<&std::path::Path>,
        package_dirs: &[PathBuf],
    ) -> Result<Vec<(String, PathBuf)>, RobotError> {
        urdf::mesh_files(xml, base_dir, package_dirs)
    }

    /// Disables the SRDF's `<disable_collisions link1=".." link2=".."/>` pairs. Pairs naming a
    /// link without geometry, or a link the robot does not have, are ignored (MoveIt warns and
    /// ignores them too: the MotionBenchMaker Fetch SRDF names links its URDF lacks). Returns
    /// how many object pairs it disabled.
    ///
    /// # Errors
    /// [`RobotError::Parse`] for bad XML or a `<disable_collisions>` without both links.
    pub fn apply_srdf_str(&mut self, xml: &str) -> Result<usize, RobotError> {
        let pairs = srdf::disabled_pairs(xml)?;
        let mut n = 0;
        for (a, b) in pairs {
            n += self.allow_link_pair(&a, &b).unwrap_or(false) as usize;
        }
        self.update_pairs();
        Ok(n)
    }

    /// [`Robot::apply_srdf_str`] on a file.
    ///
    /// # Errors
    /// As [`Robot::apply_srdf_str`], and [`RobotError::Parse`] when the file cannot be read.
    pub fn apply_srdf_file(
        &mut self,
        path: impl AsRef<std::path::Path>,
    ) -> Result<usize, RobotError> {
        let path = path.as_ref();
        let xml = std::fs::read_to_string(path).map_err(|e| RobotError::Parse {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        self.apply_srdf_str(&xml).map_err(|e| match e {
            RobotError::Parse { message, .. } => RobotError::Parse {
                path: path.to_path_buf(),
                message,
            },
            other => other,
        })
    }

    /// Allows two links (or attached objects) to touch: their pair is never checked.
    ///
    /// # Errors
    /// [`RobotError::UnknownName`] when a name is neither a link nor an attached object.
    pub fn allow_collision(&mut self, a: &str, b: &str) -> Result<(), RobotError> {
        self.allow_link_pair(a, b)?;
        self.update_pairs();
        Ok(())
    }

    /// Attaches `mesh` (its vertices in the link's frame after `pose`: `x_link = pose * x`) to
    /// `link`, as a collision object named `name` that may touch its own body and the links in
    /// `touch_links` (e.g. a gripper's fingers around a grasped part).
    ///
    /// # Errors
    /// [`RobotError::UnknownName`] for an unknown link; [`RobotError::Model`] for a name
    /// already taken; [`RobotError::Mesh`] if the transformed mesh is invalid.
    pub fn attach(
        &mut self,
        name: &str,
        mesh: &TriMesh,
        link: &str,
        pose: &Pose,
        touch_links: &[&str],
    ) -> Result<(), RobotError> {
        if self.links.iter().any(|l| l.0 == name) || self.objects.iter().any(|o| o.name == name) {
            return Err(RobotError::Model(format!(
                "cannot attach {name:?}: the name is already a link or object"
            )));
        }
        let (_, body, in_body) = self.link(link)?.clone();
        let to_body = in_body.mul(pose);
        let vertices: Vec<Vec3> = mesh
            .vertices()
            .iter()
            .map(|&v| to_body.transform_point(v))
            .collect();
        let object = make_object(name, body, vertices, mesh.triangles().to_vec())?;
        self.objects.push(object);
        let mut bodies = vec![body];
        for t in touch_links {
            bodies.push(self.link(t)?.1);
        }
        self.touch.push((self.objects.len() - 1, bodies));
        self.update_pairs();
        Ok(())
    }

    /// Removes an attached object.
    ///
    /// # Errors
    /// [`RobotError::UnknownName`] when no attached object has this name.
    pub fn detach(&mut self, name: &str) -> Result<(), RobotError> {
        let Some(i) = self
            .touch
            .iter()
            .map(|t| t.0)
            .find(|&i| self.objects[i].name == name)
        else {
            return Err(RobotError::UnknownName {
                what: "attached object",
                name: name.to_string(),
            });
        };
        self.objects.remove(i);
        self.touch.retain(|t| t.0 != i);
        for t in &mut self.touch {
            if t.0 > i {
                t.0 -= 1;
            }
        }
        self.allowed = self
            .allowed
            .iter()
            .filter(|p| p.0 != i && p.1 != i)
            .map(|&(a, b)| (a - (a > i) as usize, b - (b > i) as usize))
            .collect();
        self.update_pairs();
        Ok(())
    }

    /// The robot's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Number of configuration entries.
    pub fn dof(&self) -> usize {
        self.dof_names.len()
    }

    /// Names of the configuration entries (actuated joints, URDF order).
    pub fn joint_names(&self) -> &[String] {
        &self.dof_names
    }

    /// Lower and upper limit of each configuration entry (infinite for continuous joints).
    pub fn joint_limits(&self) -> &[(f64, f64)] {
        &self.dof_limits
    }

    /// Every URDF link's name, in the order of [`Robot::link_poses`].
    pub fn link_names(&self) -> Vec<&str> {
        self.links.iter().map(|l| l.0.as_str()).collect()
    }

    /// The bodies (merged links).
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The moving joints, in tree order.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The collision objects.
    pub fn objects(&self) -> &[CollisionObject] {
        &self.objects
    }

    /// Object index pairs checked for self-collision.
    pub fn self_pairs(&self) -> &[(usize, usize)] {
        &self.self_pairs
    }

    /// The world pose of the root link (identity unless set).
    pub fn base(&self) -> Pose {
        self.base
    }

    /// Places the robot's root link in the world.
    pub fn set_base(&mut self, base: Pose) {
        self.base = base;
    }

    /// Checks a configuration's length and values; `which` names it in the error.
    ///
    /// # Errors
    /// [`RobotError::Configuration`].
    pub fn check_configuration(&self, q: &[f64], which: &str) -> Result<(), RobotError> {
        if q.len() != self.dof() {
            return Err(RobotError::Configuration {
                which: which.to_string(),
                message: format!(
                    "has {} values, the robot has {} joints",
                    q.len(),
                    self.dof()
                ),
            });
        }
        if let Some(i) = q.iter().position(|v| !v.is_finite() || v.abs() > 1e12) {
            return Err(RobotError::Configuration {
                which: which.to_string(),
                message: format!(
                    "joint {} ({}) is {:?} (must be finite, magnitude at most 1e12)",
                    i, self.dof_names[i], q[i]
                ),
            });
        }
        Ok(())
    }

    /// Whether `q` lies within the joint limits (inclusive, with `tolerance`).
    pub fn within_limits(&self, q: &[f64], tolerance: f64) -> bool {
        q.len() == self.dof()
            && q.iter()
                .zip(&self.dof_limits)
                .all(|(v, (lo, hi))| *v >= lo - tolerance && *v <= hi + tolerance)
    }

    /// The value of every moving joint at configuration `q` (mimics applied).
    pub(crate) fn joint_values(&self, q: &[f64]) -> Vec<f64> {
        self.joints.iter().map(|j| joint_value(j, q)).collect()
    }

    /// World pose of every body at `q` (unchecked).
    pub(crate) fn body_poses(&self, q: &[f64]) -> Vec<Pose> {
        self.body_poses_from_values(&self.joint_values(q))
    }

    /// World pose of every body from every moving joint's value (mimics applied).
    pub(crate) fn body_poses_from_values(&self, values: &[f64]) -> Vec<Pose> {
        let mut poses = vec![self.base; self.bodies.len()];
        for (j, &v) in self.joints.iter().zip(values) {
            poses[j.child] = poses[j.parent].mul(&j.frame.at(v));
        }
        poses
    }

    /// [`Robot::body_poses_from_values`] into `poses` (one per body; body 0 is the root, every
    /// other body hangs from a moving joint), given each joint's value and its sine and cosine
    /// (`trig`, used for revolute joints).
    pub(crate) fn body_poses_into(&self, values: &[f64], trig: &[(f64, f64)], poses: &mut [Pose]) {
        poses[0] = self.base;
        for ((j, &v), &(s, c)) in self.joints.iter().zip(values).zip(trig) {
            poses[j.child] = poses[j.parent].mul(&j.frame.at_sin_cos(v, s, c));
        }
    }

    /// World pose of every URDF link at `q`, in the order of [`Robot::link_names`].
    ///
    /// # Errors
    /// [`RobotError::Configuration`] for a bad configuration.
    pub fn link_poses(&self, q: &[f64]) -> Result<Vec<Pose>, RobotError> {
        self.check_configuration(q, "q")?;
        let bodies = self.body_poses(q);
        Ok(self
            .links
            .iter()
            .map(|(_, b, off)| bodies[*b].mul(off))
            .collect())
    }

    /// World pose of every collision object at `q` (their vertices are in their body's frame).
    ///
    /// # Errors
    /// [`RobotError::Configuration`] for a bad configuration.
    pub fn object_poses(&self, q: &[f64]) -> Result<Vec<Pose>, RobotError> {
        self.check_configuration(q, "q")?;
        let bodies = self.body_poses(q);
        Ok(self.objects.iter().map(|o| bodies[o.body]).collect())
    }

    /// The chain path of object `o` between the joint values `v0` and `v1`; with `skip > 0`,
    /// relative to the body after the first `skip` joints of its chain (the base is then that
    /// body's frame).
    pub(crate) fn object_path(
        &self,
        o: usize,
        v0: &[f64],
        v1: &[f64],
        skip: usize,
    ) -> chain::ChainPath<'_> {
        let object = &self.objects[o];
        let steps = self.bodies[object.body].chain[skip..]
            .iter()
            .map(|&j| {
                let joint = &self.joints[j];
                chain::ChainStep {
                    frame: &joint.frame,
                    q0: v0[j],
                    dq: v1[j] - v0[j],
                    r_chain: 0.0,
                    omega_before: 0.0,
                    v_rel: 0.0,
                }
            })
            .collect();
        let base = if skip == 0 { self.base } else { Pose::IDENTITY };
        chain::ChainPath::new(base, steps, object.reach)
    }

    fn link(&self, name: &str) -> Result<&(String, usize, Pose), RobotError> {
        self.links
            .iter()
            .find(|l| l.0 == name)
            .ok_or_else(|| RobotError::UnknownName {
                what: "link",
                name: name.to_string(),
            })
    }

    /// Allows every object pair between the two names (a link's object or an attached object).
    /// Returns whether a pair was newly allowed.
    fn allow_link_pair(&mut self, a: &str, b: &str) -> Result<bool, RobotError> {
        let object_of = |name: &str| -> Result<Option<usize>, RobotError> {
            if let Some(i) = self.objects.iter().position(|o| o.name == name) {
                return Ok(Some(i));
            }
            if self.links.iter().any(|l| l.0 == name) {
                return Ok(None); // a link without geometry
            }
            Err(RobotError::UnknownName {
                what: "link",
                name: name.to_string(),
            })
        };
        match (object_of(a)?, object_of(b)?) {
            (Some(i), Some(j)) if i != j => Ok(self.allowed.insert((i.min(j), i.max(j)))),
            _ => Ok(false),
        }
    }

    /// Recomputes the checked self pairs from the bodies, adjacency, allowed pairs and
    /// attachments.
    fn update_pairs(&mut self) {
        let adjacent = |a: usize, b: usize| {
            let parent = |x: usize| self.bodies[x].joint.map(|j| self.joints[j].parent);
            a == b || parent(a) == Some(b) || parent(b) == Some(a)
        };
        let touches = |i: usize, body: usize| {
            self.touch
                .iter()
                .any(|(o, bodies)| *o == i && bodies.contains(&body))
        };
        let mut pairs = Vec::new();
        for i in 0..self.objects.len() {
            for j in i + 1..self.objects.len() {
                let (bi, bj) = (self.objects[i].body, self.objects[j].body);
                if adjacent(bi, bj)
                    || self.allowed.contains(&(i, j))
                    || touches(i, bj)
                    || touches(j, bi)
                {
                    continue;
                }
                pairs.push((i, j));
            }
        }
        self.self_pairs = pairs;
    }
}

/// The value of joint `j` at configuration `q`.
fn joint_value(j: &Joint, q: &[f64]) -> f64 {
    match j.source {
        JointSource::Dof(i) => q[i],
        JointSource::Mimic {
            dof,
            multiplier,
            offset,
        } => multiplier * q[dof] + offset,
    }
}

/// A collision object from body-frame vertices.
fn make_object(
    name: &str,
    body: usize,
    vertices: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
) -> Result<CollisionObject, RobotError> {
    let reach = vertices.iter().fold(0.0_f64, |m, v| m.max(v.length()));
    let mesh = TriMesh::new(vertices, triangles).map_err(|source| RobotError::Mesh {
        link: name.to_string(),
        source,
    })?;
    Ok(CollisionObject {
        name: name.to_string(),
        body,
        mesh: Arc::new(mesh),
        reach,
    })
}

//! URDF to [`Robot`]: parsing (urdf-rs), the tree checks, fixed joints merged, mimic joints
//! resolved, mesh paths resolved, collision geometry gathered per link.
//!
//! Decisions: only `<collision>` elements are used (never `<visual>`); a link without them has
//! no collision object. Meshes are read by the crate's loaders (OBJ, STL, PLY, COLLADA: see
//! `mesh/collada.rs` for what of a `.dae` is read). Configuration entries are
//! the revolute, continuous and prismatic joints that are not mimics, in the order the file
//! lists them. A continuous joint has infinite limits; a revolute or prismatic joint whose
//! limits are missing or reversed is refused.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::primitives::{box_soup, capsule_soup, cylinder_soup, sphere_soup, Soup};
use super::{make_object, Body, Joint, JointKind, JointSource, Robot, RobotError};
use crate::math::{Mat3, Pose, Vec3};
use crate::TriMesh;

pub(super) fn from_file(path: &Path, package_dirs: &[PathBuf]) -> Result<Robot, RobotError> {
    let xml = std::fs::read_to_string(path).map_err(|e| RobotError::Parse {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let dir = path.parent().map(Path::to_path_buf);
    from_str(&xml, dir.as_deref(), package_dirs, path.to_path_buf())
}

pub(super) fn from_str(
    xml: &str,
    base_dir: Option<&Path>,
    package_dirs: &[PathBuf],
    origin: PathBuf,
) -> Result<Robot, RobotError> {
    build(&parse(xml, origin)?, base_dir, package_dirs, None)
}

/// The URDF text parsed by urdf-rs, with what is never read here and what urdf-rs trips on
/// where urdfdom (ROS's parser) does not left out first: every `<visual>` (pybullet's racecar
/// writes a `<material>` inside a visual's `<geometry>`), every `<texture>` without a
/// `filename` (urdf-rs requires one; iCub's and Romeo's URDFs in example-robot-data write
/// `<texture />` in materials), and every element of `<robot>` other than `<link>`, `<joint>`
/// and `<material>` (`<gazebo>`, `<transmission>`, `<ros2_control>` and other extensions).
fn parse(xml: &str, origin: PathBuf) -> Result<urdf_rs::Robot, RobotError> {
    let mut text = std::borrow::Cow::Borrowed(xml);
    if let Ok(doc) = crate::xml::parse(xml) {
        let robot = doc.root_element();
        let extension = |n: &roxmltree::Node<'_, '_>| {
            n.parent() == Some(robot)
                && n.is_element()
                && !["link", "joint", "material"].contains(&n.tag_name().name())
        };
        let cut: Vec<std::ops::Range<usize>> = doc
            .descendants()
            .filter(|n| {
                (n.has_tag_name("texture") && n.attribute("filename").is_none())
                    || (n.has_tag_name("visual")
                        && n.parent().is_some_and(|p| p.has_tag_name("link")))
                    || extension(n)
            })
            .map(|n| n.range())
            .collect();
        if !cut.is_empty() {
            // A texture inside a cut visual or extension goes with it.
            text = std::borrow::Cow::Owned(crate::xml::without(xml, cut));
        }
    }
    urdf_rs::read_from_string(&text).map_err(|e| RobotError::Parse {
        path: origin,
        message: e.to_string(),
    })
}

/// The vertices and triangles of a mesh file, before any URDF scale.
pub type RawMesh = (Vec<Vec3>, Vec<[u32; 3]>);

/// As [`from_str`], with the meshes whose URDF filename is a key of `provided` taken from it
/// instead of from files.
pub(super) fn from_str_with(
    xml: &str,
    base_dir: Option<&Path>,
    package_dirs: &[PathBuf],
    provided: &HashMap<String, RawMesh>,
) -> Result<Robot, RobotError> {
    let model = parse(xml, PathBuf::from("<string>"))?;
    build(&model, base_dir, package_dirs, Some(provided))
}

/// Every collision mesh filename the URDF text names (each once, in order) and the file it
/// resolves to.
pub(super) fn mesh_files(
    xml: &str,
    base_dir: Option<&Path>,
    package_dirs: &[PathBuf],
) -> Result<Vec<(String, PathBuf)>, RobotError> {
    let model = parse(xml, PathBuf::from("<string>"))?;
    let mut out: Vec<(String, PathBuf)> = Vec::new();
    for link in &model.links {
        for c in &link.collision {
            if let urdf_rs::Geometry::Mesh { filename, .. } = &c.geometry {
                if !out.iter().any(|(f, _)| f == filename) {
                    out.push((
                        filename.clone(),
                        resolve(&link.name, filename, base_dir, package_dirs)?,
                    ));
                }
            }
        }
    }
    Ok(out)
}

fn pose_of(p: &urdf_rs::Pose) -> Result<Pose, RobotError> {
    let [x, y, z] = p.xyz.0;
    let [r, pi, ya] = p.rpy.0;
    if ![x, y, z, r, pi, ya].iter().all(|v| v.is_finite()) {
        return Err(RobotError::Model(format!(
            "an origin has a non-finite value: xyz {:?} rpy {:?}",
            p.xyz.0, p.rpy.0
        )));
    }
    // Each origin within the supported range, as every pose is: a chain of them stays far
    // inside the range where the kernels' products of lengths are finite (to about 1e38 per
    // length; math::MAX_COORDINATE).
    let translation = Vec3::new(x, y, z);
    crate::math::check_translation(translation)
        .map_err(|e| RobotError::Model(format!("an origin {:?}: {e}", p.xyz.0)))?;
    // URDF: fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
    let rotation = Mat3::from_rotation_z(ya) * Mat3::from_rotation_y(pi) * Mat3::from_rotation_x(r);
    Ok(Pose {
        rotation,
        translation,
    })
}

fn build(
    model: &urdf_rs::Robot,
    base_dir: Option<&Path>,
    package_dirs: &[PathBuf],
    provided: Option<&HashMap<String, RawMesh>>,
) -> Result<Robot, RobotError> {
    let mut index: HashMap<&str, usize> = HashMap::new();
    for (i, l) in model.links.iter().enumerate() {
        if index.insert(l.name.as_str(), i).is_some() {
            return Err(RobotError::Model(format!(
                "link {:?} is defined twice",
                l.name
            )));
        }
    }
    if model.links.is_empty() {
        return Err(RobotError::Model("the robot has no links".into()));
    }
    // Parent joint of every link.
    let mut parent_joint: Vec<Option<usize>> = vec![None; model.links.len()];
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); model.links.len()];
    let mut joint_names = HashMap::new();
    for (k, j) in model.joints.iter().enumerate() {
        if joint_names.insert(j.name.as_str(), k).is_some() {
            return Err(RobotError::Model(format!(
                "joint {:?} is defined twice",
                j.name
            )));
        }
        let find = |name: &str| {
            index.get(name).copied().ok_or_else(|| {
                RobotError::Model(format!(
                    "joint {:?} names an unknown link {:?}",
                    j.name, name
                ))
            })
        };
        let (p, c) = (find(&j.parent.link)?, find(&j.child.link)?);
        if let Some(other) = parent_joint[c] {
            return Err(RobotError::Model(format!(
                "link {:?} has two parent joints ({:?} and {:?}): not a tree",
                j.child.link, model.joints[other].name, j.name
            )));
        }
        parent_joint[c] = Some(k);
        children[p].push(k);
    }
    let roots: Vec<usize> = (0..model.links.len())
        .filter(|&i| parent_joint[i].is_none())
        .collect();
    if roots.len() != 1 {
        let names: Vec<&str> = roots
            .iter()
            .map(|&i| model.links[i].name.as_str())
            .collect();
        return Err(RobotError::Model(if roots.is_empty() {
            "every link has a parent joint: the joints form a cycle".to_string()
        } else {
            format!(
                "the robot has {} root links {:?}: they must form one tree",
                roots.len(),
                names
            )
        }));
    }
    // Configuration entries: moving, non-mimic joints in file order.
    let moving = |j: &urdf_rs::Joint| -> Result<Option<JointKind>, RobotError> {
        use urdf_rs::JointType as T;
        match j.joint_type {
            T::Fixed => Ok(None),
            T::Revolute | T::Continuous => Ok(Some(JointKind::Revolute)),
            T::Prismatic => Ok(Some(JointKind::Prismatic)),
            ref other => Err(RobotError::Model(format!(
                "joint {:?}: type {:?} is not supported (revolute, continuous, prismatic and fixed are)",
                j.name, other
            ))),
        }
    };
    let mut dof_of_joint: HashMap<usize, usize> = HashMap::new();
    let mut dof_names = Vec::new();
    let mut dof_limits = Vec::new();
    for (k, j) in model.joints.iter().enumerate() {
        if moving(j)?.is_some() && j.mimic.is_none() {
            dof_of_joint.insert(k, dof_names.len());
            dof_names.push(j.name.clone());
            dof_limits.push(limits(j)?);
        }
    }
    // Walk the tree from the root: bodies, link offsets, joints in tree order.
    let root = roots[0];
    let mut bodies = vec![Body {
        name: model.links[root].name.clone(),
        joint: None,
        chain: Vec::new(),
    }];
    let mut link_place: Vec<Option<(usize, Pose)>> = vec![None; model.links.len()];
    link_place[root] = Some((0, Pose::IDENTITY));
    let mut joints: Vec<Joint> = Vec::new();
    let mut joint_index: HashMap<usize, usize> = HashMap::new();
    let mut stack = vec![root];
    let mut order = Vec::new();
    while let Some(l) = stack.pop() {
        order.push(l);
        let (body, offset) = link_place[l].expect("placed before it is pushed");
        for &k in children[l].iter().rev() {
            let j = &model.joints[k];
            let c = index[j.child.link.as_str()];
            let origin = offset.mul(&pose_of(&j.origin)?);
            match moving(j)? {
                None => link_place[c] = Some((body, origin)),
                Some(kind) => {
                    let axis = Vec3::from_array(j.axis.xyz.0);
                    let Some(axis) = axis.try_normalize().filter(|a| a.is_finite()) else {
                        return Err(RobotError::Model(format!(
                            "joint {:?}: axis {:?} has no direction",
                            j.name, j.axis.xyz.0
                        )));
                    };
                    let b = bodies.len();
                    let mut chain = bodies[body].chain.clone();
                    chain.push(joints.len());
                    bodies.push(Body {
                        name: j.child.link.clone(),
                        joint: Some(joints.len()),
                        chain,
                    });
                    joint_index.insert(k, joints.len());
                    joints.push(Joint {
                        name: j.name.clone(),
                        kind,
                        axis,
                        origin,
                        child: b,
                        parent: body,
                        limits: limits(j)?,
                        source: JointSource::Dof(usize::MAX), // set below
                        frame: super::chain::JointFrame::new(
                            origin,
                            axis,
                            kind == JointKind::Prismatic,
                        ),
                    });
                    link_place[c] = Some((b, Pose::IDENTITY));
                }
            }
            stack.push(c);
        }
    }
    if order.len() != model.links.len() {
        return Err(RobotError::Model(
            "some links are not reachable from the root: the joints form a cycle".into(),
        ));
    }
    // Sources, with mimics resolved to a configuration entry.
    for (k, j) in model.joints.iter().enumerate() {
        let Some(&ji) = joint_index.get(&k) else {
            continue;
        };
        let (mut multiplier, mut offset, mut cur) = (1.0, 0.0, k);
        let mut seen = 0;
        let dof = loop {
            let cj = &model.joints[cur];
            match &cj.mimic {
                None => break dof_of_joint[&cur],
                Some(m) => {
                    let (a, b) = (m.multiplier.unwrap_or(1.0), m.offset.unwrap_or(0.0));
                    if !(a.is_finite() && b.is_finite()) {
                        return Err(RobotError::Model(format!(
                            "joint {:?}: mimic multiplier and offset must be finite",
                            cj.name
                        )));
                    }
                    // q_cur = a q_src + b, and q_k = multiplier q_cur + offset.
                    offset += multiplier * b;
                    multiplier *= a;
                    let Some(&src) = joint_names.get(m.joint.as_str()) else {
                        return Err(RobotError::Model(format!(
                            "joint {:?} mimics an unknown joint {:?}",
                            cj.name, m.joint
                        )));
                    };
                    if moving(&model.joints[src])?.is_none() {
                        return Err(RobotError::Model(format!(
                            "joint {:?} mimics the fixed joint {:?}",
                            cj.name, m.joint
                        )));
                    }
                    seen += 1;
                    if seen > model.joints.len() {
                        return Err(RobotError::Model(format!(
                            "joint {:?}: its mimic joints form a cycle",
                            j.name
                        )));
                    }
                    cur = src;
                }
            }
        };
        joints[ji].source = if j.mimic.is_some() {
            JointSource::Mimic {
                dof,
                multiplier,
                offset,
            }
        } else {
            JointSource::Dof(dof)
        };
    }
    // Links and their collision objects.
    let mut links = Vec::new();
    let mut objects = Vec::new();
    for (i, link) in model.links.iter().enumerate() {
        let (body, offset) = link_place[i].expect("every link is placed");
        links.push((link.name.clone(), body, offset));
        if link.collision.is_empty() {
            continue;
        }
        let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
        for c in &link.collision {
            let to_body = offset.mul(&pose_of(&c.origin)?);
            let (v, t) = geometry(&link.name, &c.geometry, base_dir, package_dirs, provided)?;
            let base = u32::try_from(vertices.len()).map_err(|_| {
                RobotError::Model(format!("link {:?}: too many vertices", link.name))
            })?;
            vertices.extend(v.into_iter().map(|p| to_body.transform_point(p)));
            triangles.extend(t.into_iter().map(|tri| tri.map(|x| x + base)));
        }
        objects.push(make_object(&link.name, body, vertices, triangles)?);
    }
    let mut robot = Robot {
        name: model.name.clone(),
        base: Pose::IDENTITY,
        bodies,
        joints,
        dof_names,
        dof_limits,
        links,
        objects,
        allowed: Default::default(),
        touch: Vec::new(),
        self_pairs: Vec::new(),
    };
    robot.update_pairs();
    Ok(robot)
}

fn limits(j: &urdf_rs::Joint) -> Result<(f64, f64), RobotError> {
    if j.joint_type == urdf_rs::JointType::Continuous {
        return Ok((f64::NEG_INFINITY, f64::INFINITY));
    }
    if j.joint_type == urdf_rs::JointType::Fixed {
        return Ok((0.0, 0.0));
    }
    let (lo, hi) = (j.limit.lower, j.limit.upper);
    if lo.is_nan() || hi.is_nan() || lo > hi {
        return Err(RobotError::Model(format!(
            "joint {:?}: limits [{lo}, {hi}] are not an interval",
            j.name
        )));
    }
    Ok((lo, hi))
}

/// One collision element's soup in its own frame.
fn geometry(
    link: &str,
    g: &urdf_rs::Geometry,
    base_dir: Option<&Path>,
    package_dirs: &[PathBuf],
    provided: Option<&HashMap<String, RawMesh>>,
) -> Result<Soup, RobotError> {
    use urdf_rs::Geometry as G;
    let positive = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(RobotError::Model(format!(
                "link {link:?}: {name} {v} must be positive and finite"
            )))
        }
    };
    Ok(match g {
        G::Box { size } => {
            let [x, y, z] = size.0;
            box_soup(Vec3::new(
                positive("box size", x)?,
                positive("box size", y)?,
                positive("box size", z)?,
            ))
        }
        G::Sphere { radius } => sphere_soup(positive("sphere radius", *radius)?),
        G::Cylinder { radius, length } => cylinder_soup(
            positive("cylinder radius", *radius)?,
            positive("cylinder length", *length)?,
        ),
        G::Capsule { radius, length } => {
            capsule_soup(positive("capsule radius", *radius)?, length.max(0.0))
        }
        G::Mesh { filename, scale } => {
            let given = provided.and_then(|m| m.get(filename.as_str()));
            let (mut v, t) = match given {
                Some(raw) => raw.clone(),
                None => read_mesh(link, filename, base_dir, package_dirs)?,
            };
            if let Some(s) = scale {
                let s = Vec3::from_array(s.0);
                if !s.is_finite() {
                    return Err(RobotError::Model(format!(
                        "link {link:?}: mesh scale {:?} is not finite",
                        s
                    )));
                }
                v.iter_mut().for_each(|p| *p *= s);
            }
            (v, t)
        }
    })
}

/// A URDF mesh file's vertices and triangles.
fn read_mesh(
    link: &str,
    filename: &str,
    base_dir: Option<&Path>,
    package_dirs: &[PathBuf],
) -> Result<RawMesh, RobotError> {
    let path = resolve(link, filename, base_dir, package_dirs)?;
    TriMesh::load_raw(&path).map_err(|source| RobotError::Mesh {
        link: link.to_string(),
        source,
    })
}

/// The file a URDF mesh filename names (see [`Robot::from_urdf_str`]).
fn resolve(
    link: &str,
    filename: &str,
    base_dir: Option<&Path>,
    package_dirs: &[PathBuf],
) -> Result<PathBuf, RobotError> {
    let mut tried = Vec::new();
    let mut candidates = Vec::new();
    if let Some(rest) = filename.strip_prefix("package://") {
        let (pkg, inner) = rest.split_once('/').unwrap_or((rest, ""));
        let mut dirs: Vec<PathBuf> = package_dirs.to_vec();
        if let Some(b) = base_dir {
            dirs.extend(b.ancestors().map(Path::to_path_buf));
        }
        for d in &dirs {
            candidates.push(d.join(pkg).join(inner));
            if d.file_name().and_then(|n| n.to_str()) == Some(pkg) {
                candidates.push(d.join(inner));
            }
        }
        if let Some(b) = base_dir {
            candidates.push(b.join(rest));
        }
    } else {
        let plain = filename.strip_prefix("file://").unwrap_or(filename);
        let p = Path::new(plain);
        if p.is_absolute() {
            candidates.push(p.to_path_buf());
        } else {
            if let Some(b) = base_dir {
                candidates.push(b.join(p));
            }
            for d in package_dirs {
                candidates.push(d.join(p));
            }
            if base_dir.is_none() {
                candidates.push(p.to_path_buf());
            }
        }
    }
    for c in candidates {
        if c.is_file() {
            return Ok(c);
        }
        tried.push(c.display().to_string());
    }
    let tried = if tried.is_empty() {
        // A `package://` name from a string with neither a base directory nor package
        // directories has nowhere to be looked for: say so rather than list nothing.
        "nowhere: give `package_dirs` or a base directory".to_string()
    } else {
        tried.join(", ")
    };
    Err(RobotError::MissingMesh {
        link: link.to_string(),
        filename: filename.to_string(),
        tried,
    })
}

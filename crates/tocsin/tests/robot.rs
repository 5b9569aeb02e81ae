//! Robots: URDF loading and its edge cases, forward kinematics, conservative primitives, and
//! the segment queries against their oracle (dense sampling of the joint path with the exact
//! `collide` on every checked pair, refined by bisection).

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;

use rand::Rng;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use tocsin::robot::query::{self, Scene};
use tocsin::robot::{primitives, RobotOptions};
use tocsin::{collide, distance, DistanceOptions, Pose, Robot, RobotError, TriMesh, Vec3};

/// A fresh folder for one test's files.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tocsin-robot-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write_obj(path: &Path, mesh: &TriMesh) {
    let mut s = String::new();
    for v in mesh.vertices() {
        s += &format!("v {} {} {}\n", v.x, v.y, v.z);
    }
    for t in mesh.triangles() {
        s += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, s).unwrap();
}

const LINK: &str = "<inertial><mass value='1'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' izz='1'/></inertial>";

fn link(name: &str, geometry: &str) -> String {
    if geometry.is_empty() {
        format!("<link name='{name}'/>")
    } else {
        format!("<link name='{name}'>{LINK}<collision><geometry>{geometry}</geometry></collision></link>")
    }
}

fn joint(name: &str, kind: &str, parent: &str, child: &str, xyz: &str, axis: &str) -> String {
    format!(
        "<joint name='{name}' type='{kind}'><parent link='{parent}'/><child link='{child}'/>\
         <origin xyz='{xyz}' rpy='0 0 0'/><axis xyz='{axis}'/>\
         <limit lower='-3' upper='3' effort='1' velocity='1'/></joint>"
    )
}

fn robot_xml(body: &str) -> String {
    format!("<?xml version='1.0'?><robot name='r'>{body}</robot>")
}

#[test]
fn package_and_relative_paths_resolve_and_errors_say_what_was_tried() {
    let dir = scratch("paths");
    let cube = tocsin::mesh::box_mesh(Vec3::splat(0.1)).unwrap();
    write_obj(&dir.join("pkgs/my_robot/meshes/a.obj"), &cube);
    write_obj(&dir.join("urdf/meshes/b.obj"), &cube);
    write_obj(&dir.join("urdf/c.obj"), &cube);
    let xml = robot_xml(&format!(
        "{}{}{}{}{}",
        link("a", "<mesh filename='package://my_robot/meshes/a.obj'/>"),
        link(
            "b",
            "<mesh filename='package://meshes/b.obj' scale='2 1 1'/>"
        ),
        link("c", "<mesh filename='c.obj'/>"),
        joint("j1", "revolute", "a", "b", "0 0 1", "0 0 1"),
        joint("j2", "revolute", "b", "c", "0 0 1", "0 1 0"),
    ));
    let urdf = dir.join("urdf/robot.urdf");
    std::fs::write(&urdf, &xml).unwrap();
    let pkgs = vec![dir.join("pkgs")];
    let robot = Robot::from_urdf_file(&urdf, &pkgs).unwrap();
    assert_eq!(robot.objects().len(), 3);
    // The scale doubles b along x.
    let b = &robot.objects()[1].mesh;
    let xs: Vec<f64> = b.vertices().iter().map(|v| v.x).collect();
    assert_eq!(xs.iter().cloned().fold(f64::MIN, f64::max), 0.2);
    // Without the package folder, a's mesh is missing and the error lists the places tried.
    let err = Robot::from_urdf_file(&urdf, &[]).unwrap_err();
    match &err {
        RobotError::MissingMesh { link, tried, .. } => {
            assert_eq!(link, "a");
            assert!(tried.contains("my_robot/meshes/a.obj"), "{tried}");
        }
        other => panic!("expected a missing mesh, got {other}"),
    }
    assert!(err.to_string().contains("not found"));
    // From a string with no directory at all, a package mesh has nowhere to be looked for, and
    // the message says what to give (it listed nothing: "tried: ").
    let err = Robot::from_urdf_str(&xml, None, &[]).unwrap_err();
    assert!(
        err.to_string()
            .contains("tried: nowhere: give `package_dirs`"),
        "{err}"
    );
}

#[test]
fn bad_models_are_refused_with_clear_errors() {
    let bx = "<box size='0.1 0.1 0.1'/>";
    let cases = [
        (
            format!(
                "{}{}{}",
                link("a", bx),
                link("b", bx),
                joint("j", "floating", "a", "b", "0 0 0", "1 0 0")
            ),
            "not supported",
        ),
        (
            format!(
                "{}{}{}{}",
                link("a", bx),
                link("b", bx),
                joint("j1", "revolute", "a", "b", "0 0 0", "1 0 0"),
                joint("j2", "revolute", "b", "a", "0 0 0", "1 0 0")
            ),
            "cycle",
        ),
        (format!("{}{}", link("a", bx), link("b", bx)), "root links"),
        (
            format!(
                "{}{}{}",
                link("a", bx),
                link("b", bx),
                joint("j", "revolute", "a", "b", "0 0 0", "0 0 0")
            ),
            "no direction",
        ),
        (
            format!(
                "{}{}",
                link("a", bx),
                joint("j", "revolute", "a", "zz", "0 0 0", "1 0 0")
            ),
            "unknown link",
        ),
        (
            link("a", "<mesh filename='/nonexistent/x.dae'/>"),
            "not found",
        ),
        (link("a", "<cylinder radius='-1' length='1'/>"), "positive"),
        (
            format!(
                "{}{}{}",
                link("a", bx),
                link("b", bx),
                joint("j", "revolute", "a", "b", "2e30 0 0", "1 0 0")
            ),
            "supported range",
        ),
        ("<robot name='r'><link name='a'>".to_string(), ""),
    ];
    for (body, needle) in cases {
        let xml = if body.starts_with("<robot") {
            body.clone()
        } else {
            robot_xml(&body)
        };
        let err = Robot::from_urdf_str(&xml, None, &[]).unwrap_err();
        assert!(
            err.to_string().contains(needle),
            "{err} should mention {needle:?}"
        );
    }
    // A broken COLLADA file is an error that names the format.
    let dir = scratch("dae");
    std::fs::write(dir.join("m.dae"), "<COLLADA/>").unwrap();
    let xml = robot_xml(&link("a", "<mesh filename='m.dae'/>"));
    let err = Robot::from_urdf_str(&xml, Some(&dir), &[]).unwrap_err();
    assert!(err.to_string().contains("COLLADA"), "{err}");
}

/// A COLLADA file with the 12 triangles of `mesh`, in centimetres, placed by a node that
/// translates it by (1, 2, 3) cm; `<up_axis>` Y_UP (ignored).
fn write_dae(path: &Path, mesh: &TriMesh) {
    let v: Vec<String> = mesh
        .vertices()
        .iter()
        .map(|p| format!("{} {} {}", p.x * 100.0, p.y * 100.0, p.z * 100.0))
        .collect();
    let t: Vec<String> = mesh
        .triangles()
        .iter()
        .map(|t| format!("{} {} {}", t[0], t[1], t[2]))
        .collect();
    let (nv, nt) = (mesh.vertices().len(), mesh.triangles().len());
    let text = format!(
        r##"<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
<asset><unit name="centimeter" meter="0.01"/><up_axis>Y_UP</up_axis></asset>
<library_geometries><geometry id="box"><mesh>
<source id="p"><float_array id="pa" count="{}">{}</float_array><technique_common>
<accessor source="#pa" count="{nv}" stride="3"><param name="X" type="float"/>
<param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
<vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
<triangles count="{nt}"><input semantic="VERTEX" source="#v" offset="0"/><p>{}</p></triangles>
</mesh></geometry></library_geometries>
<library_visual_scenes><visual_scene id="s"><node><translate>1 2 3</translate>
<instance_geometry url="#box"/></node></visual_scene></library_visual_scenes>
<scene><instance_visual_scene url="#s"/></scene></COLLADA>"##,
        3 * nv,
        v.join(" "),
        t.join(" ")
    );
    std::fs::write(path, text).unwrap();
}

#[test]
fn collada_meshes_load_with_units_and_nodes_and_what_urdfdom_ignores_is_ignored() {
    let dir = scratch("collada");
    let cube = tocsin::mesh::box_mesh(Vec3::new(0.1, 0.2, 0.3)).unwrap();
    write_dae(&dir.join("box.dae"), &cube);
    // iCub's and Romeo's URDFs write `<texture />` in visual materials; urdf-rs needs a
    // filename there, urdfdom does not.
    let visual = "<visual><geometry><box size='1 1 1'/></geometry><material name='m'>\
                  <texture /><color rgba='0 0 0 1'/></material></visual>";
    // ROS extensions beside the links, and a visual that urdf-rs cannot read (pybullet's
    // racecar puts a <material> inside its <geometry>): none of it is read.
    let visual = format!(
        "{visual}<visual><geometry><mesh filename='nowhere.obj'/><material name='grey'/>\
         </geometry></visual>"
    );
    let extensions = "<gazebo reference='a'><mu1 value='1'/><material>Gazebo/Blue</material>\
                      </gazebo><transmission name='t'><type>x</type></transmission>";
    let xml = robot_xml(&format!(
        "<link name='a'>{visual}<collision><geometry><mesh filename='box.dae'/></geometry>\
         </collision></link>{extensions}"
    ));
    let robot = Robot::from_urdf_str(&xml, Some(&dir), &[]).unwrap();
    let mesh = &robot.objects()[0].mesh;
    assert_eq!(mesh.triangles().len(), cube.triangles().len());
    let shift = Vec3::new(0.01, 0.02, 0.03);
    let corner = |m: &TriMesh, t: usize, k: usize| m.vertices()[m.triangles()[t][k] as usize];
    for t in 0..cube.triangles().len() {
        for k in 0..3 {
            // Read as f32 by the file's reader: within 1e-7 of the size.
            let (a, b) = (corner(mesh, t, k), corner(&cube, t, k) + shift);
            assert!((a - b).length() < 1e-7, "{a} vs {b}");
        }
    }
}

#[test]
fn fixed_joints_merge_mimics_follow_and_kinematics_match_by_hand() {
    let bx = "<box size='0.1 0.1 0.1'/>";
    let xml = robot_xml(&format!(
        "{}{}{}{}{}{}{}{}<joint name='m' type='prismatic'><parent link='b'/><child link='d'/>\
         <origin xyz='0 0 0'/><axis xyz='0 0 1'/><limit lower='0' upper='1' effort='1' velocity='1'/>\
         <mimic joint='j2' multiplier='2' offset='0.5'/></joint>",
        link("a", bx),
        link("b", bx),
        link("c", bx),
        link("d", bx),
        link("e", ""),
        joint("j1", "revolute", "a", "b", "1 0 0", "0 0 1"),
        joint("fixed", "fixed", "b", "e", "0 2 0", "1 0 0"),
        joint("j2", "prismatic", "e", "c", "0 0 0", "1 0 0"),
    ));
    let robot = Robot::from_urdf_str(&xml, None, &[]).unwrap();
    assert_eq!(robot.dof(), 2);
    assert_eq!(robot.joint_names(), ["j1", "j2"]);
    assert_eq!(robot.bodies().len(), 4, "e merges into b");
    let q = [std::f64::consts::FRAC_PI_2, 0.3];
    let poses = robot.link_poses(&q).unwrap();
    let names = robot.link_names();
    let at = |n: &str| poses[names.iter().position(|x| *x == n).unwrap()].translation;
    // b at (1, 0, 0) turned 90 degrees about z; e 2 along b's y, so at (1 - 2, 0, 0).
    assert!((at("b") - Vec3::new(1.0, 0.0, 0.0)).length() < 1e-12);
    assert!((at("e") - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-12);
    // c slides 0.3 along e's x (world y).
    assert!((at("c") - Vec3::new(-1.0, 0.3, 0.0)).length() < 1e-12);
    // d mimics j2: 2 * 0.3 + 0.5 along b's z.
    assert!((at("d") - Vec3::new(1.0, 0.0, 1.1)).length() < 1e-12);
    // Adjacent bodies are not checked; a and c are (two joints apart).
    let pairs: Vec<(String, String)> = robot
        .self_pairs()
        .iter()
        .map(|&(i, j)| {
            (
                robot.objects()[i].name.clone(),
                robot.objects()[j].name.clone(),
            )
        })
        .collect();
    assert!(pairs.contains(&("a".into(), "c".into())));
    assert!(!pairs.contains(&("a".into(), "b".into())));
    // Bad configurations.
    assert!(matches!(
        robot.link_poses(&[0.0]),
        Err(RobotError::Configuration { .. })
    ));
    assert!(matches!(
        robot.link_poses(&[0.0, f64::NAN]),
        Err(RobotError::Configuration { .. })
    ));
}

#[test]
fn srdf_user_pairs_and_attachments_change_the_checked_pairs() {
    let bx = "<box size='0.1 0.1 0.1'/>";
    let xml = robot_xml(&format!(
        "{}{}{}{}{}",
        link("a", bx),
        link("b", bx),
        link("c", bx),
        joint("j1", "revolute", "a", "b", "0 0 1", "0 0 1"),
        joint("j2", "revolute", "b", "c", "0 0 1", "0 0 1"),
    ));
    let mut robot = Robot::from_urdf_str(&xml, None, &[]).unwrap();
    assert_eq!(robot.self_pairs().len(), 1); // a-c
    let n = robot
        .apply_srdf_str(
            "<robot name='r'><disable_collisions link1='a' link2='c' reason='Never'/></robot>",
        )
        .unwrap();
    assert_eq!(n, 1);
    assert!(robot.self_pairs().is_empty());
    // A link the robot does not have is ignored, as MoveIt does.
    let unknown = "<robot><disable_collisions link1='a' link2='zz'/></robot>";
    assert_eq!(robot.apply_srdf_str(unknown).unwrap(), 0);
    assert!(robot
        .apply_srdf_str("<robot><disable_collisions link1='a'/></robot>")
        .is_err());
    assert!(robot.apply_srdf_str("<robot").is_err());
    let part = tocsin::mesh::box_mesh(Vec3::splat(0.02)).unwrap();
    robot
        .attach(
            "part",
            &part,
            "c",
            &Pose::from_translation(Vec3::new(0.0, 0.0, 0.1)),
            &[],
        )
        .unwrap();
    // The part may touch c, but not a (two joints away).
    let names: Vec<(String, String)> = robot
        .self_pairs()
        .iter()
        .map(|&(i, j)| {
            (
                robot.objects()[i].name.clone(),
                robot.objects()[j].name.clone(),
            )
        })
        .collect();
    assert_eq!(names, vec![("a".to_string(), "part".to_string())]);
    robot.allow_collision("part", "a").unwrap();
    assert!(robot.self_pairs().is_empty());
    assert!(robot
        .attach("part", &part, "c", &Pose::IDENTITY, &[])
        .is_err());
    robot.detach("part").unwrap();
    assert_eq!(robot.objects().len(), 3);
    assert!(robot.detach("part").is_err());
}

/// Every point of the true primitive lies inside its tessellation (the mesh is convex: inside
/// every face plane), and the slack is what the docs say.
#[test]
fn primitives_contain_the_true_shapes() {
    let mut rng = common::rng(5);
    for (geometry, kind) in [
        ("<cylinder radius='0.3' length='1.2'/>", 0),
        ("<sphere radius='0.4'/>", 1),
        ("<capsule radius='0.2' length='0.6'/>", 2),
    ] {
        let robot = Robot::from_urdf_str(&robot_xml(&link("a", geometry)), None, &[]).unwrap();
        let mesh = &robot.objects()[0].mesh;
        let planes: Vec<(Vec3, f64)> = mesh
            .triangles()
            .iter()
            .filter_map(|t| {
                let [a, b, c] = t.map(|i| mesh.vertices()[i as usize]);
                let m = (b - a).cross(c - a).try_normalize()?;
                let m = if m.dot(a + b + c) < 0.0 { -m } else { m };
                Some((m, m.dot(a)))
            })
            .collect();
        let mut farthest = 0.0_f64;
        for _ in 0..20_000 {
            let u = common::random_unit(&mut rng);
            let p = match kind {
                0 => {
                    let (r, h) = (0.3, 0.6);
                    let along = rng.random_range(-h..h);
                    let dir = Vec3::new(u.x, u.y, 0.0).normalize_or(Vec3::X);
                    if rng.random_bool(0.2) {
                        // a point of an end disc
                        dir * r * rng.random_range(0.0_f64..1.0).sqrt()
                            + Vec3::Z * if along > 0.0 { h } else { -h }
                    } else {
                        dir * r + Vec3::Z * along
                    }
                }
                1 => u * 0.4,
                _ => {
                    let c = Vec3::Z * rng.random_range(-0.3..0.3);
                    let c = if u.z > 0.0 {
                        c.max(Vec3::ZERO)
                    } else {
                        c.min(Vec3::ZERO)
                    };
                    Vec3::new(0.0, 0.0, c.z) + u * 0.2
                }
            };
            for (m, d) in &planes {
                assert!(
                    m.dot(p) <= d + 1e-12,
                    "a point of the true shape {kind} lies outside"
                );
            }
            farthest = farthest.max(p.length());
        }
        assert!(farthest > 0.0);
        // Slack: no vertex reaches farther than the documented fraction beyond the shape.
        let (radius, half) = [(0.3, 0.6), (0.4, 0.0), (0.2, 0.3)][kind];
        let slack = primitives::primitive_slack(kind != 0);
        assert!(
            slack < if kind == 0 { 0.005 } else { 0.021 },
            "slack {slack}"
        );
        for v in mesh.vertices() {
            let axial = (v.z.abs() - half).max(0.0);
            let radial = (v.x * v.x + v.y * v.y).sqrt();
            let beyond = if kind == 0 {
                radial - radius
            } else {
                (radial * radial + axial * axial).sqrt() - radius
            };
            assert!(
                beyond <= radius * slack + 1e-12,
                "kind {kind}: vertex {beyond} beyond"
            );
        }
    }
}

/// A random serial chain of 2 to 8 links: soups (with degenerate and duplicated triangles),
/// boxes and cylinders; revolute and prismatic joints with random axes.
fn random_chain(rng: &mut impl Rng, dir: &Path, links: usize) -> Robot {
    let mut body = String::new();
    for i in 0..links {
        let geometry = match i % 3 {
            0 => {
                let soup = common::random_soup(rng, 12, 0.12);
                let file = dir.join(format!("l{i}.obj"));
                write_obj(&file, &soup);
                format!("<mesh filename='{}'/>", file.display())
            }
            1 => "<box size='0.08 0.08 0.4'/>".to_string(),
            _ => "<cylinder radius='0.05' length='0.3'/>".to_string(),
        };
        body += &format!(
            "<link name='l{i}'>{LINK}<collision><origin xyz='0 0 0.15' rpy='0.1 0 0'/>\
             <geometry>{geometry}</geometry></collision></link>"
        );
        if i > 0 {
            let a = common::random_unit(rng);
            let kind = if rng.random_bool(0.25) {
                "prismatic"
            } else {
                "revolute"
            };
            body += &joint(
                &format!("j{i}"),
                kind,
                &format!("l{}", i - 1),
                &format!("l{i}"),
                &format!("0 {} 0.3", rng.random_range(-0.1..0.1)),
                &format!("{} {} {}", a.x, a.y, a.z),
            );
        }
    }
    Robot::from_urdf_str(&robot_xml(&body), None, &[]).unwrap()
}

/// Exact collision of the robot at `q` (every checked pair, collide without culling).
fn oracle_collides(robot: &Robot, q: &[f64], scene: &Scene) -> bool {
    let poses = robot.object_poses(q).unwrap();
    let o = robot.objects();
    robot
        .self_pairs()
        .iter()
        .any(|&(i, j)| collide(&o[i].mesh, &poses[i], &o[j].mesh, &poses[j]))
        || o.iter().enumerate().any(|(i, a)| {
            scene
                .obstacles()
                .iter()
                .any(|b| collide(&a.mesh, &poses[i], &b.mesh, &b.pose))
        })
}

/// Exact collision by brute force over every triangle pair of every checked pair: the oracle
/// of the oracle (`collide` itself once missed a box whose hierarchy had a degenerate axis).
fn brute_collides(robot: &Robot, q: &[f64], scene: &Scene) -> bool {
    let poses = robot.object_poses(q).unwrap();
    let o = robot.objects();
    robot.self_pairs().iter().any(|&(i, j)| {
        !common::brute_pairs(&o[i].mesh, &poses[i], &o[j].mesh, &poses[j]).is_empty()
    }) || o.iter().enumerate().any(|(i, a)| {
        scene
            .obstacles()
            .iter()
            .any(|b| !common::brute_pairs(&a.mesh, &poses[i], &b.mesh, &b.pose).is_empty())
    })
}

/// Smallest distance over every checked pair at `q`.
fn oracle_distance(robot: &Robot, q: &[f64], scene: &Scene) -> f64 {
    let poses = robot.object_poses(q).unwrap();
    let o = robot.objects();
    let opts = DistanceOptions::default();
    let mut d = f64::INFINITY;
    for &(i, j) in robot.self_pairs() {
        d = d.min(
            distance(&o[i].mesh, &poses[i], &o[j].mesh, &poses[j], &opts)
                .unwrap()
                .distance,
        );
    }
    for (i, a) in o.iter().enumerate() {
        for b in scene.obstacles() {
            d = d.min(
                distance(&a.mesh, &poses[i], &b.mesh, &b.pose, &opts)
                    .unwrap()
                    .distance,
            );
        }
    }
    d
}

/// The distance at `q` between a contact's two objects: what the contact reports (at least the
/// robot's smallest, [`oracle_distance`]; another pair may be closer, within the tolerance's
/// band).
fn pair_distance(robot: &Robot, q: &[f64], scene: &Scene, c: &query::RobotContact) -> f64 {
    let poses = robot.object_poses(q).unwrap();
    let o = robot.objects();
    let find = |name: &str| o.iter().position(|x| x.name == name).unwrap();
    let i = find(&c.object1);
    let (mesh, pose) = if c.self_collision {
        let j = find(&c.object2);
        (&o[j].mesh, poses[j])
    } else {
        let b = scene
            .obstacles()
            .iter()
            .find(|b| b.name == c.object2)
            .unwrap();
        (&b.mesh, b.pose)
    };
    distance(
        &o[i].mesh,
        &poses[i],
        mesh,
        &pose,
        &DistanceOptions::default(),
    )
    .unwrap()
    .distance
}

fn lerp(q0: &[f64], q1: &[f64], t: f64) -> Vec<f64> {
    q0.iter().zip(q1).map(|(a, b)| a + t * (b - a)).collect()
}

/// First sampled collision time (2,000 samples, then bisection to 1e-9), if any.
fn oracle_first_collision(robot: &Robot, q0: &[f64], q1: &[f64], scene: &Scene) -> Option<f64> {
    let n = 2000;
    let mut prev = 0.0;
    for k in 0..=n {
        let t = k as f64 / n as f64;
        if oracle_collides(robot, &lerp(q0, q1, t), scene) {
            if k == 0 {
                return Some(0.0);
            }
            let (mut lo, mut hi) = (prev, t);
            while hi - lo > 1e-9 {
                let mid = 0.5 * (lo + hi);
                if oracle_collides(robot, &lerp(q0, q1, mid), scene) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return Some(hi);
        }
        prev = t;
    }
    None
}

/// The segment queries on `q0 -> q1` against the oracle: never a missed or late collision,
/// never a contact farther apart than the tolerance, `path_is_free` agreeing, the reported
/// distances and points right, and a free answer confirmed by brute force at 201 evenly
/// spaced configurations. `Some(self_collision)` for a contact, `None` for a free segment.
fn check_edge(robot: &Robot, q0: &[f64], q1: &[f64], scene: &Scene, case: &str) -> Option<bool> {
    check_edge_within(robot, (q0, q1), scene, None, case)
}

/// [`check_edge`] with the tolerance `tolerance` (the robot's default for `None`).
fn check_edge_within(
    robot: &Robot,
    (q0, q1): (&[f64], &[f64]),
    scene: &Scene,
    tolerance: Option<f64>,
    case: &str,
) -> Option<bool> {
    let opts = RobotOptions {
        witnesses: tocsin::Witnesses::Contact,
        tolerance,
        ..RobotOptions::default()
    };
    let tol = query::robot_tolerance(robot, &opts);
    let got = query::time_of_contact(robot, q0, q1, scene, &opts).unwrap();
    let is_free = query::path_is_free(robot, q0, q1, scene, &opts).unwrap();
    assert_eq!(is_free, got.is_none(), "{case}: path_is_free disagrees");
    let first = oracle_first_collision(robot, q0, q1, scene);
    match (&got, first) {
        (None, Some(t)) => panic!("{case}: missed a collision at t = {t}"),
        (Some(c), first) => {
            if let Some(t) = first {
                assert!(c.time <= t + 1e-12, "{case}: late ({} > {t})", c.time);
            }
            let d = oracle_distance(robot, &lerp(q0, q1, c.time), scene);
            assert!(
                d <= tol * (1.0 + 1e-9),
                "{case}: false positive, distance {d} > {tol}"
            );
            // The contact pair's points: as far apart as the distance reported, which is
            // within the tolerance and at least the robot's.
            assert!(
                c.distance >= d - 1e-9 && c.distance <= tol * (1.0 + 1e-9),
                "{case}: contact distance {} vs {d} (tolerance {tol})",
                c.distance
            );
            assert!(((c.point2 - c.point1).length() - c.distance).abs() <= 1e-9);
            // The closest points (the default): the same contact, at the exact distance.
            let closest = RobotOptions {
                tolerance,
                ..RobotOptions::default()
            };
            let e = query::time_of_contact(robot, q0, q1, scene, &closest)
                .unwrap()
                .expect("the same advancement");
            assert_eq!(
                (e.time, &e.object1, &e.object2),
                (c.time, &c.object1, &c.object2)
            );
            // The two objects' exact distance, at least the robot's: another pair may be
            // closer in the band the tolerance leaves (a soak sample's one-joint turn ended
            // on a pair 2.13e-4 apart while another was 1.66e-4 apart).
            let own = pair_distance(robot, &lerp(q0, q1, c.time), scene, &e);
            assert!(
                (e.distance - own).abs() <= 1e-9 && e.distance >= d - 1e-9,
                "{case}: reported distance {} vs the objects' {own} (the robot's {d})",
                e.distance
            );
            Some(c.self_collision)
        }
        (None, None) => {
            for k in 0..=200 {
                let q = lerp(q0, q1, k as f64 / 200.0);
                assert!(
                    !brute_collides(robot, &q, scene),
                    "{case}: collision at sample {k} missed"
                );
            }
            None
        }
    }
}

#[test]
fn random_chains_against_dense_sampling() {
    let dir = scratch("chains");
    let mut rng = common::rng(31);
    let (mut contacts, mut free, mut self_hits) = (0, 0, 0);
    let mut single = (0, 0);
    for case in 0..150 {
        let links = 2 + case % 7;
        let robot = random_chain(&mut rng, &dir, links);
        let mut scene = Scene::new();
        for k in 0..3 {
            let mesh = if k < 2 {
                tocsin::mesh::box_mesh(Vec3::new(0.02, 0.4, 0.4)).unwrap()
            } else {
                common::random_soup(&mut rng, 20, 0.1)
            };
            scene.add(
                &format!("o{k}"),
                Arc::new(mesh),
                common::random_pose(&mut rng, 0.6),
            );
        }
        let q0: Vec<f64> = (0..robot.dof())
            .map(|_| rng.random_range(-1.0..1.0))
            .collect();
        if oracle_collides(&robot, &q0, &scene) {
            continue;
        }
        let q1: Vec<f64> = q0.iter().map(|q| q + rng.random_range(-2.0..2.0)).collect();
        match check_edge(&robot, &q0, &q1, &scene, &format!("case {case}")) {
            Some(self_collision) => {
                self_hits += usize::from(self_collision);
                contacts += 1;
            }
            None => free += 1,
        }
        // One joint alone, by up to 4.5 rad: a revolute joint's links then turn about a line
        // fixed in the world (or in the frame of the body a self pair hangs from) and go
        // through the rigid query with its rotation certificates, turns over pi included.
        let mut q1 = q0.clone();
        let j = rng.random_range(0..robot.dof());
        q1[j] += rng.random_range(0.5..4.5) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        match check_edge(&robot, &q0, &q1, &scene, &format!("case {case}, joint {j}")) {
            Some(_) => single.0 += 1,
            None => single.1 += 1,
        }
    }
    common::assert_mixed(
        contacts >= 20 && free >= 20,
        &format!("{contacts} contacts, {free} free: the set should mix both"),
    );
    common::assert_mixed(self_hits >= 1, "no self-collision among the contacts");
    common::assert_mixed(
        single.0 >= 20 && single.1 >= 20,
        &format!("one joint: {single:?} contacts and free edges: the set should mix both"),
    );
}

/// A robot whose lever swings about the base's z axis and spins `shaft` (written to `dir`)
/// about z at 0.3 along it.
fn shaft_on_a_lever(dir: &Path, shaft: &TriMesh) -> Robot {
    let file = dir.join("shaft.obj");
    write_obj(&file, shaft);
    let xml = robot_xml(&format!(
        "{}{}{}{}{}",
        link("base", ""),
        link("lever", ""),
        link("shaft", &format!("<mesh filename='{}'/>", file.display())),
        joint("swing", "revolute", "base", "lever", "0 0 0", "0 0 1"),
        joint("spin", "continuous", "lever", "shaft", "0.3 0 0", "0 0 1"),
    ));
    Robot::from_urdf_str(&xml, None, &[]).unwrap()
}

/// A 64-sided shaft of radius 0.05 and length 0.2 about z, and a 64-sided bore of length 0.3
/// whose faces clear the shaft's edges by `clearance` of its radius. `keyed`: a key on the
/// shaft (radius 0.06 for angles below 0.3 rad) runs in a groove of the bore (radius 0.07)
/// that is closed by a stop (the bore's radius) from pi to pi + 0.3 rad.
fn shaft_and_bore(keyed: bool, clearance: f64) -> (TriMesh, TriMesh) {
    use std::f64::consts::PI;
    let (r, n) = (0.05, 64);
    // The bore's faces lie at `R cos(pi / n)` from the axis.
    let bore_r = r * (1.0 + clearance) / (PI / n as f64).cos();
    let in_stop = |a: f64| (PI..PI + 0.3).contains(&a);
    let shaft = tocsin::mesh::revolved(
        |a, _| if keyed && a < 0.3 { r + 0.01 } else { r },
        0.2,
        n,
        4,
    )
    .unwrap();
    let bore = tocsin::mesh::revolved(
        |a, _| if !keyed || in_stop(a) { bore_r } else { 0.07 },
        0.3,
        n,
        4,
    )
    .unwrap();
    (shaft, bore)
}

/// A 64-sided shaft turning one and a half turns in a 64-sided bore whose faces clear its
/// edges by 0.5% of its radius (above the tolerance: free), and the same with a key on the
/// shaft that runs in a groove of the bore until it meets a stop half a turn on (a contact).
/// The bore is an obstacle, then a link the shaft's chain hangs from while the arm carrying
/// both also moves (a self pair, relative to that link); the answers go against the oracle.
#[test]
fn shafts_turning_in_bores_against_dense_sampling() {
    use std::f64::consts::PI;
    let dir = scratch("shafts");
    for keyed in [false, true] {
        let (shaft, bore) = shaft_and_bore(keyed, 0.005);
        let (shaft_file, bore_file) = (dir.join("shaft.obj"), dir.join("bore.obj"));
        write_obj(&shaft_file, &shaft);
        write_obj(&bore_file, &bore);
        let shaft_link = format!("<mesh filename='{}'/>", shaft_file.display());
        // The bore as an obstacle, the shaft on one continuous joint.
        let xml = robot_xml(&format!(
            "{}{}{}",
            link("base", ""),
            link("shaft", &shaft_link),
            joint("spin", "continuous", "base", "shaft", "0 0 0", "0 0 1"),
        ));
        let robot = Robot::from_urdf_str(&xml, None, &[]).unwrap();
        let mut scene = Scene::new();
        scene.add("bore", Arc::new(bore.clone()), Pose::IDENTITY);
        let case = format!("keyed {keyed}, bore obstacle");
        let got = check_edge(&robot, &[0.0], &[3.0 * PI], &scene, &case);
        assert_eq!(got.is_some(), keyed, "{case}");
        // The bore on a link, the shaft two joints below it, all on an arm that swings.
        let xml = robot_xml(&format!(
            "{}{}{}{}{}{}{}",
            link("base", ""),
            link(
                "holder",
                &format!("<mesh filename='{}'/>", bore_file.display())
            ),
            link("mid", ""),
            link("shaft", &shaft_link),
            joint("arm", "revolute", "base", "holder", "0.3 0 0", "0 1 0"),
            joint("still", "revolute", "holder", "mid", "0 0 0", "0 0 1"),
            joint("spin", "continuous", "mid", "shaft", "0 0 0", "0 0 1"),
        ));
        let robot = Robot::from_urdf_str(&xml, None, &[]).unwrap();
        assert_eq!(robot.self_pairs().len(), 1, "holder and shaft are checked");
        let case = format!("keyed {keyed}, bore on the arm");
        let got = check_edge(
            &robot,
            &[0.0, 0.0, 0.0],
            &[0.5, 0.0, -3.0 * PI],
            &Scene::new(),
            &case,
        );
        assert_eq!(got, keyed.then_some(true), "{case}");
    }
}

/// The shaft of [`shaft_and_bore`] spinning one and a half turns at the end of a lever
/// 0.3 long that swings a few milliradians about z, in a bore that stands in the world at 1%
/// clearance: the spin's axis moves, and the frozen check (`robot/query/frozen.rs`) certifies
/// the spin in the lever's frame with the bore's drift allowed for. The lever's swing carries
/// the shaft 0.3 to 0.72 mm sideways against a clearance of 0.5 mm: free, a contact the drift
/// causes, and the key meeting its stop. The answers go against the oracle.
#[test]
fn shafts_spinning_on_a_swinging_lever_against_dense_sampling() {
    use std::f64::consts::PI;
    let dir = scratch("lever");
    for (keyed, swing, contact) in [
        (false, 1e-3, false),
        (false, 2.4e-3, true),
        (true, 5e-4, true),
    ] {
        let (shaft, bore) = shaft_and_bore(keyed, 0.01);
        let robot = shaft_on_a_lever(&dir, &shaft);
        let mut scene = Scene::new();
        let at = Pose::from_translation(Vec3::new(0.3, 0.0, 0.0));
        scene.add("bore", Arc::new(bore), at);
        let case = format!("keyed {keyed}, swing {swing}");
        // The default tolerance (0.17 mm) and one of 20 um, far below the drift.
        for tolerance in [None, Some(2e-5)] {
            let case = format!("{case}, tolerance {tolerance:?}");
            let edge = (&[0.0, 0.0][..], &[swing, 3.0 * PI][..]);
            let got = check_edge_within(&robot, edge, &scene, tolerance, &case);
            assert_eq!(got.is_some(), contact, "{case}");
        }
    }
}

/// A rod turning about z sweeps its tip past a box: free at 1% clearance, a contact at -1%,
/// and touching at the start is reported at t = 0.
#[test]
fn near_misses_grazing_and_start_in_contact() {
    let xml = robot_xml(&format!(
        "{}{}{}",
        link("base", ""),
        "<link name='rod'><collision><origin xyz='0.5 0 0'/><geometry><box size='1 0.02 0.02'/></geometry></collision></link>",
        joint("j", "continuous", "base", "rod", "0 0 0", "0 0 1"),
    ));
    let robot = Robot::from_urdf_str(&xml, None, &[]).unwrap();
    let opts = RobotOptions::default();
    for (clearance, expect_free) in [(0.01, true), (-0.01, false), (0.003, true)] {
        // The tip's corner reaches sqrt(1 + 0.01^2) from the axis: a box face at that distance
        // plus the clearance, facing the tip when the rod points along x.
        let reach = (1.0_f64 + 0.01 * 0.01).sqrt();
        let mut scene = Scene::new();
        let wall = tocsin::mesh::box_mesh(Vec3::new(0.05, 0.05, 0.05)).unwrap();
        scene.add(
            "wall",
            Arc::new(wall),
            Pose::from_translation(Vec3::new(reach + clearance + 0.05, 0.0, 0.0)),
        );
        let got = query::time_of_contact(&robot, &[-1.0], &[1.0], &scene, &opts).unwrap();
        assert_eq!(got.is_none(), expect_free, "clearance {clearance}");
        if let Some(c) = got {
            assert!(
                c.time < 0.5,
                "contact before the rod points at the wall: {}",
                c.time
            );
            assert_eq!(c.object2, "wall");
            // The rod turns towards +y: its side meets the wall's corner, so the normal from rod
            // to wall points along +y.
            assert!(c.normal.y > 0.9, "normal {:?} from rod to wall", c.normal);
        }
    }
    let mut scene = Scene::new();
    let wall = tocsin::mesh::box_mesh(Vec3::splat(0.05)).unwrap();
    scene.add(
        "wall",
        Arc::new(wall),
        Pose::from_translation(Vec3::new(0.5, 0.0, 0.0)),
    );
    let c = query::time_of_contact(&robot, &[0.0], &[1.0], &scene, &opts)
        .unwrap()
        .unwrap();
    assert_eq!(c.time, 0.0);
    assert_eq!(c.status, tocsin::ContactStatus::StartedInContact);
    assert!(!query::path_is_free(&robot, &[0.0], &[1.0], &scene, &opts).unwrap());
    assert!(query::in_collision(&robot, &[0.0], &scene).unwrap());
}

#[test]
fn batches_match_single_calls_and_bad_input_is_refused() {
    let dir = scratch("batch");
    let mut rng = common::rng(8);
    let robot = random_chain(&mut rng, &dir, 5);
    let mut scene = Scene::new();
    scene.add(
        "o",
        Arc::new(tocsin::mesh::box_mesh(Vec3::splat(0.2)).unwrap()),
        common::random_pose(&mut rng, 0.5),
    );
    let segments: Vec<(Vec<f64>, Vec<f64>)> = (0..40)
        .map(|_| {
            let q0: Vec<f64> = (0..robot.dof())
                .map(|_| rng.random_range(-1.0..1.0))
                .collect();
            let q1 = q0.iter().map(|q| q + rng.random_range(-0.5..0.5)).collect();
            (q0, q1)
        })
        .collect();
    let opts = RobotOptions::default();
    let batch = query::time_of_contact_batch(&robot, &segments, &scene, &opts).unwrap();
    let free = query::path_is_free_batch(&robot, &segments, &scene, &opts).unwrap();
    let mut cache = query::RobotCache::default();
    for ((s, b), f) in segments.iter().zip(&batch).zip(&free) {
        let single = query::time_of_contact(&robot, &s.0, &s.1, &scene, &opts).unwrap();
        // Warm starts from earlier segments change no answer.
        let warm =
            query::path_is_free_with_cache(&robot, &s.0, &s.1, &scene, &opts, &mut cache).unwrap();
        assert_eq!(warm, single.is_none());
        let warm_toc =
            query::time_of_contact_with_cache(&robot, &s.0, &s.1, &scene, &opts, &mut cache)
                .unwrap();
        assert_eq!(warm_toc.is_none(), single.is_none());
        assert_eq!(b.as_ref().unwrap(), &single);
        assert_eq!(*f.as_ref().unwrap(), single.is_none());
    }
    let qs: Vec<Vec<f64>> = segments.iter().map(|s| s.0.clone()).collect();
    let checks = query::check_configurations(&robot, &qs, &scene).unwrap();
    for (q, c) in qs.iter().zip(&checks) {
        assert_eq!(*c, oracle_collides(&robot, q, &scene));
    }
    let bad = RobotOptions {
        tolerance: Some(-1.0),
        ..opts
    };
    assert!(query::time_of_contact(&robot, &qs[0], &qs[1], &scene, &bad).is_err());
    assert!(query::time_of_contact(&robot, &qs[0][..1], &qs[1], &scene, &opts).is_err());
    assert!(query::check_configurations(&robot, &[vec![f64::NAN; robot.dof()]], &scene).is_err());
}

/// A key passing a bump of its bore while the bore drifts: the case the frozen check's drift
/// allowance is for (`robot/query/frozen.rs`). The shaft (radius 0.05, its key of radius 0.06
/// on its upper part only) spins one and a half turns backwards on a lever that swings;
/// below, the bore clears the shaft by 0.5% of its radius (the clearance that sizes the frozen
/// pieces); above, a groove clears the key by 10 mm but for a bump (at 1.7 or 2.1 rad) that
/// the key passes `pass` apart at the start's pose. The swing carries the bump towards the
/// shaft, so the key meets it late in a piece: a check that took the frozen distance for the
/// true one finds that contact late (`pass` 60 um at 2.1 rad). At a tolerance of 20 um a near
/// miss at 1.5 tolerances also took the chain over 1,000 iterations where it took over within
/// 2 tolerances of a frozen contact. The answers go against the oracle.
#[test]
fn a_key_passing_a_bump_while_its_bore_drifts() {
    use std::f64::consts::PI;
    let dir = scratch("bump");
    let (r, n) = (0.05, 64);
    let half = PI / n as f64;
    let shaft = tocsin::mesh::revolved(
        |a, z| if z >= 0.05 && a < 0.3 { r + 0.01 } else { r },
        0.2,
        n,
        8,
    )
    .unwrap();
    let robot = shaft_on_a_lever(&dir, &shaft);
    let (mut contacts, mut free) = (0, 0);
    for (bump_at, pass, swings) in [
        (1.7, 1.2e-4, &[6e-4, 1e-3][..]),
        (2.1, 6e-5, &[6e-4, 1e-3]),
        (2.1, 1.2e-4, &[6e-4, 1e-3]),
        // 1.15 tolerances, the arm drifting 3 um: the checks' certificates asked for the whole
        // tolerance and, with the chain's slacks, their 32 iterations ran out; the chain then
        // stopped at its cap (an error; forty-seventh session).
        (2.1, 2.3e-5, &[1e-5]),
    ] {
        // The bump's faces, between its corners, lie `pass` beyond the key's corners.
        let bump = (r + 0.01 + pass) / half.cos();
        let bore = tocsin::mesh::revolved(
            move |a, z| {
                if z <= 0.0 {
                    r * 1.005 / half.cos()
                } else if (a - bump_at).abs() < 0.2 {
                    bump
                } else {
                    0.07
                }
            },
            0.3,
            n,
            12,
        )
        .unwrap();
        let mut scene = Scene::new();
        scene.add(
            "bore",
            Arc::new(bore),
            Pose::from_translation(Vec3::new(0.3, 0.0, 0.0)),
        );
        for &swing in swings {
            let case = format!("bump at {bump_at}, pass {pass}, swing {swing}");
            let edge = (&[0.0, 0.0][..], &[swing, -3.0 * PI][..]);
            match check_edge_within(&robot, edge, &scene, Some(2e-5), &case) {
                Some(_) => contacts += 1,
                None => free += 1,
            }
        }
    }
    // Contacts the drift brings, and near misses the drift allowance lets through.
    assert!(
        contacts >= 2 && free >= 2,
        "{contacts} contacts, {free} free"
    );
}

/// A plain 32-sided shaft spinning half a turn in its bore, whose faces clear its corners by
/// 0.3 to 1.3 tolerances (20 um), on a lever that swings 1e-5 rad (the bore drifts 3 um across
/// the clearance), and 1e-4 rad where the drift closes it. Clear by 1.05 to 1.3 tolerances,
/// the frozen checks' rotation certificates, which asked for the whole tolerance, could not
/// settle the corners passing the faces; the checks handed the pair to the chain, which pays
/// the spin's tangential speed on every step and stopped at its 1,000-iteration cap (an
/// error). The answers go against the oracle.
#[test]
fn a_shaft_spinning_within_the_tolerance_band_while_its_bore_drifts() {
    use std::f64::consts::PI;
    let dir = scratch("band");
    let (r, n, tol) = (0.05, 32, 2e-5);
    let half = PI / n as f64;
    let shaft = tocsin::mesh::revolved(|_, _| r, 0.2, n, 2).unwrap();
    let robot = shaft_on_a_lever(&dir, &shaft);
    let mut contacts = 0;
    for (clear, swing) in [
        (0.3, 1e-5),
        (0.8, 1e-5),
        (1.05, 1e-5),
        (1.3, 1e-5),
        (1.05, 1e-4),
    ] {
        let bore_r = (r + clear * tol) / half.cos();
        let bore = tocsin::mesh::revolved(move |_, _| bore_r, 0.3, n, 3).unwrap();
        let mut scene = Scene::new();
        scene.add(
            "bore",
            Arc::new(bore),
            Pose::from_translation(Vec3::new(0.3, 0.0, 0.0)),
        );
        let case = format!("bore {clear} tolerances clear, swing {swing}");
        let edge = (&[0.0, 0.0][..], &[swing, -PI][..]);
        contacts += check_edge_within(&robot, edge, &scene, Some(tol), &case).is_some() as usize;
    }
    // The corners come within 0.3 tolerances, and the larger swing closes the clearance.
    assert!(contacts >= 2, "{contacts} contacts");
}

/// The smallest sampled distance over the robot's checked pairs (its self pairs and each object
/// against each obstacle) over `n + 1` evenly spaced configurations of the segment, with the two
/// closest points there.
fn sampled_closest(
    robot: &Robot,
    (q0, q1): (&[f64], &[f64]),
    scene: &Scene,
    n: usize,
) -> (f64, Vec3, Vec3) {
    let opts = DistanceOptions::default();
    let o = robot.objects();
    let mut best = (f64::INFINITY, Vec3::ZERO, Vec3::ZERO);
    for k in 0..=n {
        let poses = robot
            .object_poses(&lerp(q0, q1, k as f64 / n as f64))
            .unwrap();
        let mut keep = |mesh1, pose1, mesh2, pose2| {
            let d = distance(mesh1, pose1, mesh2, pose2, &opts).unwrap();
            if d.distance < best.0 {
                best = (d.distance, d.point1, d.point2);
            }
        };
        for &(i, j) in robot.self_pairs() {
            keep(&o[i].mesh, &poses[i], &o[j].mesh, &poses[j]);
        }
        for (i, a) in o.iter().enumerate() {
            for b in scene.obstacles() {
                keep(&a.mesh, &poses[i], &b.mesh, &b.pose);
            }
        }
    }
    best
}

/// A link to spin: a barrel of 8 to 32 sides about its z axis (`kind` 0), a random soup (1) or a
/// box (2).
fn random_spinner(rng: &mut rand_chacha::ChaCha8Rng, kind: usize) -> TriMesh {
    match kind {
        0 => {
            let (n, r, wobble) = (
                rng.random_range(8..33),
                rng.random_range(0.03..0.08),
                rng.random_range(0.0..0.03),
            );
            tocsin::mesh::revolved(move |_, z| r * (1.0 + wobble * (10.0 * z).sin()), 0.2, n, 4)
                .unwrap()
        }
        1 => common::random_soup(rng, 20, 0.08),
        _ => tocsin::mesh::box_mesh(Vec3::new(0.02, 0.06, 0.1)).unwrap(),
    }
}

/// What a spinner of `kind` ([`random_spinner`]) turns beside: a plate, for half the barrels,
/// else a random soup.
fn random_neighbour(rng: &mut rand_chacha::ChaCha8Rng, kind: usize) -> TriMesh {
    if kind == 0 && rng.random_bool(0.5) {
        tocsin::mesh::box_mesh(Vec3::new(0.2, 0.2, 0.01)).unwrap()
    } else {
        common::random_soup(rng, 20, 0.1)
    }
}

/// `v`'s coordinates as a URDF attribute.
fn xyz(v: Vec3) -> String {
    format!("{} {} {}", v.x, v.y, v.z)
}

/// 1 or -1, alike.
fn random_sign(rng: &mut rand_chacha::ChaCha8Rng) -> f64 {
    if rng.random_bool(0.5) {
        1.0
    } else {
        -1.0
    }
}

/// How far a slowly moving joint moves: 1e-5 to 1e-2, log-uniform, of either sign.
fn small_move(rng: &mut rand_chacha::ChaCha8Rng) -> f64 {
    10f64.powf(rng.random_range(-5.0..-2.0)) * random_sign(rng)
}

/// A randomized test's tally of free segments and contacts mixes both: at least a fifth of the
/// cases free and a tenth in contact.
fn assert_mix(tally: [usize; 2], cases: usize) {
    common::assert_mixed(
        tally[0] >= cases / 5 && tally[1] >= cases / 10,
        &format!("{tally:?} free and contact: the set should mix both"),
    );
}

/// [`check_edge_within`], then the contract: no configuration of 4,000 sampled before the answer
/// (the contact's time, or the segment's end) has a checked pair closer than half the tolerance.
/// `Some(self_collision)` for a contact, `None` for a free segment.
fn check_edge_and_contract(
    robot: &Robot,
    (q0, q1): (&[f64], &[f64]),
    scene: &Scene,
    tolerance: Option<f64>,
    label: &str,
) -> Option<bool> {
    let opts = RobotOptions {
        tolerance,
        ..RobotOptions::default()
    };
    let tol = query::robot_tolerance(robot, &opts);
    let got = check_edge_within(robot, (q0, q1), scene, tolerance, label);
    let until = match got {
        Some(_) => {
            let c = query::time_of_contact(robot, q0, q1, scene, &opts).unwrap();
            c.unwrap().time
        }
        None => 1.0,
    };
    let n = 4000;
    for k in 0..n {
        let t = until * k as f64 / n as f64;
        if t >= until {
            break;
        }
        let d = oracle_distance(robot, &lerp(q0, q1, t), scene);
        assert!(
            d >= 0.5 * tol * (1.0 - 1e-9),
            "{label}: at t = {t} the distance {d} is under half the tolerance, before the \
             answer {until}"
        );
    }
    got
}

/// A link (`spinner`) on a joint that turns it 1.5 to 4.5 rad, carried by an arm that swings 1e-5
/// to 1e-2 rad at 0.3 from its axis, or stands still (a third of the cases: the rigid query and its
/// rotation certificates); beside an obstacle moved until its sampled closest approach is 0.2 to 3
/// tolerances. The spinner is a barrel of 8 to 32 sides about its turning axis (the frozen checks'
/// case, `robot/query/frozen.rs`), a random soup or a box; the obstacle a random soup or, beside a
/// barrel, a plate; the tolerance the robot's default or 20 um. Each segment goes against the
/// oracle ([`check_edge_within`]) and the contract: no configuration of 4,000 sampled before the
/// answer is closer than half the tolerance. An earlier form of it, run over some 15,000 cases when
/// it was written, found a contact missed where a node's centre lay on the turning axis (its ranges
/// across the axis lost its width to rounding; a unit test in `shells.rs` holds that case), and
/// close approaches of 1.04 to 1.3 tolerances that ran to the 1,000-iteration cap (the triangles'
/// ranges over their whole length).
#[test]
fn spinning_links_beside_close_obstacles_against_the_contract() {
    use std::f64::consts::PI;
    let dir = scratch("spinners");
    // Of seeds 1 to 40, the session's start fails this one only (the iteration cap).
    let (mut rng, cases) = (common::rng(17), 150);
    let mut tally = [0usize; 2];
    for case in 0..cases {
        let kind = case % 3;
        let spinner = random_spinner(&mut rng, kind);
        let file = dir.join(format!("s{case}.obj"));
        write_obj(&file, &spinner);
        let spin = if kind == 0 {
            Vec3::Z
        } else {
            common::random_unit(&mut rng)
        };
        let swing_axis = common::random_unit(&mut rng);
        let xml = robot_xml(&format!(
            "{}{}{}{}{}",
            link("base", ""),
            link("arm", ""),
            link("spinner", &format!("<mesh filename='{}'/>", file.display())),
            joint(
                "swing",
                "revolute",
                "base",
                "arm",
                "0 0 0",
                &xyz(swing_axis)
            ),
            joint(
                "spin",
                "continuous",
                "arm",
                "spinner",
                "0.3 0 0",
                &xyz(spin)
            ),
        ));
        let robot = Robot::from_urdf_str(&xml, None, &[]).unwrap();
        let tolerance = rng.random_bool(0.5).then_some(2e-5);
        let opts = RobotOptions {
            tolerance,
            ..RobotOptions::default()
        };
        let tol = query::robot_tolerance(&robot, &opts);
        let q0 = [rng.random_range(-0.5..0.5), rng.random_range(-PI..PI)];
        let swing = small_move(&mut rng);
        let swing = if case % 3 == 1 { 0.0 } else { swing };
        let q1 = [
            q0[0] + swing,
            q0[1] + rng.random_range(1.5..4.5) * random_sign(&mut rng),
        ];
        let obstacle = Arc::new(random_neighbour(&mut rng, kind));
        let centre = robot.object_poses(&q0).unwrap()[0].translation;
        let mut at = common::random_pose(&mut rng, 0.1);
        at.translation = centre + 0.3 * common::random_unit(&mut rng);
        let target = rng.random_range(0.2..3.0) * tol;
        let place = |at: Pose| {
            let mut scene = Scene::new();
            scene.add("o", obstacle.clone(), at);
            scene
        };
        for _ in 0..4 {
            let (d, p1, p2) = sampled_closest(&robot, (&q0, &q1), &place(at), 400);
            at.translation += (target - d) * (p2 - p1).normalize_or_zero();
        }
        let scene = place(at);
        let label = format!(
            "case {case}: kind {kind}, tolerance {tol:e}, closest {:.2} tolerances, q1 {q1:?}",
            target / tol
        );
        let got = check_edge_and_contract(&robot, (&q0, &q1), &scene, tolerance, &label);
        tally[usize::from(got.is_some())] += 1;
    }
    assert_mix(tally, cases);
}

/// The spinner of [`spinning_links_beside_close_obstacles_against_the_contract`] beside a post of
/// the same robot: a self pair, which the frozen checks never take, advanced in the frame of the
/// deepest body both hang from. The spinner turns 1.5 to 4.5 rad on an arm that swings 1e-5 to
/// 1e-2 rad, slides as much along a random axis, slides 1e-4 to 0.05 along the spin axis (a
/// screw) or stands still while the post drifts 1e-5 to 1e-2 on a slide of its own; the post (a
/// random soup or a plate) is moved until the pair's sampled closest approach is 0.2 to 3
/// tolerances. Each segment against the oracle and the contract ([`check_edge_and_contract`]).
/// When it was written, a barrel screwed past the post by the arm's slide ran to the
/// 1,000-iteration cap: the chain's bound charged its corners their whole turning speed at each
/// pass, where a screw's certificates settle the pair (`ChainPath::rigid` now takes such a slide
/// and turn as one screw).
#[test]
fn spinning_links_beside_their_own_robot_against_the_contract() {
    use std::f64::consts::PI;
    let dir = scratch("self-spinners");
    // Of seeds 1 to 80, the session's start fails 53 and 76 only (the iteration cap, on screws).
    let (mut rng, cases) = (common::rng(53), 120);
    let mut tally = [0usize; 2];
    for case in 0..cases {
        let (kind, motion) = ((case / 4) % 3, case % 4);
        let spinner = random_spinner(&mut rng, kind);
        let (spinner_file, post_file) = (
            dir.join(format!("s{case}.obj")),
            dir.join(format!("p{case}.obj")),
        );
        write_obj(&spinner_file, &spinner);
        let post = random_neighbour(&mut rng, kind);
        // Bake a random attitude into the post: the mount's origin carries no rotation.
        let turned = common::random_rotation(&mut rng);
        let post = TriMesh::new(
            post.vertices().iter().map(|&v| turned * v).collect(),
            post.triangles().to_vec(),
        )
        .unwrap();
        write_obj(&post_file, &post);
        let spin = if kind == 0 {
            Vec3::Z
        } else {
            common::random_unit(&mut rng)
        };
        // The arm's joint, its axis and how far it moves; the post's slide and its drift.
        let (arm_kind, arm_axis, arm_move, post_drift) = match motion {
            0 => (
                "revolute",
                common::random_unit(&mut rng),
                small_move(&mut rng),
                0.0,
            ),
            1 => (
                "prismatic",
                common::random_unit(&mut rng),
                small_move(&mut rng),
                0.0,
            ),
            2 => {
                let pitch = 10f64.powf(rng.random_range(-4.0..-1.3)) * random_sign(&mut rng);
                ("prismatic", spin, pitch, 0.0)
            }
            _ => (
                "revolute",
                common::random_unit(&mut rng),
                0.0,
                small_move(&mut rng),
            ),
        };
        let post_axis = common::random_unit(&mut rng);
        let build = |mount: Vec3| {
            let xml = robot_xml(&format!(
                "{}{}{}{}{}{}{}",
                link("base", ""),
                link("arm", ""),
                link(
                    "spinner",
                    &format!("<mesh filename='{}'/>", spinner_file.display())
                ),
                link(
                    "post",
                    &format!("<mesh filename='{}'/>", post_file.display())
                ),
                joint("arm", arm_kind, "base", "arm", "0 0 0", &xyz(arm_axis)),
                joint(
                    "spin",
                    "continuous",
                    "arm",
                    "spinner",
                    "0.3 0 0",
                    &xyz(spin)
                ),
                joint(
                    "slide",
                    "prismatic",
                    "base",
                    "post",
                    &xyz(mount),
                    &xyz(post_axis)
                ),
            ));
            Robot::from_urdf_str(&xml, None, &[]).unwrap()
        };
        let q0 = [
            if arm_kind == "revolute" {
                rng.random_range(-0.5..0.5)
            } else {
                rng.random_range(-0.05..0.05)
            },
            rng.random_range(-PI..PI),
            rng.random_range(-0.05..0.05),
        ];
        let q1 = [
            q0[0] + arm_move,
            q0[1] + rng.random_range(1.5..4.5) * random_sign(&mut rng),
            q0[2] + post_drift,
        ];
        let tolerance = rng.random_bool(0.5).then_some(2e-5);
        let opts = RobotOptions {
            tolerance,
            ..RobotOptions::default()
        };
        let mut mount = Vec3::new(0.3, 0.0, 0.0) + 0.3 * common::random_unit(&mut rng);
        let tol = query::robot_tolerance(&build(mount), &opts);
        let target = rng.random_range(0.2..3.0) * tol;
        let scene = Scene::new();
        for _ in 0..4 {
            let robot = build(mount);
            // The one checked pair, the spinner first: the post moves along `p2 - p1`.
            let first = robot
                .self_pairs()
                .iter()
                .map(|&(i, _)| &robot.objects()[i].name);
            assert_eq!(first.collect::<Vec<_>>(), ["spinner"]);
            let (d, p1, p2) = sampled_closest(&robot, (&q0, &q1), &scene, 400);
            mount += (target - d) * (p2 - p1).normalize_or_zero();
        }
        let robot = build(mount);
        assert_eq!(query::robot_tolerance(&robot, &opts), tol);
        let label = format!(
            "case {case}: kind {kind}, motion {motion}, tolerance {tol:e}, closest {:.2} \
             tolerances, q0 {q0:?}, q1 {q1:?}",
            target / tol
        );
        let got = check_edge_and_contract(&robot, (&q0, &q1), &scene, tolerance, &label);
        if let Some(self_collision) = got {
            assert!(self_collision, "{label}: only the self pair can touch");
        }
        tally[usize::from(got.is_some())] += 1;
    }
    assert_mix(tally, cases);
}

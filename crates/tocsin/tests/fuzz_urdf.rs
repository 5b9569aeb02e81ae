//! A seeded fuzzer for the URDF loader and the robot queries, run by `make test` in bounded
//! time: a robot with every joint kind (revolute, prismatic, continuous, fixed, a mimic) and
//! every primitive, mutated (attribute values replaced by NaN, infinities, huge, empty and
//! malformed values, other link names and joint kinds; ranges of the text cut or repeated),
//! must load or fail with a `RobotError`, never panic; a robot that loads must answer its link
//! poses, a collision test, `path_is_free` and `time_of_contact` at random configurations
//! without panicking. 12,000 cases found no panic (docs/BENCHMARKS.md, twenty-sixth session);
//! the default is 600 (`TOCSIN_FUZZ_CASES` sets it).

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use tocsin::robot::query::{in_collision, path_is_free, time_of_contact};
use tocsin::robot::{Robot, RobotOptions, Scene};

const BASE: &str = r#"<robot name="r">
<link name="base"><collision><origin xyz="0 0 0.1" rpy="0 0 0"/><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
<link name="l1"><collision><origin xyz="0 0 0.3" rpy="0.1 0 0"/><geometry><cylinder radius="0.05" length="0.5"/></geometry></collision></link>
<link name="l2"><collision><geometry><sphere radius="0.08"/></geometry></collision><collision><geometry><capsule radius="0.02" length="0.3"/></geometry></collision></link>
<link name="l3"><visual><geometry><box size="1 1 1"/></geometry></visual><collision><origin xyz="0.1 0 0"/><geometry><box size="0.1 0.05 0.3"/></geometry></collision></link>
<link name="tip"/>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.2" rpy="0 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
<joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.6"/><axis xyz="1 0 0"/><limit lower="0" upper="0.5" effort="1" velocity="1"/></joint>
<joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/><origin xyz="0 0.1 0" rpy="1.57 0 0"/><axis xyz="0 1 0"/></joint>
<joint name="j4" type="fixed"><parent link="l3"/><child link="tip"/><origin xyz="0 0 0.2"/></joint>
<joint name="m" type="revolute"><parent link="base"/><child link="l0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="j1" multiplier="2" offset="0.1"/></joint>
<link name="l0"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
</robot>"#;

const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "0",
    "-0",
    "1e-320",
    "",
    " ",
    "1 2",
    "a",
    "-1",
    "1e999",
    "0 0 0",
    "1 1 1 1",
    "<",
    ">",
    "base",
    "l1",
    "tip",
    "j1",
    "revolute",
    "floating",
    "planar",
    "fixed",
    "continuous",
    "prismatic",
];

/// `BASE` with up to two mutations.
fn mutated(rng: &mut ChaCha8Rng) -> String {
    let mut s = BASE.to_string();
    for _ in 0..rng.random_range(0..3) {
        let kind = rng.random_range(0..4);
        let quotes: Vec<usize> = s.match_indices('"').map(|(i, _)| i).collect();
        if kind < 2 && quotes.len() >= 2 {
            let k = rng.random_range(0..quotes.len() / 2) * 2;
            let token = TOKENS[rng.random_range(0..TOKENS.len())];
            s.replace_range(quotes[k] + 1..quotes[k + 1], token);
        } else {
            let a = rng.random_range(0..s.len());
            let b = (a + rng.random_range(0..if kind == 2 { 80 } else { 200 })).min(s.len());
            if s.is_char_boundary(a) && s.is_char_boundary(b) {
                if kind == 2 {
                    s.replace_range(a..b, "");
                } else {
                    let piece = s[a..b].to_string();
                    s.insert_str(b, &piece);
                }
            }
        }
    }
    s
}

#[test]
fn mutated_urdf_loads_or_fails_cleanly_and_queries_never_panic() {
    assert!(
        Robot::from_urdf_str(BASE, None, &[]).is_ok(),
        "the seed robot loads"
    );
    let cases: usize = std::env::var("TOCSIN_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let mut rng = common::rng(26);
    let (mut loaded, mut refused) = (0, 0);
    for case in 0..cases {
        let xml = mutated(&mut rng);
        let outcome = std::panic::catch_unwind(|| match Robot::from_urdf_str(&xml, None, &[]) {
            Ok(robot) => {
                let mut q_rng = common::rng(case as u64);
                let mut q = || -> Vec<f64> {
                    (0..robot.dof())
                        .map(|_| q_rng.random_range(-1.5..1.5))
                        .collect()
                };
                let (q0, q1) = (q(), q());
                let scene = Scene::new();
                let options = RobotOptions::default();
                let _ = robot.link_poses(&q0);
                let _ = in_collision(&robot, &q0, &scene);
                let _ = path_is_free(&robot, &q0, &q1, &scene, &options);
                let _ = time_of_contact(&robot, &q0, &q1, &scene, &options);
                true
            }
            Err(e) => {
                assert!(!e.to_string().is_empty(), "an error says what is wrong");
                false
            }
        });
        match outcome {
            Ok(true) => loaded += 1,
            Ok(false) => refused += 1,
            Err(_) => panic!("case {case} panicked on:\n{xml}"),
        }
    }
    // The mutations both keep robots loadable and break them.
    assert!(
        loaded > cases / 10 && refused > cases / 10,
        "{loaded} loaded, {refused} refused"
    );
}

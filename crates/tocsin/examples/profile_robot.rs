//! Robot segment checks on a URDF and a box/cylinder scene file, with a dense-sampling oracle:
//! `cargo run --release --example profile_robot -- robot.urdf robot.srdf scene.txt [edges]`.
//! Scene lines: `box name sx sy sz px py pz qx qy qz qw` or `cylinder name length radius px py
//! pz qx qy qz qw` (MoveIt's conventions). Configurations: random within limits, edges of
//! 0.5 rad from them. With `REPLAY=manifest`, replays the edges of a manifest instead (see
//! `replay`; `TIMES=1` also times each replayed edge, the least of five warm calls, and prints
//! the median per scenario and kind). With `COLD=1`, each edge is timed cache-cold instead
//! (the least of five calls, each after writing 40 MB elsewhere): what a call costs when the
//! caller's own work has evicted tocsin's data and code, 2-3x a warm call on table_under_pick.
//! (The robot benchmark runs each checker over a scene's edges as a block, so its calls are
//! warmer than this.)

use rand::{Rng, SeedableRng};
use std::sync::Arc;
use std::time::Instant;
use tocsin::robot::{query, RobotOptions, Scene};
use tocsin::{Mat3, Pose, Robot, TriMesh, Vec3};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut robot = Robot::from_urdf_file(&args[1], &[]).expect("urdf");
    robot.apply_srdf_file(&args[2]).expect("srdf");
    if let Ok(manifest) = std::env::var("REPLAY") {
        replay(&robot, &manifest);
        return;
    }
    let scene = load_scene(&args[3]);
    let edges: usize = args.get(4).map_or(200, |s| s.parse().expect("edges"));
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let limits = robot.joint_limits().to_vec();
    let opts = RobotOptions::default();
    let mut free_t = Vec::new();
    let mut coll_t = Vec::new();
    let mut n_free = 0;
    let mut shared = query::RobotCache::default();
    let use_cache = std::env::var("CACHE").is_ok();
    let mut starts = 0;
    while free_t.len() + coll_t.len() < edges {
        let q0: Vec<f64> = match std::env::var("START") {
            Ok(s) => s.split(',').map(|x| x.parse().expect("START")).collect(),
            Err(_) => limits
                .iter()
                .map(|(lo, hi)| rng.random_range(*lo..=*hi))
                .collect(),
        };
        if query::in_collision(&robot, &q0, &scene).expect("q") {
            continue;
        }
        starts += 1;
        let dir: Vec<f64> = (0..q0.len()).map(|_| rng.random_range(-1.0..1.0)).collect();
        let norm = dir.iter().map(|d| d * d).sum::<f64>().sqrt();
        let q1: Vec<f64> = q0
            .iter()
            .zip(&dir)
            .zip(&limits)
            .map(|((q, d), (lo, hi))| (q + 0.5 * d / norm).clamp(*lo, *hi))
            .collect();
        if std::env::var_os("COLD").is_some() {
            let mut dt = f64::INFINITY;
            let mut free = false;
            for _ in 0..5 {
                thrash();
                let t = Instant::now();
                free = query::path_is_free(&robot, &q0, &q1, &scene, &opts).expect("free");
                dt = dt.min(t.elapsed().as_secs_f64() * 1e6);
            }
            if free {
                n_free += 1;
                free_t.push(dt);
            } else {
                coll_t.push(dt);
            }
            continue;
        }
        let t = Instant::now();
        let free = if use_cache {
            query::path_is_free_with_cache(&robot, &q0, &q1, &scene, &opts, &mut shared)
        } else {
            query::path_is_free(&robot, &q0, &q1, &scene, &opts)
        }
        .expect("free");
        let dt = t.elapsed().as_secs_f64() * 1e6;
        let toc = query::time_of_contact(&robot, &q0, &q1, &scene, &opts).expect("toc");
        assert_eq!(free, toc.is_none());
        // Oracle: 2000 samples.
        let mut first = None;
        let samples = if std::env::var("ORACLE").is_ok() {
            2000
        } else {
            0
        };
        for k in 0..=samples {
            let s = k as f64 / samples.max(1) as f64;
            let q: Vec<f64> = q0.iter().zip(&q1).map(|(a, b)| a + s * (b - a)).collect();
            if query::in_collision(&robot, &q, &scene).expect("q") {
                first = Some(s);
                break;
            }
        }
        if let Some(s) = first {
            let c = toc.as_ref().expect("a sampled collision was missed");
            assert!(c.time <= s + 1e-12, "late: {} vs {s}", c.time);
        }
        if free {
            n_free += 1;
            free_t.push(dt);
        } else {
            coll_t.push(dt);
        }
    }
    let med = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        if v.is_empty() {
            (f64::NAN, f64::NAN)
        } else {
            (v[v.len() / 2], v[v.len() * 9 / 10])
        }
    };
    println!(
        "{} objects, {} self pairs, {} obstacles; {starts} starts; free {n_free}: median/p90 {:?} us; colliding {}: {:?} us",
        robot.objects().len(),
        robot.self_pairs().len(),
        scene.obstacles().len(),
        med(&mut free_t),
        coll_t.len(),
        med(&mut coll_t)
    );
}

/// The scene of a scene file (module docs).
fn load_scene(path: &str) -> Scene {
    let mut scene = Scene::new();
    for line in std::fs::read_to_string(path).expect("scene").lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let v: Vec<f64> = f[2..].iter().map(|x| x.parse().expect("number")).collect();
        let rest = if f[0] == "box" { &v[3..] } else { &v[2..] };
        let mesh = if f[0] == "box" {
            tocsin::mesh::box_mesh(Vec3::new(v[0], v[1], v[2]) * 0.5).expect("box")
        } else {
            robot_cyl(v[0], v[1])
        };
        let q = glam::DQuat::from_xyzw(rest[3], rest[4], rest[5], rest[6]).normalize();
        let pose = Pose {
            rotation: Mat3::from_quat(q),
            translation: Vec3::new(rest[0], rest[1], rest[2]),
        };
        scene.add(f[1], Arc::new(mesh), pose);
    }
    scene
}

/// Replays the edges of a manifest (lines `scenario scene_file edges_file`; edge lines
/// `rand|goal q0 q1`, comma-separated values), as `bench/robot_mbm.py` draws them: the
/// instruction count of a fixed workload for callgrind. Prints the verdicts per scenario.
fn replay(robot: &Robot, manifest: &str) {
    let opts = RobotOptions::default();
    let parse = |s: &str| -> Vec<f64> { s.split(',').map(|x| x.parse().expect("value")).collect() };
    let mut counts = std::collections::BTreeMap::new();
    let mut times: std::collections::BTreeMap<(String, String), Vec<f64>> = Default::default();
    let timed = std::env::var_os("TIMES").is_some();
    let mut firsts: std::collections::BTreeMap<(String, String), Vec<f64>> = Default::default();
    for line in std::fs::read_to_string(manifest).expect("manifest").lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        let scene = load_scene(f[1]);
        for edge in std::fs::read_to_string(f[2]).expect("edges").lines() {
            let e: Vec<&str> = edge.split_whitespace().collect();
            let (q0, q1) = (parse(e[1]), parse(e[2]));
            let t0 = Instant::now();
            let free = query::path_is_free(robot, &q0, &q1, &scene, &opts).expect("free");
            let first = t0.elapsed().as_secs_f64() * 1e6;
            if timed {
                let kind = if free { "free" } else { "colliding" };
                firsts
                    .entry((f[0].to_string(), format!("{} {kind}", e[0])))
                    .or_default()
                    .push(first);
                let best = (0..5)
                    .map(|_| {
                        let t = Instant::now();
                        let _ = query::path_is_free(robot, &q0, &q1, &scene, &opts);
                        t.elapsed().as_secs_f64() * 1e6
                    })
                    .fold(f64::INFINITY, f64::min);
                let kind = if free { "free" } else { "colliding" };
                times
                    .entry((f[0].to_string(), format!("{} {kind}", e[0])))
                    .or_default()
                    .push(best);
            }
            let c = counts
                .entry((f[0].to_string(), e[0].to_string()))
                .or_insert((0, 0));
            if free {
                c.0 += 1;
            } else {
                c.1 += 1;
            }
        }
    }
    for ((scenario, kind), (free, colliding)) in counts {
        println!("{scenario} {kind}: {free} free, {colliding} colliding");
    }
    for ((scenario, kind), mut t) in times {
        t.sort_by(f64::total_cmp);
        println!(
            "{scenario} {kind}: {} edges, median {:.1} us, mean {:.1} us (least of 5 calls each)",
            t.len(),
            t[t.len() / 2],
            t.iter().sum::<f64>() / t.len() as f64
        );
        let mut f = firsts
            .remove(&(scenario.clone(), kind.clone()))
            .unwrap_or_default();
        f.sort_by(f64::total_cmp);
        println!(
            "{scenario} {kind}: first calls, median {:.1} us, mean {:.1} us",
            f[f.len() / 2],
            f.iter().sum::<f64>() / f.len() as f64
        );
    }
}

fn robot_cyl(length: f64, radius: f64) -> TriMesh {
    let xml = format!(
        "<robot name='c'><link name='a'><collision><geometry><cylinder radius='{radius}' length='{length}'/></geometry></collision></link></robot>"
    );
    let r = Robot::from_urdf_str(&xml, None, &[]).expect("cyl");
    (*r.objects()[0].mesh).clone()
}

/// Evicts the caches: writes one byte per line of 40 MB.
#[inline(never)]
fn thrash() {
    let mut junk = vec![1u8; 40 << 20];
    for (i, b) in junk.iter_mut().enumerate().step_by(64) {
        *b = b.wrapping_add(i as u8);
    }
    std::hint::black_box(&junk);
}

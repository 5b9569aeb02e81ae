//! The contact-time bench's query set without its oracle, for profiling where a query's time
//! goes: per motion kind, 30 passes through and 20 near misses at 1% of the radius (the
//! generator of `benches/contact_time.rs`), each timed as `time_of_contact`, as
//! `motion_is_free`, and as the exact distance at the returned time warm-started from the
//! returned pair (what the witnesses cost).
//!
//! `cargo run --release --example profile_contact_set [model] [repeats]`, model one of
//! knot2.8k, knot34k (default), sphere, or a mesh file (.obj, .stl: the bunny or a Panda link
//! of pybullet_data); `ONLY=toc|free` runs only that call and `SET=pass|near` only the passes
//! or the near misses (for callgrind); `WITNESSES=contact` asks the contact pair's points
//! ([`Witnesses::Contact`]) instead of the closest ones.
#[path = "../benches/common/mod.rs"]
mod common;

use std::time::Instant;
use tocsin::{
    distance_with_cache, mesh, motion_is_free, time_of_contact, ContactOptions, DistanceCache,
    DistanceOptions, Motion, Pose, TriMesh, Witnesses,
};

/// The bench's 30 passes and 20 near misses of each motion kind, tagged with the kind.
fn queries(m: &TriMesh) -> Vec<(usize, Motion)> {
    (0..3)
        .flat_map(|kind| {
            common::contact_queries(m, kind, 30, 20)
                .into_iter()
                .map(move |mo| (kind, mo))
        })
        .collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let model = args.get(1).map_or("knot34k", String::as_str);
    let repeats: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(3);
    let only = std::env::var("ONLY").unwrap_or_default();
    let set = std::env::var("SET").unwrap_or_default();
    let m = match model {
        "knot2.8k" => mesh::torus_knot(175, 8),
        "sphere" => mesh::sphere(1.0, 64, 128),
        "knot34k" => mesh::torus_knot(680, 25),
        path if path.ends_with(".obj") || path.ends_with(".stl") => TriMesh::load(path),
        other => {
            eprintln!("unknown model {other:?}: knot2.8k, knot34k, sphere or an .obj/.stl file");
            std::process::exit(2);
        }
    };
    let m = match m {
        Ok(m) => m,
        Err(e) => {
            eprintln!("cannot load {model}: {e}");
            std::process::exit(2);
        }
    };
    let qs = queries(&m);
    let still = Motion::stationary(Pose::IDENTITY);
    // `WITNESSES=contact`: the contact pair's points instead of the closest ones.
    let opts = ContactOptions {
        witnesses: if std::env::var("WITNESSES").is_ok_and(|w| w == "contact") {
            Witnesses::Contact
        } else {
            Witnesses::Closest
        },
        ..ContactOptions::default()
    };
    let (mut toc, mut free, mut witness, mut iters) = (
        vec![Vec::new(); 3],
        vec![Vec::new(); 3],
        vec![Vec::new(); 3],
        vec![Vec::new(); 3],
    );
    // `motion_is_free` on the passes (which collide) and the near misses (free) apart.
    let (mut free_pass, mut free_near) = (vec![Vec::new(); 3], vec![Vec::new(); 3]);
    for _ in 0..repeats {
        for (q, (kind, mo)) in qs.iter().enumerate() {
            let pass = q % 50 < 30;
            if (set == "pass" && !pass) || (set == "near" && pass) {
                continue;
            }
            if only.is_empty() || only == "toc" {
                let s = Instant::now();
                let c = time_of_contact(&m, mo, &m, &still, &opts).ok().flatten();
                toc[*kind].push(s.elapsed().as_secs_f64() * 1e6);
                if let Some(c) = c {
                    iters[*kind].push(c.iterations as f64);
                    if only.is_empty() {
                        let p = mo.pose_at(c.time);
                        let opts = DistanceOptions::default();
                        let mut cache = DistanceCache::default();
                        let closest = |cache: &mut DistanceCache| {
                            distance_with_cache(&m, &p, &m, &Pose::IDENTITY, &opts, cache)
                        };
                        // An untimed call finds the closest pair; the timed one starts from
                        // it, as `finish` starts from the pair the advancement ended on.
                        let _ = closest(&mut cache);
                        let s = Instant::now();
                        let _ = closest(&mut cache);
                        witness[*kind].push(s.elapsed().as_secs_f64() * 1e6);
                    }
                }
            }
            if only.is_empty() || only == "free" {
                let s = Instant::now();
                let _ = motion_is_free(&m, mo, &m, &still, &opts);
                let us = s.elapsed().as_secs_f64() * 1e6;
                free[*kind].push(us);
                if pass {
                    free_pass[*kind].push(us);
                } else {
                    free_near[*kind].push(us);
                }
            }
        }
    }
    println!(
        "| {model} | toc median | free median | free: passes / near misses | witness distance median | iterations |"
    );
    for (k, name) in ["translation", "interp", "screw"].iter().enumerate() {
        println!(
            "| {name} | {:.0} | {:.0} | {:.0} / {:.0} | {:.0} | {:.0} |",
            common::median(toc[k].clone()),
            common::median(free[k].clone()),
            common::median(free_pass[k].clone()),
            common::median(free_near[k].clone()),
            common::median(witness[k].clone()),
            common::median(iters[k].clone())
        );
    }
}

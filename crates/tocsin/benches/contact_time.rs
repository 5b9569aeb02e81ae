//! Time-of-contact benchmark with its oracle (`make bench`; not part of `make test`).
//!
//! Per model and motion kind, seeded: 60 queries driving body 1 from clear through body 2
//! (fixed at the identity) with a 30 to 90 degree rotation (none for translations), and 40
//! near misses whose closest approach is about 1% of the bounding radius. Reports median and
//! 90th-percentile time per query, median iterations, and against an oracle (1,000 exact
//! collide samples refined by bisection; exact distance at the reported time): misses, late
//! answers and false positives (a reported time whose distance exceeds the tolerance or that is
//! in collision). Models: knot2.8k, knot11k, knot34k, and when pybullet_data is found (set
//! TOCSIN_PYBULLET_DATA or install it in .venv) the bunny and a Franka Panda visual link.
//! `TOCSIN_BENCH_QUICK=1` runs 10 + 5 queries per cell; `TOCSIN_BENCH_MODELS=knot34k,bunny`
//! keeps only those models.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::contact_queries;

use std::time::Instant;
use tocsin::{
    collide, distance, mesh, time_of_contact, ContactOptions, DistanceOptions, Motion, Pose,
    TriMesh,
};

fn pybullet_data() -> Option<std::path::PathBuf> {
    if let Ok(p) = std::env::var("TOCSIN_PYBULLET_DATA") {
        return Some(p.into());
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../.venv/lib");
    std::fs::read_dir(root)
        .ok()?
        .flatten()
        .map(|e| e.path().join("site-packages/pybullet_data"))
        .find(|p| p.exists())
}

fn models() -> Vec<(String, TriMesh)> {
    let mut out = vec![
        ("knot2.8k".to_string(), mesh::torus_knot(175, 8).unwrap()),
        ("knot11k".to_string(), mesh::torus_knot(344, 16).unwrap()),
        ("knot34k".to_string(), mesh::torus_knot(680, 25).unwrap()),
    ];
    if let Some(root) = pybullet_data() {
        for (name, rel) in [
            ("bunny", "bunny.obj"),
            ("panda_link1", "franka_panda/meshes/visual/link1.obj"),
        ] {
            match TriMesh::load(root.join(rel)) {
                Ok(m) => out.push((name.to_string(), m)),
                Err(e) => eprintln!("skipping {name}: {e}"),
            }
        }
    } else {
        eprintln!("pybullet_data not found: bunny and Panda skipped");
    }
    if let Ok(keep) = std::env::var("TOCSIN_BENCH_MODELS") {
        let keep: Vec<&str> = keep.split(',').collect();
        out.retain(|(name, _)| keep.contains(&name.as_str()));
    }
    out
}

struct Oracle {
    first: Option<f64>,
}

fn oracle(m: &TriMesh, mo: &Motion) -> Oracle {
    let hit = |t: f64| collide(m, &mo.pose_at(t), m, &Pose::IDENTITY);
    let n = 1000;
    for i in 0..=n {
        let t = i as f64 / n as f64;
        if hit(t) {
            let (mut lo, mut hi) = (t - 1.0 / n as f64, t);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if hit(mid) {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            return Oracle { first: Some(hi) };
        }
    }
    Oracle { first: None }
}

fn percentile(v: &mut [f64], p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
}

fn main() {
    let quick = std::env::var_os("TOCSIN_BENCH_QUICK").is_some();
    let (n_through, n_near) = if quick { (10, 5) } else { (60, 40) };
    println!("| model | triangles | motion | median (us) | p90 (us) | median iterations | contacts | misses | late | false positives |");
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|");
    for (name, m) in models() {
        let opts = ContactOptions::default();
        let still = Motion::stationary(Pose::IDENTITY);
        let delta = tocsin::query::contact_time::effective_tolerance(&m, &still, &m, &still, &opts);
        for (kind, kind_name) in [(0, "translation"), (1, "interp"), (2, "screw")] {
            let queries = contact_queries(&m, kind, n_through, n_near);
            let (mut times, mut iters) = (Vec::new(), Vec::new());
            let (mut contacts, mut misses, mut late, mut fps) = (0, 0, 0, 0);
            for mo in queries {
                let still = Motion::stationary(Pose::IDENTITY);
                let start = Instant::now();
                let result = time_of_contact(&m, &mo, &m, &still, &opts).unwrap();
                times.push(start.elapsed().as_secs_f64() * 1e6);
                let o = oracle(&m, &mo);
                match (&result, o.first) {
                    (None, Some(_)) => misses += 1,
                    (Some(c), first) => {
                        contacts += 1;
                        iters.push(c.iterations as f64);
                        if first.is_some_and(|f| c.time > f) {
                            late += 1;
                        }
                        let p1 = mo.pose_at(c.time);
                        let exact =
                            distance(&m, &p1, &m, &Pose::IDENTITY, &DistanceOptions::default())
                                .unwrap()
                                .distance;
                        if exact > delta * (1.0 + 1e-9) || collide(&m, &p1, &m, &Pose::IDENTITY) {
                            fps += 1;
                        }
                    }
                    (None, None) => {}
                }
            }
            let med = percentile(&mut times.clone(), 0.5);
            let p90 = percentile(&mut times, 0.9);
            let it = if iters.is_empty() {
                0.0
            } else {
                percentile(&mut iters, 0.5)
            };
            println!(
                "| {name} | {} | {kind_name} | {med:.0} | {p90:.0} | {it:.0} | {contacts}/{} | {misses} | {late} | {fps} |",
                m.num_triangles(),
                n_through + n_near
            );
        }
    }
}

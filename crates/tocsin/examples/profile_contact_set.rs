//! The contact-time bench's query set without its oracle, for profiling where a query's time
//! goes: per motion kind, 30 passes through and 20 near misses at 1% of the radius (the
//! generator of `benches/contact_time.rs`), each timed as `time_of_contact`, as
//! `motion_is_free`, and as the exact distance at the returned time warm-started from the
//! returned pair (what the witnesses cost).
//!
//! `cargo run --release --example profile_contact_set [model] [repeats]`, model one of
//! knot2.8k, knot34k (default), sphere, or a mesh file (.obj, .stl: the bunny or a Panda link
//! of pybullet_data); `ONLY=toc|free` runs only that call (for callgrind).
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use tocsin::{
    collide, distance_with_cache, mesh, motion_is_free, time_of_contact, ContactOptions,
    DistanceCache, DistanceOptions, Mat3, Motion, Pose, TriMesh, Vec3,
};

fn unit(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.length() > 0.2 && v.length() <= 1.0 {
            return v.normalize();
        }
    }
}

fn motion(kind: usize, from: Vec3, to: Vec3, axis: Vec3, angle: f64) -> Option<Motion> {
    let r0 = Mat3::from_axis_angle(axis.any_orthonormal_vector(), 0.4);
    let start = Pose {
        rotation: r0,
        translation: from,
    };
    let end = Pose {
        rotation: Mat3::from_axis_angle(axis, angle) * r0,
        translation: to,
    };
    match kind {
        0 => Motion::translation(
            start,
            Pose {
                rotation: r0,
                translation: to,
            },
        )
        .ok(),
        1 => Motion::interp(start, end, Vec3::ZERO).ok(),
        _ => Motion::screw(start, end).ok(),
    }
}

fn queries(m: &TriMesh) -> Vec<(usize, Motion)> {
    let r = m.bounding_radius();
    let mut out = Vec::new();
    for kind in 0..3 {
        let mut rng = ChaCha8Rng::seed_from_u64(7 + kind as u64);
        for q in 0..50 {
            let d = unit(&mut rng);
            let axis = unit(&mut rng);
            let angle = rng.random_range(30f64..90.0).to_radians();
            let lateral = unit(&mut rng).cross(d).normalize() * rng.random_range(0.0..0.2) * r;
            let mo = if q < 30 {
                motion(
                    kind,
                    -2.5 * r * d + lateral,
                    2.5 * r * d - lateral,
                    axis,
                    angle,
                )
            } else {
                let side = unit(&mut rng).cross(d).normalize();
                let shifted = |o: f64| {
                    motion(
                        kind,
                        -2.5 * r * d + side * o,
                        2.5 * r * d + side * o,
                        axis,
                        angle,
                    )
                };
                let collides = |o: f64| {
                    shifted(o).is_some_and(|mo| {
                        (0..=200)
                            .any(|k| collide(m, &mo.pose_at(k as f64 / 200.0), m, &Pose::IDENTITY))
                    })
                };
                let (mut lo, mut hi) = (0.0, 3.0 * r);
                for _ in 0..30 {
                    let mid = 0.5 * (lo + hi);
                    if collides(mid) {
                        lo = mid
                    } else {
                        hi = mid
                    }
                }
                shifted(hi + 0.01 * r)
            };
            if let Some(mo) = mo {
                out.push((kind, mo));
            }
        }
    }
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        0.0
    } else {
        v[v.len() / 2]
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let model = args.get(1).map_or("knot34k", String::as_str);
    let repeats: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(3);
    let only = std::env::var("ONLY").unwrap_or_default();
    let m = match model {
        "knot2.8k" => mesh::torus_knot(175, 8),
        "sphere" => mesh::sphere(1.0, 64, 128),
        path if path.ends_with(".obj") || path.ends_with(".stl") => TriMesh::load(path),
        _ => mesh::torus_knot(680, 25),
    };
    let Ok(m) = m else {
        return;
    };
    let qs = queries(&m);
    let still = Motion::stationary(Pose::IDENTITY);
    let opts = ContactOptions::default();
    let (mut toc, mut free, mut witness, mut iters) = (
        vec![Vec::new(); 3],
        vec![Vec::new(); 3],
        vec![Vec::new(); 3],
        vec![Vec::new(); 3],
    );
    for _ in 0..repeats {
        for (kind, mo) in &qs {
            if only.is_empty() || only == "toc" {
                let s = Instant::now();
                let c = time_of_contact(&m, mo, &m, &still, &opts).ok().flatten();
                toc[*kind].push(s.elapsed().as_secs_f64() * 1e6);
                if let Some(c) = c {
                    iters[*kind].push(c.iterations as f64);
                    if only.is_empty() {
                        let mut cache = DistanceCache::default();
                        let p = mo.pose_at(c.time);
                        // Warm from the pair the advancement ended on, as `finish` is.
                        let _ = distance_with_cache(
                            &m,
                            &p,
                            &m,
                            &Pose::IDENTITY,
                            &DistanceOptions::default(),
                            &mut cache,
                        );
                        let s = Instant::now();
                        let _ = distance_with_cache(
                            &m,
                            &p,
                            &m,
                            &Pose::IDENTITY,
                            &DistanceOptions::default(),
                            &mut cache,
                        );
                        witness[*kind].push(s.elapsed().as_secs_f64() * 1e6);
                    }
                }
            }
            if only.is_empty() || only == "free" {
                let s = Instant::now();
                let _ = motion_is_free(&m, mo, &m, &still, &opts);
                free[*kind].push(s.elapsed().as_secs_f64() * 1e6);
            }
        }
    }
    println!("| {model} | toc median | free median | witness distance median | iterations |");
    for (k, name) in ["translation", "interp", "screw"].iter().enumerate() {
        println!(
            "| {name} | {:.0} | {:.0} | {:.0} | {:.0} |",
            median(toc[k].clone()),
            median(free[k].clone()),
            median(witness[k].clone()),
            median(iters[k].clone())
        );
    }
}

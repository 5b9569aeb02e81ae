//! The cost of near misses against their clearance: for each motion kind, passes of a mesh past
//! a still copy of itself (the contact-time bench's motions, shifted sideways), the shift set
//! by bisection so that the smallest distance along the motion is `c R` for `c` = 1%, 0.1% and
//! 0.01% of the radius `R`. The smallest distance is measured independently of the advancement:
//! the exact distance at 2,000 evenly spaced times, refined by golden-section search around the
//! smallest sample. Each query asks `motion_is_free` and `time_of_contact` with the tolerance
//! `c R / 10`, and both must say free (the clearance is ten times the tolerance).
//!
//! `cargo run --release --example profile_near_miss [model] [queries per kind] [repeats]`,
//! model knot2.8k, knot34k (default) or a mesh file. `NEAR_MISS_CACHE=file` keeps the shifts
//! found (their search is most of the run); `ONLY=free` times `motion_is_free` alone and
//! counts no iterations (for callgrind).
#[path = "../benches/common/mod.rs"]
mod common;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use tocsin::{
    distance, mesh, motion_is_free, time_of_contact, ContactOptions, DistanceOptions, Motion, Pose,
    TriMesh, Vec3,
};

/// The smallest exact distance along the motion: 2,000 samples, then golden-section search
/// on the bracket around the smallest one.
fn min_distance(m: &TriMesh, mo: &Motion) -> f64 {
    let d = |t: f64| {
        distance(
            m,
            &mo.pose_at(t),
            m,
            &Pose::IDENTITY,
            &DistanceOptions::default(),
        )
        .map_or(f64::INFINITY, |r| r.distance)
    };
    let n: usize = 2000;
    let (mut k_best, mut d_best) = (0usize, f64::INFINITY);
    for k in 0..=n {
        let v = d(k as f64 / n as f64);
        if v < d_best {
            (k_best, d_best) = (k, v);
        }
    }
    let (mut a, mut b) = (
        (k_best.saturating_sub(1)) as f64 / n as f64,
        ((k_best + 1).min(n)) as f64 / n as f64,
    );
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (x1, x2) = (b - g * (b - a), a + g * (b - a));
        let (d1, d2) = (d(x1), d(x2));
        if d1 < d2 {
            b = x2;
        } else {
            a = x1;
        }
        d_best = d_best.min(d1).min(d2);
    }
    d_best
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let model = args.get(1).map_or("knot34k", String::as_str);
    let per_kind: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(10);
    let repeats: usize = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(3);
    let m = match model {
        "knot2.8k" => mesh::torus_knot(175, 8),
        "knot34k" => mesh::torus_knot(680, 25),
        path => TriMesh::load(path),
    }
    .expect("mesh");
    let r = m.bounding_radius();
    let still = Motion::stationary(Pose::IDENTITY);
    let only_free = std::env::var("ONLY").is_ok_and(|v| v == "free");
    let cache_file = std::env::var("NEAR_MISS_CACHE").ok();
    let mut saved: Vec<(String, Vec<f64>)> = cache_file
        .as_ref()
        .and_then(|f| std::fs::read_to_string(f).ok())
        .map(|text| {
            text.lines()
                .filter_map(|l| {
                    let (k, v) = l.split_once(':')?;
                    let v = v
                        .split_whitespace()
                        .filter_map(|x| x.parse().ok())
                        .collect();
                    Some((k.to_string(), v))
                })
                .collect()
        })
        .unwrap_or_default();
    println!("| model | motion | clearance | queries | motion_is_free median (us) | time_of_contact median (us) | median iterations | all free |");
    println!("|---|---|---:|---:|---:|---:|---:|---|");
    for kind in 0..3 {
        let mut rng = ChaCha8Rng::seed_from_u64(101 + kind as u64);
        // The passes: as the bench's, a random direction, turn and sideways direction each.
        let passes: Vec<_> = (0..per_kind)
            .map(|_| {
                let d = common::unit(&mut rng);
                let axis = common::unit(&mut rng);
                let angle = rng.random_range(30f64..90.0).to_radians();
                let side = common::unit(&mut rng).cross(d).normalize();
                (d, axis, angle, side)
            })
            .collect();
        for c in [1e-2, 1e-3, 1e-4] {
            let target = c * r;
            let shifted = |&(d, axis, angle, side): &(Vec3, Vec3, f64, Vec3), o: f64| {
                common::motion(
                    kind,
                    -2.5 * r * d + side * o,
                    2.5 * r * d + side * o,
                    axis,
                    angle,
                )
            };
            // The shift of each pass, found once and kept in `NEAR_MISS_CACHE` when set (the
            // search costs a few thousand exact distances per pass; profilers reuse it).
            let key = format!("{model} {kind} {c}");
            let shifts: Vec<f64> = match saved.iter().find(|(k, _)| *k == key) {
                Some((_, v)) => v.clone(),
                None => {
                    let v: Vec<f64> = passes
                        .iter()
                        .map(|p| {
                            // Bisection on the shift: the smallest distance grows with it.
                            let (mut lo, mut hi) = (0.0, 3.0 * r);
                            for _ in 0..50 {
                                let mid = 0.5 * (lo + hi);
                                let gap = shifted(p, mid)
                                    .map_or(f64::INFINITY, |mo| min_distance(&m, &mo));
                                if (gap - target).abs() < 0.02 * target {
                                    return mid;
                                }
                                if gap < target {
                                    lo = mid;
                                } else {
                                    hi = mid;
                                }
                            }
                            hi
                        })
                        .collect();
                    saved.push((key, v.clone()));
                    v
                }
            };
            let queries: Vec<Motion> = passes
                .iter()
                .zip(&shifts)
                .filter_map(|(p, &o)| shifted(p, o))
                .collect();
            let opts = ContactOptions {
                tolerance: Some(0.1 * target),
                ..ContactOptions::default()
            };
            let (mut free_t, mut toc_t, mut iters, mut all_free) =
                (Vec::new(), Vec::new(), Vec::new(), true);
            for rep in 0..repeats {
                for mo in &queries {
                    // The two calls alternate which goes first (the first meets colder caches).
                    let free = || {
                        let s = Instant::now();
                        let f = motion_is_free(&m, mo, &m, &still, &opts);
                        (f, s.elapsed().as_secs_f64() * 1e6)
                    };
                    let toc = || {
                        if only_free {
                            return (Ok(None), 0.0);
                        }
                        let s = Instant::now();
                        let c = time_of_contact(&m, mo, &m, &still, &opts);
                        (c, s.elapsed().as_secs_f64() * 1e6)
                    };
                    let ((f, tf), (c, tc)) = if rep % 2 == 0 {
                        let a = free();
                        (a, toc())
                    } else {
                        let b = toc();
                        (free(), b)
                    };
                    free_t.push(tf);
                    toc_t.push(tc);
                    all_free &= matches!(f, Ok(true)) && matches!(c, Ok(None));
                    if rep == 0 && !only_free {
                        iters.push(iterations(&m, mo, &opts));
                    }
                }
            }
            let names = ["translation", "interp", "screw"];
            println!(
                "| {model} | {} | {}% R | {} | {:.0} | {:.0} | {:.0} | {} |",
                names[kind],
                c * 100.0,
                queries.len(),
                common::median(free_t),
                common::median(toc_t),
                common::median(iters),
                if all_free { "yes" } else { "NO" }
            );
        }
    }
    if let Some(f) = cache_file {
        let text: String = saved
            .iter()
            .map(|(k, v)| {
                let v: Vec<String> = v.iter().map(|x| format!("{x:e}")).collect();
                format!("{k}:{}\n", v.join(" "))
            })
            .collect();
        std::fs::write(f, text).expect("cache file");
    }
}

/// Iterations of a free query: the advancement's count is reported only with a contact, so
/// the query is asked again with a cap, doubling it until the answer no longer hits the cap.
fn iterations(m: &TriMesh, mo: &Motion, opts: &ContactOptions) -> f64 {
    let still = Motion::stationary(Pose::IDENTITY);
    let (mut lo, mut hi) = (0usize, 1usize);
    while motion_is_free(
        m,
        mo,
        m,
        &still,
        &ContactOptions {
            max_iterations: hi,
            ..*opts
        },
    )
    .is_err()
    {
        lo = hi;
        hi *= 2;
        if hi > opts.max_iterations {
            return f64::NAN;
        }
    }
    // The smallest cap that answers, by bisection between lo (errs) and hi (answers).
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        let ok = motion_is_free(
            m,
            mo,
            m,
            &still,
            &ContactOptions {
                max_iterations: mid,
                ..*opts
            },
        )
        .is_ok();
        if ok {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi as f64
}

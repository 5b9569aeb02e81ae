//! Batch throughput on knot34k vs knot34k at 1 and 2 threads (`make bench`).
//! Time of contact: 200 seeded interp passes of body 1 through body 2 (30 to 90 degree turns);
//! the same passes as yes/no questions (`motion_is_free_batch`), and moved sideways by 0.7
//! radii so that some pass beside body 2 (how many are free is printed); distance: 400 seeded
//! random poses. Prints queries per second and the 2-thread speed-up.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::unit;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;
use tocsin::{
    collide_batch, distance_batch, mesh, motion_is_free_batch, time_of_contact_batch,
    ContactOptions, DistanceOptions, Mat3, Motion, Pose, Vec3,
};

fn best_of<T>(n: usize, mut f: impl FnMut() -> T) -> f64 {
    (0..n)
        .map(|_| {
            let t = Instant::now();
            std::hint::black_box(f());
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let knot = mesh::torus_knot(680, 25).unwrap();
    let r = knot.bounding_radius();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let still = Motion::stationary(Pose::IDENTITY);
    let motions: Vec<(Motion, Motion)> = (0..200)
        .map(|_| {
            let d = unit(&mut rng);
            let (axis, angle) = (unit(&mut rng), rng.random_range(30f64..90.0).to_radians());
            let start = Pose {
                rotation: Mat3::IDENTITY,
                translation: -2.5 * r * d,
            };
            let end = Pose {
                rotation: Mat3::from_axis_angle(axis, angle),
                translation: 2.5 * r * d,
            };
            (Motion::interp(start, end, Vec3::ZERO).unwrap(), still)
        })
        .collect();
    // The same passes moved sideways (across their direction) by 0.7 radii: some free.
    let beside: Vec<(Motion, Motion)> = motions
        .iter()
        .map(|(m, s)| {
            let (a, b) = (m.pose_at(0.0), m.pose_at(1.0));
            let side = (b.translation - a.translation).any_orthonormal_vector() * 0.7 * r;
            let moved = |p: Pose| Pose {
                rotation: p.rotation,
                translation: p.translation + side,
            };
            (Motion::interp(moved(a), moved(b), Vec3::ZERO).unwrap(), *s)
        })
        .collect();
    let poses: Vec<(Pose, Pose)> = (0..400)
        .map(|_| {
            let p = Pose {
                rotation: Mat3::from_axis_angle(unit(&mut rng), rng.random_range(0.0..3.0)),
                translation: unit(&mut rng) * rng.random_range(0.0..2.5 * r),
            };
            (Pose::IDENTITY, p)
        })
        .collect();
    println!("| query (knot34k vs knot34k) | batch | 1 thread (queries/s) | 2 threads (queries/s) | speed-up |");
    println!("|---|---:|---:|---:|---:|");
    let run = |label: &str, n: usize, f: &(dyn Fn() + Sync)| {
        let rate = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            n as f64 / pool.install(|| best_of(3, f))
        };
        let (one, two) = (rate(1), rate(2));
        println!(
            "| {label} | {n} | {one:.0} | {two:.0} | {:.2}x |",
            two / one
        );
    };
    let copts = ContactOptions::default();
    run("time_of_contact_batch (interp)", motions.len(), &|| {
        time_of_contact_batch(&knot, &knot, &motions, &copts).unwrap();
    });
    run(
        "motion_is_free_batch (the same passes)",
        motions.len(),
        &|| {
            motion_is_free_batch(&knot, &knot, &motions, &copts).unwrap();
        },
    );
    let free = motion_is_free_batch(&knot, &knot, &beside, &copts)
        .unwrap()
        .iter()
        .filter(|f| matches!(f, Ok(true)))
        .count();
    run(
        &format!("motion_is_free_batch (beside: {free} free)"),
        beside.len(),
        &|| {
            motion_is_free_batch(&knot, &knot, &beside, &copts).unwrap();
        },
    );
    run("distance_batch", poses.len(), &|| {
        distance_batch(&knot, &knot, &poses, &DistanceOptions::default()).unwrap();
    });
    run("collide_batch", poses.len(), &|| {
        collide_batch(&knot, &knot, &poses);
    });
}

//! Distance on tied geometry (every triangle pair at the minimum): two parallel plates and
//! coincident copies of one triangle, a plate just above a larger floor, as in
//! `bench/compare_fcl_ties.py`, for profiling.
//! Prints the best mean time per query. Usage: `profile_ties [repeats]`.
use tocsin::{distance, mesh, DistanceOptions, Pose, TriMesh, Vec3};

fn time(m1: &TriMesh, m2: &TriMesh, pose2: &Pose, repeats: u32) -> f64 {
    let opts = DistanceOptions::default();
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = std::time::Instant::now();
        for _ in 0..repeats {
            std::hint::black_box(distance(m1, &Pose::IDENTITY, m2, pose2, &opts).ok());
        }
        best = best.min(t.elapsed().as_secs_f64() / f64::from(repeats));
    }
    best
}

fn main() {
    let repeats: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(2000);
    let up = |z: f64| Pose::from_translation(Vec3::new(0.0, 0.0, z));
    if let Ok(p) = mesh::plate(1.0, 300) {
        let us = time(&p, &p, &up(0.1), repeats) * 1e6;
        println!("parallel plates, 180K + 180K: {us:.2} us");
    }
    // The last distance of a plate dropped flat onto a floor (as in the benchmark).
    for (n_plate, n_floor, z) in [
        (64, 128, 0.000_846_347_748_665_210_5),
        (128, 256, 0.001_016),
    ] {
        if let (Ok(p), Ok(f)) = (mesh::plate(1.0, n_plate), mesh::plate(2.0, n_floor)) {
            let us = time(&f, &p, &up(z), repeats) * 1e6;
            let t = 2 * n_plate * n_plate;
            println!("plate {t} over floor, {z} apart: {us:.2} us");
        }
    }
    for n in [4000, 16000] {
        let v = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        if let Ok(c) = TriMesh::new(v, vec![[0, 1, 2]; n]) {
            let us = time(&c, &c, &up(0.5), repeats) * 1e6;
            println!("{n} coincident copies: {us:.2} us");
        }
    }
}

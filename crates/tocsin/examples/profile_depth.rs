//! Penetration depth on a torus knot and a turned copy pushed in by 5% of the radius, timed
//! over several directions (for profiling): `profile_depth [n_u n_v] [fraction]`; with
//! `MESH=file.obj`, that mesh instead of the knot (`n_u n_v` ignored); with `POINTWISE=rel`, the
//! pointwise penetration depth (error `rel` times the radius) at the same poses instead; with
//! `POSES=file`, the copy at the poses of that file (the grid's, `bench/surface_queries.py
//! --grid --dump-poses DIR`) instead of the 24 built here.
use std::time::Instant;
use tocsin::{
    mesh, penetration_depth, pointwise_penetration, time_of_contact, ContactOptions, DepthOptions,
    Mat3, Motion, Pose, Vec3,
};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n_u: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(175);
    let n_v: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(8);
    let f: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(0.05);
    // A mesh file instead of the knot: `MESH=file.obj profile_depth 0 0 [fraction]`.
    let m = match std::env::var("MESH") {
        Ok(path) => tocsin::TriMesh::load(path).expect("mesh"),
        Err(_) => mesh::torus_knot(n_u, n_v).expect("knot"),
    };
    let r = m.bounding_radius();
    let mut times = Vec::new();
    if let Ok(path) = std::env::var("POSES") {
        // Poses of mesh 2 from a file (mesh 1 at the identity): 12 numbers a line, the rows of
        // the 3x4 matrix [R | t], as `bench/surface_queries.py --grid --dump-poses DIR` writes them.
        let text = std::fs::read_to_string(path).expect("poses file");
        for (k, line) in text.lines().enumerate() {
            let v: Vec<f64> = line
                .split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect();
            if v.len() != 12 {
                continue;
            }
            let rot = Mat3::from_cols(
                Vec3::new(v[0], v[4], v[8]),
                Vec3::new(v[1], v[5], v[9]),
                Vec3::new(v[2], v[6], v[10]),
            );
            let p2 = Pose::new(rot, Vec3::new(v[3], v[7], v[11])).expect("pose");
            times.push(query(&m, &p2, r, k));
        }
        report(times);
        return;
    }
    for k in 0..24 {
        let a = k as f64 * 2.399;
        let u = Vec3::new(
            a.cos() * (1.0 - (k as f64 / 24.0)),
            a.sin() * 0.8,
            (k as f64 / 24.0) - 0.5,
        )
        .normalize();
        let rot = Mat3::from_axis_angle(Vec3::new(0.3, 1.0, -0.2).normalize(), 0.7 * k as f64);
        let far = 4.0 * r + 1.0;
        let start = Pose::new(rot, u * far).expect("pose");
        let end = Pose::new(rot, Vec3::ZERO).expect("pose");
        let still = Motion::stationary(Pose::IDENTITY);
        let c = time_of_contact(
            &m,
            &still,
            &m,
            &Motion::translation(start, end).expect("m"),
            &ContactOptions::default(),
        )
        .expect("toc");
        let Some(c) = c else { continue };
        let p2 = Pose::new(rot, u * (far * (1.0 - c.time) - f * r)).expect("pose");
        times.push(query(&m, &p2, r, k));
    }
    report(times);
}

/// One timed query at mesh 2's pose `p2` (ms): the pointwise depth with `POINTWISE=rel`, else
/// the penetration depth; `DEPTHS=1` prints its answer.
fn query(m: &tocsin::TriMesh, p2: &Pose, r: f64, k: usize) -> f64 {
    let clock = Instant::now();
    if let Some(rel) = std::env::var("POINTWISE")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
    {
        let p = pointwise_penetration(m, &Pose::IDENTITY, m, p2, rel * r).expect("pw");
        let ms = clock.elapsed().as_secs_f64() * 1e3;
        if std::env::var("DEPTHS").is_ok() {
            println!("{k} {:.17e} {:.17e}", p.depth, p.upper_bound);
        }
        return ms;
    }
    let d = penetration_depth(m, &Pose::IDENTITY, m, p2, &DepthOptions::default()).expect("pd");
    let ms = clock.elapsed().as_secs_f64() * 1e3;
    if std::env::var("DEPTHS").is_ok() {
        println!("{k} {:.17e} {:?}", d.depth, d.translation);
    }
    ms
}

/// Prints the count, median and largest of the times (ms).
fn report(mut times: Vec<f64>) {
    times.sort_by(f64::total_cmp);
    println!(
        "{} queries, median {:.2} ms, max {:.2} ms",
        times.len(),
        times[times.len() / 2],
        times[times.len() - 1]
    );
}

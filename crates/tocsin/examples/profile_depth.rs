//! Penetration depth on a torus knot and a turned copy pushed in by 5% of the radius, timed
//! over several directions (for profiling): `profile_depth [n_u n_v] [fraction]`; with
//! `MESH=file.obj`, that mesh instead of the knot (`n_u n_v` ignored); with `POINTWISE=rel`, the
//! pointwise penetration depth (error `rel` times the radius) at the same poses instead.
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
        let clock = Instant::now();
        if let Some(rel) = std::env::var("POINTWISE")
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
        {
            let p = pointwise_penetration(&m, &Pose::IDENTITY, &m, &p2, rel * r).expect("pw");
            times.push(clock.elapsed().as_secs_f64() * 1e3);
            if std::env::var("DEPTHS").is_ok() {
                println!("{k} {:.17e} {:.17e}", p.depth, p.upper_bound);
            }
            continue;
        }
        let d =
            penetration_depth(&m, &Pose::IDENTITY, &m, &p2, &DepthOptions::default()).expect("pd");
        times.push(clock.elapsed().as_secs_f64() * 1e3);
        if std::env::var("DEPTHS").is_ok() {
            println!("{k} {:.17e} {:?}", d.depth, d.translation);
        }
    }
    times.sort_by(f64::total_cmp);
    println!(
        "{} queries, median {:.2} ms, max {:.2} ms",
        times.len(),
        times[times.len() / 2],
        times[times.len() - 1]
    );
}

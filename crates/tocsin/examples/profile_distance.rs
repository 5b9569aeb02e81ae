//! Repeats one distance query (knot34k, 10% separation) for profiling.
use tocsin::{distance, mesh, DistanceOptions, Pose, Vec3};
fn main() {
    let Ok(m) = mesh::torus_knot(680, 25) else {
        return;
    };
    let rot = Pose::from_axis_angle(Vec3::new(0.2, 0.5, 1.0), 0.7, Vec3::ZERO);
    let dir = Vec3::new(1.0, 0.3, 0.1).normalize();
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(2000);
    let mut acc = 0.0;
    let t = std::time::Instant::now();
    for (k, s) in [6.039773, 6.404069, 9.660091]
        .into_iter()
        .cycle()
        .take(n)
        .enumerate()
    {
        let p2 = Pose {
            rotation: rot.rotation,
            translation: dir * (s + 1e-9 * k as f64),
        };
        if let Ok(d) = distance(&m, &Pose::IDENTITY, &m, &p2, &DistanceOptions::default()) {
            acc += d.distance;
        }
    }
    println!("{acc} {:?} per query", t.elapsed() / n as u32);
}

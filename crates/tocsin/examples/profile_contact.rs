//! Repeats one time-of-contact query (knot34k, interp with 75 degrees) for profiling.
use tocsin::{mesh, time_of_contact, ContactOptions, Motion, Pose, Vec3};
fn main() {
    let Ok(knot) = mesh::torus_knot(680, 25) else {
        return;
    };
    let start = Pose::from_translation(Vec3::new(-14.0, 1.0, 0.5));
    let end = Pose::from_axis_angle(
        Vec3::new(0.0, 0.3, 1.0),
        75f64.to_radians(),
        Vec3::new(14.0, -0.5, 0.0),
    );
    let (Ok(mo), still) = (
        Motion::interp(start, end, Vec3::ZERO),
        Motion::stationary(Pose::IDENTITY),
    ) else {
        return;
    };
    let n: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(300);
    let t0 = std::time::Instant::now();
    let mut iters = 0;
    for _ in 0..n {
        if let Ok(Some(c)) = time_of_contact(&knot, &mo, &knot, &still, &ContactOptions::default())
        {
            iters = c.iterations;
        }
    }
    println!("{:?} per query, {iters} iterations", t0.elapsed() / n);
}

//! `make demo`: two built-in torus knots (34,000 triangles each), distance, tolerance and
//! collision queries at several separations, with results and timings.

use std::time::Instant;
use tocsin::{collide, distance, mesh, within_distance, DistanceOptions, Pose, TriMesh, Vec3};

fn time<T>(repeats: u32, mut f: impl FnMut() -> T) -> (T, f64) {
    let start = Instant::now();
    let mut out = f();
    for _ in 1..repeats {
        out = f();
    }
    (
        out,
        start.elapsed().as_secs_f64() / f64::from(repeats) * 1e6,
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let knot = mesh::torus_knot(680, 25)?;
    let build_ms = start.elapsed().as_secs_f64() * 1e3;
    println!("tocsin demo: two (2,3) torus knots, {} triangles each (built with hierarchy in {build_ms:.1} ms)", knot.num_triangles());
    println!(
        "bounding radius {:.3}; mesh 2 turned 40 degrees and moved along x\n",
        knot.bounding_radius()
    );
    println!(
        "{:>8} {:>10} {:>9} {:>10} {:>9} {:>10} {:>10}",
        "offset", "distance", "us", "collide", "us", "within 0.1", "us"
    );
    let show = |m: &TriMesh, x: f64| -> Result<(), Box<dyn std::error::Error>> {
        let pose2 = Pose::from_axis_angle(
            Vec3::new(0.3, 0.4, 1.0),
            40f64.to_radians(),
            Vec3::new(x, 0.2, 0.1),
        );
        let (d, dt) = time(20, || {
            distance(m, &Pose::IDENTITY, m, &pose2, &DistanceOptions::default())
        });
        let d = d?;
        let (c, ct) = time(20, || collide(m, &Pose::IDENTITY, m, &pose2));
        let (w, wt) = time(20, || within_distance(m, &Pose::IDENTITY, m, &pose2, 0.1));
        println!(
            "{x:>8.2} {:>10.6} {dt:>9.1} {c:>10} {ct:>9.1} {:>10} {wt:>10.1}",
            d.distance, w?
        );
        Ok(())
    };
    for x in [0.5, 5.0, 6.5, 7.0, 8.0, 10.0, 14.0] {
        show(&knot, x)?;
    }
    let pose2 = Pose::from_axis_angle(
        Vec3::new(0.3, 0.4, 1.0),
        40f64.to_radians(),
        Vec3::new(7.0, 0.2, 0.1),
    );
    let d = distance(
        &knot,
        &Pose::IDENTITY,
        &knot,
        &pose2,
        &DistanceOptions::default(),
    )?;
    println!("\nclosest pair at offset 7.00: triangle {} at {:.4?} and triangle {} at {:.4?} (world frame)",
        d.triangle1, d.point1.to_array(), d.triangle2, d.point2.to_array());
    Ok(())
}

//! Symmetric Hausdorff distance between a torus knot and a copy moved by (0.3, 0.1, 0.05), the
//! benchmark's hard case (the distance is nearly the same over most of the surface), timed a
//! few times for profiling: `profile_hausdorff [n_u n_v] [relative error] [repeats]
//! [pointwise]`; with `pointwise`, the pointwise penetration depth of the same pair instead
//! (the copy overlaps the knot); `TURN=angle` turns the copy instead of only moving it;
//! `MESH=file.obj` that mesh instead of the knot (`n_u n_v` ignored).
use tocsin::{hausdorff_distance, mesh, pointwise_penetration, Pose, Vec3};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n_u: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(175);
    let n_v: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(8);
    let rel: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1e-3);
    let repeats: usize = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(5);
    let m = match std::env::var("MESH") {
        Ok(path) => tocsin::TriMesh::load(path),
        Err(_) => mesh::torus_knot(n_u, n_v),
    };
    let Ok(m) = m else {
        return;
    };
    // `TURN=angle`: the copy turned by that angle (radians) about a fixed axis and moved by 5%
    // of the radius instead (the benchmark's turned copies; the search's common case).
    let moved = match std::env::var("TURN")
        .ok()
        .and_then(|a| a.parse::<f64>().ok())
    {
        Some(angle) => Pose::from_axis_angle(
            Vec3::new(0.3, 1.0, -0.2).normalize(),
            angle,
            Vec3::new(0.6, -0.3, 0.74).normalize() * (0.05 * m.bounding_radius()),
        ),
        None => Pose::from_translation(Vec3::new(0.3, 0.1, 0.05)),
    };
    let error = rel * m.bounding_radius();
    if args.get(5).is_some_and(|a| a == "pointwise") {
        for _ in 0..repeats {
            let t = std::time::Instant::now();
            let r = pointwise_penetration(&m, &Pose::IDENTITY, &m, &moved, error);
            let ms = t.elapsed().as_secs_f64() * 1e3;
            if let Ok(p) = r {
                println!(
                    "{ms:.2} ms: depth {:.9} (upper {:.9})",
                    p.depth, p.upper_bound
                );
            }
        }
        return;
    }
    for _ in 0..repeats {
        let t = std::time::Instant::now();
        let r = hausdorff_distance(&m, &Pose::IDENTITY, &m, &moved, error, true);
        let ms = t.elapsed().as_secs_f64() * 1e3;
        if let Ok(h) = r {
            println!("{ms:.2} ms: {:.9} (upper {:.9})", h.distance, h.upper_bound);
        }
    }
}

//! Times of contact and distances between two convex polytopes (UV spheres of 1,000 and 4,000
//! triangles stretched into ellipsoids), for profiling the GJK path: `profile_convex [N]`
//! passes of every motion kind (or only `profile_convex N translation|interp|screw`), each
//! followed by the distance at its start.
use tocsin::{
    distance, mesh, time_of_contact, ContactOptions, DistanceOptions, Motion, Pose, Vec3,
};

fn ellipsoid(n_lat: usize, n_lon: usize) -> Option<tocsin::TriMesh> {
    let ball = mesh::sphere(1.0, n_lat, n_lon).ok()?;
    let v = ball
        .vertices()
        .iter()
        .map(|p| Vec3::new(p.x, 0.7 * p.y, 0.5 * p.z))
        .collect();
    tocsin::TriMesh::new(v, ball.triangles().to_vec()).ok()
}

fn main() {
    let Some(hull) = ellipsoid(16, 32) else {
        return;
    };
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(2000);
    let only = std::env::args().nth(2);
    let still = Motion::stationary(Pose::IDENTITY);
    let (mut contacts, mut iterations) = (0, 0);
    let t0 = std::time::Instant::now();
    for k in 0..n {
        let a = k as f64 * 0.7;
        let dir = Vec3::new(a.cos(), a.sin(), 0.3 * (1.3 * a).sin()).normalize();
        let side = dir.cross(Vec3::Z).normalize() * (0.2 * (k % 5) as f64);
        let start = Pose::from_axis_angle(Vec3::new(0.2, 1.0, 0.3), 0.1 * a, -2.5 * dir + side);
        let turned =
            Pose::from_axis_angle(Vec3::new(1.0, 0.2, 0.4), 0.5 + 0.1 * a, 2.5 * dir + side);
        let end = Pose {
            rotation: if k % 3 == 0 {
                start.rotation
            } else {
                turned.rotation
            },
            translation: turned.translation,
        };
        let kind = match only.as_deref() {
            Some("translation") => 0,
            Some("interp") => 1,
            Some("screw") => 2,
            _ => k % 3,
        };
        let end = if kind == 0 {
            Pose {
                rotation: start.rotation,
                ..end
            }
        } else {
            end
        };
        let motion = match kind {
            0 => Motion::translation(start, end),
            1 => Motion::interp(start, end, Vec3::ZERO),
            _ => Motion::screw(start, end),
        };
        let Ok(motion) = motion else {
            continue;
        };
        if let Ok(Some(c)) =
            time_of_contact(&hull, &motion, &hull, &still, &ContactOptions::default())
        {
            contacts += 1;
            iterations += c.iterations;
        }
        let _ = distance(
            &hull,
            &start,
            &hull,
            &Pose::IDENTITY,
            &DistanceOptions::default(),
        );
    }
    println!(
        "{:?} per pass and distance, {contacts} contacts, {:.2} iterations each",
        t0.elapsed() / n as u32,
        iterations as f64 / contacts.max(1) as f64
    );
}

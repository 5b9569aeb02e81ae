//! Tied geometry: many triangle pairs at exactly the minimum distance (parallel plates,
//! coincident copies, a plate just above a larger floor, grids offset by half a cell). The
//! search skips pairs that can only tie with its best; the answer must still be the brute-force
//! minimum, to the documented 2e-13 of the scene scale, at scales from 1e-6 to 1e6.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::*;
use tocsin::{distance, mesh, DistanceOptions, Pose, TriMesh, Vec3};

fn check(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose, what: &str) {
    let d = distance(m1, p1, m2, p2, &DistanceOptions::default()).unwrap();
    let (bd, _, _) = brute_distance(m1, p1, m2, p2);
    let scale = m1.bounding_radius()
        + m2.bounding_radius()
        + p1.translation.length()
        + p2.translation.length();
    assert!(
        (d.distance - bd).abs() <= 2e-13 * scale,
        "{what}: {} vs brute force {bd}",
        d.distance
    );
    // The witnesses realise the distance.
    assert!(
        ((d.point2 - d.point1).length() - d.distance).abs() <= 1e-12 * scale,
        "{what}"
    );
}

fn scaled(m: &TriMesh, s: f64) -> TriMesh {
    let v = m.vertices().iter().map(|&v| v * s).collect();
    TriMesh::new(v, m.triangles().to_vec()).unwrap()
}

#[test]
fn parallel_faces_and_copies_give_the_brute_force_minimum() {
    let mut rng = rng(70);
    for &s in &[1e-6, 1.0, 1e6] {
        let plate = scaled(&mesh::plate(1.0, 12).unwrap(), s);
        let floor = scaled(&mesh::plate(2.0, 24).unwrap(), s);
        let one = TriMesh::new(
            vec![Vec3::ZERO, Vec3::X * s, Vec3::Y * s],
            vec![[0, 1, 2]; 300],
        )
        .unwrap();
        for &gap in &[0.1, 8.463e-4, 1e-9] {
            let up = Pose::from_translation(Vec3::new(0.0, 0.0, gap * s));
            check(&plate, &Pose::IDENTITY, &plate, &up, "plates");
            check(&floor, &Pose::IDENTITY, &plate, &up, "plate over floor");
            check(&one, &Pose::IDENTITY, &one, &up, "coincident copies");
            // Half a cell off: vertices over edge midpoints.
            let off = Pose::from_translation(Vec3::new(s / 48.0, s / 48.0, gap * s));
            check(&floor, &Pose::IDENTITY, &plate, &off, "offset grids");
        }
        // Random rigid placements of the same tied pair.
        for _ in 0..10 {
            let p1 = random_pose(&mut rng, 3.0 * s);
            let up = Pose::from_translation(Vec3::new(0.0, 0.0, 0.01 * s));
            check(&floor, &p1, &plate, &p1.mul(&up), "moved plate over floor");
        }
    }
}

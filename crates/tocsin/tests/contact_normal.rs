//! Normals and tolerances where the distance says nothing: contacts found at a distance of
//! rounding level (a tolerance of 1e-300), and degenerate meshes (a single point, radius 0).
//! Regression cases of the hardening issue, which reported `[0, 0, 1]` for both.

#![allow(clippy::unwrap_used, clippy::panic)]

use tocsin::query::contact_time::{effective_tolerance, DISTANCE_RESOLUTION};
use tocsin::{mesh, time_of_contact, ContactOptions, Motion, Pose, TriMesh, Vec3};

fn slide(from: Vec3, to: Vec3) -> Motion {
    Motion::translation(Pose::from_translation(from), Pose::from_translation(to)).unwrap()
}

fn point_mesh(p: Vec3) -> TriMesh {
    TriMesh::new(vec![p], vec![[0, 0, 0]]).unwrap()
}

#[test]
fn box_face_on_at_rounding_tolerance_gets_the_approach_normal() {
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let still = Motion::stationary(Pose::IDENTITY);
    for (dir, tol) in [
        (Vec3::X, 1e-300),
        (Vec3::X, 1e-15),
        (-Vec3::Y, 1e-300),
        (Vec3::Z, 1e-200),
    ] {
        let opts = ContactOptions {
            tolerance: Some(tol),
            ..Default::default()
        };
        let c = time_of_contact(&cube, &slide(-3.0 * dir, 3.0 * dir), &cube, &still, &opts)
            .unwrap()
            .unwrap();
        // Below the distances' resolution a pair that close ends the advancement.
        let scale = 2.0 * cube.bounding_radius() + 3.0;
        assert!(c.distance <= tol.max(DISTANCE_RESOLUTION * scale));
        // Body 1 approaches along `dir`: the normal from body 1 to body 2 is `dir`.
        assert!(
            (c.normal - dir).length() < 1e-6,
            "dir {dir}, tolerance {tol:e}: normal {} at distance {:e}",
            c.normal,
            c.distance
        );
    }
}

#[test]
fn a_point_mesh_has_a_real_default_tolerance_and_normal() {
    let point = point_mesh(Vec3::ZERO);
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let still = Motion::stationary(Pose::IDENTITY);
    let fly = slide(Vec3::new(-3.0, 0.1, 0.2), Vec3::new(3.0, 0.1, 0.2));
    let opts = ContactOptions::default();
    let delta = effective_tolerance(&point, &fly, &cube, &still, &opts);
    // 1e-6 of the box's radius: no longer 1e-3 of the point's zero radius.
    assert!(delta >= 1e-6 * cube.bounding_radius(), "{delta:e}");
    let c = time_of_contact(&point, &fly, &cube, &still, &opts)
        .unwrap()
        .unwrap();
    assert!(c.time > 0.0 && c.time < 0.5);
    assert!((c.normal - Vec3::X).length() < 1e-6, "{}", c.normal);
    // Two points: the scene scale sets the tolerance.
    let other = point_mesh(Vec3::ZERO);
    let delta = effective_tolerance(&point, &fly, &other, &still, &opts);
    assert!(delta > 0.0 && delta.is_finite());
    assert!(time_of_contact(&point, &fly, &other, &still, &opts)
        .unwrap()
        .is_none());
    let head_on = slide(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0));
    let c = time_of_contact(&point, &head_on, &other, &still, &opts)
        .unwrap()
        .unwrap();
    assert!((c.time - 0.5).abs() < 1e-6);
    assert!((c.normal - Vec3::X).length() < 1e-6, "{}", c.normal);
}

/// A tolerance below what the distances resolve (1e-300, or 1e-16 of the scene) ends where a
/// triangle pair comes within [`DISTANCE_RESOLUTION`] of the scene scale: a box a million
/// units wide turning past a small one crawled to the iteration cap before (each step taken
/// against the rounding of the distances). At every scale the answer is found in a few
/// iterations, within that distance, with no collision before it (dense samples of `collide`),
/// and the yes/no query agrees.
#[test]
fn a_tolerance_below_the_distance_resolution_ends_at_it() {
    use tocsin::{collide, motion_is_free};
    for size in [1.0, 1e3, 1e6] {
        let big = mesh::box_mesh(Vec3::splat(0.5 * size)).unwrap();
        let small = mesh::box_mesh(Vec3::splat(0.01 * size)).unwrap();
        let axis = Vec3::new(0.2, 0.3, 1.0).normalize();
        let start = Pose::from_axis_angle(axis, 0.0, Vec3::new(-2.0, 0.1, 0.05) * size);
        let end = Pose::from_axis_angle(axis, 60f64.to_radians(), Vec3::new(2.0, -0.1, 0.0) * size);
        let turn = Motion::screw(start, end).unwrap();
        let still = Motion::stationary(Pose::IDENTITY);
        let scale = big.bounding_radius() + small.bounding_radius() + 2.0 * size * 1.0026;
        for tol in [1e-300, 1e-16 * size] {
            let opts = ContactOptions {
                tolerance: Some(tol),
                ..Default::default()
            };
            assert_eq!(effective_tolerance(&big, &turn, &small, &still, &opts), tol);
            let c = time_of_contact(&big, &turn, &small, &still, &opts)
                .unwrap()
                .unwrap();
            assert!(
                c.iterations < 100,
                "{size} {tol:e}: {} iterations",
                c.iterations
            );
            assert!(
                c.distance <= DISTANCE_RESOLUTION * scale,
                "{size} {tol:e}: distance {:e}",
                c.distance
            );
            for k in 0..=2000 {
                let t = c.time * f64::from(k) / 2000.0;
                if t < c.time {
                    assert!(!collide(&big, &turn.pose_at(t), &small, &Pose::IDENTITY));
                }
            }
            assert!(!motion_is_free(&big, &turn, &small, &still, &opts).unwrap());
        }
    }
}

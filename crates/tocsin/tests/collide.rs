//! `collide` and `collide_pairs` against brute force over all triangle pairs.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::*;
use tocsin::{collide, collide_pairs, mesh, Pose, TriMesh, Vec3};

#[test]
fn random_soups_match_brute_force() {
    let mut rng = rng(10);
    let mut hits = 0;
    for scale in [1e-3, 1.0, 1e4] {
        for i in 0..200 {
            let m1 = random_soup(&mut rng, 1 + i % 40, scale);
            let m2 = random_soup(&mut rng, 1 + (i * 3) % 41, scale);
            let spread = scale * [0.3, 1.0, 3.0][i % 3];
            let (p1, p2) = (random_pose(&mut rng, spread), random_pose(&mut rng, spread));
            let brute = brute_pairs(&m1, &p1, &m2, &p2);
            assert_eq!(
                collide(&m1, &p1, &m2, &p2),
                !brute.is_empty(),
                "collide, case {i} scale {scale}"
            );
            assert_eq!(
                collide_pairs(&m1, &p1, &m2, &p2),
                brute,
                "pairs, case {i} scale {scale}"
            );
            hits += usize::from(!brute.is_empty());
        }
    }
    assert!(
        hits > 50 && hits < 550,
        "the sample should mix colliding and free cases, got {hits}"
    );
}

#[test]
fn knots_match_brute_force() {
    let mut rng = rng(11);
    let knot = mesh::torus_knot(40, 6).unwrap();
    for _ in 0..40 {
        let p2 = random_pose(&mut rng, 4.0);
        let brute = brute_pairs(&knot, &Pose::IDENTITY, &knot, &p2);
        assert_eq!(collide_pairs(&knot, &Pose::IDENTITY, &knot, &p2), brute);
    }
}

#[test]
fn hand_cases() {
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let at = |x: f64, y: f64, z: f64| Pose::from_translation(Vec3::new(x, y, z));
    let c = |p: &Pose| collide(&cube, &Pose::IDENTITY, &cube, p);
    assert!(c(&at(1.0, 0.0, 0.0)), "touching faces");
    assert!(c(&at(1.0, 1.0, 0.0)), "touching edges");
    assert!(c(&at(1.0, 1.0, 1.0)), "touching vertices");
    assert!(!c(&at(1.0 + 1e-9, 0.0, 0.0)), "just apart");
    assert!(c(&Pose::IDENTITY), "identical meshes");
    assert!(c(&at(0.5, 0.3, 0.1)), "overlapping");
    assert!(!c(&at(5.0, 0.0, 0.0)), "far apart");
    // Coplanar overlapping triangles.
    let t1 = TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
    assert!(
        collide(&t1, &Pose::IDENTITY, &t1, &at(0.2, 0.2, 0.0)),
        "coplanar overlap"
    );
    assert!(
        !collide(&t1, &Pose::IDENTITY, &t1, &at(0.6, 0.6, 0.0)),
        "coplanar apart"
    );
    // Nested surfaces do not intersect (no inside in a soup); a crossing one does.
    let big = mesh::box_mesh(Vec3::splat(2.0)).unwrap();
    assert!(!collide(&big, &Pose::IDENTITY, &cube, &Pose::IDENTITY));
    assert!(collide(&big, &Pose::IDENTITY, &cube, &at(2.0, 0.0, 0.0)));
}

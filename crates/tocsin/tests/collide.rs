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
    assert_mixed(
        hits > 50 && hits < 550,
        &format!("the sample should mix colliding and free cases, got {hits}"),
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

/// Near-touching meshes, where the volumes overlap far down the hierarchies and small subtrees
/// are told apart by projecting their corners: knots (and a knot against a coarse soup) moved
/// along their closest points' direction until they are `gap` apart (just apart, or just
/// overlapping for a negative gap), at three scales, against brute force.
#[test]
fn near_touching_matches_brute_force() {
    let mut rng = rng(12);
    let (mut free, mut hit) = (0, 0);
    for scale in [1e-3, 1.0, 1e4] {
        let knot = mesh::torus_knot(40, 6).unwrap();
        let knot = TriMesh::new(
            knot.vertices().iter().map(|&v| v * scale).collect(),
            knot.triangles().to_vec(),
        )
        .unwrap();
        let soup = random_soup(&mut rng, 60, scale);
        for i in 0..40 {
            let other = if i % 3 == 0 { &soup } else { &knot };
            let p2 = random_pose(&mut rng, 4.0 * scale);
            let d =
                tocsin::distance(&knot, &Pose::IDENTITY, other, &p2, &Default::default()).unwrap();
            if d.distance <= 0.0 {
                continue;
            }
            let n = (d.point2 - d.point1) / d.distance;
            for rel in [1e-9, 1e-6, 1e-3, -1e-6] {
                let gap = rel * scale;
                let moved = Pose {
                    rotation: p2.rotation,
                    translation: p2.translation - n * (d.distance - gap),
                };
                let brute = brute_pairs(&knot, &Pose::IDENTITY, other, &moved);
                assert_eq!(
                    collide(&knot, &Pose::IDENTITY, other, &moved),
                    !brute.is_empty(),
                    "case {i} scale {scale} gap {gap}"
                );
                assert_eq!(collide_pairs(&knot, &Pose::IDENTITY, other, &moved), brute);
                if brute.is_empty() {
                    free += 1;
                } else {
                    hit += 1;
                }
            }
        }
    }
    assert!(free > 80 && hit > 20, "free {free}, colliding {hit}");
}

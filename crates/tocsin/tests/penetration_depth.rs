//! Translational penetration depth: the guarantee on every answer (after the translation the
//! meshes do not intersect and are within the tolerance), the global value for boxes against
//! the separating-axis oracle (the exact penetration depth of two convex polytopes is the
//! smallest overlap over their face normals and edge cross products), containment, and the
//! separated case.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;

use tocsin::{
    collide, distance, mesh, penetration_depth, DepthOptions, DepthStatus, DistanceOptions, Mat3,
    Pose, TriMesh, Vec3,
};

fn moved(pose: &Pose, t: Vec3) -> Pose {
    Pose {
        rotation: pose.rotation,
        translation: pose.translation + t,
    }
}

/// Exact penetration depth of two boxes (half extents, poses): the smallest overlap of their
/// projections over the 15 separating-axis candidates.
fn box_depth(h1: Vec3, p1: &Pose, h2: Vec3, p2: &Pose) -> f64 {
    let a = [p1.rotation.x_axis, p1.rotation.y_axis, p1.rotation.z_axis];
    let b = [p2.rotation.x_axis, p2.rotation.y_axis, p2.rotation.z_axis];
    let mut axes: Vec<Vec3> = a.iter().chain(b.iter()).copied().collect();
    for x in a {
        for y in b {
            if let Some(c) = x.cross(y).try_normalize() {
                axes.push(c);
            }
        }
    }
    let d = p2.translation - p1.translation;
    let ext = |axes3: &[Vec3; 3], h: Vec3, u: Vec3| {
        h.x * axes3[0].dot(u).abs() + h.y * axes3[1].dot(u).abs() + h.z * axes3[2].dot(u).abs()
    };
    axes.iter()
        .map(|&u| ext(&a, h1, u) + ext(&b, h2, u) - d.dot(u).abs())
        .fold(f64::INFINITY, f64::min)
}

fn check_answer(
    m1: &TriMesh,
    p1: &Pose,
    m2: &TriMesh,
    p2: &Pose,
    r: &tocsin::PenetrationDepth,
    tol: f64,
    case: &str,
) {
    let after = moved(p2, r.translation);
    assert!(
        !collide(m1, p1, m2, &after),
        "{case}: still intersecting after the translation"
    );
    let d = distance(m1, p1, m2, &after, &DistanceOptions::default())
        .unwrap()
        .distance;
    assert!(
        d <= tol * (1.0 + 1e-9),
        "{case}: {d} apart after the translation (tolerance {tol})"
    );
    let extra = r.translation.length() - r.depth;
    if r.exact {
        // The exact path moves half the tolerance farther, so the bodies end apart.
        assert!(
            extra >= 0.0 && extra <= tol,
            "{case}: translation {extra} past the depth"
        );
    } else {
        assert!(extra.abs() < 1e-12);
    }
}

#[test]
fn boxes_reach_the_separating_axis_depth() {
    let mut rng = common::rng(41);
    let mut count = 0;
    for case in 0..40 {
        let h1 = Vec3::new(0.5, 0.3, 0.8);
        let h2 = Vec3::new(0.4, 0.6, 0.2);
        let (b1, b2) = (mesh::box_mesh(h1).unwrap(), mesh::box_mesh(h2).unwrap());
        let p1 = common::random_pose(&mut rng, 0.2);
        let p2 = common::random_pose(&mut rng, 0.6);
        let exact = box_depth(h1, &p1, h2, &p2);
        if exact <= 1e-3 {
            continue;
        }
        count += 1;
        let r = penetration_depth(&b1, &p1, &b2, &p2, &DepthOptions::default()).unwrap();
        let tol = 1e-3 * 0.2f64.min(0.8);
        let tol = tol.max(1e-3 * b1.bounding_radius().min(b2.bounding_radius()));
        check_answer(&b1, &p1, &b2, &p2, &r, tol, &format!("case {case}"));
        // A separating translation is never shorter than the depth (up to the tolerance), and
        // the refinement reaches the global value for boxes.
        assert!(
            r.depth >= exact - 2.0 * tol,
            "case {case}: {} below the exact {exact}",
            r.depth
        );
        assert!(
            r.depth <= exact * 1.02 + 2.0 * tol,
            "case {case}: {} vs exact {exact} ({:?})",
            r.depth,
            r.status
        );
    }
    assert!(count >= 20);
}

#[test]
fn soups_get_a_separating_touching_translation() {
    let mut rng = common::rng(43);
    for case in 0..15 {
        let a = common::random_soup(&mut rng, 30, 1.0);
        let b = common::random_soup(&mut rng, 30, 1.0);
        let (pa, pb) = (
            common::random_pose(&mut rng, 0.3),
            common::random_pose(&mut rng, 0.3),
        );
        let r = penetration_depth(&a, &pa, &b, &pb, &DepthOptions::default()).unwrap();
        if r.status == DepthStatus::Separated {
            assert!(!collide(&a, &pa, &b, &pb));
            continue;
        }
        let tol = 1e-3 * a.bounding_radius().min(b.bounding_radius());
        check_answer(&a, &pa, &b, &pb, &r, tol, &format!("soup {case}"));
    }
}

#[test]
fn containment_separated_and_a_knot_through_a_knot() {
    // A small box inside a big one: the surfaces do not intersect, but it is inside: the depth
    // takes it out (about the distance to the nearest face plus its own size).
    let (big, small) = (
        mesh::box_mesh(Vec3::splat(1.0)).unwrap(),
        mesh::box_mesh(Vec3::splat(0.1)).unwrap(),
    );
    let inside = Pose::from_translation(Vec3::new(0.6, 0.0, 0.0));
    let r = penetration_depth(
        &big,
        &Pose::IDENTITY,
        &small,
        &inside,
        &DepthOptions::default(),
    )
    .unwrap();
    assert_eq!(r.status, DepthStatus::Converged);
    assert!((r.depth - 0.5).abs() < 0.01, "{}", r.depth); // out through x = 1: 1 - 0.6 + 0.1
    assert!(r.direction.x > 0.99);
    let apart = Pose::from_translation(Vec3::new(5.0, 0.0, 0.0));
    let s = penetration_depth(
        &big,
        &Pose::IDENTITY,
        &small,
        &apart,
        &DepthOptions::default(),
    )
    .unwrap();
    assert_eq!((s.status, s.depth), (DepthStatus::Separated, 0.0));
    let bad = DepthOptions {
        tolerance: Some(-1.0),
        ..DepthOptions::default()
    };
    assert!(penetration_depth(&big, &Pose::IDENTITY, &small, &inside, &bad).is_err());
    let knot = mesh::torus_knot(120, 8).unwrap();
    let p2 = Pose {
        rotation: Mat3::from_axis_angle(Vec3::new(0.3, 1.0, 0.2).normalize(), 0.9),
        translation: Vec3::new(0.4, 0.2, 0.0),
    };
    let k =
        penetration_depth(&knot, &Pose::IDENTITY, &knot, &p2, &DepthOptions::default()).unwrap();
    let tol = 1e-3 * knot.bounding_radius();
    check_answer(&knot, &Pose::IDENTITY, &knot, &p2, &k, tol, "knots");
    assert!(k.depth > 0.0 && k.depth < 2.0 * knot.bounding_radius());
}

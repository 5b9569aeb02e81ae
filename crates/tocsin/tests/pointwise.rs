//! Pointwise penetration depth against a closed form (two overlapping boxes) and against dense
//! sampling: every triangle of both surfaces sampled, the samples inside the other body (exact
//! winding number) measured against its surface by brute force.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;

use common::brute_point_distance;
use tocsin::{
    mesh, pointwise_penetration, time_of_contact, winding_number, ContactOptions, Motion, Pose,
    TriMesh, Vec3, WindingOptions,
};

const EXACT: WindingOptions = WindingOptions {
    beta: f64::INFINITY,
};

/// The largest distance to B's surface over samples of A's surface inside B.
fn dense(a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose, k: usize) -> f64 {
    let mut pts = Vec::new();
    for i in 0..a.num_triangles() {
        let t = a.triangle(i).map(|p| pa.transform_point(p));
        for u in 0..=k {
            for v in 0..=(k - u) {
                let (s, r) = (u as f64 / k as f64, v as f64 / k as f64);
                pts.push(t[0] + (t[1] - t[0]) * s + (t[2] - t[0]) * r);
            }
        }
    }
    let w = winding_number(b, pb, &pts, &EXACT).unwrap();
    pts.iter()
        .zip(&w)
        .filter(|(_, w)| w.abs() > 0.5)
        .map(|(p, _)| brute_point_distance(*p, b, pb))
        .fold(0.0, f64::max)
}

#[test]
fn two_overlapping_boxes() {
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let shifted = Pose::from_translation(Vec3::new(0.8, 0.0, 0.0));
    let r = pointwise_penetration(&cube, &Pose::IDENTITY, &cube, &shifted, 1e-6).unwrap();
    assert!((r.depth - 0.2).abs() < 1e-6, "{}", r.depth);
    assert!(r.upper_bound - r.depth <= 1e-6 * (1.0 + 1e-9));
    assert!(((r.point2 - r.point1).length() - r.depth).abs() < 1e-12);
    let apart = Pose::from_translation(Vec3::new(3.0, 0.0, 0.0));
    let s = pointwise_penetration(&cube, &Pose::IDENTITY, &cube, &apart, 1e-6).unwrap();
    assert_eq!(s.depth, 0.0);
    assert!(pointwise_penetration(&cube, &Pose::IDENTITY, &cube, &apart, 0.0).is_err());
}

#[test]
fn against_dense_sampling_on_closed_meshes() {
    let mut rng = common::rng(77);
    let sphere = mesh::sphere(0.6, 8, 16).unwrap();
    let cube = mesh::box_mesh(Vec3::new(0.5, 0.3, 0.4)).unwrap();
    for case in 0..8 {
        let (pa, pb) = (
            common::random_pose(&mut rng, 0.3),
            common::random_pose(&mut rng, 0.3),
        );
        let (a, b) = if case % 2 == 0 {
            (&sphere, &cube)
        } else {
            (&cube, &cube)
        };
        let e = 1e-4;
        let r = pointwise_penetration(a, &pa, b, &pb, e).unwrap();
        let sampled = dense(a, &pa, b, &pb, 10).max(dense(b, &pb, a, &pa, 10));
        assert!(
            sampled <= r.upper_bound + 1e-12,
            "case {case}: sampled {sampled} > {}",
            r.upper_bound
        );
        assert!(
            r.depth >= sampled - 0.02,
            "case {case}: {} well below sampling {sampled}",
            r.depth
        );
        if r.depth > 0.0 {
            // The witness is inside the other body and at the depth from its surface.
            let (other, po) = if r.from_first { (b, &pb) } else { (a, &pa) };
            let w = winding_number(other, po, &[r.point1], &EXACT).unwrap()[0];
            assert!(w > 0.5, "case {case}: witness not inside ({w})");
            assert!((brute_point_distance(r.point1, other, po) - r.depth).abs() < 1e-9);
        }
    }
}

#[test]
fn knot_against_a_moved_copy_within_the_bound_of_dense_sampling() {
    // The copy overlaps the knot along all of its length: every triangle is refined.
    let knot = mesh::torus_knot(40, 5).unwrap();
    let e = 1e-3 * knot.bounding_radius();
    let moved = Pose::from_axis_angle(Vec3::new(0.2, 1.0, -0.4), 0.1, Vec3::new(0.3, 0.1, 0.05));
    let r = pointwise_penetration(&knot, &Pose::IDENTITY, &knot, &moved, e).unwrap();
    assert!(r.upper_bound - r.depth <= e * (1.0 + 1e-9));
    let sampled = dense(&knot, &Pose::IDENTITY, &knot, &moved, 6).max(dense(
        &knot,
        &moved,
        &knot,
        &Pose::IDENTITY,
        6,
    ));
    assert!(
        sampled <= r.upper_bound + 1e-12,
        "sampled {sampled} > {}",
        r.upper_bound
    );
    assert!(
        r.depth >= sampled - e,
        "{} below sampling {sampled}",
        r.depth
    );
    let po = if r.from_first { moved } else { Pose::IDENTITY };
    assert!(winding_number(&knot, &po, &[r.point1], &EXACT).unwrap()[0].abs() > 0.5);
    assert!((brute_point_distance(r.point1, &knot, &po) - r.depth).abs() < 1e-9);
}

#[test]
fn shallow_penetrations_of_a_knot_within_the_bound_of_dense_sampling() {
    // A turned copy touching the knot from a random direction, pushed in by 2% or 8% of the
    // radius: the inside parts are small patches, and most of either surface lies outside the
    // other, next to parts inside (the classification of pieces off the other surface, shared
    // between neighbours, is what this exercises).
    let knot = mesh::torus_knot(40, 5).unwrap();
    let radius = knot.bounding_radius();
    let e = 1e-3 * radius;
    let mut rng = common::rng(2024);
    let mut deep = 0;
    for case in 0..6 {
        let u = common::random_unit(&mut rng);
        let rot = common::random_rotation(&mut rng);
        let far = 4.0 * radius + 1.0;
        let motion = Motion::translation(
            Pose::new(rot, u * far).unwrap(),
            Pose::new(rot, Vec3::ZERO).unwrap(),
        )
        .unwrap();
        let still = Motion::stationary(Pose::IDENTITY);
        let contact = time_of_contact(&knot, &still, &knot, &motion, &ContactOptions::default())
            .unwrap()
            .unwrap();
        let push = if case % 2 == 0 { 0.02 } else { 0.08 } * radius;
        let pose = Pose::new(rot, u * (far * (1.0 - contact.time) - push)).unwrap();
        let r = pointwise_penetration(&knot, &Pose::IDENTITY, &knot, &pose, e).unwrap();
        let sampled = dense(&knot, &Pose::IDENTITY, &knot, &pose, 8).max(dense(
            &knot,
            &pose,
            &knot,
            &Pose::IDENTITY,
            8,
        ));
        assert!(r.upper_bound - r.depth <= e * (1.0 + 1e-9));
        assert!(
            sampled <= r.upper_bound + 1e-12,
            "case {case}: sampled {sampled} > {}",
            r.upper_bound
        );
        assert!(
            r.depth >= sampled - e,
            "case {case}: {} below sampling {sampled}",
            r.depth
        );
        if sampled > 0.25 * push {
            deep += 1;
        }
    }
    // The cases penetrate: the sampled depth is a fair part of the push in most of them.
    assert!(deep >= 4, "only {deep} cases penetrate");
}

#[test]
fn soups_with_degenerate_and_duplicated_triangles_keep_the_contract() {
    // Random soups (points, segments, duplicates, no closure): inside is only the winding
    // number's there, so the value is not compared with sampling; what always holds is
    // checked: a finite depth within the error of its upper bound, and a witness pair at
    // that distance whose second point is on the other mesh.
    let mut rng = common::rng(31);
    let mut deep = 0;
    for case in 0..12 {
        let a = common::random_soup(&mut rng, 40 + 10 * case, 1.0);
        let b = common::random_soup(&mut rng, 30 + 5 * case, 0.8);
        let (pa, pb) = (
            common::random_pose(&mut rng, 0.3),
            common::random_pose(&mut rng, 0.3),
        );
        let e = 1e-3;
        let r = pointwise_penetration(&a, &pa, &b, &pb, e).unwrap();
        assert!(
            r.depth.is_finite() && r.depth >= 0.0,
            "case {case}: {}",
            r.depth
        );
        assert!(
            r.upper_bound >= r.depth && r.upper_bound - r.depth <= e * (1.0 + 1e-9),
            "case {case}: {} against {}",
            r.depth,
            r.upper_bound
        );
        if r.depth > 0.0 {
            deep += 1;
            let (own, other, po, pt) = if r.from_first {
                (&a, &b, &pb, &pa)
            } else {
                (&b, &a, &pa, &pb)
            };
            assert!((r.point2 - r.point1).length() - r.depth <= 1e-9);
            assert!(brute_point_distance(r.point2, other, po) <= 1e-9);
            assert!((brute_point_distance(r.point1, other, po) - r.depth).abs() <= 1e-9);
            assert!(brute_point_distance(r.point1, own, pt) <= 1e-9);
        }
    }
    // Soups this dense overlap: most cases have points inside the other's winding number.
    assert!(deep >= 6, "{deep} of 12 cases with a depth");
}

/// An error bound below the distances' accuracy (1e-300, or 1e-16 of the size) is raised to it
/// ([`tocsin::query::contact_time::DISTANCE_RESOLUTION`] of the radii plus the poses' distances
/// from the origin): with 1e-16 on a knot's depth of 0.37 the search subdivided for minutes,
/// its pieces' upper bounds unable to come within a bound that rounds away. Now both the
/// pointwise depth and the Hausdorff distance answer, their bracket within that accuracy and
/// holding the default bound's answer.
#[test]
fn an_error_bound_below_the_distance_accuracy_is_raised_to_it() {
    use tocsin::hausdorff_distance;
    use tocsin::query::contact_time::DISTANCE_RESOLUTION;
    let knot = mesh::torus_knot(100, 8).unwrap();
    let mut rng = common::rng(16);
    for size in [1.0, 1e6] {
        let k = common::scaled(&knot, size);
        for _ in 0..3 {
            let (pa, pb) = common::overlapping_poses(&mut rng, size);
            let accuracy =
                DISTANCE_RESOLUTION * (2.0 * k.bounding_radius() + pb.translation.length());
            let coarse = 1e-4 * k.bounding_radius();
            for bound in [1e-300, 1e-16 * size] {
                let fine = pointwise_penetration(&k, &pa, &k, &pb, bound).unwrap();
                let rough = pointwise_penetration(&k, &pa, &k, &pb, coarse).unwrap();
                assert!(fine.upper_bound - fine.depth <= accuracy * (1.0 + 1e-9));
                assert!(fine.depth >= rough.depth - 1e-9 * size);
                assert!(fine.depth <= rough.upper_bound + 1e-9 * size);
                let h = hausdorff_distance(&k, &pa, &k, &pb, bound, true).unwrap();
                assert!(h.upper_bound - h.distance <= accuracy * (1.0 + 1e-9));
            }
        }
    }
}

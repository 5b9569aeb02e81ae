//! The supported coordinate range (1e-30 to 1e30, `math::MAX_COORDINATE` and `MIN_SCALE`): at
//! both ends every query gives its unit-scale answer scaled, and past them meshes and poses are
//! refused. The cases are the ones a sweep found wrong past the old range's safe part: a point
//! of one triangle over the middle of another's face (the nearest points inside a face), a
//! translation through a triangle, screw motions of knots, the inside of a sphere.

#![allow(clippy::unwrap_used, clippy::panic)]

use tocsin::{
    collide, contains, distance, hausdorff_distance, mesh, pointwise_penetration, time_of_contact,
    winding_number, ContactOptions, DistanceOptions, Motion, Pose, TriMesh, Vec3, WindingOptions,
};

/// `m` with every vertex multiplied by `s`.
fn scaled(m: &TriMesh, s: f64) -> TriMesh {
    let v = m.vertices().iter().map(|p| *p * s).collect();
    TriMesh::new(v, m.triangles().to_vec()).unwrap()
}

/// A big triangle in z = 0 and a small one whose nearest corner is 1 above its face.
fn face_pair() -> (TriMesh, TriMesh) {
    let big = TriMesh::new(
        vec![
            Vec3::ZERO,
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 4.0, 0.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let small = TriMesh::new(
        vec![
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.5, 1.0, 2.0),
            Vec3::new(1.0, 1.5, 2.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    (big, small)
}

/// Every query's answer at scale `s`, divided by `s` where it is a length: the face pair's
/// distance and collision, its time of contact along a translation down through the big
/// triangle, the times of contact of knot pairs on screw motions, and a sphere pushed into
/// another's pointwise depth, Hausdorff distance, winding numbers and inside test.
fn answers(s: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let (big, small) = face_pair();
    let (big, small) = (scaled(&big, s), scaled(&small, s));
    let id = Pose::IDENTITY;
    let d = distance(&big, &id, &small, &id, &DistanceOptions::default()).unwrap();
    out.push(d.distance / s);
    out.push(f64::from(u8::from(collide(&big, &id, &small, &id))));
    let still = Motion::stationary(id);
    let down = Motion::translation(id, Pose::from_translation(Vec3::new(0.0, 0.0, -2.0 * s)));
    let c = time_of_contact(
        &big,
        &still,
        &small,
        &down.unwrap(),
        &ContactOptions::default(),
    );
    out.push(c.unwrap().map_or(-1.0, |c| c.time));
    let knot = scaled(&mesh::torus_knot(30, 4).unwrap(), s);
    for k in 0..4 {
        let axis = Vec3::new(0.3, 1.0 - 0.4 * k as f64, 0.5).normalize();
        let start = Pose::from_axis_angle(axis, 0.4 * k as f64, Vec3::new(9.0, 1.0, -0.5) * s);
        let end = Pose::from_axis_angle(axis, 1.5 + 0.4 * k as f64, Vec3::new(0.5, 0.2, 0.1) * s);
        let screw = Motion::screw(start, end).unwrap();
        let c = time_of_contact(&knot, &still, &knot, &screw, &ContactOptions::default());
        out.push(c.unwrap().map_or(-1.0, |c| c.time));
    }
    let ball = scaled(&mesh::sphere(1.0, 12, 24).unwrap(), s);
    let pushed = Pose::from_translation(Vec3::new(0.7, 0.2, -0.1) * s);
    let pw = pointwise_penetration(&ball, &id, &ball, &pushed, 1e-4 * s).unwrap();
    out.push(pw.depth / s);
    let h = hausdorff_distance(&ball, &id, &knot, &pushed, 1e-4 * s, true).unwrap();
    out.push(h.distance / s);
    let points: Vec<Vec3> = (0..40)
        .map(|k| Vec3::new(0.05 * k as f64 - 1.0, 0.3, 0.02 * k as f64 - 0.4) * s)
        .collect();
    let exact = WindingOptions {
        beta: f64::INFINITY,
    };
    out.extend(winding_number(&ball, &id, &points, &exact).unwrap());
    out.extend(
        contains(&ball, &id, &points)
            .into_iter()
            .map(|b| f64::from(u8::from(b))),
    );
    out
}

#[test]
fn both_ends_of_the_range_give_the_unit_answers() {
    let unit = answers(1.0);
    // The face pair: 1 apart (the small triangle's corner over the face), touching after half
    // the way down; every screw meets (times in (0, 1)); the ball's centre inside, the line's
    // ends outside.
    assert_eq!(unit[0], 1.0);
    assert_eq!(unit[1], 0.0);
    assert!((unit[2] - 0.5).abs() < 1e-3, "{}", unit[2]);
    assert!(unit[3..7].iter().all(|&t| t > 0.0 && t < 1.0), "{unit:?}");
    assert!(unit[7] > 0.5 && unit[8] > 0.5, "{unit:?}");
    // Scales that put the largest coordinates at the range's ends: 1e-30 (the sphere's radius)
    // and 9e29 (the screws' starts).
    for s in [1e-30, 1e29] {
        let got = answers(s);
        assert_eq!(got.len(), unit.len());
        for (k, (g, u)) in got.iter().zip(&unit).enumerate() {
            // Times of contact within the tolerance's band, lengths within the errors asked
            // for (1e-4) or to rounding, winding numbers to rounding, verdicts exactly.
            let allowed = match k {
                0 => 1e-12,
                1 => 0.0,
                2..=6 => 1e-3,
                7 | 8 => 2e-4,
                _ => 1e-9,
            };
            assert!(
                (g - u).abs() <= allowed,
                "scale {s}, answer {k}: {g} against {u}"
            );
        }
    }
}

#[test]
fn past_the_range_meshes_and_poses_are_refused() {
    let (big, _) = face_pair();
    for s in [1e31, 1e-31] {
        let v: Vec<Vec3> = big.vertices().iter().map(|p| *p * s).collect();
        assert!(TriMesh::new(v, vec![[0, 1, 2]]).is_err(), "scale {s}");
    }
    assert!(Pose::new(tocsin::Mat3::IDENTITY, Vec3::new(0.0, 2e30, 0.0)).is_err());
    // The ends themselves are accepted.
    assert!(scaled(&big, 2.5e29).vertices().len() == 3);
    assert!(scaled(&big, 2.5e-31).vertices().len() == 3);
}

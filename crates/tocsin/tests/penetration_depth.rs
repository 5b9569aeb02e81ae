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
    // Directions are allocated at once: too many is an error, not an aborted allocation.
    for directions in [
        tocsin::query::penetration::depth::MAX_DIRECTIONS + 1,
        usize::MAX,
    ] {
        let many = DepthOptions {
            directions,
            ..DepthOptions::default()
        };
        assert!(penetration_depth(&big, &Pose::IDENTITY, &small, &inside, &many).is_err());
    }
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

/// A soup made of boxes (half extents, centres), their surfaces merged as they are.
fn boxes(parts: &[(Vec3, Vec3)]) -> TriMesh {
    let (mut v, mut t) = (Vec::new(), Vec::new());
    for (h, c) in parts {
        let b = mesh::box_mesh(*h).unwrap();
        let base = v.len() as u32;
        v.extend(b.vertices().iter().map(|p| *p + *c));
        t.extend(b.triangles().iter().map(|f| f.map(|i| i + base)));
    }
    TriMesh::new(v, t).unwrap()
}

/// Whether body 2 translated by `t` penetrates body 1 (surfaces intersect or one contains the
/// other), by the exact `collide` and the winding number.
fn penetrates(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose, t: Vec3) -> bool {
    let after = moved(p2, t);
    if collide(m1, p1, m2, &after) {
        return true;
    }
    let c2 = after.transform_point(m2.vertices()[0]);
    let c1 = p1.transform_point(m1.vertices()[0]);
    tocsin::contains(m1, p1, &[c2])[0] || tocsin::contains(m2, &after, &[c1])[0]
}

/// The directional depth along `u`: the smallest `s >= 0` at which body 2 moved by `s u` no
/// longer penetrates, by sampling `s` on a grid and bisecting the first change.
fn directional(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose, u: Vec3, far: f64) -> f64 {
    let n = 200;
    let mut prev = 0.0;
    for k in 1..=n {
        let s = far * k as f64 / n as f64;
        if !penetrates(m1, p1, m2, p2, u * s) {
            let (mut lo, mut hi) = (prev, s);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if penetrates(m1, p1, m2, p2, u * mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return hi;
        }
        prev = s;
    }
    far
}

/// Hand cases: hooked L shapes (the depth is not along the centroids' line), a peg deep in a
/// hole, a thin plate through a box, identical meshes at the same pose, duplicated triangles.
/// Every answer separates the meshes within the tolerance and is compared with the best of 300
/// sampled directions (dense sampling plus bisection with the exact collide): the factor is
/// printed, and must stay below 1.25.
#[test]
fn hand_cases_against_sampled_directions() {
    let l_shape = boxes(&[
        (Vec3::new(1.0, 0.2, 0.2), Vec3::new(0.0, 0.0, 0.0)),
        (Vec3::new(0.2, 0.8, 0.2), Vec3::new(0.8, 0.6, 0.0)),
    ]);
    let hole = boxes(&[
        (Vec3::new(0.3, 1.0, 0.5), Vec3::new(-0.5, 0.0, 0.0)),
        (Vec3::new(0.3, 1.0, 0.5), Vec3::new(0.5, 0.0, 0.0)),
        (Vec3::new(0.8, 0.2, 0.5), Vec3::new(0.0, -0.8, 0.0)),
    ]);
    let peg = mesh::box_mesh(Vec3::new(0.15, 0.7, 0.15)).unwrap();
    let plate = mesh::plate(1.5, 4).unwrap();
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let mut dup_v = cube.vertices().to_vec();
    dup_v.extend_from_slice(cube.vertices());
    let mut dup_t = cube.triangles().to_vec();
    dup_t.extend(cube.triangles().iter().map(|f| f.map(|i| i + 8)));
    let duplicated = TriMesh::new(dup_v, dup_t).unwrap();
    let turn = |deg: f64, t: Vec3| Pose::from_axis_angle(Vec3::Z, deg.to_radians(), t);
    let cases: Vec<(&str, &TriMesh, &TriMesh, Pose)> = vec![
        (
            "hooked L",
            &l_shape,
            &l_shape,
            turn(180.0, Vec3::new(1.4, 1.0, 0.1)),
        ),
        (
            "peg in hole",
            &hole,
            &peg,
            Pose::from_translation(Vec3::new(0.1, 0.3, 0.0)),
        ),
        (
            "plate through box",
            &cube,
            &plate,
            Pose::from_axis_angle(Vec3::X, 1.2, Vec3::new(0.1, 0.0, 0.0)),
        ),
        ("same pose", &cube, &cube, Pose::IDENTITY),
        (
            "duplicated",
            &duplicated,
            &l_shape,
            Pose::from_translation(Vec3::new(0.3, 0.2, 0.1)),
        ),
    ];
    let mut rng = common::rng(5);
    for (name, m1, m2, p2) in cases {
        let p1 = Pose::IDENTITY;
        let r = penetration_depth(m1, &p1, m2, &p2, &DepthOptions::default()).unwrap();
        assert_ne!(r.status, DepthStatus::Separated, "{name}");
        let tol = 1e-3 * m1.bounding_radius().min(m2.bounding_radius());
        check_answer(m1, &p1, m2, &p2, &r, tol, name);
        let far = 2.5 * (m1.bounding_radius() + m2.bounding_radius());
        let best = (0..300)
            .map(|_| directional(m1, &p1, m2, &p2, common::random_unit(&mut rng), far))
            .fold(f64::INFINITY, f64::min);
        let factor = r.depth / best;
        eprintln!(
            "{name}: depth {:.4}, best of 300 sampled directions {best:.4}, factor {factor:.3}",
            r.depth
        );
        assert!(factor < 1.25, "{name}: {} vs sampled {best}", r.depth);
    }
}

/// Shallow penetrations (1% and 3% of the radius) of a knot and a turned copy, pushed in along
/// a random direction `u` from a touching start: the answer leaves the bodies apart by at most
/// 1e-3 of the depth (the final polish; the default tolerance alone, 1e-3 of the radius, is a
/// tenth of a 1% depth), and is within 1% of the directional depth along `u` (dense sampling
/// plus bisection with the exact collide and the winding number), which bounds the true
/// depth from above.
#[test]
fn shallow_depths_end_close() {
    let knot = mesh::torus_knot(100, 8).unwrap();
    let r = knot.bounding_radius();
    let mut rng = common::rng(19);
    let p1 = Pose::IDENTITY;
    let mut checked = 0;
    for case in 0..6 {
        let f = [0.01, 0.03][case % 2];
        let u = common::random_unit(&mut rng);
        let rot = common::random_rotation(&mut rng);
        // Touching from outside along u: the exact directional depth of the copy at the
        // centre, then pushed back in by f R.
        let centred = Pose::new(rot, Vec3::ZERO).unwrap();
        let far = 2.5 * (2.0 * r);
        let touch = directional(&knot, &p1, &knot, &centred, u, far);
        let p2 = moved(&centred, u * (touch - f * r));
        let r_depth = penetration_depth(&knot, &p1, &knot, &p2, &DepthOptions::default()).unwrap();
        assert_ne!(r_depth.status, DepthStatus::Separated, "case {case}");
        let after = moved(&p2, r_depth.translation);
        assert!(!collide(&knot, &p1, &knot, &after), "case {case}");
        let gap = distance(&knot, &p1, &knot, &after, &DistanceOptions::default())
            .unwrap()
            .distance;
        assert!(
            gap <= 1e-3 * r_depth.depth * (1.0 + 1e-9),
            "case {case}: {gap} apart at depth {}",
            r_depth.depth
        );
        let along_u = directional(&knot, &p1, &knot, &p2, u, far);
        assert!(
            r_depth.depth <= 1.01 * along_u,
            "case {case}: depth {} against {along_u} along u",
            r_depth.depth
        );
        checked += 1;
    }
    assert_eq!(checked, 6);
}

#[test]
fn far_from_the_origin_and_at_extreme_scales() {
    // Soups, boxes and a knot against a sphere, of sizes 1e-6 to 1e6, up to 1e6 of their size
    // from the origin: every answer separates the meshes and leaves them within the tolerance
    // (to the rounding of the world coordinates there), with a unit direction.
    use rand::Rng;
    let mut rng = common::rng(26);
    let knot = mesh::torus_knot(40, 6).unwrap();
    let mut penetrating = 0;
    for case in 0..45 {
        let scale = 10f64.powi(rng.random_range(-6..=6));
        let offset = 10f64.powi(rng.random_range(0..=6)) * scale * common::random_unit(&mut rng);
        let (a, b) = match case % 3 {
            0 => (
                common::random_soup(&mut rng, 25, scale),
                common::random_soup(&mut rng, 25, scale),
            ),
            1 => (
                mesh::box_mesh(Vec3::new(0.5, 0.3, 0.8) * scale).unwrap(),
                mesh::box_mesh(Vec3::new(0.4, 0.6, 0.2) * scale).unwrap(),
            ),
            _ => (
                TriMesh::new(
                    knot.vertices().iter().map(|&v| v * (scale / 6.0)).collect(),
                    knot.triangles().to_vec(),
                )
                .unwrap(),
                mesh::sphere(0.5 * scale, 8, 16).unwrap(),
            ),
        };
        let near = |rng: &mut rand_chacha::ChaCha8Rng| Pose {
            rotation: common::random_rotation(rng),
            translation: offset + common::random_unit(rng) * 0.3 * scale,
        };
        let (pa, pb) = (near(&mut rng), near(&mut rng));
        let r = penetration_depth(&a, &pa, &b, &pb, &DepthOptions::default()).unwrap();
        let label = format!(
            "case {case}: scale {scale:e}, {:e} from the origin",
            offset.length()
        );
        if r.status == DepthStatus::Separated {
            assert!(
                !collide(&a, &pa, &b, &pb),
                "{label}: separated but colliding"
            );
            continue;
        }
        penetrating += 1;
        let after = moved(&pb, r.translation);
        assert!(!collide(&a, &pa, &b, &after), "{label}: still intersecting");
        let tol = 1e-3 * a.bounding_radius().min(b.bounding_radius());
        let rounding = 16.0 * f64::EPSILON * (offset.length() + scale);
        let d = distance(&a, &pa, &b, &after, &DistanceOptions::default())
            .unwrap()
            .distance;
        assert!(
            d <= tol * (1.0 + 1e-9) + rounding,
            "{label}: {d} apart (tolerance {tol})"
        );
        assert!(
            r.depth == 0.0 || (r.direction.length() - 1.0).abs() < 1e-12,
            "{label}"
        );
    }
    assert!(penetrating > 30, "{penetrating} of 45 penetrate");
}

/// A tolerance below twice the distances' accuracy (1e-300, or 1e-20 of the size) is raised to
/// it: the touching translations had ended at rounding level, where the bodies still touched
/// (`collide` true after the translation on 21 of 45 knot pairs at sizes 1 to 1e6 by the local
/// search, and on most box pairs by the exact convex path). Every answer now separates, within
/// the raised tolerance, and the exact depth is the one the default tolerance gives.
#[test]
fn a_tolerance_below_the_distance_accuracy_still_separates() {
    use tocsin::query::contact_time::DISTANCE_RESOLUTION;
    let mut rng = common::rng(40);
    let knot = mesh::torus_knot(100, 8).unwrap();
    let mut penetrating = 0;
    for case in 0..36 {
        let size = [1.0, 1e3, 1e6][case % 3];
        let a = if case % 2 == 0 {
            common::scaled(&knot, size)
        } else {
            mesh::box_mesh(Vec3::new(0.4, 0.3, 0.2) * size).unwrap()
        };
        let b = a.clone();
        let (pa, pb) = common::overlapping_poses(&mut rng, size);
        for tolerance in [1e-300, 1e-20 * size] {
            let options = DepthOptions {
                tolerance: Some(tolerance),
                ..DepthOptions::default()
            };
            let r = penetration_depth(&a, &pa, &b, &pb, &options).unwrap();
            if r.status == DepthStatus::Separated {
                continue;
            }
            penetrating += 1;
            let raised = 2.0
                * DISTANCE_RESOLUTION
                * (a.bounding_radius() + b.bounding_radius() + pb.translation.length());
            check_answer(
                &a,
                &pa,
                &b,
                &pb,
                &r,
                raised,
                &format!("case {case} {tolerance:e}"),
            );
            if r.exact {
                let default = penetration_depth(&a, &pa, &b, &pb, &DepthOptions::default());
                assert_eq!(r.depth, default.unwrap().depth, "case {case}");
            }
        }
    }
    assert!(penetrating >= 40, "{penetrating}");
}

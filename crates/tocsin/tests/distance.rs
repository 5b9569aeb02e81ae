//! `distance`: the triangle kernel against an independent formulation, and the hierarchy
//! against brute force over all triangle pairs, on seeded random soups and hand cases.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::*;
use rand::Rng;
use tocsin::query::distance::{distance_triangle_triangle, intersect_triangle_triangle};
use tocsin::{
    distance, distance_with_cache, mesh, DistanceCache, DistanceOptions, Pose, TriMesh, Vec3,
};

fn random_triangle_pair(rng: &mut impl Rng, case: usize) -> ([Vec3; 3], [Vec3; 3]) {
    let mut p = || {
        Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    };
    let a = [p(), p(), p()];
    let mut b = [p(), p(), p()];
    match case % 8 {
        0 => b.iter_mut().for_each(|v| v.z = a[0].z), // b in a horizontal plane
        1 => {
            // coplanar with a
            let n = (a[1] - a[0]).cross(a[2] - a[0]).normalize();
            b.iter_mut().for_each(|v| *v -= n * n.dot(*v - a[0]));
        }
        2 => {
            // parallel to a, offset
            let n = (a[1] - a[0]).cross(a[2] - a[0]).normalize();
            b.iter_mut()
                .for_each(|v| *v -= n * (n.dot(*v - a[0]) - 0.1));
        }
        3 => b[0] = a[1],                        // shared vertex
        4 => b[2] = b[1],                        // b is a segment
        5 => b = [b[0]; 3],                      // b is a point
        6 => b[2] = b[0] + (b[1] - b[0]) * 0.37, // collinear corners
        _ => {}
    }
    (a, b)
}

#[test]
fn triangle_kernel_matches_independent_formulation() {
    let mut rng = rng(1);
    for scale in [1e-3, 1.0, 1e4] {
        for case in 0..4000 {
            let (a, b) = random_triangle_pair(&mut rng, case);
            let (a, b) = (a.map(|v| v * scale), b.map(|v| v * scale));
            let k = distance_triangle_triangle(&a, &b);
            let o = oracle_triangle_distance(&a, &b);
            assert_rel(
                k.distance,
                o,
                1e-9,
                1e-12 * scale,
                &format!("case {case} scale {scale}: {a:?} {b:?}"),
            );
            // Witnesses realise the distance and lie on their triangles.
            assert_rel(
                (k.point1 - k.point2).length(),
                k.distance,
                1e-9,
                1e-12 * scale,
                "witness gap",
            );
            assert!(
                oracle_point_triangle(k.point1, &a) <= 1e-9 * scale,
                "point1 off triangle a"
            );
            assert!(
                oracle_point_triangle(k.point2, &b) <= 1e-9 * scale,
                "point2 off triangle b"
            );
        }
    }
}

/// Regression: coplanar triangles whose edges cross gave witnesses 5.5e-17 apart, and the
/// edge-pair separation certificate accepted that rounding gap instead of reporting contact.
#[test]
fn coplanar_crossing_edges_are_in_contact() {
    let a = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let b = a.map(|p| p + Vec3::new(0.2, 0.2, 0.0));
    assert_eq!(distance_triangle_triangle(&a, &b).distance, 0.0);
    assert_eq!(distance_triangle_triangle(&b, &a).distance, 0.0);
}

/// The intersection test (plane rejection, then the interval test on the planes' common line
/// where it is certain, else the distance) gives the verdict of `distance == 0` on every pair:
/// random pairs of every kind above at scales 1e-6 to 1e6 and far from the origin, and pairs
/// built to touch or nearly touch (a vertex on the other plane inside the other triangle, an
/// edge crossing an edge, then moved by a few rounding units either way); and on the pairs
/// that are clearly apart or clearly crossing it agrees with the independent formulation
/// (counted: both kinds occur).
#[test]
fn intersection_test_gives_the_distance_verdict() {
    let mut rng = rng(21);
    let (mut hits, mut misses, mut crossing) = (0, 0, 0);
    for scale in [1e-6, 1e-3, 1.0, 1e3, 1e6] {
        for offset in [0.0, 1e3] {
            for case in 0..4000 {
                let (a, b) = random_triangle_pair(&mut rng, case);
                let shift = Vec3::splat(offset);
                let (a, b) = (
                    a.map(|v| (v + shift) * scale),
                    b.map(|v| (v + shift) * scale),
                );
                let (mut a, mut b) = (a, b);
                if case % 5 == 4 {
                    // Touching by construction: a point of b's interior (or an edge point) put
                    // on a, then nudged along a's normal by a few rounding units.
                    let n = (a[1] - a[0]).cross(a[2] - a[0]);
                    let (u, v): (f64, f64) =
                        (rng.random_range(0.0..0.5), rng.random_range(0.0..0.5));
                    let on_a = a[0] + (a[1] - a[0]) * u + (a[2] - a[0]) * v;
                    let w: f64 = if case % 10 == 4 { 0.5 } else { 0.0 };
                    let on_b = b[0] * (1.0 - w) + b[1] * w;
                    let nudge = n.normalize_or_zero()
                        * ((rng.random_range(-4..=4) as f64)
                            * f64::EPSILON
                            * scale
                            * (1.0 + offset));
                    let t = on_a - on_b + nudge;
                    b = b.map(|p| p + t);
                }
                if case % 7 == 6 {
                    std::mem::swap(&mut a, &mut b);
                }
                let fast = intersect_triangle_triangle(&a, &b);
                let slow = distance_triangle_triangle(&a, &b).distance == 0.0;
                assert_eq!(
                    fast, slow,
                    "case {case} scale {scale} offset {offset}: {a:?} {b:?}"
                );
                // The independent formulation where the answer is clear: apart by more than
                // rounding, or an edge crossing the other triangle in a generic pair (not built
                // to touch, no shared vertex, segment, point or collinear corners).
                let o = oracle_triangle_distance(&a, &b);
                if o > 1e-6 * scale {
                    assert!(!fast, "apart by {o}: case {case} {a:?} {b:?}");
                } else if o == 0.0 && case % 5 != 4 && matches!(case % 8, 0 | 7) {
                    assert!(fast, "crossing: case {case} {a:?} {b:?}");
                    crossing += 1;
                }
                if fast {
                    hits += 1;
                } else {
                    misses += 1;
                }
            }
        }
    }
    assert!(
        hits > 5000 && misses > 5000 && crossing > 1000,
        "{hits} intersecting ({crossing} generic crossings), {misses} apart"
    );
}

#[test]
fn triangle_kernel_is_a_lower_bound_of_sampled_pairs() {
    let mut rng = rng(2);
    for case in 0..300 {
        let (a, b) = random_triangle_pair(&mut rng, case);
        let d = distance_triangle_triangle(&a, &b).distance;
        for _ in 0..200 {
            let bary = |rng: &mut rand_chacha::ChaCha8Rng, t: &[Vec3; 3]| {
                let (mut u, mut v): (f64, f64) = (rng.random(), rng.random());
                if u + v > 1.0 {
                    (u, v) = (1.0 - u, 1.0 - v);
                }
                t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v
            };
            let (x, y) = (bary(&mut rng, &a), bary(&mut rng, &b));
            assert!(
                (x - y).length() >= d - 1e-12,
                "sampled pair closer than kernel distance"
            );
        }
    }
}

fn check_against_brute(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose, scale: f64) {
    let r = distance(m1, p1, m2, p2, &DistanceOptions::default()).unwrap();
    let (bd, _, _) = brute_distance(m1, p1, m2, p2);
    assert_rel(
        r.distance,
        bd,
        1e-9,
        1e-13 * scale,
        "distance vs brute force",
    );
    assert_rel(
        (r.point1 - r.point2).length(),
        r.distance,
        1e-9,
        1e-12 * scale,
        "witnesses realise the distance",
    );
    let t1 = world_triangle(m1, p1, r.triangle1);
    let t2 = world_triangle(m2, p2, r.triangle2);
    assert!(
        oracle_point_triangle(r.point1, &t1) <= 1e-9 * scale,
        "point1 not on triangle1"
    );
    assert!(
        oracle_point_triangle(r.point2, &t2) <= 1e-9 * scale,
        "point2 not on triangle2"
    );
    assert_rel(
        distance_triangle_triangle(&t1, &t2).distance,
        r.distance,
        1e-9,
        1e-13 * scale,
        "reported pair",
    );
}

#[test]
fn random_soups_match_brute_force() {
    let mut rng = rng(3);
    for scale in [1e-3, 1.0, 1e4] {
        for i in 0..150 {
            let m1 = random_soup(&mut rng, 1 + i % 40, scale);
            let m2 = random_soup(&mut rng, 1 + (i * 7) % 37, scale);
            let spread = scale * [0.5, 2.0, 10.0][i % 3];
            let (p1, p2) = (random_pose(&mut rng, spread), random_pose(&mut rng, spread));
            check_against_brute(&m1, &p1, &m2, &p2, scale * (1.0 + spread / scale));
        }
    }
}

#[test]
fn approximate_distance_respects_its_bounds() {
    let mut rng = rng(4);
    let knot = mesh::torus_knot(60, 8).unwrap();
    for i in 0..60 {
        let p2 = random_pose(&mut rng, 8.0);
        let exact = distance(
            &knot,
            &Pose::IDENTITY,
            &knot,
            &p2,
            &DistanceOptions::default(),
        )
        .unwrap();
        let (rel, abs) = ([0.0, 0.1, 0.5][i % 3], [0.0, 0.05][i % 2]);
        let opts = DistanceOptions {
            relative_error: rel,
            absolute_error: abs,
        };
        let approx = distance(&knot, &Pose::IDENTITY, &knot, &p2, &opts).unwrap();
        assert!(approx.distance >= exact.distance - 1e-12);
        assert!(approx.distance <= exact.distance * (1.0 + rel) + abs + 1e-12);
        assert_rel(
            (approx.point1 - approx.point2).length(),
            approx.distance,
            1e-9,
            1e-12,
            "approx witnesses",
        );
    }
}

#[test]
fn cache_gives_identical_answers_along_a_path() {
    let knot = mesh::torus_knot(100, 8).unwrap();
    let mut cache = DistanceCache::default();
    for k in 0..50 {
        let t = k as f64 / 50.0;
        let p2 = Pose::from_axis_angle(
            Vec3::new(0.3, 1.0, 0.2),
            t,
            Vec3::new(9.0 - 6.0 * t, 0.5, 0.0),
        );
        let cold = distance(
            &knot,
            &Pose::IDENTITY,
            &knot,
            &p2,
            &DistanceOptions::default(),
        )
        .unwrap();
        let warm = distance_with_cache(
            &knot,
            &Pose::IDENTITY,
            &knot,
            &p2,
            &DistanceOptions::default(),
            &mut cache,
        )
        .unwrap();
        assert_rel(warm.distance, cold.distance, 1e-12, 0.0, "cached vs cold");
    }
    // A cache from another mesh pair is only a hint.
    let small = mesh::box_mesh(Vec3::ONE).unwrap();
    let far = Pose::from_translation(Vec3::new(20.0, 0.0, 0.0));
    let r = distance_with_cache(
        &small,
        &Pose::IDENTITY,
        &small,
        &far,
        &DistanceOptions::default(),
        &mut cache,
    )
    .unwrap();
    assert_rel(r.distance, 18.0, 1e-12, 0.0, "foreign cache");
}

#[test]
fn hand_cases() {
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let at = |x: f64, y: f64, z: f64| Pose::from_translation(Vec3::new(x, y, z));
    let d = |p2: &Pose| {
        distance(
            &cube,
            &Pose::IDENTITY,
            &cube,
            p2,
            &DistanceOptions::default(),
        )
        .unwrap()
        .distance
    };
    assert_eq!(d(&at(1.0, 0.0, 0.0)), 0.0, "touching faces");
    assert_eq!(d(&at(1.0, 1.0, 0.0)), 0.0, "touching along an edge");
    assert_eq!(d(&at(1.0, 1.0, 1.0)), 0.0, "touching at a vertex");
    assert_rel(d(&at(1.25, 0.0, 0.0)), 0.25, 1e-12, 0.0, "parallel faces");
    assert_rel(
        d(&at(2.0, 2.0, 2.0)),
        3f64.sqrt(),
        1e-12,
        0.0,
        "vertex-vertex",
    );
    assert_eq!(d(&Pose::IDENTITY), 0.0, "identical meshes");
    assert_rel(d(&at(1e4, 0.0, 0.0)), 1e4 - 1.0, 1e-12, 0.0, "far apart");
    // One mesh strictly inside the other: the surfaces do not meet, so the distance is the gap
    // between the surfaces (polygon soups have no inside).
    let big = mesh::box_mesh(Vec3::splat(2.0)).unwrap();
    let r = distance(
        &big,
        &Pose::IDENTITY,
        &cube,
        &Pose::IDENTITY,
        &DistanceOptions::default(),
    )
    .unwrap();
    assert_rel(r.distance, 1.5, 1e-12, 0.0, "nested surfaces");
    // Edge crossing through a face, no vertex or edge contact.
    let plate = mesh::plate(4.0, 1).unwrap();
    let stick = TriMesh::new(
        vec![
            Vec3::new(0.1, 0.2, -1.0),
            Vec3::new(0.1, 0.2, 1.0),
            Vec3::new(0.1, 0.2, 1.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let r = distance(
        &plate,
        &Pose::IDENTITY,
        &stick,
        &Pose::IDENTITY,
        &DistanceOptions::default(),
    )
    .unwrap();
    assert_eq!(r.distance, 0.0, "segment piercing a plate");
    assert!((r.point1 - Vec3::new(0.1, 0.2, 0.0)).length() < 1e-12);
}

#[test]
fn bad_options_are_errors() {
    let cube = mesh::box_mesh(Vec3::ONE).unwrap();
    for (rel, abs) in [(-1.0, 0.0), (f64::NAN, 0.0), (0.0, f64::INFINITY)] {
        let o = DistanceOptions {
            relative_error: rel,
            absolute_error: abs,
        };
        assert!(distance(&cube, &Pose::IDENTITY, &cube, &Pose::IDENTITY, &o).is_err());
    }
}

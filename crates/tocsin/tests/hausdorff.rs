//! Hausdorff distance within its error bound, against brute force: every triangle of A sampled
//! densely, each sample's distance to every triangle of B; closed forms for offset plates and
//! identical meshes.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::brute_point_distance;

use tocsin::query::distance::distance_triangle_triangle;
use tocsin::{hausdorff_distance, mesh, Pose, TriMesh, Vec3};

/// Largest distance to B over `k`-by-`k` barycentric samples of every triangle of A (world).
fn sampled(a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose, k: usize) -> f64 {
    let tb: Vec<[Vec3; 3]> = (0..b.num_triangles())
        .map(|j| b.triangle(j).map(|p| pb.transform_point(p)))
        .collect();
    let mut worst: f64 = 0.0;
    for i in 0..a.num_triangles() {
        let t = a.triangle(i).map(|p| pa.transform_point(p));
        for u in 0..=k {
            for v in 0..=(k - u) {
                let (s, r) = (u as f64 / k as f64, v as f64 / k as f64);
                let p = t[0] + (t[1] - t[0]) * s + (t[2] - t[0]) * r;
                let d = tb
                    .iter()
                    .map(|q| distance_triangle_triangle(&[p; 3], q).distance)
                    .fold(f64::INFINITY, f64::min);
                worst = worst.max(d);
            }
        }
    }
    worst
}

#[test]
fn within_the_error_bound_of_dense_sampling_on_random_soups() {
    let mut rng = common::rng(21);
    for case in 0..12 {
        let a = common::random_soup(&mut rng, 15, 1.0);
        let b = common::random_soup(&mut rng, 25, 1.0);
        let (pa, pb) = (
            common::random_pose(&mut rng, 1.0),
            common::random_pose(&mut rng, 1.0),
        );
        for symmetric in [false, true] {
            let e = 1e-3;
            let r = hausdorff_distance(&a, &pa, &b, &pb, e, symmetric).unwrap();
            assert!(
                r.upper_bound - r.distance <= e * (1.0 + 1e-9),
                "case {case}: gap"
            );
            // The witness is real: its distance is the value returned.
            let (from, to, pto) = if r.from_first {
                (&a, &b, &pb)
            } else {
                (&b, &a, &pa)
            };
            let _ = from;
            let d = brute_point_distance(r.point1, to, pto);
            assert!(
                (d - r.distance).abs() < 1e-9,
                "case {case}: witness {d} vs {}",
                r.distance
            );
            // Nothing sampled lies farther than the upper bound.
            let mut dense = sampled(&a, &pa, &b, &pb, 12);
            if symmetric {
                dense = dense.max(sampled(&b, &pb, &a, &pa, 12));
            }
            assert!(
                dense <= r.upper_bound + 1e-12,
                "case {case}: sampled {dense} > {}",
                r.upper_bound
            );
            assert!(
                r.distance >= dense - 0.05,
                "case {case}: {} far below sampling {dense}",
                r.distance
            );
        }
    }
}

#[test]
fn closed_forms_plates_and_identical_meshes() {
    // Two parallel plates 0.3 apart: every point of one is 0.3 from the other, and the bound
    // for triangles lying over one triangle of the other is exact, so this ends quickly.
    let plate = mesh::plate(2.0, 8).unwrap();
    let up = Pose::from_translation(Vec3::new(0.0, 0.0, 0.3));
    let r = hausdorff_distance(&plate, &Pose::IDENTITY, &plate, &up, 1e-9, true).unwrap();
    assert!((r.distance - 0.3).abs() < 1e-12 && (r.upper_bound - 0.3).abs() < 1e-9);
    // A plate against a bigger one: one-sided 0.3, but the bigger one's rim is farther.
    let big = mesh::plate(4.0, 8).unwrap();
    let one = hausdorff_distance(&plate, &Pose::IDENTITY, &big, &up, 1e-6, false).unwrap();
    assert!((one.distance - 0.3).abs() < 1e-6);
    let back = hausdorff_distance(&big, &up, &plate, &Pose::IDENTITY, 1e-6, false).unwrap();
    let expect = (1.0_f64 * 1.0 * 2.0 + 0.09).sqrt(); // corner (2, 2) to corner (1, 1), 0.3 up
    assert!(
        (back.distance - expect).abs() < 1e-6,
        "{} vs {expect}",
        back.distance
    );
    // Identical meshes: 0.
    let knot = mesh::torus_knot(60, 6).unwrap();
    let same =
        hausdorff_distance(&knot, &Pose::IDENTITY, &knot, &Pose::IDENTITY, 1e-6, true).unwrap();
    assert!(same.distance <= 1e-12 && same.upper_bound <= 1e-6);
    assert!(hausdorff_distance(&knot, &Pose::IDENTITY, &knot, &Pose::IDENTITY, 0.0, true).is_err());
}

/// Checks a Hausdorff answer of `a` (at the identity) against `b` at `pose`: within the error
/// `e`, its witness at the distance it reports, no densely sampled point above its upper bound
/// and none more than the error above its distance.
fn check_against_sampling(
    a: &TriMesh,
    b: &TriMesh,
    pose: &Pose,
    e: f64,
    symmetric: bool,
    label: &str,
) {
    let h = hausdorff_distance(a, &Pose::IDENTITY, b, pose, e, symmetric).unwrap();
    assert!(h.upper_bound - h.distance <= e * (1.0 + 1e-9), "{label}");
    let (target, to) = if h.from_first {
        (b, *pose)
    } else {
        (a, Pose::IDENTITY)
    };
    let d = brute_point_distance(h.point1, target, &to);
    assert!(
        (d - h.distance).abs() < 1e-9,
        "{label}: witness {d} vs {}",
        h.distance
    );
    let mut dense = sampled(a, &Pose::IDENTITY, b, pose, 6);
    if symmetric {
        dense = dense.max(sampled(b, pose, a, &Pose::IDENTITY, 6));
    }
    assert!(
        dense <= h.upper_bound + 1e-12,
        "{label}: sampled {dense} > {}",
        h.upper_bound
    );
    assert!(
        h.distance >= dense - e,
        "{label}: {} below sampling {dense}",
        h.distance
    );
}

#[test]
fn knot_against_a_moved_copy_within_the_bound_of_dense_sampling() {
    // The hard case of the benchmark: the distance is nearly the same over the whole surface.
    let knot = mesh::torus_knot(40, 5).unwrap();
    let e = 1e-3 * knot.bounding_radius();
    for (k, moved) in [
        Pose::from_translation(Vec3::new(0.3, 0.1, 0.05)),
        Pose::from_axis_angle(Vec3::new(0.2, 1.0, -0.4), 0.3, Vec3::new(-0.1, 0.2, 0.0)),
    ]
    .iter()
    .enumerate()
    {
        check_against_sampling(&knot, &knot, moved, e, true, &format!("pose {k}"));
    }
}

#[test]
fn copies_with_the_same_triangles_within_the_bound_of_dense_sampling() {
    // B with A's triangle list: a separately built equal knot at another pose, and a copy whose
    // vertices moved by up to 2% of the radius (its points correspond to A's, which bounds the
    // search: `hausdorff.rs`, `Copies`); random soups with their own vertices moved, where
    // degenerate and duplicated triangles keep their correspondence too.
    use rand::Rng;
    let knot = mesh::torus_knot(40, 5).unwrap();
    let r = knot.bounding_radius();
    let mut rng = common::rng(77);
    let mut jitter = |m: &TriMesh, size: f64| {
        let v: Vec<Vec3> = m
            .vertices()
            .iter()
            .map(|p| {
                *p + Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                ) * size
            })
            .collect();
        TriMesh::new(v, m.triangles().to_vec()).unwrap()
    };
    let mut cases = vec![
        (
            knot.clone(),
            mesh::torus_knot(40, 5).unwrap(),
            Pose::from_axis_angle(Vec3::new(0.2, 1.0, -0.4), 0.05, Vec3::new(-0.1, 0.2, 0.0)),
        ),
        (
            knot.clone(),
            jitter(&knot, 0.02 * r),
            Pose::from_translation(Vec3::new(0.05, 0.02, 0.0)),
        ),
    ];
    let mut soups = common::rng(78);
    for _ in 0..4 {
        let a = common::random_soup(&mut soups, 20, 1.0);
        let b = jitter(&a, 0.05);
        let pose = common::random_pose(&mut soups, 0.1);
        cases.push((a, b, pose));
    }
    for (k, (a, b, pose)) in cases.iter().enumerate() {
        let e = 1e-3 * a.bounding_radius();
        for symmetric in [false, true] {
            check_against_sampling(a, b, pose, e, symmetric, &format!("case {k}"));
        }
    }
}

#[test]
fn a_translated_copy_is_exactly_as_far_as_the_move() {
    // Any soup against itself moved by `t`: no point moves farther than `|t|`, and the corner
    // farthest along `t` is at least `|t|` from every point of the copy (which lies behind the
    // plane through it, `|t|` back), so the Hausdorff distance is `|t|` exactly: an oracle
    // independent of the search. Random soups with degenerate and repeated triangles, knots,
    // tiny and huge scales, world poses turned as well (where the copy is not recognised as a
    // pure translation of the frame and the search bounds it as any copy).
    let mut rng = common::rng(5);
    let mut cases: Vec<(TriMesh, f64)> = vec![(mesh::torus_knot(60, 6).unwrap(), 1.0)];
    for scale in [1e-6, 1.0, 1e6] {
        cases.push((common::random_soup(&mut rng, 30, scale), scale));
    }
    for (k, (m, scale)) in cases.iter().enumerate() {
        for turned in [false, true] {
            let base = if turned {
                common::random_pose(&mut rng, *scale)
            } else {
                Pose::IDENTITY
            };
            let t = Vec3::new(0.3, -0.2, 0.1) * (*scale * (1 + k) as f64 * 0.2);
            let moved = Pose {
                translation: base.translation + t,
                ..base
            };
            let e = 1e-4 * m.bounding_radius();
            for symmetric in [false, true] {
                let r = hausdorff_distance(m, &base, m, &moved, e, symmetric).unwrap();
                let exact = t.length();
                let rounding = 1e-12 * (exact + base.translation.length() + *scale);
                assert!(
                    r.distance <= exact + rounding && exact <= r.upper_bound + rounding,
                    "case {k} (turned {turned}): [{}, {}] does not hold {exact}",
                    r.distance,
                    r.upper_bound
                );
                assert!(r.upper_bound - r.distance <= e * (1.0 + 1e-9));
                let d =
                    brute_point_distance(r.point1, m, if r.from_first { &moved } else { &base });
                assert!((d - r.distance).abs() <= rounding, "case {k}: witness");
            }
        }
    }
}

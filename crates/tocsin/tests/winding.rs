//! The generalized winding number and the inside test, against closed-form values: 1 inside and
//! 0 outside closed meshes (-1 inside-out), the solid angle of a rectangle from a point on its
//! axis, invariance under the mesh's pose, and the hierarchical far field against the exact sum.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;

use rand::Rng;
use tocsin::{contains, mesh, winding_number, Pose, TriMesh, Vec3, WindingOptions};

const EXACT: WindingOptions = WindingOptions {
    beta: f64::INFINITY,
};

fn random_points(rng: &mut impl Rng, n: usize, half: f64) -> Vec<Vec3> {
    (0..n)
        .map(|_| {
            Vec3::new(
                rng.random_range(-half..half),
                rng.random_range(-half..half),
                rng.random_range(-half..half),
            )
        })
        .collect()
}

#[test]
fn closed_meshes_are_one_inside_and_zero_outside() {
    let mut rng = common::rng(1);
    let sphere = mesh::sphere(1.0, 24, 48).unwrap();
    let cube = mesh::box_mesh(Vec3::new(0.5, 0.3, 0.8)).unwrap();
    let points = random_points(&mut rng, 3000, 1.5);
    for (name, m) in [("sphere", &sphere), ("box", &cube)] {
        // The sphere's faces are chords: clearly inside below 0.95, outside beyond 1.
        let inside = |p: Vec3| match name {
            "sphere" => p.length() < 0.95,
            _ => p.x.abs() < 0.5 && p.y.abs() < 0.3 && p.z.abs() < 0.8,
        };
        let outside = |p: Vec3| match name {
            "sphere" => p.length() > 1.0,
            _ => p.x.abs() > 0.5 || p.y.abs() > 0.3 || p.z.abs() > 0.8,
        };
        let exact = winding_number(m, &Pose::IDENTITY, &points, &EXACT).unwrap();
        let fast = winding_number(m, &Pose::IDENTITY, &points, &WindingOptions::default()).unwrap();
        let inside_test = contains(m, &Pose::IDENTITY, &points);
        let mut checked = 0;
        for (k, &p) in points.iter().enumerate() {
            if inside(p) {
                assert!((exact[k] - 1.0).abs() < 1e-9, "{name}: {} at {p}", exact[k]);
                assert!(inside_test[k]);
                checked += 1;
            } else if outside(p) {
                assert!(exact[k].abs() < 1e-9, "{name}: {} at {p}", exact[k]);
                assert!(!inside_test[k]);
                checked += 1;
            }
            assert!(
                (fast[k] - exact[k]).abs() < 0.05,
                "{name}: far field {} vs {}",
                fast[k],
                exact[k]
            );
        }
        assert!(checked > 2000);
    }
}

#[test]
fn inside_out_is_minus_one_and_the_pose_moves_the_inside() {
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let flipped = TriMesh::new(
        cube.vertices().to_vec(),
        cube.triangles()
            .iter()
            .map(|t| [t[0], t[2], t[1]])
            .collect(),
    )
    .unwrap();
    let w = winding_number(&flipped, &Pose::IDENTITY, &[Vec3::ZERO], &EXACT).unwrap();
    assert!((w[0] + 1.0).abs() < 1e-12);
    // A soup has no reliable orientation: inside-out has the same inside.
    assert_eq!(
        contains(&flipped, &Pose::IDENTITY, &[Vec3::ZERO, Vec3::splat(2.0)]),
        vec![true, false]
    );
    let pose = Pose::from_axis_angle(Vec3::new(0.2, 1.0, 0.3), 0.7, Vec3::new(10.0, -3.0, 2.0));
    let points = [pose.transform_point(Vec3::new(0.4, 0.0, 0.0)), Vec3::ZERO];
    assert_eq!(contains(&cube, &pose, &points), vec![true, false]);
}

#[test]
fn an_open_rectangle_gives_its_solid_angle() {
    // A square plate of side 2 (two triangles, or a finer grid) seen from its axis at height d:
    // Omega = 4 asin(a b / sqrt((a^2 + d^2)(b^2 + d^2))), w = Omega / (4 pi). The plate's
    // triangles face +z, and a point in front of a face sees it with a negative angle (inside a
    // closed mesh facing outwards is behind every face).
    for plate in [mesh::plate(2.0, 1).unwrap(), mesh::plate(2.0, 9).unwrap()] {
        for d in [0.01_f64, 0.3, 1.0, 7.0, -2.0] {
            let expect = -(1.0 / (1.0 + d * d)).asin() / std::f64::consts::PI * d.signum();
            let w =
                winding_number(&plate, &Pose::IDENTITY, &[Vec3::new(0.0, 0.0, d)], &EXACT).unwrap();
            assert!((w[0] - expect).abs() < 1e-12, "d {d}: {} vs {expect}", w[0]);
        }
    }
}

#[test]
fn far_field_tracks_the_exact_sum_on_soups_and_degenerate_triangles_add_nothing() {
    let mut rng = common::rng(7);
    let knot = mesh::torus_knot(175, 8).unwrap();
    let points = random_points(&mut rng, 2000, 5.0);
    let exact = winding_number(&knot, &Pose::IDENTITY, &points, &EXACT).unwrap();
    for beta in [2.0, 4.0] {
        let fast =
            winding_number(&knot, &Pose::IDENTITY, &points, &WindingOptions { beta }).unwrap();
        let worst = exact
            .iter()
            .zip(&fast)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        let mut errors: Vec<f64> = exact
            .iter()
            .zip(&fast)
            .map(|(a, b)| (a - b).abs())
            .collect();
        errors.sort_by(f64::total_cmp);
        eprintln!(
            "beta {beta}: median error {:e}, 99th {:e}, worst {worst:e}",
            errors[1000], errors[1980]
        );
        assert!(
            worst < if beta == 2.0 { 0.05 } else { 0.01 },
            "beta {beta}: {worst}"
        );
    }
    // The knot is a closed tube: 0 or 1 everywhere but on the surface.
    let near_integer = exact
        .iter()
        .filter(|w| (*w - w.round()).abs() < 1e-6)
        .count();
    assert!(near_integer > 1990);
    // A soup with point and segment triangles: they contribute exactly nothing.
    let soup = common::random_soup(&mut rng, 40, 1.0);
    let mut v = soup.vertices().to_vec();
    let mut t = soup.triangles().to_vec();
    let base = v.len() as u32;
    v.extend([Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0)]);
    t.extend([[base, base, base], [base, base + 1, base + 2]]);
    let with = TriMesh::new(v, t).unwrap();
    let p = random_points(&mut rng, 50, 2.0);
    let a = winding_number(&soup, &Pose::IDENTITY, &p, &EXACT).unwrap();
    let b = winding_number(&with, &Pose::IDENTITY, &p, &EXACT).unwrap();
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-12);
    }
    assert!(winding_number(&soup, &Pose::IDENTITY, &p, &WindingOptions { beta: 0.5 }).is_err());
    assert!(winding_number(
        &soup,
        &Pose::IDENTITY,
        &p,
        &WindingOptions { beta: f64::NAN }
    )
    .is_err());
}

//! `within_distance` against the brute-force distance, around the threshold.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::*;
use tocsin::{mesh, within_distance, Pose, Vec3};

#[test]
fn random_soups_match_brute_force() {
    let mut rng = rng(20);
    for i in 0..200 {
        let scale = [1e-3, 1.0, 1e4][i % 3];
        let m1 = random_soup(&mut rng, 1 + i % 30, scale);
        let m2 = random_soup(&mut rng, 1 + (i * 5) % 29, scale);
        let (p1, p2) = (
            random_pose(&mut rng, 2.0 * scale),
            random_pose(&mut rng, 2.0 * scale),
        );
        let (d, _, _) = brute_distance(&m1, &p1, &m2, &p2);
        for f in [0.0, 0.5, 0.999, 1.001, 2.0] {
            let threshold = d * f;
            assert_eq!(
                within_distance(&m1, &p1, &m2, &p2, threshold).unwrap(),
                d <= threshold,
                "case {i}, factor {f}"
            );
        }
    }
}

#[test]
fn hand_cases_and_bad_thresholds() {
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let p2 = Pose::from_translation(Vec3::new(1.5, 0.0, 0.0));
    assert!(within_distance(&cube, &Pose::IDENTITY, &cube, &p2, 0.5).unwrap());
    assert!(!within_distance(&cube, &Pose::IDENTITY, &cube, &p2, 0.4999).unwrap());
    assert!(within_distance(&cube, &Pose::IDENTITY, &cube, &Pose::IDENTITY, 0.0).unwrap());
    assert!(within_distance(&cube, &Pose::IDENTITY, &cube, &p2, -1.0).is_err());
    assert!(within_distance(&cube, &Pose::IDENTITY, &cube, &p2, f64::NAN).is_err());
}

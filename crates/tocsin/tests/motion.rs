//! Motions: endpoints, the three interpolations, rotation at pi, and the directional bound
//! checked against finite differences of real trajectories.

#![allow(clippy::unwrap_used, clippy::panic)]

mod common;
use common::*;
use rand::Rng;
use tocsin::motion::{rotation_exp, rotation_log};
use tocsin::{Mat3, Motion, MotionError, Pose, Vec3};

fn close(a: &Pose, b: &Pose, tol: f64) -> bool {
    (a.rotation - b.rotation)
        .to_cols_array()
        .iter()
        .all(|v| v.abs() < tol)
        && (a.translation - b.translation).length() < tol
}

fn motions(rng: &mut impl Rng) -> Vec<Motion> {
    let (a, b) = (random_pose(rng, 3.0), random_pose(rng, 3.0));
    let c = Vec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    vec![
        Motion::translation(
            a,
            Pose {
                rotation: a.rotation,
                translation: b.translation,
            },
        )
        .unwrap(),
        Motion::interp(a, b, c).unwrap(),
        Motion::interp(a, b, Vec3::ZERO).unwrap(),
        Motion::screw(a, b).unwrap(),
        // A turn of up to 1.5 revolutions about a line through `3 c`.
        Motion::turn(a, c * 3.0, random_unit(rng) * rng.random_range(-9.5..9.5)).unwrap(),
    ]
}

#[test]
fn endpoints_are_the_given_poses() {
    let mut rng = rng(40);
    for _ in 0..200 {
        for m in motions(&mut rng) {
            assert!(close(&m.pose_at(0.0), &m.start(), 1e-9), "{:?}", m.kind());
            assert!(close(&m.pose_at(1.0), &m.end(), 1e-9), "{:?}", m.kind());
            assert!(
                close(&m.pose_at(0.999_999_999), &m.end(), 1e-6),
                "{:?} continuity",
                m.kind()
            );
        }
    }
}

#[test]
fn interpolations_follow_their_definitions() {
    let mut rng = rng(41);
    for _ in 0..100 {
        let (a, b) = (random_pose(&mut rng, 3.0), random_pose(&mut rng, 3.0));
        let c = Vec3::new(0.3, -0.2, 0.5);
        let m = Motion::interp(a, b, c).unwrap();
        let s = Motion::screw(a, b).unwrap();
        let rel = rotation_log(&(b.rotation * a.rotation.transpose()));
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            // interp: the centre moves on a straight line, R(t) = exp(t log(R1 R0^T)) R0.
            let p = m.pose_at(t);
            let centre = p.transform_point(c);
            let expected = a.transform_point(c) * (1.0 - t) + b.transform_point(c) * t;
            assert!((centre - expected).length() < 1e-9);
            let r = rotation_exp(rel * t) * a.rotation;
            assert!((p.rotation - r)
                .to_cols_array()
                .iter()
                .all(|v| v.abs() < 1e-9));
            // screw: T(t) T0^-1 is a screw, so the rotation is the same and every point's
            // distance from the screw axis is constant: check that T(t) T0^-1 composes.
            let ps = s.pose_at(t);
            assert!((ps.rotation - r)
                .to_cols_array()
                .iter()
                .all(|v| v.abs() < 1e-9));
            let half = s.pose_at(0.5 * t);
            let twice = half.mul(&a.inverse()).mul(&half);
            assert!(
                close(&twice, &ps, 1e-8),
                "screw: T(t/2) T0^-1 T(t/2) = T(t)"
            );
        }
    }
}

#[test]
fn rotation_by_exactly_pi() {
    for axis in [
        Vec3::X,
        Vec3::Y,
        Vec3::Z,
        Vec3::new(1.0, 1.0, 0.0).normalize(),
        Vec3::new(-1.0, 2.0, 3.0).normalize(),
    ] {
        let r = Mat3::from_axis_angle(axis, std::f64::consts::PI);
        let w = rotation_log(&r);
        assert!((w.length() - std::f64::consts::PI).abs() < 1e-9);
        assert!(
            w.normalize().cross(axis).length() < 1e-9,
            "axis {axis} -> {w}"
        );
        assert!((rotation_exp(w) - r)
            .to_cols_array()
            .iter()
            .all(|v| v.abs() < 1e-9));
        let start = Pose::IDENTITY;
        let end = Pose {
            rotation: r,
            translation: Vec3::new(1.0, 2.0, 3.0),
        };
        for m in [
            Motion::interp(start, end, Vec3::ZERO).unwrap(),
            Motion::screw(start, end).unwrap(),
        ] {
            assert!(close(&m.pose_at(1.0), &end, 1e-9));
            assert!((m.angular_velocity().length() - std::f64::consts::PI).abs() < 1e-9);
        }
    }
}

#[test]
fn directional_bound_holds_along_trajectories() {
    let mut rng = rng(42);
    for _ in 0..100 {
        for m in motions(&mut rng) {
            for _ in 0..10 {
                let x = Vec3::new(
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-2.0..2.0),
                );
                let n = random_unit(&mut rng);
                let mu = m.directional_bound(n, m.axis_distance(x));
                let h = 1e-6;
                for k in 0..20 {
                    let t = k as f64 / 20.0;
                    let speed = n
                        .dot(m.pose_at(t + h).transform_point(x) - m.pose_at(t).transform_point(x))
                        / h;
                    assert!(
                        speed <= mu + 1e-4 * (1.0 + mu.abs()),
                        "{:?}: speed {speed} > bound {mu}",
                        m.kind()
                    );
                }
            }
        }
    }
}

#[test]
fn bad_motions_are_errors() {
    let a = Pose::IDENTITY;
    let b = Pose::from_axis_angle(Vec3::Z, 0.1, Vec3::X);
    assert!(matches!(
        Motion::translation(a, b),
        Err(MotionError::RotationChanges { .. })
    ));
    let bad = Pose {
        rotation: Mat3::from_diagonal(Vec3::new(1.0, 1.0, -1.0)),
        translation: Vec3::ZERO,
    };
    assert!(Motion::interp(a, bad, Vec3::ZERO).is_err());
    assert!(Motion::screw(a, Pose::from_translation(Vec3::new(f64::NAN, 0.0, 0.0))).is_err());
    assert!(Motion::interp(a, b, Vec3::new(f64::INFINITY, 0.0, 0.0)).is_err());
    let nan = Vec3::new(f64::NAN, 0.0, 0.0);
    assert!(matches!(
        Motion::turn(a, nan, Vec3::Z),
        Err(MotionError::NonFinite)
    ));
    assert!(matches!(
        Motion::turn(a, Vec3::ZERO, Vec3::Z * f64::INFINITY),
        Err(MotionError::NonFinite)
    ));
    assert!(matches!(
        Motion::turn(bad, Vec3::ZERO, Vec3::Z),
        Err(MotionError::Pose(_))
    ));
}

/// A turn goes round as many times as its angle says: its pose at `t` is the start turned by
/// `t angular` about the line (Rodrigues' rotation about the origin, moved to the line), for
/// angles up to four revolutions; its axis is fixed and its kind is `Turn`.
#[test]
fn turns_go_round_by_their_whole_angle() {
    let mut rng = rng(44);
    for _ in 0..200 {
        let start = random_pose(&mut rng, 3.0);
        let point = random_unit(&mut rng) * rng.random_range(0.0..4.0);
        let dir = random_unit(&mut rng);
        let angle = rng.random_range(-25.0..25.0);
        let m = Motion::turn(start, point, dir * angle).unwrap();
        assert_eq!(m.kind(), tocsin::MotionKind::Turn);
        let axis = m.fixed_axis().expect("a fixed axis");
        assert_eq!(axis.along, 0.0);
        for k in 0..=8 {
            let t = f64::from(k) / 8.0;
            let turn = Pose::from_axis_angle(dir, angle * t, Vec3::ZERO);
            let expect = Pose {
                rotation: turn.rotation * start.rotation,
                translation: turn.rotation * (start.translation - point) + point,
            };
            assert!(close(&m.pose_at(t), &expect, 1e-11), "angle {angle}, t {t}");
        }
    }
    let still = Motion::turn(Pose::IDENTITY, Vec3::X, Vec3::ZERO).unwrap();
    assert!(still.is_stationary());
}

#[test]
fn windowed_bound_holds_over_its_window() {
    let mut rng = rng(43);
    for _ in 0..100 {
        for m in motions(&mut rng) {
            for _ in 0..10 {
                let center = Vec3::new(
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-2.0..2.0),
                    rng.random_range(-2.0..2.0),
                );
                let radius = rng.random_range(0.0..0.5);
                let x = center + random_unit(&mut rng) * radius * rng.random_range(0.0..1.0);
                let n = random_unit(&mut rng);
                let t: f64 = rng.random_range(0.0..0.9);
                let window: f64 = rng.random_range(0.001..(1.0 - t));
                let rot = m.pose_at(t).rotation;
                let mu = m.directional_bound_window(n, &rot, center, radius, window);
                let h = 1e-7;
                for k in 0..=20 {
                    let s = t + window * k as f64 / 20.0;
                    let speed = n
                        .dot(m.pose_at(s + h).transform_point(x) - m.pose_at(s).transform_point(x))
                        / h;
                    assert!(
                        speed <= mu + 1e-4 * (1.0 + mu.abs()),
                        "{:?}: speed {speed} > windowed bound {mu}",
                        m.kind()
                    );
                }
            }
        }
    }
}

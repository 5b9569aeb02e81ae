//! Helpers shared by the bench programs (and, through `#[path]`, by
//! `examples/profile_contact_set.rs`). Each program uses part of them.

#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tocsin::{collide, Mat3, Motion, Pose, TriMesh, Vec3};

/// A uniformly random unit vector (rejection sampling in the unit ball).
pub fn unit(rng: &mut ChaCha8Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        if v.length() > 0.2 && v.length() <= 1.0 {
            return v.normalize();
        }
    }
}

/// The median of `v` (the upper one of an even count); 0 when `v` is empty (a column a run
/// did not measure).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// Body 1's motion of the given kind (0 translation, 1 interp, 2 screw) from `from` to `to`,
/// rotating by `angle` about `axis` (none for a translation).
pub fn motion(kind: usize, from: Vec3, to: Vec3, axis: Vec3, angle: f64) -> Option<Motion> {
    let r0 = Mat3::from_axis_angle(axis.any_orthonormal_vector(), 0.4);
    let start = Pose {
        rotation: r0,
        translation: from,
    };
    let end = Pose {
        rotation: Mat3::from_axis_angle(axis, angle) * r0,
        translation: to,
    };
    match kind {
        0 => Motion::translation(
            start,
            Pose {
                rotation: r0,
                translation: to,
            },
        )
        .ok(),
        1 => Motion::interp(start, end, Vec3::ZERO).ok(),
        _ => Motion::screw(start, end).ok(),
    }
}

/// The contact-time bench's queries of one motion kind on `m` against a still copy of itself at
/// the identity, seeded by the kind: `n_through` passes from clear through the copy with a 30
/// to 90 degree turn, then `n_near` near misses, each pass shifted sideways to where body 1
/// just stops colliding (bisection on 200 collide samples) plus 1% of the radius.
pub fn contact_queries(m: &TriMesh, kind: usize, n_through: usize, n_near: usize) -> Vec<Motion> {
    let r = m.bounding_radius();
    let mut rng = ChaCha8Rng::seed_from_u64(7 + kind as u64);
    let mut out = Vec::new();
    for q in 0..n_through + n_near {
        let d = unit(&mut rng);
        let axis = unit(&mut rng);
        let angle = rng.random_range(30f64..90.0).to_radians();
        let lateral = unit(&mut rng).cross(d).normalize() * rng.random_range(0.0..0.2) * r;
        let mo = if q < n_through {
            motion(
                kind,
                -2.5 * r * d + lateral,
                2.5 * r * d - lateral,
                axis,
                angle,
            )
        } else {
            let side = unit(&mut rng).cross(d).normalize();
            let shifted = |o: f64| {
                motion(
                    kind,
                    -2.5 * r * d + side * o,
                    2.5 * r * d + side * o,
                    axis,
                    angle,
                )
            };
            let collides = |o: f64| {
                shifted(o).is_some_and(|mo| {
                    (0..=200).any(|k| collide(m, &mo.pose_at(k as f64 / 200.0), m, &Pose::IDENTITY))
                })
            };
            let (mut lo, mut hi) = (0.0, 3.0 * r);
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                if collides(mid) {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            shifted(hi + 0.01 * r)
        };
        out.extend(mo);
    }
    out
}

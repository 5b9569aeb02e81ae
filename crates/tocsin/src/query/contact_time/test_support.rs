//! Helpers shared by the continuous-collision unit tests.

use crate::math::Vec3;
use crate::motion::Motion;
use crate::query::distance::distance_triangle_triangle;
use rand::Rng;

/// Asserts that `bound` is at most the distance between the turning triangle `turning` (in the
/// body frame of `motion`) and the still triangle `still` (world frame) at `samples + 1` evenly
/// spaced times of the motion.
pub(crate) fn assert_below_sampled(
    bound: f64,
    motion: &Motion,
    (turning, still): (&[Vec3; 3], &[Vec3; 3]),
    samples: u32,
    label: &str,
) {
    for k in 0..=samples {
        let pose = motion.pose_at(f64::from(k) / f64::from(samples));
        let moved = turning.map(|p| pose.transform_point(p));
        let d = distance_triangle_triangle(&moved, still).distance;
        assert!(
            bound <= d * (1.0 + 1e-9) + 1e-12,
            "{label}: bound {bound} above the distance {d} at sample {k}"
        );
    }
}

/// A uniformly random point of the triangle.
pub(crate) fn point_on(rng: &mut impl Rng, tri: &[Vec3; 3]) -> Vec3 {
    let (a, b): (f64, f64) = (rng.random(), rng.random());
    let (a, b) = if a + b > 1.0 {
        (1.0 - a, 1.0 - b)
    } else {
        (a, b)
    };
    tri[0] + (tri[1] - tri[0]) * a + (tri[2] - tri[0]) * b
}

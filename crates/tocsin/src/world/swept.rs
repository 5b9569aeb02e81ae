//! Axis-aligned boxes and the conservative box a body sweeps over a time interval.
//!
//! A body's mesh is bounded in its own frame by the box of its vertices (`local`, computed once
//! per mesh). Over `[t0, t1]`:
//! - a body that does not turn moves every point along a straight line (the rotation is
//!   constant), so the box of its start and end boxes holds the whole sweep, exactly;
//! - a turning body's interval is cut into `k` pieces; on each, the local box placed at the
//!   piece's middle time holds every point at that time, and no point moves farther than
//!   `v h / 2` in a piece of length `h`, `v` the motion's speed bound for points as far from the
//!   rotation axis as the local box reaches ([`Motion::speed_bound`]); the piece's box is grown
//!   by that much. `k` is chosen so the growth stays under a quarter of the box's half diagonal
//!   (at most [`MAX_PIECES`]).
//!
//! Tests sample the motions densely and check every vertex stays inside.

use crate::math::{Pose, Vec3};
use crate::motion::Motion;

/// Most pieces a turning body's sweep is cut into.
pub const MAX_PIECES: usize = 32;

/// An axis-aligned box, world frame (or the body frame for a mesh's own box). `min <= max` in
/// every coordinate for a box that holds anything.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Aabb {
    /// The box of a set of points (`None` for no points).
    pub fn of_points(points: &[Vec3]) -> Option<Self> {
        let first = *points.first()?;
        Some(points.iter().fold(
            Self {
                min: first,
                max: first,
            },
            |b, &p| Self {
                min: b.min.min(p),
                max: b.max.max(p),
            },
        ))
    }

    /// Whether the boxes share a point (touching counts).
    #[inline]
    pub fn overlaps(&self, other: &Self) -> bool {
        self.min.x <= other.max.x
            && other.min.x <= self.max.x
            && self.min.y <= other.max.y
            && other.min.y <= self.max.y
            && self.min.z <= other.max.z
            && other.min.z <= self.max.z
    }

    /// The smallest box holding both.
    #[inline]
    pub fn union(&self, other: &Self) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// The box grown by `r` on every side.
    #[inline]
    pub fn inflated(&self, r: f64) -> Self {
        Self {
            min: self.min - Vec3::splat(r),
            max: self.max + Vec3::splat(r),
        }
    }

    /// Centre of the box.
    #[inline]
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Half of the box's extent along each axis.
    #[inline]
    pub fn half_extents(&self) -> Vec3 {
        0.5 * (self.max - self.min)
    }

    /// The world box of this body-frame box placed at `pose` (exact for the rotated box).
    #[inline]
    pub fn placed(&self, pose: &Pose) -> Self {
        let c = pose.transform_point(self.center());
        let h = self.half_extents();
        let r = &pose.rotation;
        let e = Vec3::new(
            r.x_axis.x.abs() * h.x + r.y_axis.x.abs() * h.y + r.z_axis.x.abs() * h.z,
            r.x_axis.y.abs() * h.x + r.y_axis.y.abs() * h.y + r.z_axis.y.abs() * h.z,
            r.x_axis.z.abs() * h.x + r.y_axis.z.abs() * h.y + r.z_axis.z.abs() * h.z,
        );
        Self {
            min: c - e,
            max: c + e,
        }
    }
}

/// A box holding every point of the body-frame box `local` moving by `motion` over
/// `[t0, t1]` (module docs), grown by `margin`.
pub fn swept_box(local: &Aabb, motion: &Motion, t0: f64, t1: f64, margin: f64) -> Aabb {
    let (t0, t1) = (
        t0.clamp(0.0, 1.0),
        t1.clamp(0.0, 1.0).max(t0.clamp(0.0, 1.0)),
    );
    if motion.angular_velocity() == Vec3::ZERO {
        let a = local.placed(&motion.pose_at(t0));
        let b = local.placed(&motion.pose_at(t1));
        return a.union(&b).inflated(margin);
    }
    let half = local.half_extents().length();
    let reach = motion.axis_distance(local.center()) + half;
    let speed = motion.speed_bound(reach);
    let span = t1 - t0;
    // Growth per piece `speed * span / (2 k)` at most a quarter of the half diagonal.
    let wanted = (2.0 * speed * span / half.max(f64::MIN_POSITIVE)).ceil();
    let pieces = if wanted.is_finite() {
        (wanted as usize).clamp(1, MAX_PIECES)
    } else {
        MAX_PIECES
    };
    let h = span / pieces as f64;
    let grow = 0.5 * speed * h;
    let mut out: Option<Aabb> = None;
    for i in 0..pieces {
        let mid = t0 + (i as f64 + 0.5) * h;
        let b = local.placed(&motion.pose_at(mid)).inflated(grow);
        out = Some(out.map_or(b, |o| o.union(&b)));
    }
    // `pieces >= 1`, so the fold produced a box.
    out.unwrap_or(*local).inflated(margin)
}

/// A ball holding every point within `radius` of the body-frame point `center` moving by
/// `motion` over `[t0, t1]`: centred where `center` is at the middle time, grown by the
/// distance the centre can travel in half the interval ([`Motion::speed_bound`] at its
/// distance from the rotation axis). Returns the world centre and the radius.
pub fn swept_ball(center: Vec3, radius: f64, motion: &Motion, t0: f64, t1: f64) -> (Vec3, f64) {
    let (t0, t1) = (
        t0.clamp(0.0, 1.0),
        t1.clamp(0.0, 1.0).max(t0.clamp(0.0, 1.0)),
    );
    let mid = 0.5 * (t0 + t1);
    let c = motion.pose_at(mid).transform_point(center);
    let speed = motion.speed_bound(motion.axis_distance(center));
    (c, radius + 0.5 * speed * (t1 - t0))
}

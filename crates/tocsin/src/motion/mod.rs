//! Rigid motions over `t in [0, 1]` and their directional motion bounds (C2A, Tang et al. 2009).
//!
//! Every motion here moves each body point `x` (body frame) with a constant world linear
//! velocity `v` and angular velocity `w` about an axis that is fixed in the body frame:
//! `dX/dt = v + w x (X(t) - A(t))`, where `A(t)` is the axis point carried by the motion.
//!
//! **The bound.** For a unit world direction `n` and a set `S` of body points,
//! `n . dX/dt = n . v + n . (w x r)` with `r = X - A`. Since `n . (w x r) = r . (n x w)` and
//! `n x w` is orthogonal to `w`, only the part of `r` orthogonal to `w` counts, whose length is
//! the point's distance `rho(x)` from the rotation axis; so `n . dX/dt <= n . v + |w x n| rho(x)`.
//! A rotation about that axis keeps `rho(x)` constant and the axis is fixed in the body frame,
//! so `mu(n, S) = n . v + |w x n| max_S rho` bounds the speed along `n` of every point of `S` for
//! the whole of `[0, 1]` (seed talk, slide "Motion Bound Calculation").
//!
//! **Signs.** Conservative advancement needs how fast the gap along `n` (from body 1 to body 2)
//! can close: body 1's points moving along `+n` and body 2's moving along `-n`. The safe step
//! for a gap `d` is `d / (mu_1(n) + mu_2(-n))`; the linear term keeps its sign (a body moving
//! away has a negative one), and a non-positive sum means the gap cannot close. Using `+n` for
//! both bodies is the mistake of FCL issue #555.
//!
//! - `translation`: `w = 0`, `v = p1 - p0`.
//! - `interp`: the centre `c` moves on a straight line, `v = (R1 c + p1) - (R0 c + p0)`, and the
//!   body turns about it at constant `w = rotvec(R1 R0^T)`; the axis passes through `c` with
//!   body direction `R0^T w`.
//! - `screw`: `T(t) = exp(t log(T1 T0^-1)) T0`; `w` as above, `v` is the translation along the
//!   screw axis and the axis is the screw axis, mapped to the body frame by `T0^-1`.
//!
//! **Precision.** Poses are computed from quantities of the body's own size, never by
//! subtracting large ones: a screw's pose is `exp(t w) p0 + V(t w) t u` from its twist `(w, u)`
//! (`V` the left Jacobian of SO(3), each coefficient without cancellation), not from its axis
//! point, which lies `|u| / |w|` away (1e12 units for a 3e-12 rad turn, where the old formula
//! was 7e-4 off at `t = 0`). Rotation logarithms go through quaternions (accurate to rounding
//! at 0 and near pi). The axis point still serves the bounds, where only `|w| rho` counts: its
//! relative rounding costs `|w|` times 1e-16 of the axis distance, a rounding-level speed.
//!
//! **Windowed bound.** Over a window `[t, t + h]` only, `r(s) = X(s) - A(s)` is `r(t)` turned by at
//! most `|w| h` about `w`, so `|r(s) - r(t)| <= |w| h rho`, and
//! `n . (w x r(s)) = r(s) . (n x w) <= r(t) . (n x w) + |n x w| |w| h rho`. For a set of points
//! within `R` of a centre `C`, `r(t) . (n x w) <= (C(t) - A(t)) . (n x w) + |n x w| R`, hence
//! `mu_h(n, S) = n . v + (C(t) - A(t)) . (n x w) + |n x w| (R + |w| h rho)`: the centre's exact
//! velocity along `n` plus two small terms. It is much tighter than `mu` when the rotation axis
//! is far from the body (screws), and it never exceeds `mu` by more than `|n x w| |w| h rho`.
//! The term `|n x w| R` is the ball's reach along `n x w`; the step search takes a hierarchy
//! volume's own reach there instead (its support along `n x w`, `Spread`): the points of a
//! rectangle swept by a ball are `C + x e1 + y e2 + z`, so `(p - C) . g <= h1 |e1 . g| +
//! h2 |e2 . g| + r |g|`, which never exceeds `(h1 + h2 + r) |g|` and is about half of it for
//! a thin or flat volume.
//!
//! The rotation angle is taken in `[0, pi]`. At exactly `pi` both senses of rotation are
//! geodesics; the axis is then taken from `(R + I) / 2` with its largest component positive.

mod rotation;

use crate::error::MotionError;
use crate::math::{Pose, Vec3};
pub use rotation::{rotation_exp, rotation_log};

/// A rotation axis fixed in the world ([`Motion::fixed_axis`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixedAxis {
    /// A point of the axis, body frame.
    pub body_point: Vec3,
    /// Unit direction of the axis, body frame.
    pub body_dir: Vec3,
    /// World position of `body_point` at `t = 0`; at time `t` it is
    /// `world_point + world_dir * along * t`.
    pub world_point: Vec3,
    /// Unit direction of the axis, world frame (the sense of the rotation).
    pub world_dir: Vec3,
    /// Speed along the axis (model units per unit of `t`, signed along `world_dir`).
    pub along: f64,
    /// Angular speed about `world_dir` (radians per unit of `t`, positive): with `along`, the
    /// helix the body's points follow advances `along / angular_speed` per radian.
    pub angular_speed: f64,
}

/// Which interpolation a [`Motion`] follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum MotionKind {
    /// Constant rotation, straight-line translation.
    Translation,
    /// A centre point on a straight line, constant angular velocity about it.
    Interp,
    /// The SE(3) geodesic: rotation about a fixed axis with translation along it.
    Screw,
    /// Rotation about a fixed axis by any angle ([`Motion::turn`]).
    Turn,
}

/// A rigid motion from `start` (t = 0) to `end` (t = 1), world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    kind: MotionKind,
    start: Pose,
    end: Pose,
    /// World linear velocity of the axis point (model units per unit t).
    linear: Vec3,
    /// World angular velocity (radians per unit t).
    angular: Vec3,
    /// A point of the rotation axis, body frame.
    axis_point: Vec3,
    /// Unit direction of the rotation axis, body frame (any unit vector when `angular = 0`).
    axis_dir: Vec3,
    /// World position of the axis point at t = 0 (translation, interp: the path's reference
    /// point; it is not used for a screw's poses).
    axis_start: Vec3,
    /// A screw's twist linear part `u`: the world velocity field is `u + angular x X`.
    twist: Vec3,
}

/// Tolerance for `translation`: the end rotation must equal the start rotation within this.
pub const SAME_ROTATION_TOLERANCE: f64 = 1e-9;

/// Smallest relative rotation (radians) that [`Motion::screw`] turns by; below it the screw is
/// a translation. A turn this small moves a point by `1e-15` of its distance from the origin,
/// below the rounding of the rotation matrices' own entries.
pub const MIN_SCREW_ANGLE: f64 = 1e-15;

impl Motion {
    /// A body that does not move.
    pub fn stationary(pose: Pose) -> Self {
        Self::build(
            MotionKind::Translation,
            pose,
            pose,
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::ZERO,
            pose.translation,
        )
    }

    /// Pure translation: `X(t) = R0 x + (1 - t) p0 + t p1`. The rotations of `start` and `end`
    /// must agree within [`SAME_ROTATION_TOLERANCE`].
    pub fn translation(start: Pose, end: Pose) -> Result<Self, MotionError> {
        check_poses(&start, &end)?;
        let diff = (start.rotation - end.rotation)
            .to_cols_array()
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        if diff > SAME_ROTATION_TOLERANCE {
            return Err(MotionError::RotationChanges { difference: diff });
        }
        let end = Pose {
            rotation: start.rotation,
            translation: end.translation,
        };
        Ok(Self::build(
            MotionKind::Translation,
            start,
            end,
            end.translation - start.translation,
            Vec3::ZERO,
            Vec3::ZERO,
            start.translation,
        ))
    }

    /// Linear interpolation of the point `center` (body frame) with constant angular velocity
    /// about it: `X(t) = R(t) (x - c) + (1 - t)(R0 c + p0) + t (R1 c + p1)`,
    /// `R(t) = exp(t log(R1 R0^T)) R0`. With `center = 0` this is FCL's `InterpMotion` and parry's
    /// `NonlinearRigidMotion` with local centre 0.
    pub fn interp(start: Pose, end: Pose, center: Vec3) -> Result<Self, MotionError> {
        check_poses(&start, &end)?;
        crate::math::check_translation(center).map_err(MotionError::Pose)?;
        let angular = rotation_log(&(end.rotation * start.rotation.transpose()));
        let c0 = start.transform_point(center);
        let c1 = end.transform_point(center);
        Ok(Self::build(
            MotionKind::Interp,
            start,
            end,
            c1 - c0,
            angular,
            center,
            c0,
        ))
    }

    /// The SE(3) geodesic `T(t) = exp(t log(T1 T0^-1)) T0`: a screw about a fixed world axis.
    /// A relative rotation below [`MIN_SCREW_ANGLE`] is taken as none (a translation with the
    /// start's rotation): the two rotations then agree to the rounding of their entries.
    pub fn screw(start: Pose, end: Pose) -> Result<Self, MotionError> {
        check_poses(&start, &end)?;
        let r_rel = end.rotation * start.rotation.transpose();
        let angular = rotation_log(&r_rel);
        let theta = angular.length();
        if theta < MIN_SCREW_ANGLE {
            return Self::translation(
                start,
                Pose {
                    rotation: start.rotation,
                    translation: end.translation,
                },
            );
        }
        // The twist (angular, twist): T1 T0^-1 = exp of it, so its translation part is
        // V(angular) twist = p1 - R_rel p0. Poses along the way come from the twist, never from
        // the axis point, which is |twist| / theta away (1e12 units at theta = 1e-12).
        let p_rel = end.translation - r_rel * start.translation;
        let twist = rotation::jacobian_inverse_apply(angular, p_rel);
        let w = angular / theta;
        let along = w * w.dot(twist);
        // Points of the axis move along it: twist + angular x q = along for q = w x twist / theta.
        let q = w.cross(twist) / theta;
        let axis_point = start.inverse().transform_point(q);
        let mut m = Self::build(MotionKind::Screw, start, end, along, angular, axis_point, q);
        m.twist = twist;
        Ok(m)
    }

    /// A turn about the world line through `point` by the rotation vector `angular` (the
    /// axis direction times the angle in radians, of any size: a wheel may turn several
    /// revolutions), from `start`: the pose at `t` is `start` turned by `t angular` about that
    /// line, and the velocity field is `angular x (X - point)`. A screw between two poses
    /// stops at pi; this is the motion of a robot link when one revolute joint above it
    /// moves. Its kind is [`MotionKind::Turn`]. `point` is used as given: one near the body
    /// keeps its poses precise.
    ///
    /// # Errors
    /// [`MotionError::Pose`] for a start that is not a rigid transform,
    /// [`MotionError::NonFinite`] for a point or rotation vector with a NaN or infinite
    /// coordinate.
    pub fn turn(start: Pose, point: Vec3, angular: Vec3) -> Result<Self, MotionError> {
        check_poses(&start, &start)?;
        if !(point.is_finite() && angular.is_finite()) {
            return Err(MotionError::NonFinite);
        }
        Ok(Self::turn_unchecked(start, point, angular))
    }

    /// [`Motion::turn`] for inputs the caller knows are valid (a robot's joint frames).
    pub(crate) fn turn_unchecked(start: Pose, point: Vec3, angular: Vec3) -> Self {
        if angular == Vec3::ZERO {
            return Self::stationary(start);
        }
        let axis_point = start.inverse().transform_point(point);
        let mut m = Self::build(
            MotionKind::Turn,
            start,
            start,
            Vec3::ZERO,
            angular,
            axis_point,
            point,
        );
        m.twist = point.cross(angular);
        m.end = m.screw_pose(1.0);
        m
    }

    /// [`Motion::turn_unchecked`] while sliding at the world velocity `slide` along the axis
    /// (parallel to `angular`): a screw about the world line through `point`, of any angle (a
    /// robot link turned by a revolute joint while slides along its axis move it).
    pub(crate) fn turn_and_slide(start: Pose, point: Vec3, angular: Vec3, slide: Vec3) -> Self {
        let mut m = Self::turn_unchecked(start, point, angular);
        if angular != Vec3::ZERO && slide != Vec3::ZERO {
            m.linear = slide;
            m.twist += slide;
            m.end = m.screw_pose(1.0);
        }
        m
    }

    fn build(
        kind: MotionKind,
        start: Pose,
        end: Pose,
        linear: Vec3,
        angular: Vec3,
        axis_point: Vec3,
        axis_start: Vec3,
    ) -> Self {
        let axis_dir = (start.rotation.transpose() * angular).normalize_or(Vec3::Z);
        Self {
            kind,
            start,
            end,
            linear,
            angular,
            axis_point,
            axis_dir,
            axis_start,
            twist: Vec3::ZERO,
        }
    }

    /// The kind of interpolation.
    pub fn kind(&self) -> MotionKind {
        self.kind
    }

    /// The pose at `t = 0`.
    pub fn start(&self) -> Pose {
        self.start
    }

    /// The pose at `t = 1` (for `translation`, with the start's rotation).
    pub fn end(&self) -> Pose {
        self.end
    }

    /// World linear velocity of the axis point, model units per unit of `t`.
    pub fn linear_velocity(&self) -> Vec3 {
        self.linear
    }

    /// World angular velocity, radians per unit of `t`.
    pub fn angular_velocity(&self) -> Vec3 {
        self.angular
    }

    /// The pose at time `t` (any real `t`; the motion is defined on `[0, 1]`). At `t = 0` and
    /// `t = 1` it is within rounding of `start` and `end` (exactly `end` at `t = 1`), for every
    /// angle in `[0, pi]` and however far the rotation axis is from the body.
    pub fn pose_at(&self, t: f64) -> Pose {
        if t == 1.0 {
            return self.end;
        }
        match self.kind {
            MotionKind::Translation => Pose {
                rotation: self.start.rotation,
                translation: self.start.translation + self.linear * t,
            },
            MotionKind::Interp => {
                // The centre moves on a straight line and the body turns about it:
                // p(t) = c(t) - R(t) c = p0 + t v - (exp(t w) - I) R0 c, the last term taken
                // without cancellation (the centre may be far from the body's origin).
                let turn = self.angular * t;
                let lever = self.start.rotation * self.axis_point;
                Pose {
                    rotation: rotation_exp(turn) * self.start.rotation,
                    translation: self.start.translation + self.linear * t
                        - rotation::turn_displacement(turn, lever),
                }
            }
            MotionKind::Screw | MotionKind::Turn => self.screw_pose(t),
        }
    }

    /// A screw's pose at `t`: `exp(t (angular, twist))` applied to the start pose.
    fn screw_pose(&self, t: f64) -> Pose {
        let turn = rotation_exp(self.angular * t);
        Pose {
            rotation: turn * self.start.rotation,
            translation: turn * self.start.translation
                + rotation::jacobian_apply(self.angular * t, self.twist * t),
        }
    }

    /// A point of the rotation axis, body frame (any point when the motion does not turn).
    pub fn axis_point(&self) -> Vec3 {
        self.axis_point
    }

    /// Whether the body does not move at all.
    pub fn is_stationary(&self) -> bool {
        self.linear == Vec3::ZERO && self.angular == Vec3::ZERO
    }

    /// The rotation axis when it is a line fixed in the world (a screw; an interp whose centre
    /// moves along the axis or not at all): the body turns about it and slides along it, so
    /// every body point keeps its distance from the line and its axial coordinate relative to
    /// the axis point. `None` for translations and for interps whose axis line moves.
    pub fn fixed_axis(&self) -> Option<FixedAxis> {
        let theta = self.angular.length();
        if theta == 0.0 {
            return None;
        }
        let dir = self.angular / theta;
        let along = self.linear.dot(dir);
        let across = (self.linear - dir * along).length();
        if across > 1e-12 * self.linear.length().max(f64::MIN_POSITIVE) && across > 0.0 {
            return None;
        }
        Some(FixedAxis {
            body_point: self.axis_point,
            body_dir: self.axis_dir,
            world_point: self.axis_start,
            world_dir: dir,
            along,
            angular_speed: theta,
        })
    }

    /// Distance of a body-frame point from the rotation axis (0 for a translation).
    #[inline]
    pub fn axis_distance(&self, x: Vec3) -> f64 {
        if self.angular == Vec3::ZERO {
            return 0.0;
        }
        let r = x - self.axis_point;
        (r - self.axis_dir * r.dot(self.axis_dir)).length()
    }

    /// Upper bound on the speed along the unit world direction `n` of any body point whose
    /// distance from the rotation axis is at most `axis_distance`, valid over all of `[0, 1]`.
    /// May be negative (the points all move against `n`).
    #[inline]
    pub fn directional_bound(&self, n: Vec3, axis_distance: f64) -> f64 {
        n.dot(self.linear) + self.angular.cross(n).length() * axis_distance
    }

    /// Upper bound on the speed along the unit world direction `n` of any body point within
    /// `radius` of the body-frame point `center`, valid over `[t, t + h]` where `rotation` is the
    /// body's world rotation at `t` (the windowed bound in the module docs).
    #[inline]
    pub fn directional_bound_window(
        &self,
        n: Vec3,
        rotation: &crate::math::Mat3,
        center: Vec3,
        radius: f64,
        h: f64,
    ) -> f64 {
        if self.angular == Vec3::ZERO {
            return n.dot(self.linear);
        }
        let nxw = n.cross(self.angular);
        let lever = *rotation * (center - self.axis_point);
        let rho = self.axis_distance(center) + radius;
        n.dot(self.linear)
            + lever.dot(nxw)
            + nxw.length() * (radius + self.angular.length() * h * rho)
    }

    /// Upper bound on the speed of any point within `axis_distance` of the axis, in any
    /// direction (for a time-independent bound).
    pub fn speed_bound(&self, axis_distance: f64) -> f64 {
        self.linear.length() + self.angular.length() * axis_distance
    }
}

/// How far a set of body points reaches from its centre along any direction, for the
/// directional motion bounds: the points `c + x e1 + y e2 + z` with `|x| <= h1`, `|y| <= h2` and
/// `|z| <= r` (a rectangle swept by a ball, the hierarchy's volumes; a ball has `h1 = h2 = 0`).
/// The rotation terms of the bounds are linear in the point, so over the set they reach their
/// largest at the centre's value plus the set's support along the term's direction; the
/// support is at most (and for a thin or flat volume often half) the bounding radius
/// `h1 + h2 + r` times the direction's length, which the bounds took before.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Spread {
    e1: Vec3,
    e2: Vec3,
    h1: f64,
    h2: f64,
    r: f64,
}

impl Spread {
    /// The ball of radius `r` about the centre.
    #[inline]
    pub(crate) fn ball(r: f64) -> Self {
        Self {
            e1: Vec3::ZERO,
            e2: Vec3::ZERO,
            h1: 0.0,
            h2: 0.0,
            r,
        }
    }

    /// An RSS whose rectangle's unit edge directions are `e1`, `e2` (in the frame the
    /// directions given to [`Self::support`] are in), half lengths `h1`, `h2`, sphere radius `r`.
    #[inline]
    pub(crate) fn rss(e1: Vec3, e2: Vec3, h1: f64, h2: f64, r: f64) -> Self {
        Self { e1, e2, h1, h2, r }
    }

    /// `max (p - c) . g` over the set's points `p` (the set is symmetric about `c`, so also
    /// `max |(p - c) . g|`).
    #[inline]
    pub(crate) fn support(&self, g: Vec3) -> f64 {
        self.h1 * self.e1.dot(g).abs() + self.h2 * self.e2.dot(g).abs() + self.r * g.length()
    }
}

fn check_poses(start: &Pose, end: &Pose) -> Result<(), MotionError> {
    for p in [start, end] {
        crate::math::check_rotation(&p.rotation, crate::math::ROTATION_TOLERANCE)
            .map_err(MotionError::Pose)?;
        crate::math::check_translation(p.translation).map_err(MotionError::Pose)?;
    }
    Ok(())
}

/// Random directions and points of swept rectangles, for the tests of the motion bounds (the
/// rigid one in the step search, the chain's in `robot/chain.rs`).
#[cfg(test)]
pub(crate) mod sampling {
    use crate::math::Vec3;
    use rand::Rng;

    /// A uniformly random unit vector.
    pub(crate) fn unit(rng: &mut impl Rng) -> Vec3 {
        loop {
            let v = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            if v.length() <= 1.0 {
                if let Some(u) = v.try_normalize() {
                    return u;
                }
            }
        }
    }

    /// A point of the rectangle `c + x e1 + y e2` (`|x| <= h1`, `|y| <= h2`) swept by a ball of
    /// radius `r`, on its corners and edges as often as inside it.
    pub(crate) fn rss_point(
        rng: &mut impl Rng,
        c: Vec3,
        (e1, e2): (Vec3, Vec3),
        (h1, h2): (f64, f64),
        r: f64,
    ) -> Vec3 {
        let mut side = || match rng.random_range(0..3) {
            0 => -1.0,
            1 => 1.0,
            _ => rng.random_range(-1.0..1.0),
        };
        let (x, y) = (side(), side());
        c + e1 * h1 * x + e2 * h2 * y + unit(rng) * r
    }
}

//! A link's motion under linear joint interpolation, and its directional motion bound (CATCH,
//! Tang, Kim and Manocha 2011, in a windowed form).
//!
//! # The motion
//!
//! A collision object rides on a body at the end of a chain of `m` moving joints, root first.
//! Joint `j` has a frame fixed in its parent body (`origin_j`, which includes every fixed joint
//! merged on the way), a unit axis `a_j` in that frame, and a value `q_j(t) = q_j(0) + t dq_j`
//! (a mimic joint follows its source linearly, so it is linear too). The body's pose is
//! `base * origin_1 * J_1(q_1) * ... * origin_m * J_m(q_m)`, with `J` a rotation about `a` (revolute)
//! or a translation along it (prismatic). A revolute joint's axis passes through its frame's
//! origin `o_j`.
//!
//! # The bound
//!
//! The world velocity of a point `x` of the object is `v = sum_j dq_j J_j(x)` with
//! `J_j(x) = a_j x (x - o_j)` (revolute) or `a_j` (prismatic). Along a unit direction `n`
//! fixed in the world, joint `j` contributes `dq_j f_j` with `f_j = n . (a_j x u_j) =
//! u_j . (n x a_j)`, `u_j = x - o_j`. Three constants per joint and edge:
//!
//! - `R_j` (`r_chain`): a bound on `|u_j|` over every configuration of the edge: the lengths
//!   `|o_{k+1} - o_k| <= |origin_{k+1}.t| (+ max |q_k|` for a prismatic `k`) for `k = j .. m-1`,
//!   plus the object's largest vertex distance from its body origin (`+ max |q_m|` for a
//!   prismatic last joint). Rotation about an axis through `o_k` keeps lengths from `o_k`.
//! - `Omega_j` (`omega_before`) `= sum_{k<j, revolute} |dq_k|`: how fast joint `j`'s frame
//!   turns (the base does not move), so `a_j` and the vector `u_j` turned rigidly with that frame
//!   move by at most `Omega_j h` radians over a window `h`.
//! - `V_j` (`v_rel`) `= sum_{k>=j} s_k` with `s_k = |dq_k| R_k` (revolute) or `|dq_k|`
//!   (prismatic): how fast `x` moves relative to joint `j`'s frame.
//!
//! Over a window `[t, t + h]`, write `u_j(s) = Q u'`, `a_j(s) = Q a_j(t)` with `Q` the turn of
//! joint `j`'s frame (angle at most `Omega_j h`) and `|u' - u_j(t)| <= V_j h`, `u_j(t)` the
//! point's lever at `t`. Then `a_j(s) x u_j(s) = Q (a_j(t) x u')`, so
//! `|a_j(s) x u_j(s) - a_j(t) x u_j(t)| <= Omega_j h |u'| + V_j h`, and `|u'| <= R_j`; a
//! prismatic joint's `a_j(s)` is within `Omega_j h` of `a_j(t)`. The point's velocity over the
//! window is therefore within `h K` of the velocity the field at `t` gives its position at `t`,
//!
//! ```text
//! K = sum_{revolute j} |dq_j| (Omega_j R_j + V_j) + sum_{prismatic j} |dq_j| Omega_j.
//! ```
//!
//! At `t` the field is one twist: `v(x) = v0 + omega x x` with `omega = sum_{revolute} dq_j a_j`
//! and `v0 = sum_{revolute} dq_j (o_j x a_j) + sum_{prismatic} dq_j a_j`. For the points of a set
//! about a centre `c` (at `t`), `n . (omega x (x - c)) = (x - c) . (n x omega)`, linear in the
//! point, so over the set it is at most the set's support `S(n x omega)`
//! ([`crate::motion::Spread`]: `|g| r` for a ball of radius `r`;
//! `h1 |e1 . g| + h2 |e2 . g| + rr |g|` for a rectangle swept by a ball, a hierarchy volume).
//! Hence, along a unit `n` and in any direction:
//!
//! ```text
//! speed along n <= min( n . v(c) + S(n x omega) + h K, V_1 )
//! speed         <= min( |v(c)| + |omega| r + h K,      V_1 )
//! ```
//!
//! with `r` the farthest the points reach from `c` and `V_1` the largest speed any point of the
//! object has on the edge. The first terms are the centre's exact velocity at `t` and the
//! set's exact spread under the link's rotation at `t`: summing the joints into one twist
//! before taking the spread is what keeps it tight (joint rotations that cancel, a wrist turning
//! back against the shoulder, cancel in `omega`; a sum of per-joint terms `|dq_j| S(n x a_j)`,
//! which the bound took before, counts each). Its evaluation is a handful of products whatever
//! the chain's length: `omega`, `v0` and `K` are computed once per time. The unit tests below
//! sample the true velocity on random chains (revolute and prismatic, windows, balls and swept
//! rectangles) and check it never exceeds either bound.

use crate::math::{Mat3, Pose, Vec3};
use crate::motion::Motion;

/// How far from parallel (the sine of the angle) a slide's axis may be from a turning joint's
/// for [`ChainPath::rigid`] to take the two as one screw: the slide's part across the axis,
/// dropped, moves the link by at most this fraction of the slide, a rounding of the axes'
/// entries.
const SAME_AXIS: f64 = 1e-12;

/// A moving joint's frame and axis, with the products that give `origin * J(q)` in one step.
///
/// For a revolute joint, Rodrigues' formula `J(q) = c I + s [a]x + (1 - c) a a^T` carried
/// through the origin's rotation `O` gives `O J(q) = c (O - O a a^T) + s O [a]x + O a a^T`:
/// three fixed matrices, so a pose costs one sine and cosine and a 3x3 combination instead of
/// building `J(q)` and multiplying (forward kinematics, the culling and the advancement's poses
/// all go through it). A prismatic joint's is `O` with the translation moved by `q O a`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointFrame {
    /// Joint frame in the parent body's frame.
    pub origin: Pose,
    pub prismatic: bool,
    /// `O a`: the axis in the parent body's frame.
    pub o_axis: Vec3,
    /// `O - O a a^T`.
    cos_part: Mat3,
    /// `O [a]x` (columns `O (a x e_i)`).
    sin_part: Mat3,
    /// `O a a^T`.
    fixed_part: Mat3,
}

impl JointFrame {
    /// The frame of a joint at `origin` (parent body frame) with unit `axis` (joint frame).
    pub fn new(origin: Pose, axis: Vec3, prismatic: bool) -> Self {
        let o = origin.rotation;
        let o_axis = o * axis;
        let fixed_part = Mat3::from_cols(o_axis * axis.x, o_axis * axis.y, o_axis * axis.z);
        let sin_part = Mat3::from_cols(
            o * axis.cross(Vec3::X),
            o * axis.cross(Vec3::Y),
            o * axis.cross(Vec3::Z),
        );
        Self {
            origin,
            prismatic,
            o_axis,
            cos_part: o - fixed_part,
            sin_part,
            fixed_part,
        }
    }

    /// `origin * J(q)`: the child body's pose in the parent body's frame at joint value `q`.
    #[inline]
    pub fn at(&self, q: f64) -> Pose {
        let (s, c) = if self.prismatic {
            (0.0, 1.0)
        } else {
            q.sin_cos()
        };
        self.at_sin_cos(q, s, c)
    }

    /// [`JointFrame::at`] given `sin q` and `cos q` (a prismatic joint uses `q` only).
    #[inline]
    pub fn at_sin_cos(&self, q: f64, sin: f64, cos: f64) -> Pose {
        if self.prismatic {
            Pose {
                rotation: self.origin.rotation,
                translation: self.origin.translation + self.o_axis * q,
            }
        } else {
            Pose {
                rotation: self.cos_part * cos + self.sin_part * sin + self.fixed_part,
                translation: self.origin.translation,
            }
        }
    }
}

/// One moving joint of a chain, as a path sees it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ChainStep<'f> {
    /// The joint's frame and axis (the robot's).
    pub frame: &'f JointFrame,
    pub q0: f64,
    pub dq: f64,
    /// Bound on the distance from this joint's origin to any point of the object, over the edge.
    pub r_chain: f64,
    /// `sum_{k<j, revolute} |dq_k|`.
    pub omega_before: f64,
    /// `sum_{k>=j} speed_k`: how fast the object's points move relative to this joint's frame.
    pub v_rel: f64,
}

/// A collision object's motion along a joint-space segment: the chain from the robot's base.
#[derive(Clone, Debug)]
pub(crate) struct ChainPath<'f> {
    pub base: Pose,
    pub steps: Vec<ChainStep<'f>>,
}

impl<'f> ChainPath<'f> {
    /// The chain of an object whose vertices lie within `reach` of its body's origin.
    /// `steps` carry the joint frames, `q0` and `dq`; the bound constants are filled here.
    pub fn new(base: Pose, mut steps: Vec<ChainStep<'f>>, reach: f64) -> Self {
        let qmax = |s: &ChainStep| s.q0.abs().max((s.q0 + s.dq).abs());
        let m = steps.len();
        // R_j from the tip down.
        let mut r = reach;
        for j in (0..m).rev() {
            if j + 1 < m {
                let next = &steps[j + 1];
                r += next.frame.origin.translation.length();
            }
            if steps[j].frame.prismatic {
                r += qmax(&steps[j]);
            }
            steps[j].r_chain = r;
        }
        let speed = |s: &ChainStep| {
            if s.frame.prismatic {
                s.dq.abs()
            } else {
                s.dq.abs() * s.r_chain
            }
        };
        let mut v = 0.0;
        for j in (0..m).rev() {
            v += speed(&steps[j]);
            steps[j].v_rel = v;
        }
        let mut omega = 0.0;
        for s in steps.iter_mut() {
            s.omega_before = omega;
            if !s.frame.prismatic {
                omega += s.dq.abs();
            }
        }
        Self { base, steps }
    }

    /// Largest speed of any point of the object at any time of the edge.
    pub fn max_speed(&self) -> f64 {
        self.steps.first().map_or(0.0, |s| s.v_rel)
    }

    /// Largest speed of any point of the object relative to the frame of the body reached after
    /// the first `skip` joints (the same `v_rel` constants: `R_j` only depends on the joints
    /// from `j` on).
    pub fn max_speed_after(&self, skip: usize) -> f64 {
        self.steps.get(skip).map_or(0.0, |s| s.v_rel)
    }

    /// The body's world pose at time `t`.
    pub fn pose_at(&self, t: f64) -> Pose {
        let mut pose = self.base;
        for s in &self.steps {
            pose = pose.mul(&s.frame.at(s.q0 + t * s.dq));
        }
        pose
    }

    /// The same motion as a rigid one, when it is one the rigid query serves better: a body
    /// that does not move, or one that turns with a single revolute joint while every other
    /// moving joint of its chain slides along that joint's axis (none, in a wrist turning at a
    /// small clearance from a shelf; a bolt driven into its nut by a slide along its axis). The
    /// turn is about a line fixed in the world, so the rigid query's rotation certificates
    /// apply (docs/BENCHMARKS.md). `None` for any other motion.
    pub fn rigid(&self) -> Option<Motion> {
        let moving = || self.steps.iter().enumerate().filter(|(_, s)| s.dq != 0.0);
        let mut turning = moving().filter(|(_, s)| !s.frame.prismatic);
        let Some((j, step)) = turning.next() else {
            return moving()
                .next()
                .is_none()
                .then(|| Motion::stationary(self.pose_at(0.0)));
        };
        if turning.next().is_some() {
            return None;
        }
        // The pose of joint j's parent body at the start; the line through the joint's origin
        // along its axis stays where it is, the slides moving it along itself.
        let parent = self.parent_pose(j, 0.0);
        let point = parent.transform_point(step.frame.origin.translation);
        let dir = (parent.rotation * step.frame.o_axis).normalize();
        // The slides' world velocity: each one's axis at the start, which a turn about `dir`
        // keeps where it is parallel to it (the slides below the joint) and no turn moves (the
        // slides above it: the only turning joint is j).
        let mut slide = Vec3::ZERO;
        for (k, s) in moving().filter(|(_, s)| s.frame.prismatic) {
            let axis = (self.parent_pose(k, 0.0).rotation * s.frame.o_axis).normalize();
            if axis.cross(dir).length() > SAME_AXIS {
                return None;
            }
            slide += dir * (axis.dot(dir) * s.dq);
        }
        Some(Motion::turn_and_slide(
            self.pose_at(0.0),
            point,
            dir * step.dq,
            slide,
        ))
    }

    /// The chain's last moving joint, when it turns (revolute) and other joints before it
    /// move too: the link then turns about a line fixed in that joint's parent body, which
    /// itself moves (a wrist turning while the arm moves a little; `query/frozen.rs`).
    pub fn last_turn(&self) -> Option<usize> {
        let j = self.steps.iter().rposition(|s| s.dq != 0.0)?;
        let before = self.steps[..j].iter().any(|s| s.dq != 0.0);
        (before && !self.steps[j].frame.prismatic).then_some(j)
    }

    /// The world pose at time `t` of the body that joint `j` hangs from.
    pub fn parent_pose(&self, j: usize, t: f64) -> Pose {
        let mut pose = self.base;
        for s in &self.steps[..j] {
            pose = pose.mul(&s.frame.at(s.q0 + t * s.dq));
        }
        pose
    }

    /// The motion of the body that joint `j` hangs from, for points within `reach` of that
    /// body's origin: its [`ChainPath::max_speed`] bounds how fast such points move.
    pub fn parent_path(&self, j: usize, reach: f64) -> ChainPath<'f> {
        ChainPath::new(self.base, self.steps[..j].to_vec(), reach)
    }

    /// Joint `j`'s turn in its parent body's frame, as a rigid motion, when every joint after
    /// it stands still: the link's pose there is `origin_j J(q_j(t)) tail`, and since turns
    /// about one axis commute, `origin_j J(q0 + t dq) = T(t dq) origin_j J(q0)` with `T` the
    /// turn about the axis line through the joint's origin.
    pub fn turn_in_parent(&self, j: usize) -> Motion {
        let step = &self.steps[j];
        let mut pose = step.frame.at(step.q0);
        for s in &self.steps[j + 1..] {
            pose = pose.mul(&s.frame.at(s.q0));
        }
        let dir = step.frame.o_axis.normalize();
        Motion::turn_unchecked(pose, step.frame.origin.translation, dir * step.dq)
    }

    /// The body's world pose at time `t`, and the link's velocity field there with the window
    /// constants (world frame, module docs): one pass down the chain gives both.
    pub fn state_at(&self, t: f64) -> (Pose, ChainKinematics) {
        let (mut omega, mut v0, mut window_rate) = (Vec3::ZERO, Vec3::ZERO, 0.0);
        let mut pose = self.base;
        for s in &self.steps {
            let axis = pose.rotation * s.frame.o_axis;
            let adq = s.dq.abs();
            if s.frame.prismatic {
                v0 += axis * s.dq;
                window_rate += adq * s.omega_before;
            } else {
                let origin = pose.transform_point(s.frame.origin.translation);
                omega += axis * s.dq;
                v0 += origin.cross(axis) * s.dq;
                window_rate += adq * (s.omega_before * s.r_chain + s.v_rel);
            }
            pose = pose.mul(&s.frame.at(s.q0 + t * s.dq));
        }
        let kinematics = ChainKinematics {
            omega,
            v0,
            window_rate,
            cap: self.max_speed(),
        };
        (pose, kinematics)
    }
}

/// A link's motion bound at one time (module docs): its velocity field `v0 + omega x x` and the
/// window and cap constants, in the frame the bound is evaluated in.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ChainKinematics {
    omega: Vec3,
    v0: Vec3,
    /// `K`: how fast a point's velocity can drift from the field's over a window.
    window_rate: f64,
    /// `V_1`: the largest speed of any point of the object on the edge.
    cap: f64,
}

impl ChainKinematics {
    /// The same field in the frame `to_frame` maps the world into: with `x' = R x + p`, the
    /// velocity `R (v0 + omega x x)` is `(R v0 - R omega x p) + R omega x x'`.
    #[inline]
    pub fn in_frame(&self, to_frame: &Pose) -> Self {
        let omega = to_frame.rotation * self.omega;
        Self {
            omega,
            v0: to_frame.rotation * self.v0 - omega.cross(to_frame.translation),
            ..*self
        }
    }

    /// Bound on the speed along the unit `n` of a set of points about `center` (both in the
    /// evaluation frame), over a window `h` (module docs); `support(g)` is the set's
    /// `max (x - c) . g` for `g` in the evaluation frame
    /// ([`crate::motion::Spread::support`]). May be negative.
    #[inline]
    pub fn bound(&self, n: Vec3, center: Vec3, support: impl Fn(Vec3) -> f64, h: f64) -> f64 {
        let along = n.dot(self.v0 + self.omega.cross(center))
            + support(n.cross(self.omega))
            + h * self.window_rate;
        along.min(self.cap)
    }

    /// Bound on the speed of the object's points within `radius` of `center`, in any
    /// direction, over a window `h`.
    #[inline]
    pub fn speed(&self, center: Vec3, radius: f64, h: f64) -> f64 {
        let any = (self.v0 + self.omega.cross(center)).length()
            + self.omega.length() * radius
            + h * self.window_rate;
        any.min(self.cap)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::sampling::{rss_point, unit};
    use crate::motion::Spread;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A joint at a random frame (turned up to 3 rad, up to 0.6 from its parent's origin) with
    /// a random axis, prismatic one time in four.
    fn random_frame(rng: &mut ChaCha8Rng) -> JointFrame {
        JointFrame::new(
            Pose::from_axis_angle(
                unit(rng),
                rng.random_range(-3.0..3.0),
                unit(rng) * rng.random_range(0.0..0.6),
            ),
            unit(rng),
            rng.random_bool(0.25),
        )
    }

    /// The chain bound against the true speed (central differences of the pose, an independent
    /// path through the code) on random chains, windows, balls, swept rectangles and directions.
    #[test]
    fn bound_holds_on_random_chains() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let mut checked = 0;
        let mut tight = 0.0_f64;
        for case in 0..400 {
            let m = 1 + case % 8;
            let joints: Vec<(JointFrame, f64, f64)> = (0..m)
                .map(|_| {
                    let frame = random_frame(&mut rng);
                    (
                        frame,
                        rng.random_range(-1.5..1.5),
                        rng.random_range(-1.2..1.2),
                    )
                })
                .collect();
            let steps: Vec<ChainStep> = joints
                .iter()
                .map(|(frame, q0, dq)| ChainStep {
                    frame,
                    q0: *q0,
                    dq: *dq,
                    r_chain: 0.0,
                    omega_before: 0.0,
                    v_rel: 0.0,
                })
                .collect();
            let yc = unit(&mut rng) * rng.random_range(0.0..0.5);
            // Half the cases a ball of radius r, half a rectangle swept by a ball (a volume
            // of the hierarchy) whose bounding radius is r: its points are
            // yc + x e1 + y e2 + z, |x| <= h1, |y| <= h2, |z| <= rr (body frame).
            let r = rng.random_range(0.0..0.2);
            let rss = (case % 2 == 1).then(|| {
                let e1 = unit(&mut rng);
                let e2 = e1.cross(unit(&mut rng)).normalize();
                let (a, b) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
                let (h1, h2, rr) = (r * a * (1.0 - b), r * (1.0 - a) * (1.0 - b), r * b);
                (e1, e2, h1, h2, rr)
            });
            let path = ChainPath::new(Pose::IDENTITY, steps, yc.length() + r);
            let t = rng.random_range(0.0..1.0);
            let h = rng.random_range(0.0..(1.0 - t)) * if case % 3 == 0 { 0.05 } else { 1.0 };
            // The field in a random frame, brought back to the world: `in_frame` checked too.
            let frame =
                Pose::from_axis_angle(unit(&mut rng), rng.random_range(-3.0..3.0), unit(&mut rng));
            let (pose, world) = path.state_at(t);
            let kin = world.in_frame(&frame).in_frame(&frame.inverse());
            assert!((pose.translation - path.pose_at(t).translation).length() < 1e-12);
            let c = pose.transform_point(yc);
            let n = unit(&mut rng);
            let rot = pose.rotation;
            // The farthest the points reach from the centre (what the step search passes).
            let (spread, reach) = match rss {
                Some((e1, e2, h1, h2, rr)) => (
                    Spread::rss(rot * e1, rot * e2, h1, h2, rr),
                    (h1 * h1 + h2 * h2).sqrt() + rr,
                ),
                None => (Spread::ball(r), r),
            };
            let bound = kin.bound(n, c, |g| spread.support(g), h);
            let speed = kin.speed(c, reach, h);
            let eps = 1e-6;
            let mut worst = f64::NEG_INFINITY;
            for _ in 0..40 {
                let y = match rss {
                    // Corners and edges of the volume as often as its inside.
                    Some((e1, e2, h1, h2, rr)) => rss_point(&mut rng, yc, (e1, e2), (h1, h2), rr),
                    None => yc + unit(&mut rng) * r * rng.random_range(0.0_f64..1.0).cbrt(),
                };
                let s = t + h * rng.random_range(0.0..1.0);
                let v = (path.pose_at(s + eps).transform_point(y)
                    - path.pose_at(s - eps).transform_point(y))
                    / (2.0 * eps);
                assert!(
                    v.dot(n) <= bound + 1e-6,
                    "case {case}: speed {} along n above the bound {bound}",
                    v.dot(n)
                );
                assert!(
                    v.length() <= speed + 1e-6,
                    "case {case}: |v| {} > {speed}",
                    v.length()
                );
                assert!(v.length() <= path.max_speed() + 1e-6);
                worst = worst.max(v.dot(n));
                checked += 1;
            }
            if bound > 0.0 && worst > 0.0 {
                tight += worst / bound;
            }
        }
        assert!(checked == 16_000);
        eprintln!("mean sampled/bound ratio {}", tight / 400.0);
        // Not a correctness condition, but a bound that is loose everywhere is useless: on
        // average the sampled speed reaches a fair part of it.
        assert!(
            tight / 400.0 > 0.2,
            "bound too loose: mean ratio {}",
            tight / 400.0
        );
    }

    /// `motion` moves a random point within 0.5 of the body's origin as `path` does, to 1e-12,
    /// at both ends and ten random times.
    fn assert_same_poses(rng: &mut ChaCha8Rng, case: usize, path: &ChainPath, motion: &Motion) {
        for k in 0..12 {
            let t = match k {
                0 => 0.0,
                1 => 1.0,
                _ => rng.random_range(0.0..1.0),
            };
            let (a, b) = (path.pose_at(t), motion.pose_at(t));
            let x = unit(rng) * 0.5;
            let gap = (a.transform_point(x) - b.transform_point(x)).length();
            assert!(gap < 1e-12, "case {case}, t {t}: {gap} apart");
        }
    }

    /// [`ChainPath::rigid`] against the chain's own poses: random chains where one joint moves
    /// (revolute: a turn of up to 4.5 rad, over pi included; prismatic: none) or none does
    /// (stationary), compared at random times and at both ends.
    #[test]
    fn rigid_turns_follow_the_chain() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut turns, mut still) = (0, 0);
        for case in 0..300 {
            let m = 1 + case % 6;
            let frames: Vec<JointFrame> = (0..m).map(|_| random_frame(&mut rng)).collect();
            let moving = (case % 5 != 0).then(|| rng.random_range(0..m));
            let steps: Vec<ChainStep> = frames
                .iter()
                .enumerate()
                .map(|(j, frame)| ChainStep {
                    frame,
                    q0: rng.random_range(-1.5..1.5),
                    dq: if moving == Some(j) {
                        rng.random_range(-4.5..4.5)
                    } else {
                        0.0
                    },
                    r_chain: 0.0,
                    omega_before: 0.0,
                    v_rel: 0.0,
                })
                .collect();
            let base = Pose::from_axis_angle(unit(&mut rng), 1.0, unit(&mut rng));
            let path = ChainPath::new(base, steps, 0.5);
            let Some(motion) = path.rigid() else {
                assert!(moving.is_some_and(|j| frames[j].prismatic), "case {case}");
                continue;
            };
            if motion.is_stationary() {
                still += 1;
            } else {
                turns += 1;
            }
            assert_same_poses(&mut rng, case, &path, &motion);
        }
        assert!(turns > 150 && still > 40, "{turns} turns, {still} still");
    }

    /// The path of `frames` from `q0` by `dq`, from `base`.
    fn chain_path<'f>(
        base: Pose,
        frames: &'f [JointFrame],
        q0: &[f64],
        dq: &[f64],
    ) -> ChainPath<'f> {
        let steps = frames
            .iter()
            .zip(q0.iter().zip(dq))
            .map(|(frame, (&q0, &dq))| ChainStep {
                frame,
                q0,
                dq,
                r_chain: 0.0,
                omega_before: 0.0,
                v_rel: 0.0,
            })
            .collect();
        ChainPath::new(base, steps, 0.5)
    }

    /// [`ChainPath::rigid`] on a turn while slides move the link along the turning axis (one
    /// or two slides, above or below the turning joint): a screw that follows the chain's poses
    /// over turns of up to 4.5 rad; a slide's axis a millionth of a radian off the turning
    /// axis is no screw.
    #[test]
    fn rigid_screws_follow_the_chain() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let mut screws = 0;
        for case in 0..200 {
            let m = 2 + case % 5;
            let mut frames: Vec<JointFrame> = (0..m).map(|_| random_frame(&mut rng)).collect();
            let j = rng.random_range(0..m);
            let slides: Vec<usize> = (0..m).filter(|&k| k != j).take(1 + case % 2).collect();
            let joint = |rng: &mut ChaCha8Rng, frame: &JointFrame, prismatic| {
                JointFrame::new(frame.origin, unit(rng), prismatic)
            };
            for (k, frame) in frames.iter_mut().enumerate() {
                *frame = joint(&mut rng, frame, slides.contains(&k));
            }
            let q0: Vec<f64> = (0..m).map(|_| rng.random_range(-1.5..1.5)).collect();
            let base = Pose::from_axis_angle(unit(&mut rng), 1.0, unit(&mut rng));
            // The slides' axes along the turning joint's, in the world at the start (the
            // parents' rotations do not depend on the slides' axes).
            let still = chain_path(base, &frames, &q0, &vec![0.0; m]);
            let dir = still.parent_pose(j, 0.0).rotation * frames[j].o_axis;
            let parents: Vec<Mat3> = (0..m).map(|k| still.parent_pose(k, 0.0).rotation).collect();
            let off = case % 10 == 9;
            for &k in &slides {
                let mut world = dir * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
                if off {
                    world = (world + 1e-6 * unit(&mut rng)).normalize();
                }
                let local = frames[k].origin.rotation.transpose() * parents[k].transpose() * world;
                frames[k] = JointFrame::new(frames[k].origin, local.normalize(), true);
            }
            let dq: Vec<f64> = (0..m)
                .map(|k| match k {
                    _ if k == j => rng.random_range(-4.5..4.5),
                    _ if slides.contains(&k) => rng.random_range(-0.5..0.5),
                    _ => 0.0,
                })
                .collect();
            let chain = chain_path(base, &frames, &q0, &dq);
            let motion = chain.rigid();
            if off {
                assert!(motion.is_none(), "case {case}: a slide across the axis");
                continue;
            }
            assert!(motion.is_some(), "case {case}: a screw");
            let Some(motion) = motion else { continue };
            assert!(motion.fixed_axis().is_some(), "case {case}");
            screws += 1;
            assert_same_poses(&mut rng, case, &chain, &motion);
        }
        assert!(screws > 150, "{screws} screws");
    }
}

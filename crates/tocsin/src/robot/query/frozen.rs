//! A link turning fast about a joint whose parent body moves slowly, past a still obstacle:
//! a wrist turning half a turn beside a shelf while the arm moves a milliradian.
//!
//! The chain's bound charges such a link the full tangential speed of its turn, at every
//! triangle pair that faces the obstacle, as the rigid bound did for a shaft turning in its
//! bore. The rigid query's rotation certificates need the turning axis fixed and the other
//! body still. In the frame of the turning joint's parent body `P`, the axis is fixed and the
//! obstacle moves by `P(t)^-1` only. The check freezes it there.
//!
//! **The frozen check.** Over `[a, b]`, with `m` its middle, place the obstacle where it is in
//! `P`'s frame at `m`. A point `z` fixed in `P`'s frame moves in the world by at most
//! `V |t - m|`, `V` the largest speed of `P`'s points within the obstacle's reach of `P`'s
//! origin ([`ChainPath::max_speed`] of `P`'s own chain). `|P(t)^-1 x - P(m)^-1 x| =
//! |x - P(t) P(m)^-1 x|`, so each obstacle point `x` in `P`'s frame stays within
//! `eps = V (b - a) / 2` of its frozen place. The rigid query on the turn and the frozen
//! obstacle, with tolerance `delta + 2 eps`, answers "free" only when the frozen distance stays
//! above `delta / 2 + eps` throughout. The true distance then stays above `delta / 2`, so the
//! pair cannot have a contact the segment query must report on `[a, b]`.
//!
//! **Pieces.** The obstacle's drift must stay well inside the clearance. An approximate distance
//! `d` at a piece's start sizes it: `eps = room / 4`, `room = d - delta`, so the drift over the
//! piece eats at most half the room, and the next piece (sized again from its own start) is shorter
//! as a contact nears. `d` can be a far phase of the turn (a shaft's corners between its bore's
//! faces), and such a piece ends at the next near phase: a far check whose first step certifies
//! under [`LEAST_FIRST_STEP`] of its piece stops as soon as its step search knows it, certifying
//! nothing, and after a far check that ends short of its piece (so, or at a frozen contact) the
//! room of later pieces is at most a quarter of its room, doubling with each piece certified
//! whole; the clearance is measured again only where a check certified some time. A clearance
//! already within `delta` hands over to the chain at once. Within `1.25 delta` the checks go on
//! near contact: a fixed drift `eps` of a tenth of the tolerance, steps against
//! `delta / 2 + eps`, and a frozen pair within `delta / 2 + 2 eps` ending the check,
//! so that its frozen contacts are true ones (within `delta / 2 + 3 eps`, under `delta`) and the
//! chain taking over there ends at once; a near check that does not answer in [`NEAR_ITERATIONS`]
//! hands over to the chain. (The chain alone within `1.25 delta` paid a spinning link's tangential
//! speed at every corner passing an obstacle 1.01 to 1.2 tolerances away, and ran to the
//! 1,000-iteration cap.) A check that finds a frozen contact at `t_c` has certified `[a, t_c)` (its
//! steps keep every pair above its half tolerance), and the next piece starts there; one that stops
//! at its iteration cap has certified up to where it reached, and the chain (or, for a far check,
//! a retry on a shorter piece) starts there. The checks are tried where the turn dominates (the
//! joint's points move [`DOMINANCE`] times faster than `P`'s points at the obstacle), where the
//! link sweeps at least [`SWEEP`] clearances (else the chain's steps are long enough on their own),
//! and where the span needs at most [`MAX_PIECES`] pieces at its start's clearance (each check
//! starts its certificates' caches cold but for the turning mesh's ranges, which the mesh keeps:
//! 0.2 to 0.4 ms on a 43K-triangle sensor). The checks only certify: every contact is still found
//! by the chain's advancement, so the segment query's answers keep their meaning. An ordinary
//! planner's edge moves every joint alike and never takes them.

use super::{span_scale, Pair, Segment};
use crate::error::ContactError;
use crate::math::Pose;
use crate::motion::Motion;
use crate::query::contact_time::{advance_paths, ContactCache, Path, Span, FAR_SLACK, NEAR_SLACK};
use crate::query::distance::{distance, DistanceOptions};
use crate::robot::chain::ChainPath;

/// How many times faster the turning joint must move its link's points than the parent body
/// moves the obstacle's (in the parent's frame) for the frozen check to be tried.
const DOMINANCE: f64 = 4.0;

/// The most iterations a frozen check takes before the chain's advancement takes over. A key
/// coming round to a bump of its bore takes a frozen check about as many iterations as its
/// clearance takes halvings to come down to the tolerance; with 10, at a tolerance of 20 um,
/// the checks stopped there and the chain, taking over, ran past 1,000 iterations.
const FROZEN_ITERATIONS: usize = 32;

/// Clearances the link's points must sweep over the span for the frozen check to be tried.
/// On the UR5 wrist beside a board at 2 to 20 mm, `wrist_1` drifting 0.001 or 0.01 rad: 30
/// took 1.2 to 2.7 ms; 200 took 8.6 to 18 ms at 2 to 5 mm (the chain alone on the gripper's
/// pairs) and 1.0 to 1.1 at 20 mm, where 30 took 1.3; 20 took 1.5 at 20 mm.
const SWEEP: f64 = 30.0;

/// The relative error of the distance that sizes the pieces.
const APPROXIMATE: f64 = 0.25;

/// The most pieces a span may need, at its start's clearance, for the frozen checks to be
/// tried. The UR5 wrist beside a board 0.15 mm away, `wrist_1` drifting 0.01 rad (24
/// clearances): 8 left it to the chain alone (33 ms); 64 certify it in pieces (17 ms, 10.6
/// with the turning mesh's ranges kept).
const MAX_PIECES: f64 = 64.0;

/// A far check whose first step certifies less than this fraction of its piece stops at once
/// (the step search stops as soon as its best step is under it) and certifies nothing; the next
/// piece takes a quarter of the room: this one was sized from a far phase of the turn.
const LEAST_FIRST_STEP: f64 = 1.0 / 64.0;

/// The most frozen checks on one span: pieces shrink with the clearance as a contact nears.
const MAX_CHECKS: usize = 128;

/// How many times a far check that could not tell is tried again on a quarter of its piece.
const SHORTER: i32 = 3;

/// The most iterations a check near contact takes before the chain takes over: where the
/// certificates settle the span it takes one or two. A keyed shaft coming round to a bump of
/// its bore on a drifting lever took 8 and handed the last 0.0006 of the segment to the chain,
/// 7 iterations of 6,000 node pairs (its drift turns no certificate on) where the check's took
/// 400: with 16 the contact took 12.5 to 13 ms instead of 18 (the obstacle spinner test's seeds
/// 1 to 10, 513 -> 521 ms in all; the UR5 wrist rows unchanged).
const NEAR_ITERATIONS: usize = 16;

/// The drift a check near contact allows (within `1.25 delta`), in tolerances: under a sixth,
/// so that its frozen contacts are true ones (a piece may run up to 1.5 times its length).
const NEAR_DRIFT: f64 = 0.1;

/// What a frozen check on a piece `[a, b]` found.
enum Checked {
    /// The pair is certified on `[a, t)`: `t = b`, or a frozen contact at `t`.
    Until(f64),
    /// A far check whose first step certified under [`LEAST_FIRST_STEP`] of the piece: it
    /// stopped at once, certifying nothing.
    Oversized,
    /// It stopped at its iteration cap, certifying `[a, t)`.
    Capped(f64),
    /// It could not tell (the turn no longer dominates).
    Unknown,
}

/// What the frozen checks of one pair share.
struct Frozen<'s> {
    path: &'s ChainPath<'s>,
    joint: usize,
    /// The link's turn in the parent body's frame.
    turn: Motion,
    /// How fast the turn moves the link's points (at most).
    turning: f64,
}

impl Segment<'_> {
    /// The time up to which the frozen check certifies the pair (robot object, obstacle)
    /// farther apart than `delta / 2` on `[start, end]` (module docs); `start` when it does
    /// not apply or certifies nothing.
    pub(super) fn frozen_until(&self, pair: Pair, start: f64, end: f64) -> f64 {
        if !pair.obstacle || self.rigid[pair.a].is_some() {
            return start;
        }
        let path = &self.paths[pair.a];
        let Some(joint) = path.last_turn() else {
            return start;
        };
        if !self.scene.obstacles[pair.b].motion.is_stationary() {
            return start;
        }
        let step = &path.steps[joint];
        let frozen = Frozen {
            path,
            joint,
            turn: path.turn_in_parent(joint),
            turning: step.dq.abs() * step.r_chain,
        };
        let Some((speed, _)) = self.parent_speed(pair, &frozen, 0.5 * (start + end)) else {
            return start;
        };
        let mut t = start;
        // Quartered after a far check that could not tell, up to `SHORTER` times.
        let mut shorter = 0;
        // The most room a piece is sized with (below).
        let mut most_room = f64::INFINITY;
        // The last clearance measured, and where.
        let mut measured: Option<(f64, f64)> = None;
        for check in 0..MAX_CHECKS {
            if t >= end {
                return end;
            }
            // Worked out again only where a check certified some time: an oversized one
            // leaves the piece's start where it was.
            let d = match measured {
                Some((at, d)) if at == t => d,
                _ => self.clearance(pair, path, t),
            };
            measured = Some((t, d));
            if check == 0 && d * SWEEP >= frozen.turning * (end - start) {
                // The link's points sweep fewer than `SWEEP` clearances: the chain's steps
                // are long enough on its own (a gripper 20 mm from the board).
                return start;
            }
            if d <= self.delta {
                // Within the tolerance already (`d` is at least the distance): the chain's
                // advancement, taking over here, has a pair within reach of its contact test,
                // where a check near contact crawls past the turn's corners (a shaft spinning
                // on a swinging lever into its bore: 19 ms of 66).
                return t;
            }
            // A far check ends at a frozen pair within `delta + 2 eps`, and the frozen
            // distance is about `d - eps` where the clearance holds: a piece of length `len`
            // drifts by `eps = speed len / 2 = room / 4`, `room = d - delta`, and the room left
            // after it is at least half. Within `1.25 delta` the checks go on near contact
            // with a fixed drift ([`NEAR_DRIFT`]), whose frozen contacts are true ones.
            let room = (d - self.delta).min(most_room);
            let near = room <= 0.25 * self.delta;
            let eps = if near {
                NEAR_DRIFT * self.delta
            } else {
                0.25 * room
            };
            let len = 2.0 * eps / speed;
            if check == 0 && (end - t) > MAX_PIECES * len {
                return start;
            }
            let len = if shorter == 0 {
                len
            } else {
                len.min(end - t) * 0.25f64.powi(shorter)
            };
            let b = if end - t < 1.5 * len { end } else { t + len };
            match self.frozen_piece(pair, &frozen, (t, b), near) {
                Checked::Until(until) if until > t => {
                    // A far check that ends short of its piece at a frozen contact (or, below,
                    // whose first step fell short): the clearance at its start can be a far
                    // phase of the turn (a shaft's corners between the faces of its bore, 4
                    // tolerances, against 1.05 where they pass the faces), and a piece sized
                    // from it ends at the next near phase, each such check costing tens of
                    // milliseconds. Later pieces take at most a quarter of its room, doubling
                    // with each piece certified whole (a wrist whose clearance grows again once
                    // past a board's edge).
                    if until >= b {
                        most_room *= 2.0;
                    } else if !near {
                        most_room = 0.25 * room;
                    }
                    (t, shorter) = (until, 0)
                }
                // A far check whose first step fell short ([`LEAST_FIRST_STEP`]): sized from a
                // far phase, it stopped before the step search finished and certified nothing
                // (a 64-sided shaft on a swinging lever: its search of every facing pair of
                // shaft and bore had cost 23 ms of 47). The next piece, from the same start,
                // takes a quarter of the room, and ends near contact when that is small.
                Checked::Oversized => most_room = 0.25 * room,
                // A far check over a long piece can run out of iterations where the link
                // passes the obstacle many times before the drift brings it within the check's
                // tolerance (a barrel spinning past a plate 1.16 tolerances away, its first
                // piece the whole span, 107 tolerances of clearance): shorter pieces, before
                // the chain crawls through it.
                Checked::Capped(until) if !near && shorter < SHORTER => {
                    (t, shorter) = (until.max(t), shorter + 1)
                }
                // The chain takes over where the check reached: a check near contact that ran
                // out of iterations had certified up to there (a keyed shaft coming round to a
                // bump of its bore, which the chain then crawled through again: 9 of its 14
                // iterations).
                Checked::Capped(until) => return until.max(t),
                _ => return t,
            }
        }
        t
    }

    /// The distance between the pair (robot object, obstacle) at time `t`, approximate: at
    /// most `1 + APPROXIMATE` times the true one, and cheaper where many pairs tie (a cylinder
    /// beside a board: the exact distance cost 2 ms more where the checks then did not pay).
    /// It only sizes the pieces, each of which bounds its own drift: one sized a quarter too
    /// long still drifts by under a third of the room.
    fn clearance(&self, pair: Pair, path: &ChainPath, t: f64) -> f64 {
        let link = &self.robot.objects[pair.a].mesh;
        let obstacle = &self.scene.obstacles[pair.b];
        let opts = DistanceOptions {
            relative_error: APPROXIMATE,
            absolute_error: 0.0,
        };
        distance(
            link,
            &path.pose_at(t),
            &obstacle.mesh,
            &obstacle.pose,
            &opts,
        )
        .map_or(0.0, |d| d.distance)
    }

    /// How fast the obstacle's points move in the frame of the turning joint's parent body
    /// about time `mid` (the parent's points within the obstacle's reach), and the map from
    /// the world into that frame at `mid`; `None` where the turn does not dominate
    /// ([`DOMINANCE`]).
    fn parent_speed(&self, pair: Pair, frozen: &Frozen, mid: f64) -> Option<(f64, Pose)> {
        let obstacle = &self.scene.obstacles[pair.b];
        let to_parent = frozen.path.parent_pose(frozen.joint, mid).inverse();
        let root = obstacle.mesh.bvh().root();
        let centre = to_parent.transform_point(obstacle.pose.transform_point(root.center));
        let reach = centre.length() + obstacle.mesh.bounding_radius();
        let speed = frozen.path.parent_path(frozen.joint, reach).max_speed();
        (speed * DOMINANCE <= frozen.turning).then_some((speed, to_parent))
    }

    /// The frozen check on `[a, b]` (`near`: a check near contact, whose frozen contacts are
    /// true ones; module docs).
    fn frozen_piece(&self, pair: Pair, frozen: &Frozen, (a, b): (f64, f64), near: bool) -> Checked {
        let obstacle = &self.scene.obstacles[pair.b];
        let Some((speed, to_parent)) = self.parent_speed(pair, frozen, 0.5 * (a + b)) else {
            return Checked::Unknown;
        };
        let eps = speed * (b - a) / 2.0;
        let still = Motion::stationary(to_parent.mul(&obstacle.pose));
        let link = &self.robot.objects[pair.a].mesh;
        let (turn, fixed) = (Path::Rigid(&frozen.turn), Path::Rigid(&still));
        let paths = (&**link, turn, &*obstacle.mesh, fixed);
        // A rigid query: the whole piece as its first window, and the rigid query's slacks. It
        // took the chain's far slack of 4 (a fifth of the best step) before: a key passing a
        // bump of its bore, the arm drifting 1e-5 rad, needed over 32 iterations, reached the
        // cap and went to the chain (1.2 s; 23 ms now).
        let mut span = Span {
            first_window: 1.0,
            slack: (FAR_SLACK, NEAR_SLACK),
            max_iterations: self.max_iterations.min(if near {
                NEAR_ITERATIONS
            } else {
                FROZEN_ITERATIONS
            }),
            least_first_step: if near { 0.0 } else { LEAST_FIRST_STEP },
            ..self.span(paths, (a, b), self.delta + 2.0 * eps, true)
        };
        if near {
            // Steps keep the frozen pairs above `delta / 2 + eps` and a pair within `delta / 2
            // + 2 eps` ends the check: the true distance there is within `delta / 2 + 3 eps`,
            // under `delta` for a drift under a sixth of it, so the chain taking over at that
            // time ends at once.
            span.contact = Span::contact(0.5 * self.delta + 2.0 * eps, span_scale(paths, a));
        }
        match advance_paths(
            link,
            turn,
            &obstacle.mesh,
            fixed,
            &span,
            &mut ContactCache::default(),
        ) {
            Ok(None) => Checked::Until(b),
            Ok(Some(ends)) => Checked::Until(ends.time),
            // The first step fell short: stopped at the piece's start. (A cap of one iteration
            // reached after a longer step certified up to where it reached: below.)
            Err(ContactError::IterationLimit {
                iterations: 1,
                time_reached,
            }) if span.least_first_step > 0.0 && time_reached <= a => Checked::Oversized,
            Err(ContactError::IterationLimit { time_reached, .. }) => Checked::Capped(time_reached),
            Err(_) => Checked::Unknown,
        }
    }
}

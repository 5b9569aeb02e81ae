//! First time of contact between two moving meshes: controlled conservative advancement
//! (C2A: Tang, Kim and Manocha, ICRA 2009) over the two RSS hierarchies.
//!
//! Each iteration, at the current time `t`, a traversal of the two hierarchies finds a step
//! `dt` that is safe for every triangle pair: a node pair (or triangle pair) separated by a gap
//! `g` along a direction `n` cannot close the gap `g - delta/2` in less than
//! `(g - delta/2) / (mu_1(n) + mu_2(-n))` (see [`crate::motion`]). The search is a branch and
//! bound on that step, children first by smaller step, starting from the last closest pair.
//!
//! Semantics (the tests check them against dense sampling): a contact is returned whenever the
//! meshes come closer than `delta / 2` (in particular whenever they collide), never when they
//! stay farther apart than `delta`, and either way in between. A returned time is no later
//! than the first collision, and the distance there is at most `delta`. A tolerance below the
//! distances' own accuracy ([`DISTANCE_RESOLUTION`] of the scene scale, about what the
//! coordinates resolve) cannot be told from contact: a triangle pair within that accuracy ends
//! the advancement too, and the distance returned is then at most it. Touching at `t = 0`
//! returns `t = 0` with [`ContactStatus::StartedInContact`]. Reaching the iteration cap first is
//! an error ([`ContactError::IterationLimit`]), never a contact.
//!
//! Witnesses ([`Witnesses`]): by default the meshes' closest points at the returned time, by
//! one exact distance query warm-started from the triangle pair that ended the advancement; on
//! request that pair's closest points, which are within `delta` (a contact, at the cost of one
//! triangle pair).
//!
//! Normal: the unit direction from `point1` to `point2` where that direction is determined, that
//! is where the distance is above [`NORMAL_RESOLUTION`] of the scene scale (computed in body 1's
//! frame from the reported triangle pair, so that it stays unit and exact far from the origin,
//! where the world points round); below it (a tolerance near
//! rounding) the direction between the closest points at the iterate before, where the meshes
//! were clearly apart; at a start in contact, the normal of `triangle1` turned towards
//! `triangle2` (a convention: touching soups have no normal).
//!
//! Deviation from C2A: steps are taken against `delta / 2` rather than 0, so that the iteration
//! provably reaches a time where a triangle pair is within `delta` (and stops) whenever the
//! meshes come closer than `delta / 2`, instead of converging to the contact from below
//! forever.
//!
//! Control (C2A's approximate-far, accurate-near): a node pair may be pruned when its step is
//! within a relative `slack` of the best, and the step taken is shrunk by `1 + slack`, which
//! keeps it safe. Far from contact (last distance above `max(50 delta, R / 50)`, R the smaller
//! bounding radius) the slack is [`FAR_SLACK`]; near contact [`NEAR_SLACK`]. Deviation: C2A is
//! exact near contact, but measured on knot34k (60 + 40 queries per motion kind) an exact
//! search there was 15 to 25% slower at the median and up to 2x at the 90th percentile: the
//! last iterations visit the most pairs, and a shorter step costs less than the visits. The
//! values were 0.5 and 0.2 until the step search bounded pairs in lanes, which made each visit
//! cheaper; re-measured then (oracle bench, knot2.8k and knot34k, seven pairs of values from
//! (0.1, 0.05) to (0.5, 0.2)), 0.25 and 0.1 were the fastest: 6 iterations instead of 7 or 8,
//! knot34k medians 251-353 -> 257-285 us in one run and 274-305 in another.

pub(crate) mod cast;
mod helix;
pub(crate) mod probe;
mod quotient;
mod shells;
#[cfg(test)]
mod test_support;
mod traverse;

use crate::error::{ContactError, OptionsError};
use crate::math::Vec3;
use crate::motion::Motion;
use crate::query::distance::{
    distance_triangle_triangle, search_distance, DistanceCache, DistanceOptions, DistanceResult,
};
use crate::robot::chain::ChainPath;
use crate::{Pose, TriMesh};
use traverse::{StepOutcome, StepSearch};

/// How a body moves over the step, as the advancement sees it: a rigid [`Motion`], or a robot
/// link carried by its chain of joints under linear joint interpolation.
#[derive(Clone, Copy)]
pub(crate) enum Path<'a> {
    Rigid(&'a Motion),
    Chain(&'a ChainPath<'a>),
}

impl Path<'_> {
    /// The body's world pose at time `t`.
    pub(crate) fn pose_at(&self, t: f64) -> Pose {
        match self {
            Path::Rigid(m) => m.pose_at(t),
            Path::Chain(c) => c.pose_at(t),
        }
    }
}

/// Below this fraction of the scene scale a distance's direction is rounding noise, and the
/// normal is taken from the iterate before (module docs). Five times the distances' own
/// accuracy ([`DISTANCE_RESOLUTION`]), so that above it the direction is off by at most a
/// fifth, and by far less as the distance grows. It was 1e-10: a contact 1.2e-11 apart
/// between soups of 1e-7 and 1e-8, 0.1 from the origin (tolerance 1e-11), took an earlier
/// iterate's direction, another pair's, which pointed against `point2 - point1` (resolved
/// there to about 1e-6).
pub const NORMAL_RESOLUTION: f64 = 1e-12;

/// The accuracy of a distance, as a fraction of the scene scale (ARCHITECTURE.md): a triangle
/// pair whose distance is within it ends the advancement whatever the tolerance, since below
/// it a distance cannot be told from contact. Without it a tolerance below the rounding of the
/// distances could not be reached: the steps, taken against `delta / 2`, shrank with that
/// rounding, and a box a million units wide turning past another with a tolerance of 1e-300
/// crawled to the iteration cap.
pub const DISTANCE_RESOLUTION: f64 = 2e-13;

/// Relative step slack far from contact (see the module docs).
pub const FAR_SLACK: f64 = 0.25;
/// Relative step slack near contact (see the module docs).
pub const NEAR_SLACK: f64 = 0.1;

/// Options of [`time_of_contact`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactOptions {
    /// Distance tolerance `delta` (model units, > 0): a returned time has distance at most this.
    /// `None` uses [`effective_tolerance`]'s default: `1e-3` times the smaller bounding radius,
    /// raised for degenerate meshes (points, segments) to `1e-6` of the larger radius and to
    /// `1e-12` of the scene scale. A tolerance below [`DISTANCE_RESOLUTION`] of the scene
    /// scale (the distances' own accuracy) is kept for the steps, but a pair within that
    /// accuracy ends the advancement (module docs).
    pub tolerance: Option<f64>,
    /// Largest number of advancement iterations (>= 1). Default 1000.
    pub max_iterations: usize,
    /// Which points a returned contact reports. Default [`Witnesses::Closest`].
    pub witnesses: Witnesses,
}

impl Default for ContactOptions {
    fn default() -> Self {
        Self {
            tolerance: None,
            max_iterations: 1000,
            witnesses: Witnesses::Closest,
        }
    }
}

/// Which points a time of contact reports (both at the returned time, world frame).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Witnesses {
    /// The meshes' closest points at the returned time and their exact distance: one exact
    /// distance query after the advancement, warm-started from the pair that ended it (15 to
    /// 25% of a knot's time of contact; docs/BENCHMARKS.md).
    #[default]
    Closest,
    /// The closest points of the triangle pair that ended the advancement: a pair within the
    /// tolerance, where the meshes come into contact, at the cost of that one pair. The
    /// `distance` reported is that pair's, at least the meshes' distance and possibly up to
    /// the tolerance above it: a caller that sets a next tolerance from it (a simulation
    /// checking a separating contact with half its distance) needs [`Witnesses::Closest`]
    /// (the command line's rain froze 88 of 90 steps with these). Where the pair touches to
    /// rounding, or the meshes touch at the start, the closest points are reported instead.
    Contact,
}

/// How a contact query ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ContactStatus {
    /// A time was reached at which the meshes are within the tolerance.
    Converged,
    /// The meshes touch or overlap at `t = 0`.
    StartedInContact,
}

/// Where and when two moving meshes first come within the tolerance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactTime {
    /// Time of contact in `[0, 1]` (the motions' parameter), no later than the first collision.
    pub time: f64,
    /// Point of mesh 1 at `time`, world frame: the meshes' closest, or the contact pair's
    /// ([`Witnesses`]).
    pub point1: Vec3,
    /// Point of mesh 2 at `time`, world frame, as `point1`.
    pub point2: Vec3,
    /// Unit normal from body 1 to body 2, world frame: the direction of `point2 - point1` (to
    /// rounding `(point2 - point1) / distance`; computed in body 1's frame), or where
    /// the distance is below rounding, the rule in the module docs.
    pub normal: Vec3,
    /// Distance between `point1` and `point2` (model units, at most the tolerance): the meshes'
    /// distance at `time` (with [`Witnesses::Contact`], at least it).
    pub distance: f64,
    /// Triangle of mesh 1 holding `point1`.
    pub triangle1: usize,
    /// Triangle of mesh 2 holding `point2`.
    pub triangle2: usize,
    /// Number of advancement iterations taken.
    pub iterations: usize,
    /// How the query ended.
    pub status: ContactStatus,
}

/// Carries the last closest triangle pair across queries on the same mesh pair.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ContactCache {
    pub(crate) pair: Option<(u32, u32)>,
    /// Where GJK ended, for two convex meshes.
    pub(crate) simplex: crate::query::distance::gjk::WarmSimplex,
}

/// The tolerance a query with these options uses on these meshes and motions (model units):
/// the option when given, else `max(1e-3 min(R1, R2), 1e-6 max(R1, R2), 1e-12 S)`, `R` the
/// bounding radii and `S` the scene scale (radii plus the largest start or end position of
/// either body). The last two terms only matter for degenerate meshes: a one-point mesh has
/// `R = 0`, and 1e-3 of it is no tolerance at all. The steps use this tolerance; a triangle
/// pair within [`DISTANCE_RESOLUTION`] of `S` ends the advancement even where it is smaller.
pub fn effective_tolerance(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    options: &ContactOptions,
) -> f64 {
    options.tolerance.unwrap_or_else(|| {
        let (r1, r2) = (mesh1.bounding_radius(), mesh2.bounding_radius());
        let scale = scene_scale(mesh1, motion1, mesh2, motion2);
        (1e-3 * r1.min(r2))
            .max(1e-6 * r1.max(r2))
            .max(1e-12 * scale)
            .max(f64::MIN_POSITIVE)
    })
}

/// Bounding radii plus the largest start or end position of either body.
pub(crate) fn scene_scale(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
) -> f64 {
    let reach = |m: &Motion| {
        m.start()
            .translation
            .length()
            .max(m.end().translation.length())
    };
    mesh1.bounding_radius() + mesh2.bounding_radius() + reach(motion1) + reach(motion2)
}

/// First time of contact of `mesh1` moving by `motion1` and `mesh2` moving by `motion2` over
/// `t in [0, 1]`: `Some` whenever they come closer than half the tolerance, `None` when they
/// stay farther apart than it (either in between; module docs).
///
/// # Errors
/// [`ContactError::Options`] for a bad option, [`ContactError::IterationLimit`] when the cap
/// is reached before the answer is known.
pub fn time_of_contact(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    options: &ContactOptions,
) -> Result<Option<ContactTime>, ContactError> {
    time_of_contact_with_cache(
        mesh1,
        motion1,
        mesh2,
        motion2,
        options,
        &mut ContactCache::default(),
    )
}

/// [`time_of_contact`] warm-started from, and updating, `cache`.
pub fn time_of_contact_with_cache(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    options: &ContactOptions,
    cache: &mut ContactCache,
) -> Result<Option<ContactTime>, ContactError> {
    let (path1, path2) = (Path::Rigid(motion1), Path::Rigid(motion2));
    Ok(
        advance(mesh1, motion1, mesh2, motion2, options, cache, false)?
            .map(|ends| finish(mesh1, path1, mesh2, path2, ends, cache, options.witnesses)),
    )
}

/// Whether the motions are free of contact: `true` when the meshes stay farther apart than
/// the tolerance over all of `[0, 1]`, `false` whenever they come closer than half of it (in
/// particular whenever they collide), either in between; the same answer as
/// `time_of_contact(..).is_none()`. The question a path planner asks: it computes no
/// witnesses, stops at the first iteration within the tolerance, and settles colliding motions
/// with exact collision tests at a few times before the advancement converges to the contact
/// (`probe.rs`'s schedule: the end, the middle, then evenly spaced times of the rest when the
/// advancement is slow; each test gives up after a budget of node pairs). A collision found so
/// is a real one, so the answer is the same.
///
/// # Errors
/// As [`time_of_contact`]: bad options, or the iteration cap reached before the answer is known.
pub fn motion_is_free(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    options: &ContactOptions,
) -> Result<bool, ContactError> {
    let checked = checked(mesh1, motion1, mesh2, motion2, options)?;
    let (path1, path2) = (Path::Rigid(motion1), Path::Rigid(motion2));
    if probe::probe_span(mesh1, path1, mesh2, path2, 0.0, 1.0).is_some() {
        return Ok(false);
    }
    // A yes/no answer needs no collision test at the start: touching meshes end the first
    // step search just the same.
    let span = Span::whole_motion(checked, true);
    let mut cache = ContactCache::default();
    Ok(
        match probe::advance_probed(mesh1, path1, mesh2, path2, &span, &mut cache)? {
            probe::Probed::Collides(_) => false,
            probe::Probed::Advanced(ends) => ends.is_none(),
        },
    )
}

/// The advancement of two rigid motions over `[0, 1]` (module docs); [`finish`] gives the
/// witnesses of where it ended. `start_free`: the caller knows the meshes are apart at `t = 0`
/// ([`Span::start_free`]).
pub(crate) fn advance(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    options: &ContactOptions,
    cache: &mut ContactCache,
    start_free: bool,
) -> Result<Option<Ends>, ContactError> {
    let checked = checked(mesh1, motion1, mesh2, motion2, options)?;
    advance_validated(mesh1, motion1, mesh2, motion2, checked, cache, start_free)
}

/// The options checked, and what the advancement takes from them: the tolerance, the scene
/// scale and the iteration cap.
fn checked(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    options: &ContactOptions,
) -> Result<(f64, f64, usize), OptionsError> {
    let delta = validate(mesh1, motion1, mesh2, motion2, options)?;
    let scale = scene_scale(mesh1, motion1, mesh2, motion2);
    Ok((delta, scale, options.max_iterations))
}

/// [`advance`] once the options are checked: tolerance `delta`, scene scale `scale`, the
/// iteration cap.
fn advance_validated(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    checked: (f64, f64, usize),
    cache: &mut ContactCache,
    start_free: bool,
) -> Result<Option<Ends>, ContactError> {
    let span = Span::whole_motion(checked, start_free);
    advance_paths(
        mesh1,
        Path::Rigid(motion1),
        mesh2,
        Path::Rigid(motion2),
        &span,
        cache,
    )
}

/// [`advance`] for two bodies that keep their rotations over a short way (body 2 translates
/// relative to body 1 by little against the bodies' size: the penetration depth's way back
/// from a nearby free sample), from a start the caller knows is apart: [`cast_translation`]
/// answers, and the advancement where it cannot. Not for long ways: the cast expands every
/// node pair that might meet before the first contact, and on knot2.8k driven through its
/// copy from 2.5 radii away its median was 24 ms (6.8 s at the 90th percentile) against the
/// advancement's 0.2 ms (docs/BENCHMARKS.md).
pub(crate) fn advance_short_translation(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    options: &ContactOptions,
    cache: &mut ContactCache,
) -> Result<Option<Ends>, ContactError> {
    let checked @ (delta, scale, _) = checked(mesh1, motion1, mesh2, motion2, options)?;
    if motion1.angular_velocity() == Vec3::ZERO && motion2.angular_velocity() == Vec3::ZERO {
        if let Some(answer) = cast_translation(mesh1, motion1, mesh2, motion2, delta, scale, cache)
        {
            return Ok(answer);
        }
    }
    // The options were checked above: not again.
    advance_validated(mesh1, motion1, mesh2, motion2, checked, cache, true)
}

/// The advancement's answer for two bodies that keep their rotations (body 2 translates
/// relative to body 1), in one traversal ([`cast`]): the first time at which the triangles,
/// widened by `delta / 2`, meet on every separating axis of some pair; no pair closer than
/// `delta / 2` before it. That pair is checked to be within `delta` there (else the widened
/// axes overstated a corner, or a degenerate pair's axes were too few), and then it is the
/// time returned, with the pair in `cache`. `None` where that check fails: the advancement
/// answers instead. `Some(None)`: no pair comes within `delta / 2` over `[0, 1]`.
fn cast_translation(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    delta: f64,
    scale: f64,
    cache: &mut ContactCache,
) -> Option<Option<Ends>> {
    let (pose1, pose2) = (motion1.pose_at(0.0), motion2.pose_at(0.0));
    let moved = |m: &Motion, p: &crate::Pose| m.pose_at(1.0).translation - p.translation;
    let disp = moved(motion2, &pose2) - moved(motion1, &pose1);
    if !disp.is_finite() {
        return None;
    }
    let margin = 0.5 * delta + CAST_MARGIN * scale;
    let Some(hit) = cast::first_hit(mesh1, &pose1, mesh2, &pose2, disp, margin, cache.pair) else {
        return Some(None);
    };
    let (p1, p2) = (motion1.pose_at(hit.time), motion2.pose_at(hit.time));
    let (l1, l2) = hit.pair;
    let a = mesh1.bvh().leaf_triangles()[l1 as usize].map(|v| p1.transform_point(v));
    let b = mesh2.bvh().leaf_triangles()[l2 as usize].map(|v| p2.transform_point(v));
    if distance_triangle_triangle(&a, &b).distance > delta {
        return None;
    }
    cache.pair = Some(hit.pair);
    Some(Some(Ends {
        time: hit.time,
        within: Some(hit.pair),
        closest: None,
        earlier: (hit.time > 0.0).then_some(0.0),
        resolution: NORMAL_RESOLUTION * scale,
        iterations: 1,
        status: ContactStatus::Converged,
    }))
}

/// The rounding margin of [`cast_translation`]'s bounds, a fraction of the scene scale: far
/// above the rounding of a projection, far below any tolerance.
const CAST_MARGIN: f64 = 1e-12;

/// What an advancement covers: the times, the tolerance, the scale below which a direction is
/// noise, and the iteration cap.
pub(crate) struct Span {
    pub start: f64,
    pub end: f64,
    pub delta: f64,
    pub resolution: f64,
    /// A triangle pair within this distance ends the advancement: `delta`, or
    /// [`DISTANCE_RESOLUTION`] of the scene scale where `delta` is below it ([`Span::contact`]).
    pub contact: f64,
    pub max_iterations: usize,
    /// The first iteration's window as a fraction of the span (at most 1): the bounds hold over
    /// the window, and pairs whose step exceeds it are not visited.
    pub first_window: f64,
    /// The step slack far from contact and near it (module docs).
    pub slack: (f64, f64),
    /// The caller knows the meshes are apart at `start` (an exact `collide` said so, or an
    /// advancement certified that time): the `collide` that would find a start in contact
    /// (asked otherwise only where the first iteration ends with a pair within the tolerance)
    /// is skipped. Were they touching after all, the first step search would find a pair within
    /// the tolerance and end at `start` just the same, with [`ContactStatus::Converged`].
    pub start_free: bool,
    /// An advancement whose first step certifies less than this fraction of the span stops
    /// there (0: never), with a one-iteration limit error at its start: the step search stops
    /// as soon as its best step is under it (`StepSearch::abort_below`). A robot's frozen check
    /// sized for more room than the turn leaves stops at once and is sized again
    /// (`robot/query/frozen.rs`).
    pub least_first_step: f64,
}

impl Span {
    /// The distance within which a triangle pair ends an advancement with tolerance `delta` in
    /// a scene of scale `scale`: `delta`, raised to [`DISTANCE_RESOLUTION`] of the scale.
    pub(crate) fn contact(delta: f64, scale: f64) -> f64 {
        delta.max(DISTANCE_RESOLUTION * scale)
    }

    /// A rigid query's span: all of `[0, 1]` with the default window and slacks, from the
    /// checked options (tolerance, scene scale, iteration cap; see `checked`).
    fn whole_motion((delta, scale, max_iterations): (f64, f64, usize), start_free: bool) -> Self {
        Self {
            start: 0.0,
            end: 1.0,
            delta,
            resolution: NORMAL_RESOLUTION * scale,
            contact: Self::contact(delta, scale),
            max_iterations,
            first_window: 1.0,
            slack: (FAR_SLACK, NEAR_SLACK),
            start_free,
            least_first_step: 0.0,
        }
    }
}

/// The advancement over `[span.start, span.end]`: where it ended when the meshes came within
/// the tolerance, `None` when they stayed apart up to `span.end`. Meshes that touch at the start
/// end it at once, with [`ContactStatus::StartedInContact`].
pub(crate) fn advance_paths(
    mesh1: &TriMesh,
    path1: Path<'_>,
    mesh2: &TriMesh,
    path2: Path<'_>,
    span: &Span,
    cache: &mut ContactCache,
) -> Result<Option<Ends>, ContactError> {
    Ok(
        match advance_core::<false>(mesh1, path1, mesh2, path2, span, cache)? {
            probe::Probed::Advanced(ends) => ends,
            // Not reached without probes; were it, a collision at `time` is a contact.
            probe::Probed::Collides(time) => Some(Ends {
                time,
                within: None,
                closest: None,
                earlier: None,
                resolution: span.resolution,
                iterations: 0,
                status: ContactStatus::Converged,
            }),
        },
    )
}

/// [`advance_paths`], and with `PROBING` the yes/no answer's probes after
/// [`probe::PROBE_AFTER`] iterations ([`probe::advance_probed`]). A constant, so that the
/// time of contact's advancement is compiled without them.
fn advance_core<const PROBING: bool>(
    mesh1: &TriMesh,
    path1: Path<'_>,
    mesh2: &TriMesh,
    path2: Path<'_>,
    span: &Span,
    cache: &mut ContactCache,
) -> Result<probe::Probed, ContactError> {
    use probe::Probed;
    let (delta, resolution) = (span.delta, span.resolution);
    let started_in_contact = Ends {
        time: span.start,
        within: None,
        closest: None,
        earlier: None,
        resolution,
        iterations: 0,
        status: ContactStatus::StartedInContact,
    };
    // Whether the start is known free. A start known free is not tested (nor are its poses
    // computed: a chain's takes a pass down its joints). Otherwise the collision test waits
    // for the first iteration: a step from the start certifies every pair apart there (a
    // positive step needs a positive gap), and where the bodies fit closely the test costs
    // more than the iteration (a third of a bolt screwed into its nut). Only a pair within
    // the tolerance at the start leaves the question to the test.
    let mut start_free = span.start_free;
    let small_radius = mesh1.bounding_radius().min(mesh2.bounding_radius());
    let far = (50.0 * delta).max(small_radius / 50.0);
    let mut search = StepSearch::new(
        mesh1,
        path1,
        mesh2,
        path2,
        (delta, span.contact),
        cache.simplex,
    );
    search.start = span.start;
    let mut t = span.start;
    let mut earlier = None;
    let mut last_distance = f64::INFINITY;
    // Bounds are taken over a window twice the last step (the whole rest at first): tighter
    // than over all of [t, end] when the rotation axis is far from the bodies.
    let mut window = (span.end - span.start) * span.first_window.clamp(f64::MIN_POSITIVE, 1.0);
    // A first step under this stops the advancement (below): the search need not finish it.
    search.abort_below = span.least_first_step * (span.end - span.start);
    for iteration in 1..=span.max_iterations {
        let slack = if last_distance > far {
            span.slack.0
        } else {
            span.slack.1
        };
        let out = search.run(t, window.min(span.end - t), slack, cache.pair);
        search.abort_below = 0.0;
        cache.simplex = search.warm_simplex();
        match out {
            StepOutcome::Within { pair, closest } => {
                if !start_free && probe::collides_at(mesh1, path1, mesh2, path2, span.start) {
                    return Ok(Probed::Advanced(Some(started_in_contact)));
                }
                cache.pair = Some(pair);
                return Ok(Probed::Advanced(Some(Ends {
                    time: t,
                    within: Some(pair),
                    closest,
                    earlier,
                    resolution,
                    iterations: iteration,
                    status: ContactStatus::Converged,
                })));
            }
            StepOutcome::Step { dt, pair, distance } => {
                start_free |= dt > 0.0;
                cache.pair = pair.or(cache.pair);
                last_distance = distance;
                if t + dt >= span.end {
                    return Ok(Probed::Advanced(None));
                }
                if distance > resolution {
                    earlier = Some(t);
                }
                if iteration == 1 && dt < span.least_first_step * (span.end - span.start) {
                    return Err(ContactError::IterationLimit {
                        iterations: 1,
                        time_reached: t,
                    });
                }
                t += dt;
                // A step that no pair limited (the whole window was certified) lets the next
                // window grow faster: a turning body certified by the rotation shells would
                // otherwise double its way to the end.
                window = if pair.is_none() { 8.0 * dt } else { 2.0 * dt };
                if PROBING && iteration == probe::PROBE_AFTER {
                    // Certified apart up to `t`: probe the rest if the pace is slow.
                    let found = probe::probe_rest(mesh1, path1, mesh2, path2, span, t, iteration);
                    if let Some(at) = found {
                        return Ok(Probed::Collides(at));
                    }
                }
            }
        }
    }
    Err(ContactError::IterationLimit {
        iterations: span.max_iterations,
        time_reached: t,
    })
}

/// The options checked, and the tolerance they give on these meshes.
fn validate(
    mesh1: &TriMesh,
    motion1: &Motion,
    mesh2: &TriMesh,
    motion2: &Motion,
    options: &ContactOptions,
) -> Result<f64, OptionsError> {
    check_options(options)?;
    Ok(effective_tolerance(mesh1, motion1, mesh2, motion2, options))
}

/// The options' ranges: a positive finite tolerance when given, at least one iteration.
pub(crate) fn check_options(options: &ContactOptions) -> Result<(), OptionsError> {
    if let Some(tolerance) = options.tolerance {
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(OptionsError::OutOfRange {
                name: "tolerance",
                requirement: "must be positive and finite",
                value: tolerance,
            });
        }
    }
    if options.max_iterations == 0 {
        return Err(OptionsError::OutOfRange {
            name: "max_iterations",
            requirement: "must be at least 1",
            value: 0.0,
        });
    }
    Ok(())
}

/// [`time_of_contact`] for every `(motion1, motion2)` in `motions`, in parallel (rayon);
/// results in input order, identical to the single queries whatever the thread count. The
/// options are checked first (also for an empty batch); each query's own outcome, an iteration
/// limit included, is its entry.
#[allow(clippy::type_complexity)]
pub fn time_of_contact_batch(
    mesh1: &TriMesh,
    mesh2: &TriMesh,
    motions: &[(Motion, Motion)],
    options: &ContactOptions,
) -> Result<Vec<Result<Option<ContactTime>, ContactError>>, OptionsError> {
    each_motion(mesh1, mesh2, motions, options, time_of_contact)
}

/// [`motion_is_free`] for every `(motion1, motion2)` in `motions`, in parallel (rayon): the
/// planner's check of many rigid motions at once. Results in input order, identical to the
/// single queries whatever the thread count; the options are checked first (also for an empty
/// batch), and each query's own outcome, an iteration limit included, is its entry.
pub fn motion_is_free_batch(
    mesh1: &TriMesh,
    mesh2: &TriMesh,
    motions: &[(Motion, Motion)],
    options: &ContactOptions,
) -> Result<Vec<Result<bool, ContactError>>, OptionsError> {
    each_motion(mesh1, mesh2, motions, options, motion_is_free)
}

/// `query` for every `(motion1, motion2)` in `motions`, in parallel (rayon), in input order,
/// once the options are checked (also for an empty batch): the motion batches' common part.
fn each_motion<T: Send>(
    mesh1: &TriMesh,
    mesh2: &TriMesh,
    motions: &[(Motion, Motion)],
    options: &ContactOptions,
    query: impl Fn(&TriMesh, &Motion, &TriMesh, &Motion, &ContactOptions) -> Result<T, ContactError>
        + Sync,
) -> Result<Vec<Result<T, ContactError>>, OptionsError> {
    use rayon::prelude::*;
    let still = Motion::stationary(crate::Pose::IDENTITY);
    validate(mesh1, &still, mesh2, &still, options)?;
    Ok(motions
        .par_iter()
        .map(|(m1, m2)| query(mesh1, m1, mesh2, m2, options))
        .collect())
}

/// How the advancement ended: the time, the last iterate before it where the meshes were
/// clearly apart, the scale below which a direction is noise, the count and the status.
pub(crate) struct Ends {
    pub time: f64,
    /// The leaf pair found within the tolerance at `time`, which ended the advancement (`None`
    /// at a start in contact or a probe's collision).
    within: Option<(u32, u32)>,
    /// That pair's closest points (mesh 1's frame) where the advancement certified them as
    /// the meshes' exact distance (two convex polytopes: [`crate::query::distance::gjk`]), so
    /// that the witnesses need no distance query.
    closest: Option<crate::query::distance::TrianglePairDistance>,
    earlier: Option<f64>,
    pub resolution: f64,
    pub iterations: usize,
    pub status: ContactStatus,
}

/// The result at `ends.time`: the witnesses that `witnesses` asks for ([`Witnesses`]); the
/// closest points take one exact distance query, warm-started from the last pair.
pub(crate) fn finish(
    mesh1: &TriMesh,
    motion1: Path<'_>,
    mesh2: &TriMesh,
    motion2: Path<'_>,
    ends: Ends,
    cache: &mut ContactCache,
    witnesses: Witnesses,
) -> ContactTime {
    if witnesses == Witnesses::Contact && ends.status == ContactStatus::Converged {
        if let Some(c) = pair_contact(mesh1, motion1, mesh2, motion2, &ends) {
            return c;
        }
    }
    let closest = |time: f64, cache: &mut ContactCache| {
        let (p1, p2) = (motion1.pose_at(time), motion2.pose_at(time));
        let mut dcache = DistanceCache {
            pair: cache.pair,
            simplex: cache.simplex,
        };
        let d = search_distance(
            mesh1,
            &p1,
            mesh2,
            &p2,
            &DistanceOptions::default(),
            &mut dcache,
        );
        (cache.pair, cache.simplex) = (dcache.pair, dcache.simplex);
        (d, p1, p2)
    };
    let (d, p1, p2) = match (ends.closest, ends.within) {
        // Certified by the advancement as the meshes' distance: no query.
        (Some(e), Some((l1, l2))) if ends.status == ContactStatus::Converged => {
            let (p1, p2) = (motion1.pose_at(ends.time), motion2.pose_at(ends.time));
            let d = DistanceResult {
                distance: e.distance,
                point1: p1.transform_point(e.point1),
                point2: p1.transform_point(e.point2),
                triangle1: mesh1.bvh().triangle_index(l1),
                triangle2: mesh2.bvh().triangle_index(l2),
            };
            cache.pair = Some((l1, l2));
            (d, p1, p2)
        }
        _ => closest(ends.time, cache),
    };
    let resolution = ends.resolution;
    let normal = if d.distance > resolution {
        pair_direction(mesh1, &p1, mesh2, &p2, cache.pair, &d)
    } else {
        // The direction at this time is rounding noise: take it where the meshes were apart.
        let mut before_cache = *cache;
        let before = ends
            .earlier
            .map(|t| {
                let (e, q1, q2) = closest(t, &mut before_cache);
                (e, q1, q2, before_cache.pair)
            })
            .filter(|(e, ..)| e.distance > resolution);
        match before {
            Some((e, q1, q2, pair)) => pair_direction(mesh1, &q1, mesh2, &q2, pair, &e),
            None => touching_normal(mesh1, &p1, d.triangle1, mesh2, &p2, d.triangle2),
        }
    };
    ContactTime {
        time: ends.time,
        point1: d.point1,
        point2: d.point2,
        normal,
        distance: d.distance,
        triangle1: d.triangle1,
        triangle2: d.triangle2,
        iterations: ends.iterations,
        status: ends.status,
    }
}

/// The contact at `ends.time` given by the leaf pair that ended the advancement within the
/// tolerance: its closest points and distance, computed in body 1's frame (as
/// [`pair_direction`] explains) and turned into the world. `None` without such a pair, or
/// where it touches to rounding (`ends.resolution`): its direction would be noise, and
/// [`finish`] asks the exact distance.
fn pair_contact(
    mesh1: &TriMesh,
    motion1: Path<'_>,
    mesh2: &TriMesh,
    motion2: Path<'_>,
    ends: &Ends,
) -> Option<ContactTime> {
    let (l1, l2) = ends.within?;
    let (p1, p2) = (motion1.pose_at(ends.time), motion2.pose_at(ends.time));
    let e = leaf_pair_in_frame1(mesh1, &p1, mesh2, &p2, (l1, l2))?;
    if e.distance.is_nan() || e.distance <= ends.resolution {
        return None;
    }
    let normal = (p1.rotation * (e.point2 - e.point1)).try_normalize()?;
    Some(ContactTime {
        time: ends.time,
        point1: p1.transform_point(e.point1),
        point2: p1.transform_point(e.point2),
        normal,
        distance: e.distance,
        triangle1: mesh1.bvh().triangle_index(l1),
        triangle2: mesh2.bvh().triangle_index(l2),
        iterations: ends.iterations,
        status: ends.status,
    })
}

/// The closest points and distance of leaf pair `(l1, l2)` with the bodies at `p1` and `p2`,
/// computed in body 1's frame (its triangle as stored, body 2's mapped by `p1^-1 p2`), where
/// they do not round at the bodies' distance from the origin; `None` for a leaf out of range.
fn leaf_pair_in_frame1(
    mesh1: &TriMesh,
    p1: &crate::Pose,
    mesh2: &TriMesh,
    p2: &crate::Pose,
    (l1, l2): (u32, u32),
) -> Option<crate::query::distance::TrianglePairDistance> {
    let pos12 = p1.inv_mul(p2);
    let a = mesh1.bvh().leaf_triangles().get(l1 as usize)?;
    let b = mesh2.bvh().leaf_triangles().get(l2 as usize)?;
    Some(distance_triangle_triangle(
        a,
        &b.map(|v| pos12.transform_point(v)),
    ))
}

/// The unit direction from `d.point1` to `d.point2` (world frame), taken from the closest
/// leaf pair `leaves` in body 1's frame and turned into the world: the world points round at
/// the scale of the bodies' distance from the origin, and far from it (a body at 1e13 whose
/// points are 148 apart) their difference over the distance was off unit length by 3e-8 and
/// off direction by as much (a fuzz test found it). Falls back to the world points' direction,
/// normalized, where the pair is missing or touches in that frame.
fn pair_direction(
    mesh1: &TriMesh,
    p1: &crate::Pose,
    mesh2: &TriMesh,
    p2: &crate::Pose,
    leaves: Option<(u32, u32)>,
    d: &crate::query::distance::DistanceResult,
) -> Vec3 {
    let local = leaves.and_then(|pair| {
        let e = leaf_pair_in_frame1(mesh1, p1, mesh2, p2, pair)?;
        (p1.rotation * (e.point2 - e.point1)).try_normalize()
    });
    local
        .or_else(|| (d.point2 - d.point1).try_normalize())
        .unwrap_or(Vec3::Z)
}

/// Normal of triangle 1 (world) turned towards triangle 2's centroid; for a degenerate
/// triangle, the direction between the centroids; `Z` if even that vanishes.
fn touching_normal(
    m1: &TriMesh,
    p1: &crate::Pose,
    t1: usize,
    m2: &TriMesh,
    p2: &crate::Pose,
    t2: usize,
) -> Vec3 {
    let a = m1.triangle(t1).map(|v| p1.transform_point(v));
    let b = m2.triangle(t2).map(|v| p2.transform_point(v));
    let towards = (b[0] + b[1] + b[2] - a[0] - a[1] - a[2]) / 3.0;
    let n = (a[1] - a[0]).cross(a[2] - a[0]);
    let n = if n.dot(towards) < 0.0 { -n } else { n };
    n.try_normalize()
        .or_else(|| towards.try_normalize())
        .unwrap_or(Vec3::Z)
}

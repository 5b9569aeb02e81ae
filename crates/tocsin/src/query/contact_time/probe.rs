//! Yes/no advancement: exact collision tests at chosen times ("probes") beside the
//! conservative advancement, for the questions that only ask whether a motion is free
//! ([`crate::motion_is_free`], the robot's `path_is_free`).
//!
//! A collision found by a probe is a real one: the meshes then come closer than `delta / 2`, so the
//! time of contact would report a contact too, and the answer "not free" is the same. A probe that
//! finds nothing proves nothing, and the advancement still certifies every free answer; so a
//! probe's collision test gives up after [`PROBE_BUDGET`] node pairs (proving a close fit apart
//! took more than the whole advancement). The probes only settle colliding motions sooner: a motion
//! that collides half way costs two collision tests instead of the advancement's converging to the
//! contact.
//!
//! The schedule (measured on the robot benches first, then on the rigid contact-time set;
//! docs/BENCHMARKS.md):
//! 1. before any advancement, the end of the span and its middle ([`probe_span`]);
//! 2. after [`PROBE_AFTER`] iterations, if the advancement is slow (its pace would not finish
//!    the span in [`PROBE_PACE`] more), the times `k / PROBES` of the rest, `k = 1 .. PROBES -
//!    1` (the rest's end is the span's end, probed already), then the advancement goes on from
//!    where it was certified ([`advance_probed`]), with its window and slack as they were.

use super::{advance_core, ContactCache, Ends, Path, Span};
use crate::error::ContactError;
use crate::query::collide::{collide, collides_within};
use crate::TriMesh;

/// The most node pairs a probe's collision test visits ([`collides_within`]): a probe that
/// finds nothing proves nothing, so it may stop early. On MotionBenchMaker Panda, UR5 and
/// Fetch (two problems per scenario) the 1,003 collisions the tests found took 25 node pairs
/// at the median, 110 at the 99th percentile and 254 at most; proving the bodies apart took
/// the close fits 1,569 (a shaft in its bore) to 27,105 (a ball in its socket), four times
/// what the motion's certificates then cost.
const PROBE_BUDGET: usize = 1024;

/// Iterations after which [`advance_probed`] probes the rest of a span at the times
/// `k / PROBES` (`k = 1 .. PROBES - 1`). The span's end, the last of the evenly spaced times,
/// was probed before any advancement and is not repeated: on UR5, where the probes of two
/// always-close link pairs (base and upper arm, forearm and wrist) cost 12 us a collision
/// test, repeating it was 6% of a free edge.
pub(crate) const PROBE_AFTER: usize = 3;
/// Probe spacing; see [`PROBE_AFTER`]. With the end and middle probes made before any
/// advancement, these catch collisions the advancement approaches slowly.
const PROBES: usize = 4;
/// An advancement whose first [`PROBE_AFTER`] iterations went at a pace that would finish its
/// span in at most this many more is not probed: finishing costs less than the probes.
/// Measured in instructions on the robots (100 random edges per scenario from the start state,
/// and the Panda bench's 1,470 edges): 0 / 3 / 6 / 8 / 12 gave box_ur5 89.2 / 82.0 / 74.8 /
/// 71.4 / 68.9M, table_under_pick_ur5 103.0 / 100.9 / 95.6 / 92.8 / 90.7M, Panda free edges
/// 514.8 / 507.9 / 505.0 / 503.5 / 502.2M, Panda colliding edges 32.7M up to 8 and 62.9M at
/// 12, start-goal edges 91.8 / 94.1 / 94.0 / 94.5 / 102.3M; 6 stays clear of the colliding
/// edges' cliff.
const PROBE_PACE: f64 = 6.0;

/// Whether the meshes collide (exact test) at time `t` of their paths.
pub(crate) fn collides_at(
    mesh1: &TriMesh,
    path1: Path<'_>,
    mesh2: &TriMesh,
    path2: Path<'_>,
    t: f64,
) -> bool {
    collide(mesh1, &path1.pose_at(t), mesh2, &path2.pose_at(t))
}

/// The probes made before any advancement: the end of `[start, end]`, then its middle. The
/// first time found colliding, if any.
pub(crate) fn probe_span(
    mesh1: &TriMesh,
    path1: Path<'_>,
    mesh2: &TriMesh,
    path2: Path<'_>,
    start: f64,
    end: f64,
) -> Option<f64> {
    [end, 0.5 * (start + end)]
        .into_iter()
        .find(|&t| probe_at(mesh1, path1, mesh2, path2, t))
}

/// A probe at time `t`: whether a collision test within [`PROBE_BUDGET`] finds the meshes
/// colliding.
fn probe_at(mesh1: &TriMesh, path1: Path<'_>, mesh2: &TriMesh, path2: Path<'_>, t: f64) -> bool {
    collides_within(
        mesh1,
        &path1.pose_at(t),
        mesh2,
        &path2.pose_at(t),
        PROBE_BUDGET,
    )
}

/// How a yes/no advancement ended.
pub(crate) enum Probed {
    /// The advancement's own answer (as [`advance_paths`](super::advance_paths)): where it
    /// came within the tolerance, or `None` when the span is free.
    Advanced(Option<Ends>),
    /// A probe found the meshes colliding at this time.
    Collides(f64),
}

/// [`advance_paths`](super::advance_paths) for a yes/no answer, with the probes of step 2 of
/// the module docs (the caller makes those of step 1 first, with [`probe_span`]).
pub(crate) fn advance_probed(
    mesh1: &TriMesh,
    path1: Path<'_>,
    mesh2: &TriMesh,
    path2: Path<'_>,
    span: &Span,
    cache: &mut ContactCache,
) -> Result<Probed, ContactError> {
    advance_core::<true>(mesh1, path1, mesh2, path2, span, cache)
}

/// Step 2 of the module docs: the advancement has certified the meshes apart up to
/// `time_reached` in `iterations` iterations; probes the rest of the span when its pace is
/// slow. The first time found colliding, if any.
pub(crate) fn probe_rest(
    mesh1: &TriMesh,
    path1: Path<'_>,
    mesh2: &TriMesh,
    path2: Path<'_>,
    span: &Span,
    time_reached: f64,
    iterations: usize,
) -> Option<f64> {
    let rest = span.end - time_reached;
    let pace = (time_reached - span.start) / iterations as f64;
    if rest <= PROBE_PACE * pace {
        return None;
    }
    (1..PROBES)
        .map(|k| time_reached + rest * k as f64 / PROBES as f64)
        .find(|&at| probe_at(mesh1, path1, mesh2, path2, at))
}

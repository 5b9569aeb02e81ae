//! Translational penetration depth between two polygon soups, after PolyDepth (Je, Tang, Lee,
//! Lee and Kim, ACM TOG 31(1), 2012): the shortest translation of body 2 found that leaves the
//! two surfaces touching (within the tolerance) and not intersecting, by out-projection with
//! the continuous collision query and in-projection on the local contact space.
//!
//! 1. **In collision?** The bodies penetrate when their surfaces intersect (`collide`), or when
//!    one lies inside the other (a corner of each tested with the winding number, see
//!    [`super::winding`]); otherwise the status is [`DepthStatus::Separated`] with depth 0.
//!    Convex pairs (both meshes closed and convex) are decided and answered before that, by
//!    the exact path of [`super::convex`] (when its candidate directions are not too many):
//!    they overlap when every candidate axis shows an overlap, and the smallest overlap is the
//!    exact depth. The winding number's inside needs the triangles oriented alike (a convex
//!    hull's need not be), so the exact path does not use it. The others go on:
//! 2. **Seeds (out-projection).** For each seed direction `d` (the centroid difference, the
//!    caller's cached direction when given, the principal axes of both root volumes both ways, a
//!    box's face normals, and `directions` directions spread over the sphere), the first free
//!    configuration along `d` is found by samples `s_k = far (k / 128)^2` (denser near the
//!    current pose, so that a free pocket next to it, a peg's room in its hole, is found; `far`
//!    is beyond both bounding radii and the centres' distance, certainly apart), and body 2 is
//!    translated straight back from there to where it is; the time of contact of that motion is
//!    where it first touches body 1 coming from the free side: a collision-free, touching
//!    translation `t = s d`. The motion is a pure translation, so the query is the cast of
//!    `contact_time::cast` (one best-first traversal for the first pair within half the
//!    tolerance, exact per triangle pair), seeded with the direction's last intersecting pair
//!    (knot2.8k: 2%, 11% and 20% fewer instructions at 1%, 5% and 20% of the radius than the
//!    advancement). The shortest `starts` (two by default) are refined, or only the shortest
//!    when it is shorter than a tenth (`SHALLOW`) of the smaller bounding radius. Five savings
//!    change no answer: a direction is dropped as soon as one of its samples still penetrates
//!    beyond the `starts`-th shortest translation found so far (the shortest, once shallow;
//!    the motion back from the free sample passes through that sample, so its translation
//!    would be longer); the
//!    directions are sampled breadth first (every live direction's k-th sample before any
//!    next one), so the directions that free up soonest set that bound early; the continuous
//!    queries of the directions freed at one sample run after that round's samples, and not at
//!    all once the round's last penetrating sample lies at or beyond the bound (a continuous
//!    query that ends at its own free sample, common at shallow depths, sets the bound to a
//!    sample exactly; the translations that follow are strictly longer than the penetrating
//!    sample they pass: knot2.8k at 1%, 13% fewer instructions with "at or" than without,
//!    the same depths bit for bit), nor for a direction whose last intersecting pair keeps
//!    intersecting up to the bound along it (the shifts where two triangles meet form an
//!    interval: coming back, the bodies touch at its end or before; `holds_until`, 7% and 2%
//!    fewer instructions at 1% and 5%, the same depths), and a live direction is dropped
//!    as soon as its intersecting pair meets at the bound (2.5% at each depth); a round whose
//!    previous sample already lies at or beyond the bound (kept translations found in the last
//!    round lowered it) tests no sample at all, since every live direction is then dropped
//!    whatever its sample shows (knot2.8k: 13%, 11% and 4% fewer instructions at 1%, 5% and
//!    20% of the radius, the same depths bit for bit); and the witnesses
//!    (the continuous query's final exact distance) are computed only for the seeds kept
//!    (knot2.8k at 5%: 8.1 to 2.5 ms, the same depths bit for bit).
//!    Where both meshes are one closed connected surface, balls inside each
//!    (`penetration/balls.rs`) give every direction a shift below which body 2 certainly still
//!    penetrates: no sample below it is tested, and a direction whose shift reaches the bound
//!    is dropped untested (a sixth saving that changes no answer; `bench/penetration_grid.py`
//!    at 20% of the radius, knot34k 3.30 -> 2.04 ms, knot11k 1.85 -> 1.42, knot2.8k 1.22 ->
//!    1.14, duck 1.14 -> 1.04; at 1% up to 15% more, the shifts' cost where they skip little).
//! 3. **Local refinement (in-projection, then out-projection).** Each out-projection ends at a
//!    touching translation `t` with a contact normal `n` (from body 1 to body 2): near it the
//!    contact space is the half-space `n . (x - t) >= 0`. The last four such planes stand for
//!    PolyDepth's local contact cone; the shortest translations on each plane, on each pair's
//!    intersection line and at each triple's corner (the in-projection; PolyDepth solves an
//!    LCP over every contact of the cone with projected Gauss-Seidel, this takes the contacts
//!    the continuous query returns, one per out-projection: a deviation) are tried shortest
//!    first, each by out-projecting along its direction; the first shorter touching
//!    translation is accepted, so the depth never grows, and the iteration ends when none is.
//!    A refinement candidate's contact normal (its plane, and the new best's) comes from the
//!    triangle pair that ended its continuous query (within the tolerance there) rather than
//!    from an exact distance query near contact; only the seeds and the answer get the exact
//!    distance (knot2.8k: 4%, 3% and 10% fewer instructions at 1%, 5% and 20% of the radius
//!    for the candidates that are not shorter, depths the same on 141 of 144 queries and
//!    within 0.5% on the others; then 3%, 3% and 8% for the new bests too, depths within
//!    0.03%; taking the seeds' normals from their pairs as well lost the polish's 1e-3 gap on
//!    a shallow test case). The other starts (deep penetrations) take theirs from their
//!    pairs; the shortest keeps the exact one (callgrind, `profile_depth` at 20% of the
//!    radius: knot2.8k 303.3M -> 291.2M, knot11k 453.1M -> 433.6M, duck 281.2M -> 263.3M; no
//!    depth longer, two of 96 shorter, by 0.9% and 4.1%. All three from their pairs took 6 to
//!    9% off but left one knot11k query 30% deeper).
//!    A direction is out-projected once per start: against a best that only shrinks, the same
//!    direction again could not give a shorter translation (knot2.8k: 5%, 6% and 24% fewer
//!    instructions at 1%, 5% and 20% of the radius, knot11k 16% at 20%; depths within 0.03% of
//!    retrying, either way: a retried direction's plane moved to the front of the four kept).
//!    A candidate whose samples still penetrate at the current length is dropped there, before
//!    its continuous query (it could not be shorter; its contact plane is then not kept): at
//!    20% of the radius 640 of a knot2.8k's 842 continuous queries were the refinement's, and
//!    the median went from 9.5 to 7.1 ms; the depths at 1% and 5% were unchanged, at 20%
//!    within 0.65% either way, and up to 18% shorter on knot34k.
//!    A candidate's samples start at its own length (the last sample at or below it) rather
//!    than next to the pose: the in-projection puts the contact space there, and every shift
//!    below it that the local model calls penetrating would cost a sample (callgrind,
//!    `profile_depth`, 24 queries at 5% / 20% of the radius: knot2.8k 94.2M / 330.1M ->
//!    94.0M / 312.9M, knot11k 141.8M / 509.9M -> 140.0M / 464.3M, duck 114.4M / 310.1M ->
//!    113.7M / 290.4M, bunny at 20% 278.1M -> 268.3M; the same depths bit for bit on all of
//!    them). A free pocket below it is then not found by that candidate; a seed's samples still
//!    start next to the pose. The first sample's hint is the leaf pair touching at the best
//!    translation (the candidates lie near it), not the pose's own intersecting pair, and the
//!    polish's continuous query bounds that pair first (knot2.8k 1.5% / 2.3% / 3.1% fewer at
//!    1% / 5% / 20%, duck 3.2% / 3.2% at 5% / 20%, the same depths).
//!    Deep penetrations' starts often end at one translation, bit for bit (the same
//!    direction out-projected from the same free sample): a start whose best reaches one of an
//!    earlier start's bests ends there, since that start went on from it to a translation no
//!    longer. With a direction given twice sampled once (both meshes' axes where their
//!    rotations agree), knot2.8k at 20% of the radius 226.9M -> 221.9M instructions, knot11k
//!    -1.7%, duck -2.4%, bunny -4.8%; the depths within 1.3e-5 relative.
//! 4. **Polish.** The best translation is out-projected once more along its own line with the
//!    tolerance `min(tolerance, 1e-3 depth)` (`polish`): the gap it leaves is then at most a
//!    thousandth of the depth, not of the radius.
//!
//! Every `collide` of the samples first tries an intersecting triangle pair of a nearby
//! configuration (that direction's previous sample; the pose's own at first): same verdicts,
//! a quarter off knot2.8k at 1% of the radius; then each of its triangles against the other's
//! vertex neighbours (7%, 23% and 22% more off at 1%, 5% and 20%).
//!
//! The result is a local optimum, an upper bound on the true depth (a translation that does
//! separate the bodies): on random overlapping boxes it is within 0.05% of the exact depth at
//! the median and 3% at worst (`bench/compare_penetration.py`, 100 pairs, with two starts or
//! three). That the final configuration does not intersect and is within the tolerance
//! follows from the continuous query's contract (its time is no later than the first contact,
//! reached from a separated start, with distance at most the tolerance); the tests check it
//! with `collide` and `distance` on every answer.

use crate::error::ContactError;
use crate::math::{Pose, Vec3};
use crate::motion::Motion;
use crate::query::collide::intersecting_leaves;
use crate::query::contact_time::cast::triangle_window;
use crate::query::contact_time::{
    advance_short_translation, effective_tolerance, finish, ContactCache, ContactOptions, Ends,
    Path, Witnesses,
};
use crate::query::distance::{distance_triangle_triangle, intersect_triangle_triangle};
use crate::query::penetration::balls::penetrating_shifts;
use crate::query::penetration::convex;
use crate::query::penetration::winding::inside;
use crate::TriMesh;

/// Options of [`penetration_depth`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthOptions {
    /// Distance tolerance of the touching configurations of the search (model units, > 0).
    /// `None`: the time of contact's default, `1e-3` of the smaller bounding radius. The
    /// answer's own gap is at most `min(tolerance, 1e-3 depth)` (the polish, module docs). A
    /// tolerance below twice the distances' accuracy
    /// ([`crate::query::contact_time::DISTANCE_RESOLUTION`] of the radii plus the poses'
    /// distances from the origin) is raised to it, so that the bodies end apart.
    pub tolerance: Option<f64>,
    /// Refinement iterations at most. Default 32.
    pub max_iterations: usize,
    /// Seed directions spread over the sphere (besides the centroid difference, the cached
    /// direction and the root volumes' axes), on a Fibonacci spiral. Default 32: on two
    /// knots (2.8K, 34K triangles) and the bunny against turned copies, 26 cube directions
    /// gave depths 2.628, 2.673, 0.850, and 27 / 40 / 64 spiral directions 2.516 / 2.479 /
    /// 2.440, 2.634 / 2.514 / 2.634, 0.845 / 0.852 / 0.877 (a local search: the seeds decide
    /// which local optimum is found), at 19 to 44 ms.
    /// At most [`MAX_DIRECTIONS`].
    pub directions: usize,
    /// A direction from an earlier query (motion coherence), tried first.
    pub cached_direction: Option<Vec3>,
    /// Answer convex pairs exactly ([`super::convex`]). Default true; false runs the local
    /// search on them too (to measure it).
    pub exact_convex: bool,
    /// How many of the seeds' shortest touching translations are refined (at least 1), where
    /// no seed is shallow (a shallow one is refined alone, module docs). Default 2. Measured on
    /// 96 queries at 20% of the radius (knot2.8k, knot11k, the bunny, the duck; 81 of them
    /// refine several starts): the third start ended shortest in 9 of the 81, by 0.0 to 6.2%
    /// (a local search: each start finds its own optimum), and its refinement and the looser
    /// pruning of the seeds it needs cost 19% of the instructions on knot2.8k;
    /// `bench/penetration_grid.py` at 20%, 3 starts -> 2: knot2.8k 1.08 -> 0.92 ms, the duck
    /// 1.02 -> 0.79, knot34k 1.94 -> 1.38, the within-1% count 43 -> 42 of 47. 3 buys
    /// those percents back at that cost.
    pub starts: usize,
}

impl Default for DepthOptions {
    fn default() -> Self {
        Self {
            tolerance: None,
            max_iterations: 32,
            directions: 32,
            cached_direction: None,
            exact_convex: true,
            starts: 2,
        }
    }
}

/// How the query ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum DepthStatus {
    /// The bodies do not penetrate: depth 0, translation 0.
    Separated,
    /// No shorter touching translation was found near the one returned.
    Converged,
    /// The refinement ran out of iterations (the result is still a valid separating
    /// translation, maybe not locally shortest).
    IterationLimit,
}

/// A penetration depth and the translation that realises it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PenetrationDepth {
    /// Length of `translation` (model units, >= 0).
    pub depth: f64,
    /// Translation to apply to body 2 (world frame) after which the bodies touch within the
    /// tolerance without intersecting.
    pub translation: Vec3,
    /// Its unit direction (`Z` when the depth is 0).
    pub direction: Vec3,
    /// Closest point on body 1 at the touching configuration (world frame).
    pub point1: Vec3,
    /// Closest point on body 2 there (world frame, body 2 translated).
    pub point2: Vec3,
    /// Refinement iterations taken.
    pub iterations: usize,
    /// How it ended.
    pub status: DepthStatus,
    /// Whether `depth` is the exact (global) penetration depth: both meshes are convex
    /// polytopes (closed and convex), answered by the exact path of [`super::convex`] (to
    /// rounding; where EPA's answer is certified first, to 1e-11 of the bodies' size). Then
    /// the translation is `depth + tolerance / 2` long, so that the bodies end apart.
    pub exact: bool,
}

/// The most seed directions a query takes ([`DepthOptions::directions`]): 24 MB of them, about
/// 20 s of out-projections on a knot of 1,600 triangles (100,000 took 2 s).
pub const MAX_DIRECTIONS: usize = 1_000_000;

/// Seed directions: `n` points spread over the unit sphere (a Fibonacci spiral).
fn sphere_directions(n: usize) -> Vec<Vec3> {
    let golden = std::f64::consts::PI * (3.0 - 5.0_f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let a = golden * i as f64;
            Vec3::new(r * a.cos(), r * a.sin(), z)
        })
        .collect()
}

/// Whether the bodies penetrate: surfaces intersect, or one lies inside the other. `hint`: an
/// intersecting leaf pair of a nearby configuration, tried first, and replaced by the pair
/// found here (see [`intersecting_leaves`]; the same verdict either way). The balls' shifts
/// ([`super::balls`]) are tested against it.
pub(crate) fn penetrating(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    hint: &mut Option<(u32, u32)>,
) -> bool {
    if let Some(pair) = intersecting_leaves(mesh1, pose1, mesh2, pose2, *hint) {
        *hint = Some(pair);
        return true;
    }
    // A corner of each in the other's frame.
    let corner2 = pose1
        .inv_mul(pose2)
        .transform_point(mesh2.vertices()[mesh2.triangles()[0][0] as usize]);
    let corner1 = pose2
        .inv_mul(pose1)
        .transform_point(mesh1.vertices()[mesh1.triangles()[0][0] as usize]);
    inside(mesh1, corner2) || inside(mesh2, corner1)
}

/// Out-projection along the unit `d`: the first configuration along `d` found free (samples
/// `far (k / 128)^2`), then body 2 comes back from there to its pose; the touching translation
/// reached (world) and the contact normal.
struct Touch {
    translation: Vec3,
    normal: Vec3,
    point1: Vec3,
    point2: Vec3,
    /// The out-projection, when the normal and witnesses above are those of the triangle pair
    /// that ended its continuous query rather than of the exact distance ([`touch`]): what
    /// [`exact`] finishes.
    pending: Option<Pending>,
    /// The leaf pair that touches there (a hint for the refinement's samples near it).
    pair: Option<(u32, u32)>,
}

/// An out-projection whose continuous query has ended, its witnesses not yet computed: the
/// seeds only need the length of their touching translation to be ranked, and only the kept
/// ones get witnesses ([`complete`]).
struct Pending {
    d: Vec3,
    s0: f64,
    motion: Motion,
    ends: Ends,
    cache: ContactCache,
}

impl Pending {
    /// Length of the touching translation.
    fn length(&self) -> f64 {
        self.s0 * (1.0 - self.ends.time)
    }
}

/// The out-projection along `d` (its direction) completed with its witnesses: the first free
/// sample from the last one at or below `from` on, then the continuous query back from it;
/// `None` as soon as a sample at or beyond `beat` still penetrates (its translation could not
/// be shorter than `beat`).
#[allow(clippy::too_many_arguments)]
fn out_project(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    d: Vec3,
    far: f64,
    options: &ContactOptions,
    mut hint: Option<(u32, u32)>,
    beat: f64,
    from: f64,
) -> Result<Option<Touch>, ContactError> {
    let Some(d) = d.try_normalize() else {
        return Ok(None);
    };
    let first = ((from / far).max(0.0).sqrt() * RAY_SAMPLES as f64).floor() as usize;
    // The nearest free configuration along d: samples denser near 0 (a free pocket next to
    // the current pose, a peg's room in its hole, is what a short translation reaches; from
    // far out along d only the outside is reachable).
    for k in first.max(1)..=RAY_SAMPLES {
        let s = sample(far, k);
        if !penetrating(mesh1, pose1, mesh2, &shifted(pose2, d * s), &mut hint) {
            return Ok(
                come_back(mesh1, pose1, mesh2, pose2, (d, s), hint, options)?
                    .map(|p| touch(mesh1, pose1, mesh2, p)),
            );
        }
        if s >= beat {
            return Ok(None);
        }
    }
    Ok(None)
}

#[cfg(test)]
thread_local! {
    /// Whether [`holds_until`] gives its bound (the tests compare the answers without it).
    static PAIR_BOUNDS: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
    /// Continuous queries run by the seeds (how much work the bound saves, in the tests).
    static SEED_QUERIES: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    /// Whether the seeds use the balls' shifts (the tests compare the answers without them).
    static BALL_SHIFTS: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
    /// Starts ended by reaching an earlier start's best ([`refine`]); `usize::MAX` turns the
    /// rule off (the tests compare the answers without it).
    static MERGES: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// A shift `h >= 0` such that leaf pair `pair` (intersecting at some shift below `h` along the
/// unit world direction `d`) still intersects with body 2 moved by `h d`: by the set of shifts
/// where two triangles meet being an interval, every shift between that one and `h` is
/// penetrating, so a free configuration beyond comes back to contact at `h` or before. The
/// interval's end from the separating axes of the two triangles, then checked with the exact
/// intersection test (0 when that fails).
fn holds_until(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    (l1, l2): (u32, u32),
    d: Vec3,
) -> f64 {
    #[cfg(test)]
    if !PAIR_BOUNDS.with(|c| c.get()) {
        return 0.0;
    }
    let pos12 = pose1.inv_mul(pose2);
    let t1 = mesh1.bvh().leaf_triangles()[l1 as usize];
    let t2 = mesh2.bvh().leaf_triangles()[l2 as usize].map(|p| pos12.transform_point(p));
    let d1 = pose1.rotation.transpose() * d;
    // The shifts at which the pair overlaps on every separating axis, from 0 (it intersects
    // there); a degenerate triangle's missing axes can overstate the end, which the exact test
    // below catches.
    let Some((_, end)) = triangle_window(&t1, &t2, d1, 0.0, (0.0, f64::INFINITY)) else {
        return 0.0;
    };
    let h = end * (1.0 - 1e-9);
    if !(h.is_finite() && h > 0.0) {
        return 0.0;
    }
    let moved = t2.map(|p| p + d1 * h);
    if intersect_triangle_triangle(&t1, &moved) {
        h
    } else {
        0.0
    }
}

/// The `k`-th sample along a direction (`1 <= k <= RAY_SAMPLES`).
fn sample(far: f64, k: usize) -> f64 {
    far * (k as f64 / RAY_SAMPLES as f64).powi(2)
}

/// Body 2's pose moved by `t`.
fn shifted(pose2: &Pose, t: Vec3) -> Pose {
    Pose {
        rotation: pose2.rotation,
        translation: pose2.translation + t,
    }
}

/// The continuous query of body 2 coming back from the free configuration `s0 d` to its pose.
/// `seed`: a leaf pair that intersects on the way back (the direction's last penetrating
/// sample's), which the query bounds first.
fn come_back(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    (d, s0): (Vec3, f64),
    seed: Option<(u32, u32)>,
    options: &ContactOptions,
) -> Result<Option<Pending>, ContactError> {
    let motion = match Motion::translation(shifted(pose2, d * s0), *pose2) {
        Ok(m) => m,
        Err(_) => return Ok(None),
    };
    let still = Motion::stationary(*pose1);
    let mut cache = ContactCache {
        pair: seed,
        ..ContactCache::default()
    };
    // Every caller found the meshes apart at `s0` with the exact `collide` (or, polishing, at a
    // touching translation the advancement left apart): not asked again.
    Ok(
        advance_short_translation(mesh1, &still, mesh2, &motion, options, &mut cache)?.map(
            |ends| Pending {
                d,
                s0,
                motion,
                ends,
                cache,
            },
        ),
    )
}

/// The shortest `starts` touching translations over the seed directions (ties in seed
/// order), or only the shortest once one shorter than `shallow` is found ([`SHALLOW`]), found
/// breadth first: every live direction's `k`-th sample is tested before any direction's next
/// one, so that the directions that free up soonest set the bound early; a direction whose
/// penetrating sample lies beyond the current `starts`-th shortest translation (the shortest,
/// once shallow) is dropped (its own would be longer). The same set as out-projecting every
/// direction in full.
#[allow(clippy::too_many_arguments)]
fn shortest_seeds(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    seeds: &[Vec3],
    far: f64,
    options: &ContactOptions,
    hint: Option<(u32, u32)>,
    shallow: f64,
    starts: usize,
) -> Result<Vec<Pending>, ContactError> {
    let dirs: Vec<Option<Vec3>> = seeds.iter().map(|d| d.try_normalize()).collect();
    // Per direction, shifts below which body 2 certainly still penetrates (the balls inside
    // closed meshes; 0 elsewhere): no sample there is tested, and a direction whose shift
    // reaches the bound is dropped untested.
    #[cfg_attr(not(test), allow(unused_mut))]
    let mut inner = penetrating_shifts(mesh1, pose1, mesh2, pose2, &dirs);
    #[cfg(test)]
    if !BALL_SHIFTS.with(|c| c.get()) {
        inner.fill(0.0);
    }
    // Each direction's last intersecting pair, the pose's own at first.
    let mut hints = vec![hint; dirs.len()];
    // Per direction, a shift its current intersecting pair meets at (-inf until computed).
    let mut until = vec![f64::NEG_INFINITY; dirs.len()];
    let mut alive: Vec<usize> = (0..dirs.len()).filter(|&i| dirs[i].is_some()).collect();
    let mut kept: Vec<(usize, Pending)> = Vec::new();
    let bound = |kept: &[(usize, Pending)]| match kept.first() {
        Some((_, p)) if p.length() < shallow => p.length(),
        _ if kept.len() < starts => f64::INFINITY,
        _ => kept[starts - 1].1.length(),
    };
    for k in 1..=RAY_SAMPLES {
        let s = sample(far, k);
        // A freed direction's translation is longer than its last penetrating sample (below):
        // at or beyond the bound, this round's samples cannot keep any direction whatever they
        // show, and the search is over.
        let last = if k > 1 { sample(far, k - 1) } else { 0.0 };
        if last >= bound(&kept) {
            break;
        }
        let mut still_alive = Vec::with_capacity(alive.len());
        // The directions that free up at this sample: their continuous queries run after the
        // round's samples, so that the round's other frees cannot be skipped by its samples
        // alone (below).
        let mut freed = Vec::new();
        for &i in &alive {
            let Some(d) = dirs[i] else { continue };
            if s < inner[i] {
                if inner[i] < bound(&kept) {
                    still_alive.push(i);
                }
                continue;
            }
            let before = hints[i];
            if penetrating(mesh1, pose1, mesh2, &shifted(pose2, d * s), &mut hints[i]) {
                // The direction's translation is longer than the shifts its intersecting pair
                // still meets at (see `holds_until`): computed once per pair, and only once a
                // bound is there to compare with.
                let limit = bound(&kept);
                if limit.is_finite() && (hints[i] != before || until[i] == f64::NEG_INFINITY) {
                    until[i] = hints[i]
                        .map_or(s, |h| holds_until(mesh1, pose1, mesh2, pose2, h, d).max(s));
                }
                if s <= limit && until[i] < limit && inner[i] < limit {
                    still_alive.push(i);
                }
            } else {
                freed.push((i, d));
            }
        }
        // A freed direction's touching translation is longer than its last penetrating sample
        // (the motion back passes through it, and stops before any contact): at or beyond the
        // `starts`-th shortest (the shortest, once shallow), its query is skipped
        // (knot2.8k at 1% and 5%: 4 to 6% fewer instructions, the same depths bit for bit).
        for (i, d) in freed {
            if last >= bound(&kept) {
                break;
            }
            // Coming back from `s`, the bodies touch no later than where the direction's last
            // intersecting pair starts to intersect again (a shift below `s`, which is free:
            // anything else is rounding, and then nothing is skipped).
            let until = hints[i].map_or(0.0, |h| holds_until(mesh1, pose1, mesh2, pose2, h, d));
            if until < s && until >= bound(&kept) {
                continue;
            }
            #[cfg(test)]
            SEED_QUERIES.with(|c| c.set(c.get() + 1));
            if let Some(p) = come_back(mesh1, pose1, mesh2, pose2, (d, s), hints[i], options)? {
                let key = (p.length(), i);
                let at = kept.partition_point(|(j, q)| (q.length(), *j) <= key);
                kept.insert(at, (i, p));
                kept.truncate(starts);
            }
        }
        alive = still_alive;
        if alive.is_empty() {
            break;
        }
    }
    if kept.first().is_some_and(|(_, p)| p.length() < shallow) {
        kept.truncate(1);
    }
    Ok(kept.into_iter().map(|(_, p)| p).collect())
}

/// An out-projection's touching translation with the normal and witnesses of the triangle
/// pair that ended its continuous query (within the tolerance there): a contact plane for the
/// refinement at the cost of one triangle pair, where the exact distance ([`complete`]) costs
/// a search near contact. Only the answer needs the exact witnesses ([`exact`]). Falls back to
/// [`complete`] when the pair touches (its direction would be rounding noise).
fn touch(mesh1: &TriMesh, pose1: &Pose, mesh2: &TriMesh, p: Pending) -> Touch {
    if let Some((l1, l2)) = p.cache.pair {
        let pose2 = p.motion.pose_at(p.ends.time);
        let a = mesh1.bvh().leaf_triangles()[l1 as usize].map(|v| pose1.transform_point(v));
        let b = mesh2.bvh().leaf_triangles()[l2 as usize].map(|v| pose2.transform_point(v));
        let d = distance_triangle_triangle(&a, &b);
        if d.distance > p.ends.resolution {
            return Touch {
                translation: p.d * p.s0 * (1.0 - p.ends.time),
                normal: (d.point2 - d.point1) / d.distance,
                point1: d.point1,
                point2: d.point2,
                pair: p.cache.pair,
                pending: Some(p),
            };
        }
    }
    complete(mesh1, pose1, mesh2, p)
}

/// `t` with the exact normal and witnesses (see [`touch`]).
fn exact(mesh1: &TriMesh, pose1: &Pose, mesh2: &TriMesh, t: Touch) -> Touch {
    match t.pending {
        Some(p) => complete(mesh1, pose1, mesh2, p),
        None => t,
    }
}

/// The witnesses of an out-projection (the continuous query's last step).
fn complete(mesh1: &TriMesh, pose1: &Pose, mesh2: &TriMesh, p: Pending) -> Touch {
    let still = Motion::stationary(*pose1);
    let mut cache = p.cache;
    let c = finish(
        mesh1,
        Path::Rigid(&still),
        mesh2,
        Path::Rigid(&p.motion),
        p.ends,
        &mut cache,
        Witnesses::Closest,
    );
    Touch {
        translation: p.d * p.s0 * (1.0 - c.time),
        normal: c.normal,
        point1: c.point1,
        point2: c.point2,
        pending: None,
        pair: cache.pair,
    }
}

/// Samples along each direction before the continuous query (see `out_project`): `s_k = far
/// (k / RAY_SAMPLES)^2`. Finer samples let the seeds' bound prune sooner at shallow depths and
/// cost more rounds at deep ones: callgrind on `profile_depth` (knot2.8k, 24 queries at 1%, 5%
/// and 20% of the radius), 48 samples 106.8M / 127.5M / 343.4M, 64 112.4M / 113.2M / 330.1M,
/// 96 93.5M / 108.4M / 354.1M, 128 88.2M / 102.5M / 356.7M, 192 83.4M / 106.7M / 386.3M; over
/// bunny, duck, knot11k and knot34k, 128 against 48: -7 to -17% at 1%, -16 to -23% at 5%, -4
/// to +6% at 20%, the grid's depths as close to the sampled bound (140 of 143 within 1%).
/// Tried and not kept: cubic and quartic schedules, geometric ones (ratio 1.15 to 1.25: finest
/// at 1%, worse at 5% and 20%), finer samples for the seeds only or the refinement only, and
/// bisecting the last interval before the continuous query (more, at every depth).
const RAY_SAMPLES: usize = 128;

/// Keeps the last four contact planes, dropping one whose normal repeats.
fn remember(planes: &mut Vec<(Vec3, f64)>, plane: (Vec3, f64)) {
    planes.retain(|p| p.0.dot(plane.0) < 1.0 - 1e-9);
    planes.push(plane);
    if planes.len() > 4 {
        planes.remove(0);
    }
}

/// The shortest translations on the contact planes, their pairwise intersection lines and
/// their triple intersection points (the faces, edges and corners of the local contact space,
/// as PolyDepth's contact cone gives them).
fn candidates(planes: &[(Vec3, f64)]) -> Vec<Vec3> {
    let mut out = Vec::new();
    for (i, &(n1, c1)) in planes.iter().enumerate() {
        if c1 > 0.0 {
            out.push(n1 * c1);
        }
        for (j, &(n2, c2)) in planes.iter().enumerate().skip(i + 1) {
            let (a, b, d) = (n1.dot(n1), n1.dot(n2), n2.dot(n2));
            let det = a * d - b * b;
            if det.abs() > 1e-9 {
                let (x, y) = ((c1 * d - c2 * b) / det, (c2 * a - c1 * b) / det);
                out.push(n1 * x + n2 * y);
            }
            for &(n3, c3) in planes.iter().skip(j + 1) {
                let m = crate::math::Mat3::from_cols(n1, n2, n3).transpose();
                if m.determinant().abs() > 1e-9 {
                    out.push(m.inverse() * Vec3::new(c1, c2, c3));
                }
            }
        }
    }
    out
}

/// The local refinement from one touching translation (module docs, step 3).
#[allow(clippy::too_many_arguments)]
fn refine(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    mut best: Touch,
    far: f64,
    contact_options: &ContactOptions,
    max_iterations: usize,
    hint: Option<(u32, u32)>,
    visited: &mut Vec<Vec3>,
) -> Result<(Touch, usize, DepthStatus), ContactError> {
    // The earlier starts' bests (this one's are pushed after them): reaching one, this start
    // would retrace that start's way from there to where it ended (below).
    let earlier = visited.len();
    visited.push(best.translation);
    let mut status = DepthStatus::IterationLimit;
    let mut iterations = 0;
    // Recent contact planes n . x = n . t (each out-projection's touching translation and
    // normal): the local contact space is on their positive sides.
    let mut planes: Vec<(Vec3, f64)> = vec![(best.normal, best.normal.dot(best.translation))];
    // Directions out-projected already: against a best no longer than when each was tried (it
    // only shrinks), the same direction could not give a shorter translation.
    let mut tried: Vec<Vec3> = Vec::new();
    for _ in 0..max_iterations {
        iterations += 1;
        let t = best.translation;
        let mut targets = candidates(&planes);
        targets.retain(|x| x.length() < t.length() * (1.0 - 1e-9));
        targets.push(0.5 * (best.normal * best.normal.dot(t) + t));
        targets.sort_by(|a, b| a.length().total_cmp(&b.length()));
        let mut improved = false;
        for target in targets {
            let dir = if target.length() > 1e-12 * far {
                target
            } else {
                best.normal
            };
            let Some(unit) = dir.try_normalize() else {
                continue;
            };
            if tried.iter().any(|u: &Vec3| u.dot(unit) >= 1.0 - 1e-12) {
                continue;
            }
            tried.push(unit);
            if let Some(c) = out_project(
                mesh1,
                pose1,
                mesh2,
                pose2,
                dir,
                far,
                contact_options,
                best.pair.or(hint),
                t.length() * (1.0 - 1e-9),
                target.length(),
            )? {
                remember(&mut planes, (c.normal, c.normal.dot(c.translation)));
                if c.translation.length() < t.length() * (1.0 - 1e-9) {
                    best = c;
                    improved = true;
                    break;
                }
            }
        }
        if !improved {
            status = DepthStatus::Converged;
            break;
        }
        // The same translation as an earlier start's best (to rounding: the same direction's
        // out-projection from the same free sample): that start went on from there to a
        // translation no longer than this one, and this start ends here.
        let merged = visited[..earlier]
            .iter()
            .any(|v| (*v - best.translation).length() <= MERGED * far);
        visited.push(best.translation);
        #[cfg(test)]
        let merged = merged && MERGES.with(|c| c.get()) != usize::MAX;
        #[cfg(test)]
        if merged {
            MERGES.with(|c| c.set(c.get() + 1));
        }
        if merged {
            status = DepthStatus::Converged;
            break;
        }
    }
    Ok((best, iterations, status))
}

/// Two starts' bests closer than this fraction of `far` are one translation (see [`refine`]):
/// far below any tolerance, above the rounding of two out-projections that retrace each other.
const MERGED: f64 = 1e-9;

/// The final gap as a fraction of the depth (see [`polish`]).
const POLISH: f64 = 1e-3;

/// The best touching translation brought closer: its out-projection ends where the bodies are
/// within the tolerance, which at a shallow penetration is a large part of the depth (at 1%
/// of the radius, the default tolerance of 1e-3 R left gaps of 0.2 to 14% of the depth on
/// knot2.8k, 8% at the median). Body 2 comes back along the same line from there with the
/// tolerance `min(tolerance, POLISH depth)`: a shorter translation that still ends apart
/// (the continuous query's contract, from a start that does not penetrate). Where that query
/// cannot finish (its iteration cap, or a tolerance below rounding), the translation is kept,
/// and where its witnesses are already that close, it is not run (knot2.8k at 1% / 5% / 20%:
/// 2.0%, 2.1% and 1.1% fewer instructions, the depths the same to 1e-15).
fn polish(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    best: Touch,
    options: &ContactOptions,
) -> Result<Touch, ContactError> {
    let t = best.translation;
    let s = t.length();
    let delta = effective_tolerance(
        mesh1,
        &Motion::stationary(*pose1),
        mesh2,
        &Motion::stationary(*pose2),
        options,
    );
    let fine = (POLISH * s).min(delta);
    let Some(d) = t.try_normalize() else {
        return Ok(best);
    };
    if fine <= 1e-12 * (s + pose2.translation.length() + pose1.translation.length()) {
        return Ok(best);
    }
    // Already within it: the witnesses' distance bounds the meshes' (exact, or a pair's).
    if (best.point2 - best.point1).length() <= fine {
        return Ok(best);
    }
    let fine_options = ContactOptions {
        tolerance: Some(fine),
        ..*options
    };
    match come_back(mesh1, pose1, mesh2, pose2, (d, s), best.pair, &fine_options) {
        Ok(Some(p)) => {
            let c = complete(mesh1, pose1, mesh2, p);
            Ok(if c.translation.length() <= s { c } else { best })
        }
        Ok(None) | Err(ContactError::IterationLimit { .. }) => Ok(best),
        Err(e) => Err(e),
    }
}

/// A seed translation shorter than this fraction of the smaller bounding radius is refined
/// alone: the other starts are neither kept nor refined, and the seeds' samples are pruned
/// against it rather than against the `starts`-th shortest. Measured on
/// `bench/penetration_grid.py` (18 cells of 8 queries: 6 models at 1%, 5% and 20% of the
/// radius), one start against three at 1% and 5%: the same number of queries within 1% of
/// the sampled-direction bound in every cell, depths within 2% of the three starts' either way
/// (the starts are ranked before the polish, so one start is sometimes shorter), at 1.2 to 1.7
/// times less time. One start at 20% too lost 5 of 48 queries from within 1% (139 -> 134 of
/// 143): deep penetrations keep all their starts (`DepthOptions::starts`; these figures are
/// from three).
const SHALLOW: f64 = 0.1;

/// Translational penetration depth of `mesh2` (placed by `pose2`) into `mesh1` (module docs).
///
/// # Errors
/// [`ContactError`] for bad options or an iteration cap of the underlying continuous queries.
pub fn penetration_depth(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    options: &DepthOptions,
) -> Result<PenetrationDepth, ContactError> {
    // A tolerance below twice the distances' accuracy would end the touching translations at
    // rounding level, where the bodies may still touch (a tolerance of 1e-300 left 21 of 45
    // knot pairs and most box pairs touching): raised to it, every translation ends apart.
    let floor = 2.0 * super::distance_accuracy((mesh1, pose1), (mesh2, pose2));
    let contact_options = ContactOptions {
        tolerance: options.tolerance.map(|t| t.max(floor)),
        ..ContactOptions::default()
    };
    if options.starts == 0 {
        return Err(crate::OptionsError::OutOfRange {
            name: "starts",
            requirement: "must be at least 1",
            value: 0.0,
        }
        .into());
    }
    // The directions are allocated at once: 1e10 of them asked for 240 GB and aborted the
    // process (a Python interpreter with it).
    if options.directions > MAX_DIRECTIONS {
        return Err(crate::OptionsError::OutOfRange {
            name: "directions",
            requirement: "must be at most 1,000,000",
            value: options.directions as f64,
        }
        .into());
    }
    if let Some(t) = options.tolerance {
        if !(t.is_finite() && t > 0.0) {
            return Err(crate::OptionsError::OutOfRange {
                name: "tolerance",
                requirement: "must be positive and finite",
                value: t,
            }
            .into());
        }
    }
    let separated = PenetrationDepth {
        depth: 0.0,
        translation: Vec3::ZERO,
        direction: Vec3::Z,
        point1: Vec3::ZERO,
        point2: Vec3::ZERO,
        iterations: 0,
        status: DepthStatus::Separated,
        exact: true,
    };
    let polytopes = if options.exact_convex {
        mesh1.convex_polytope().zip(mesh2.convex_polytope())
    } else {
        None
    };
    if let Some((a, b)) = polytopes {
        // Convex polytopes overlap exactly when every candidate axis shows an overlap: this
        // decides "penetrating" without the winding number (whose inside needs the triangles
        // oriented alike, which a convex hull's need not be).
        if let Some((o, n, sa, sb)) = convex::exact_depth(mesh1, a, pose1, mesh2, b, pose2) {
            if o <= 0.0 {
                return Ok(separated);
            }
            // The tolerance the continuous queries of the other path would use.
            let delta = effective_tolerance(
                mesh1,
                &Motion::stationary(*pose1),
                mesh2,
                &Motion::stationary(*pose2),
                &contact_options,
            );
            let translation = n * (o + 0.5 * delta);
            return Ok(PenetrationDepth {
                depth: o,
                translation,
                direction: n,
                point1: sa,
                point2: sb + translation,
                iterations: 0,
                status: DepthStatus::Converged,
                exact: true,
            });
        }
    }
    // An intersecting pair of the pose itself: the first guess of every sample near it.
    let mut hint = None;
    if !penetrating(mesh1, pose1, mesh2, pose2, &mut hint) {
        return Ok(separated);
    }
    let c1 = pose1.transform_point(mesh1.bvh().root().center);
    let c2 = pose2.transform_point(mesh2.bvh().root().center);
    let far = 2.0 * (mesh1.bounding_radius() + mesh2.bounding_radius() + (c2 - c1).length())
        + f64::MIN_POSITIVE;
    let mut seeds: Vec<Vec3> = Vec::new();
    // A direction given twice (both meshes' axes where their rotations agree, the centroid
    // difference along an axis) would be sampled twice and could take two of the starts: once.
    let add = |seeds: &mut Vec<Vec3>, d: Vec3| {
        if let Some(u) = d.try_normalize() {
            if !seeds.iter().any(|e| e.dot(u) >= 1.0 - 1e-12) {
                seeds.push(u);
            }
        }
    };
    if let Some(d) = options.cached_direction {
        add(&mut seeds, d);
    }
    add(&mut seeds, c2 - c1);
    if options.directions > 0 {
        // The principal axes of both root volumes, both ways: a box's face normals.
        for (pose, m) in [(pose1, mesh1), (pose2, mesh2)] {
            let axes = pose.rotation * m.bvh().root().axes;
            for a in [axes.x_axis, axes.y_axis, axes.z_axis] {
                add(&mut seeds, a);
                add(&mut seeds, -a);
            }
        }
    }
    seeds.extend(sphere_directions(options.directions));
    let kept = shortest_seeds(
        mesh1,
        pose1,
        mesh2,
        pose2,
        &seeds,
        far,
        &contact_options,
        hint,
        SHALLOW * mesh1.bounding_radius().min(mesh2.bounding_radius()),
        options.starts,
    )?;
    let touches: Vec<Touch> = kept
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            if i > 0 {
                touch(mesh1, pose1, mesh2, p)
            } else {
                complete(mesh1, pose1, mesh2, p)
            }
        })
        .collect();
    let mut result: Option<(Touch, usize, DepthStatus)> = None;
    let mut visited = Vec::new();
    for start in touches {
        let (t, iterations, status) = refine(
            mesh1,
            pose1,
            mesh2,
            pose2,
            start,
            far,
            &contact_options,
            options.max_iterations,
            hint,
            &mut visited,
        )?;
        if result
            .as_ref()
            .is_none_or(|r| t.translation.length() < r.0.translation.length())
        {
            result = Some((t, iterations, status));
        }
    }
    let Some((best, iterations, status)) = result else {
        // Every direction failed (degenerate input): report no separating translation found.
        return Err(ContactError::IterationLimit {
            iterations: 0,
            time_reached: 0.0,
        });
    };
    let best = polish(mesh1, pose1, mesh2, pose2, best, &contact_options)?;
    let best = exact(mesh1, pose1, mesh2, best);
    let depth = best.translation.length();
    Ok(PenetrationDepth {
        depth,
        translation: best.translation,
        direction: best.translation.try_normalize().unwrap_or(Vec3::Z),
        point1: best.point1,
        point2: best.point2,
        iterations,
        status,
        exact: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh;
    use crate::motion::sampling::unit;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// The pair-interval bound only skips work that could not change the answer: with and
    /// without it, the same depths, translations and statuses bit for bit, on knot pairs
    /// pushed in by 1%, 5% and 20% of the radius along random directions; and it does skip
    /// continuous queries there.
    #[test]
    fn pair_bounds_change_no_answer() {
        let queries = |on: bool| {
            PAIR_BOUNDS.with(|c| c.set(on));
            SEED_QUERIES.with(|c| c.set(0));
            let answers = pushed_in_answers();
            PAIR_BOUNDS.with(|c| c.set(true));
            (answers, SEED_QUERIES.with(|c| c.get()))
        };
        let (with, fewer) = queries(true);
        let (without, all) = queries(false);
        assert_eq!(with, without);
        assert!(
            fewer < all,
            "{fewer} continuous queries with the bound, {all} without"
        );
    }

    /// The balls' shifts only skip samples that penetrate and directions that could not be
    /// kept: with and without them, the same depths, translations and statuses bit for bit on
    /// knot pairs pushed in by 1%, 5% and 20% of the radius (the knot has balls, so the
    /// shifts are in use).
    #[test]
    fn ball_shifts_change_no_answer() {
        assert!(!mesh::torus_knot(100, 8)
            .expect("knot")
            .inscribed_balls()
            .is_empty());
        let queries = |on: bool| {
            BALL_SHIFTS.with(|c| c.set(on));
            let answers = pushed_in_answers();
            BALL_SHIFTS.with(|c| c.set(true));
            answers
        };
        assert_eq!(queries(true), queries(false));
    }

    /// A start that reaches an earlier start's best ends there ([`refine`]): on the queries of
    /// [`pushed_in_answers`], it happens, and no depth is longer than without it by more than
    /// 1e-6 relative (the starts' answers are ranked, and the merged start went on from the
    /// same translation).
    #[test]
    fn merged_starts_change_no_depth() {
        let queries = |on: bool| {
            MERGES.with(|c| c.set(if on { 0 } else { usize::MAX }));
            let answers = pushed_in_answers();
            let merges = MERGES.with(|c| c.replace(0));
            (answers, merges)
        };
        let (with, merges) = queries(true);
        let (without, _) = queries(false);
        assert!(merges > 0, "no start merged");
        for ((a, ..), (b, ..)) in with.iter().zip(&without) {
            assert!(
                a.length() <= b.length() * (1.0 + 1e-6),
                "{} with merges, {} without",
                a.length(),
                b.length()
            );
        }
    }

    /// Penetration depths of a knot and a turned copy touching from outside along random
    /// directions, then pushed in by 1%, 5% and 20% of the radius (60 queries).
    fn pushed_in_answers() -> Vec<(Vec3, u64, DepthStatus)> {
        pushed_in(&DepthOptions::default())
            .into_iter()
            .map(|d| (d.translation, d.depth.to_bits(), d.status))
            .collect()
    }

    /// [`penetration_depth`] with `depth_options` on 60 knot pairs pushed in by 1%, 5% and 20%
    /// of the radius.
    fn pushed_in(depth_options: &DepthOptions) -> Vec<PenetrationDepth> {
        let m = mesh::torus_knot(100, 8).expect("knot");
        let r = m.bounding_radius();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut answers = Vec::new();
        for case in 0..60 {
            let f = [0.01, 0.05, 0.2][case % 3];
            let rot = crate::math::Mat3::from_axis_angle(unit(&mut rng), (case as f64) * 0.7);
            let u = unit(&mut rng);
            // Touching from outside along u, then pushed in by f R.
            let far = 4.0 * r;
            let still = Motion::stationary(Pose::IDENTITY);
            let start = Pose::new(rot, u * far).expect("pose");
            let end = Pose::new(rot, Vec3::ZERO).expect("pose");
            let motion = Motion::translation(start, end).expect("motion");
            let options = ContactOptions::default();
            let c = crate::query::contact_time::time_of_contact(&m, &still, &m, &motion, &options)
                .expect("toc")
                .expect("contact");
            let p2 = Pose::new(rot, u * (far * (1.0 - c.time) - f * r)).expect("pose");
            let d = penetration_depth(&m, &Pose::IDENTITY, &m, &p2, depth_options).expect("pd");
            answers.push(d);
        }
        answers
    }

    /// More starts refine the same shortest seeds first and keep the shortest result, so the
    /// depth never grows with them (to rounding); on these knots a third start sometimes finds
    /// a shallower one (so the comparison is not vacuous), a single start sometimes a deeper
    /// one. Zero starts is an options error.
    #[test]
    fn more_starts_never_give_a_deeper_answer() {
        let with = |starts| {
            pushed_in(&DepthOptions {
                starts,
                ..DepthOptions::default()
            })
        };
        let (one, two, three) = (with(1), with(2), with(3));
        let mut shallower = 0;
        let mut deeper = 0;
        // The seeds' continuous queries start from other hints with other starts: the same
        // translations to rounding.
        let below = |x: f64, y: f64| x < y * (1.0 - 1e-12);
        for ((a, b), c) in one.iter().zip(&two).zip(&three) {
            assert!(
                !below(b.depth, c.depth) && !below(a.depth, b.depth),
                "{a:?} {b:?} {c:?}"
            );
            shallower += usize::from(below(c.depth, b.depth));
            deeper += usize::from(below(b.depth, a.depth));
        }
        assert!(shallower > 0 && deeper > 0, "{shallower} {deeper}");
        let m = mesh::torus_knot(60, 6).expect("knot");
        let p2 = Pose::new(crate::math::Mat3::IDENTITY, Vec3::new(0.1, 0.0, 0.0)).expect("pose");
        let zero = DepthOptions {
            starts: 0,
            ..DepthOptions::default()
        };
        assert!(matches!(
            penetration_depth(&m, &Pose::IDENTITY, &m, &p2, &zero),
            Err(ContactError::Options(_))
        ));
    }

    /// `holds_until` against dense sampling with the exact triangle test: on random
    /// intersecting triangle pairs of two knots and random directions, the pair intersects at
    /// every sampled shift up to the answer (the contract the seeds' skip relies on), and the
    /// answer is the interval's end (just past it the pair is apart) in most cases.
    #[test]
    fn a_pair_holds_until_its_interval_ends() {
        let a = mesh::torus_knot(60, 6).expect("knot");
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let pose1 = Pose::IDENTITY;
        let (mut checked, mut tight) = (0, 0);
        while checked < 300 {
            let pose2 = Pose::from_axis_angle(unit(&mut rng), 1.3, unit(&mut rng) * 0.3);
            let Some(pair) =
                crate::query::collide::intersecting_leaves(&a, &pose1, &a, &pose2, None)
            else {
                continue;
            };
            let d = unit(&mut rng);
            let h = holds_until(&a, &pose1, &a, &pose2, pair, d);
            let t1 = a.bvh().leaf_triangles()[pair.0 as usize];
            let at = |s: f64| {
                let p2 = shifted(&pose2, d * s);
                let pos12 = pose1.inv_mul(&p2);
                let t2 =
                    a.bvh().leaf_triangles()[pair.1 as usize].map(|p| pos12.transform_point(p));
                intersect_triangle_triangle(&t1, &t2)
            };
            for k in 0..=50 {
                let s = h * k as f64 / 50.0;
                assert!(at(s), "pair {pair:?} apart at {s} of {h} along {d:?}");
            }
            if !at(h * (1.0 + 1e-6) + 1e-9) {
                tight += 1;
            }
            checked += 1;
        }
        assert!(tight > 270, "{tight} of 300 answers at the interval's end");
    }
}

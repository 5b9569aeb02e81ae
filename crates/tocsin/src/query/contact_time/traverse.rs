//! One C2A iteration: the largest step `dt` certified safe by the two hierarchies at time `t`.
//!
//! Invariant: every node pair left unvisited has a certified step `s` with
//! `s (1 + slack) >= best`, so `best / (1 + slack)` would be safe for every triangle pair. The
//! step returned is larger where it can be: the smallest of `best` (every evaluated triangle
//! pair's step is at least that) and the certified steps of the pairs actually left unvisited
//! (`pruned`: each was computed before the pair was dropped, and is a certificate for every
//! triangle pair below it), never more than the window. A triangle pair within `delta` (or
//! within the scene's distance resolution, where `delta` is below it: `Span::contact`) ends
//! the search.

use super::shells::AxisShells;
use super::Path;
use crate::bvh::{
    both_at_most, rss_separation, ASide, BSide, Bvh, ColumnPair, Expansion, Lanes4, Node,
    RelativeRss, Rss, LARGE_PROJECT_MAX, PROJECT_MAX,
};
use crate::math::{Mat3, Pose, Vec3};
use crate::motion::{Motion, Spread};
use crate::query::distance::gjk::{self, Gjk, Separation, WarmSimplex};
use crate::query::distance::{distance_triangle_triangle, TrianglePairDistance};
use crate::robot::chain::ChainKinematics;
use crate::TriMesh;

/// Larger subtree pairs (up to [`LARGE_PROJECT_MAX`]) are projected while at least one such
/// projection in this many pruned its pair (see [`LARGE_PROJECT_MAX`]), counted in a record
/// that halves at every iteration, so that each iteration tries at least one.
const LARGE_PROJECT_RATIO: usize = 4;

/// Far from contact (the gap above four tolerances), GJK stops once its gap is within this
/// fraction of its upper bound `|v|`: the step is then at least nine tenths of the converged
/// one. Measured in instructions (`examples/profile_convex`, 1,000 passes per motion kind):
/// translations 3.02 -> 3.35 iterations but 8% fewer instructions, interps 9%, screws 11%
/// (docs/BENCHMARKS.md, thirty-ninth session).
const CONVEX_STEP_REL: f64 = 0.1;

/// Node pairs a traversal visits before it asks the hulls for their step
/// ([`StepSearch::hull_step`]): an iteration that certifies its window sooner (most far from
/// contact) never pays for GJK. Measured on MotionBenchMaker's Fetch (`bench/robot_mbm.py`,
/// docs/BENCHMARKS.md, forty-first session): asking at the first pair made free edges 15 to
/// 25% slower than asking after three; after 8 or 24 they were no faster than after three.
const HULL_AFTER: usize = 3;

/// The traversal stops at the hulls' step once its best is within `1 + HULL_EXIT * slack` of
/// it. Measured as for [`HULL_AFTER`]: stopping only where the hulls' step is already the
/// best (0) made free edges slower than without hulls; 1 and 2 were alike, 2 a little faster
/// at the 90th percentile.
const HULL_EXIT: f64 = 2.0;

/// A traversal whose step is more than this many times the hulls' drops them for the rest of
/// the query.
const HULL_LOOSE: f64 = 2.0;

/// The hulls' state in a query ([`StepSearch::hull_step`]): not yet asked for (their polytopes
/// are made on first use, by the first traversal that needs them: a query whose traversals all
/// end early never builds them), in use, or off for the rest of the query.
enum Hulls<'a> {
    Untried(&'a TriMesh, &'a TriMesh),
    /// GJK on the two polytopes, and whether each keeps every corner of its mesh
    /// ([`crate::mesh::Outer::exact`]).
    On(Gjk<'a>, (bool, bool)),
    Off,
}

/// What one iteration found.
pub(crate) enum StepOutcome {
    /// A triangle pair (leaf positions) is within the tolerance at the current time; with the
    /// meshes' exact distance there when the iteration already certified it (two convex
    /// polytopes: that pair's closest points, mesh 1's frame).
    Within {
        pair: (u32, u32),
        closest: Option<TrianglePairDistance>,
    },
    /// A safe step, the triangle pair that limited it (if any) and the smallest triangle-pair
    /// distance seen (an upper bound of the meshes' distance; infinite if none was evaluated),
    /// or where a certified gap gave the step without triangle pairs (two convex solids far
    /// apart, or the hulls' direction), that gap: a lower bound. The advancement uses it only
    /// to choose the slack and to tell an iterate clearly apart.
    Step {
        dt: f64,
        pair: Option<(u32, u32)>,
        distance: f64,
    },
}

/// Node pairs on which the rotation certificates may be tried in one iteration, nearly all
/// failing, before they are switched off for the rest of the query
/// ([`StepSearch::give_up_shells`]).
const SHELLS_GIVE_UP: u32 = 1024;

pub(crate) struct StepSearch<'a> {
    mesh1: &'a TriMesh,
    mesh2: &'a TriMesh,
    bvh1: &'a Bvh,
    bvh2: &'a Bvh,
    motion1: Path<'a>,
    motion2: Path<'a>,
    delta: f64,
    /// A triangle pair within this distance ends the search (`delta`, raised to the scene's
    /// distance resolution: `Span::contact`).
    contact: f64,
    // Per-iteration state.
    rot12: Mat3,
    /// `rot12` transposed: mesh 1's frame into mesh 2's.
    rot21: Mat3,
    trans12: Vec3,
    /// Mesh 1's rotation at the current time: mesh-1 frame to world.
    rot1: Mat3,
    /// Mesh 2's world rotation at the current time.
    rot2: Mat3,
    /// The two motions seen from mesh 1's frame at the current time.
    kin1: BodyKinematics,
    kin2: BodyKinematics,
    /// Both meshes' corner columns at the current relative pose (small subtree pairs are also
    /// bounded by projecting their points on the pair's axis, as in the distance search).
    columns: Option<ColumnPair<'a>>,
    lanes: Lanes4,
    /// Length of the time window the bounds are valid for (steps never exceed it).
    window: f64,
    best: f64,
    /// The smallest certified step of the pairs left unvisited (pruned by the slack).
    pruned: f64,
    best_pair: Option<(u32, u32)>,
    closest: f64,
    slack: f64,
    stack: Vec<(u32, u32, f64)>,
    /// Rotation-invariant certificates, when one body turns about a fixed axis past the other.
    shells: Option<AxisShells>,
    /// Whether the certificates are in use: from the iteration after one whose step was limited
    /// by the spread of a pair's volumes under rotation rather than by how fast they approach
    /// (see [`Self::rotation_limited`]). Where they do not help, they would only cost.
    shells_on: bool,
    /// The certificates' tries and successes this iteration (node pairs), and whether they
    /// were switched off for the rest of the query after an iteration of [`SHELLS_GIVE_UP`]
    /// tries or more that certified under one in a thousand ([`Self::give_up_shells`]).
    shell_tries: std::cell::Cell<(u32, u32)>,
    shells_given_up: bool,
    /// The time the advancement starts from (a robot pair's span may start after 0): the
    /// first iteration decides on the certificates before it traverses.
    pub(crate) start: f64,
    /// GJK on the two meshes when both are convex polytopes ([`crate::query::distance::gjk`]):
    /// the two whole bodies' separation certifies the step before any traversal.
    convex: Option<Gjk<'a>>,
    /// GJK on convex polytopes holding the two meshes where they are not both convex (a hull
    /// of each non-convex one: [`TriMesh::outer_polytope`]). Each iteration, the direction
    /// that separates the hulls, with the gap along it measured on the meshes themselves,
    /// certifies a step for every triangle pair ([`Self::hull_step`]); dropped for the rest of
    /// the query once the hulls overlap, come within the tolerance or prove loose.
    hull: Hulls<'a>,
    /// This iteration's step certified by the hulls' direction (0 without one): a step the
    /// traversal may stop at as soon as its best is within the slack of it, and a floor under
    /// the step it returns.
    hull_floor: f64,
    /// The current time.
    t: f64,
    /// Projections of subtree pairs above [`PROJECT_MAX`] made, and how many pruned their pair
    /// ([`LARGE_PROJECT_MAX`]), each halved at every iteration ([`LARGE_PROJECT_RATIO`]).
    large_projections: (usize, usize),
    /// A step known to be under this is not worked out: the traversal stops as soon as its best
    /// falls below it and returns a step of 0 (0: never). The advancement sets it for a first
    /// iteration that stops when short ([`super::Span::least_first_step`]): a robot's frozen
    /// check sized from a far phase of a turn searched every facing pair of a shaft and its
    /// bore for a step it then did not take (23 ms of a 47 ms query).
    pub(crate) abort_below: f64,
}

/// One body's motion at the current time, seen from mesh 1's frame: the motion bounds are
/// dot products and lengths, the same in every frame, so each pair's direction `n` (which the
/// separating-axis test gives in mesh 1's frame) is used as it is, without turning it into the
/// world frame and turning each node's lever with the body's rotation.
#[derive(Clone, Copy)]
struct Kinematics {
    /// Linear velocity of the axis point.
    v: Vec3,
    /// Angular velocity.
    w: Vec3,
    /// `|w|`.
    w_len: f64,
    /// `|v|`.
    v_len: f64,
    /// A point of the rotation axis, in the body's own frame.
    axis_point: Vec3,
    /// Whether the body does not move (its bound is 0: nothing to compute).
    still: bool,
}

impl Kinematics {
    fn new(motion: &Motion, to_mesh1: &Mat3) -> Self {
        let (v, w) = (
            *to_mesh1 * motion.linear_velocity(),
            *to_mesh1 * motion.angular_velocity(),
        );
        Self {
            v,
            w,
            w_len: w.length(),
            v_len: v.length(),
            axis_point: motion.axis_point(),
            still: motion.is_stationary(),
        }
    }

    /// The bound of [`Motion::directional_bound`] and [`Motion::directional_bound_window`],
    /// the smaller of the two, along the unit `m` (mesh 1's frame) for a set of points about a
    /// centre whose lever from the axis is `lever` (mesh 1's frame), all within `rho` of the
    /// axis, over a window `h`. `support(g)` is the set's `max (p - c) . g` for `g` in mesh 1's
    /// frame ([`Spread::support`]): it stands for the window bound's `|m x w| radius`, since the
    /// velocity's rotation part `(p - axis) . (m x w)` is linear in the point.
    #[inline]
    fn bound(&self, m: Vec3, lever: Vec3, support: impl Fn(Vec3) -> f64, rho: f64, h: f64) -> f64 {
        let mxw = m.cross(self.w);
        let k = mxw.length();
        if k == 0.0 {
            return m.dot(self.v);
        }
        m.dot(self.v) + (k * rho).min(lever.dot(mxw) + support(mxw) + k * self.w_len * h * rho)
    }

    /// Speed bound of points within `rho` of the axis, in any direction.
    #[inline]
    fn speed(&self, rho: f64) -> f64 {
        self.v_len + self.w_len * rho
    }
}

/// A body's motion bound at the current time: a rigid motion's velocities, or a robot link's
/// chain of joints (both in mesh 1's frame).
enum BodyKinematics {
    Rigid(Kinematics),
    Chain(ChainKinematics),
}

/// What a body's bound needs at one time before mesh 1's frame is known: the rigid motion, or
/// a chain's velocity field in the world frame.
enum WorldBound<'m> {
    Rigid(&'m Motion),
    Chain(ChainKinematics),
}

impl BodyKinematics {
    /// The body's world pose at time `t` and what its bound there needs (for a chain, one pass
    /// down the chain gives both).
    fn at<'m>(path: Path<'m>, t: f64) -> (Pose, WorldBound<'m>) {
        match path {
            Path::Rigid(m) => (m.pose_at(t), WorldBound::Rigid(m)),
            Path::Chain(c) => {
                let (pose, kinematics) = c.state_at(t);
                (pose, WorldBound::Chain(kinematics))
            }
        }
    }

    /// The bound in mesh 1's frame (`world_to_mesh1` maps the world into it).
    fn in_mesh1(bound: WorldBound<'_>, world_to_mesh1: &Pose) -> Self {
        match bound {
            WorldBound::Rigid(m) => Self::Rigid(Kinematics::new(m, &world_to_mesh1.rotation)),
            WorldBound::Chain(k) => Self::Chain(k.in_frame(world_to_mesh1)),
        }
    }
}

/// A set of body points for the motion bounds (body frame): a centre, the farthest the points
/// reach from it, the volume they fill when they are a node's (for their reach by direction,
/// [`PointSet::spread`]), and a bound `rho` on their distance from the motion's rotation axis.
struct PointSet<'a> {
    center: Vec3,
    radius: f64,
    rho: f64,
    /// The node's volume (`None`: a ball of `radius`), for the points' reach by direction.
    rss: Option<&'a Rss>,
}

impl<'a> PointSet<'a> {
    /// A node's volume (on demand: a query touches few nodes).
    #[inline]
    fn node(node: &'a Node, motion: Path<'_>) -> Self {
        Self::volume(&node.rss, motion)
    }

    /// An RSS: its centre, the farthest its points reach from it (`sqrt(h1^2 + h2^2) + r`, the
    /// rectangle's corner plus the ball; [`Rss::bounding_radius`] is the looser `h1 + h2 + r`),
    /// and the volume itself for its support.
    #[inline]
    fn volume(r: &'a Rss, motion: Path<'_>) -> Self {
        let (center, radius) = (r.center, r.corner_radius());
        let rho = match motion {
            Path::Rigid(m) => m.axis_distance(center) + radius,
            Path::Chain(_) => 0.0,
        };
        Self {
            center,
            radius,
            rho,
            rss: Some(r),
        }
    }

    /// The points' reach about the centre by direction (the body's frame).
    #[inline]
    fn spread(&self) -> Spread {
        match self.rss {
            Some(r) => r.spread(),
            None => Spread::ball(self.radius),
        }
    }

    /// A triangle: its centroid, the farthest corner, and the largest corner axis distance.
    #[inline]
    fn triangle(t: &[Vec3; 3], motion: Path<'_>) -> Self {
        let center = (t[0] + t[1] + t[2]) / 3.0;
        let radius = t.iter().fold(0.0_f64, |m, &p| m.max((p - center).length()));
        let rho = match motion {
            Path::Rigid(motion) => t
                .iter()
                .fold(0.0_f64, |m, &p| m.max(motion.axis_distance(p))),
            Path::Chain(_) => 0.0,
        };
        Self {
            center,
            radius,
            rho,
            rss: None,
        }
    }
}

impl<'a> StepSearch<'a> {
    pub(crate) fn new(
        mesh1: &'a TriMesh,
        motion1: Path<'a>,
        mesh2: &'a TriMesh,
        motion2: Path<'a>,
        (delta, contact): (f64, f64),
        simplex: WarmSimplex,
    ) -> Self {
        let shells = match (motion1, motion2) {
            (Path::Rigid(m1), Path::Rigid(m2)) => {
                AxisShells::new(m1, m2, mesh1.bvh().root(), mesh2.bvh().root())
            }
            _ => None,
        };
        let convex = gjk::polytopes(mesh1, mesh2)
            .map(|(p1, p2)| Gjk::new(mesh1, p1, mesh2, p2, None, simplex));
        let hull = match convex {
            None => Hulls::Untried(mesh1, mesh2),
            Some(_) => Hulls::Off,
        };
        Self {
            mesh1,
            mesh2,
            bvh1: mesh1.bvh(),
            bvh2: mesh2.bvh(),
            motion1,
            motion2,
            delta,
            contact,
            rot12: Mat3::IDENTITY,
            rot21: Mat3::IDENTITY,
            trans12: Vec3::ZERO,
            rot1: Mat3::IDENTITY,
            rot2: Mat3::IDENTITY,
            kin1: BodyKinematics::Chain(ChainKinematics::default()),
            kin2: BodyKinematics::Chain(ChainKinematics::default()),
            columns: None,
            lanes: Lanes4::detect(),
            window: 1.0,
            best: 0.0,
            pruned: f64::INFINITY,
            best_pair: None,
            closest: f64::INFINITY,
            slack: 0.0,
            stack: Vec::with_capacity(64),
            shells,
            shells_on: false,
            shell_tries: std::cell::Cell::new((0, 0)),
            shells_given_up: false,
            start: 0.0,
            convex,
            hull,
            hull_floor: 0.0,
            t: 0.0,
            large_projections: (0, 0),
            abort_below: 0.0,
        }
    }

    /// Safe step for a gap `gap` along the mesh-1-frame unit direction `n` (from body 1 to
    /// body 2) between the point sets `s1` (of body 1) and `s2` (of body 2). Each body's speed
    /// along the gap is the smaller of its whole-motion bound and its bound over the window.
    #[inline]
    fn step(&self, gap: f64, n: Vec3, s1: &PointSet, s2: &PointSet) -> f64 {
        let (spread1, spread2) = (s1.spread(), s2.spread());
        self.step_by(
            gap,
            n,
            (s1, s2),
            |g| spread1.support(g),
            |g| spread2.support(g),
        )
    }

    /// [`Self::step`] for two triangles (`t2` in body 2's frame), whose points' reach by
    /// direction is taken over their corners (the largest of a linear function over a
    /// triangle): exact, where the ball about the centroid charges a long triangle its length
    /// in every direction (a shaft's faces, turning, were charged four times their chord).
    #[inline]
    fn step_triangles(&self, gap: f64, n: Vec3, t1: &[Vec3; 3], t2: &[Vec3; 3]) -> f64 {
        let (s1, s2) = (
            PointSet::triangle(t1, self.motion1),
            PointSet::triangle(t2, self.motion2),
        );
        let (c1, c2) = (s1.center, s2.center);
        self.step_by(
            gap,
            n,
            (&s1, &s2),
            |g| triangle_reach(t1, c1, g),
            |g| triangle_reach(t2, c2, g),
        )
    }

    /// [`Self::step`] with each set's reach by direction given (`support1(g)` for `g` in
    /// body 1's frame, `support2(g)` in body 2's).
    #[inline(always)]
    fn step_by(
        &self,
        gap: f64,
        n: Vec3,
        (s1, s2): (&PointSet, &PointSet),
        support1: impl Fn(Vec3) -> f64,
        support2: impl Fn(Vec3) -> f64,
    ) -> f64 {
        let margin = gap - 0.5 * self.delta;
        if margin <= 0.0 {
            return 0.0;
        }
        let h = self.window;
        let mu1 = match &self.kin1 {
            BodyKinematics::Rigid(k) if k.still => 0.0,
            BodyKinematics::Rigid(k) => {
                let lever1 = s1.center - k.axis_point;
                k.bound(n, lever1, &support1, s1.rho, h)
            }
            BodyKinematics::Chain(c) => c.bound(n, s1.center, &support1, h),
        };
        let mu2 = match &self.kin2 {
            BodyKinematics::Rigid(k) if k.still => 0.0,
            BodyKinematics::Rigid(k) => {
                let lever2 = self.rot12 * (s2.center - k.axis_point);
                let support = |g: Vec3| support2(self.rot21 * g);
                k.bound(-n, lever2, support, s2.rho, h)
            }
            BodyKinematics::Chain(c) => {
                let support = |g: Vec3| support2(self.rot21 * g);
                c.bound(-n, self.rot12 * s2.center + self.trans12, support, h)
            }
        };
        let mu = mu1 + mu2;
        if mu <= 0.0 {
            f64::INFINITY
        } else {
            margin / mu
        }
    }

    /// Bound on the two point sets' speeds in any direction (over the window).
    #[inline]
    fn speed(&self, s1: &PointSet, s2: &PointSet) -> f64 {
        self.speed1(s1) + self.speed2(s2)
    }

    /// Bound on the speed of a point set of body 1 in any direction (over the window).
    #[inline]
    fn speed1(&self, s1: &PointSet) -> f64 {
        match &self.kin1 {
            BodyKinematics::Rigid(k) => k.speed(s1.rho),
            BodyKinematics::Chain(c) => c.speed(s1.center, s1.radius, self.window),
        }
    }

    /// Bound on the speed of a point set of body 2 in any direction (over the window).
    #[inline]
    fn speed2(&self, s2: &PointSet) -> f64 {
        match &self.kin2 {
            BodyKinematics::Rigid(k) => k.speed(s2.rho),
            BodyKinematics::Chain(c) => c.speed(
                self.rot12 * s2.center + self.trans12,
                s2.radius,
                self.window,
            ),
        }
    }

    /// Certified step of a node pair whose relative frame is `rel`. The separating-axis search
    /// stops early once the gap proves the pair prunable whatever the axis: every directional
    /// bound is at most the speed bound `|v| + |w| rho` of each body.
    #[inline]
    fn node_step(&self, n1: u32, n2: u32, rel: &RelativeRss) -> f64 {
        let (a, b) = (
            &self.bvh1.nodes()[n1 as usize],
            &self.bvh2.nodes()[n2 as usize],
        );
        let (s1, s2) = (
            PointSet::node(a, self.motion1),
            PointSet::node(b, self.motion2),
        );
        let mu_max = self.speed(&s1, &s2);
        let cutoff = 0.5 * self.delta + mu_max * self.best / (1.0 + self.slack);
        let (gap, axis) = rss_separation(&a.rss, &b.rss, rel, cutoff);
        let n = a.rss.axes * axis;
        let mut step = self.step(gap, n, &s1, &s2);
        // Near the leaves the volumes overhang their triangles: the subtrees' points projected
        // on the same axis (from a towards b) are often farther apart, and the same motion
        // bound then certifies a longer step.
        if let Some(c) = &self.columns {
            if gap > 0.0 && step * (1.0 + self.slack) < self.best && both_at_most(a, b, PROJECT_MAX)
            {
                let projected = c.gap(self.lanes, (n1, a), (n2, b), n);
                if projected > gap {
                    step = self.step(projected, n, &s1, &s2);
                }
            }
        }
        match &self.shells {
            // Only where the pair would be visited: the certificate is then worth its cost.
            Some(shells) if self.shells_on && step * (1.0 + self.slack) < self.best => {
                let (t, h, need) = (self.t, self.window, self.certified_apart());
                let (tries, successes) = self.shell_tries.get();
                self.shell_tries.set((tries.saturating_add(1), successes));
                let ranges = ((self.mesh1, a.leaf_range()), (self.mesh2, b.leaf_range()));
                if shells.resolved(ranges.0, ranges.1, self.delta) {
                    self.shell_tries
                        .set((tries.saturating_add(1), successes.saturating_add(1)));
                    return f64::INFINITY;
                }
                let mut lb = shells.lower_bound(&a.rss, &b.rss, (t, h), need);
                if lb <= need {
                    let (turning, still) = if shells.turning_is_1() {
                        ((self.mesh1, n1), (self.bvh2, n2))
                    } else {
                        ((self.mesh2, n2), (self.bvh1, n1))
                    };
                    lb = lb.max(shells.lower_bound_inner(turning, still, (t, h), need));
                }
                if lb <= need && a.is_leaf() && b.is_leaf() {
                    let t1 = &self.bvh1.leaf_triangles()[a.leaf_position() as usize];
                    let t2 = &self.bvh2.leaf_triangles()[b.leaf_position() as usize];
                    lb = lb.max(shells.lower_bound_triangles(t1, t2, (t, h), need));
                }
                if lb > need {
                    self.shell_tries
                        .set((tries.saturating_add(1), successes.saturating_add(1)));
                    f64::INFINITY
                } else {
                    step
                }
            }
            _ => step,
        }
    }

    /// The distance a rotation certificate must keep a pair above over the window for the
    /// search to skip it: half the tolerance, the distance the steps are taken against (a pair
    /// never closer needs no step), or half the distance resolution where that is more. It was
    /// the whole tolerance: a 64-sided shaft of radius 0.05 turning one and a half turns in its
    /// bore, whose faces clear its corners by 0.84 tolerances (allowed either answer), crawled
    /// through 29 iterations of 17 ms each to the angle where corners face faces. (The screw's
    /// quotient still settles pairs against the whole tolerance: it is built once per query.)
    #[inline]
    fn certified_apart(&self) -> f64 {
        0.5 * self.delta.max(self.contact)
    }

    /// Switches the rotation certificates off for the rest of the query after an iteration in
    /// which they were tried on [`SHELLS_GIVE_UP`] node pairs or more and certified under one
    /// in a thousand: a close fit whose facets cross within half the tolerance as it turns (a
    /// 32-sided shaft whose corners come 0.3 tolerances from its bore's faces) fails them on
    /// nearly every pair near the contact, and the pairs are then bounded four at a time,
    /// without them (20.5 -> 10.6 ms; a 64-sided one turning one and a half turns, 16
    /// certified of 42,000 tries an iteration, 200 -> 77 ms). Only the step's length can
    /// change: the directional bound is safe on its own.
    fn give_up_shells(&mut self) {
        let (tries, successes) = self.shell_tries.get();
        if self.shells_on && successes.saturating_mul(1000) < tries && tries >= SHELLS_GIVE_UP {
            self.shells_on = false;
            self.shells_given_up = true;
        }
    }

    /// Whether the rotation certificates ([`AxisShells`]), when on, certify the triangle pair
    /// for the whole window: the last iteration's closest pair, evaluated first, would
    /// otherwise limit the step with its tangential speed though it can never meet.
    fn certified_leaves(&self, leaf1: u32, leaf2: u32) -> bool {
        match &self.shells {
            Some(shells) if self.shells_on => {
                let t1 = &self.bvh1.leaf_triangles()[leaf1 as usize];
                let t2 = &self.bvh2.leaf_triangles()[leaf2 as usize];
                let need = self.certified_apart();
                shells.lower_bound_triangles(t1, t2, (self.t, self.window), need) > need
            }
            _ => false,
        }
    }

    /// Evaluates a triangle pair: `true` when it is within the tolerance.
    fn leaf_pair(&mut self, leaf1: u32, leaf2: u32) -> bool {
        let t1 = &self.bvh1.leaf_triangles()[leaf1 as usize];
        let body2 = self.bvh2.leaf_triangles()[leaf2 as usize];
        let t2 = body2.map(|p| self.rot12 * p + self.trans12);
        let d = distance_triangle_triangle(t1, &t2);
        self.closest = self.closest.min(d.distance);
        if d.distance <= self.contact {
            return true;
        }
        let n = (d.point2 - d.point1) / d.distance;
        let s = self.step_triangles(d.distance, n, t1, &body2);
        if s < self.best {
            self.best = s;
            self.best_pair = Some((leaf1, leaf2));
        }
        false
    }

    /// Where GJK ended (two convex meshes; the default otherwise), for the cache.
    pub(crate) fn warm_simplex(&self) -> WarmSimplex {
        self.convex.as_ref().map(Gjk::warm).unwrap_or_default()
    }

    /// The iteration of two convex polytopes ([`Self::convex_step`]), or `None` where the
    /// traversal must run. Far from contact (the slab across `v`'s direction wider than
    /// `delta`, and than `delta / 2` by more than rounding, after the rounding allowance), no
    /// triangle pair can be within `delta`: the step comes from that slab, without the witness
    /// pair's search, the `distance` reported being the slab's width (a lower bound) and the
    /// pair one at GJK's last supports.
    fn convex_iteration(&mut self) -> Option<StepOutcome> {
        let (rot12, trans12) = (self.rot12, self.trans12);
        let g = self.convex.as_mut()?;
        // Far from contact a rough gap makes a step nearly as long ([`CONVEX_STEP_REL`]).
        let ended = g.run_to(&rot12, trans12, CONVEX_STEP_REL, 4.0 * self.delta)?;
        let (gap, normal) = ended.coarse();
        let rounding = gjk::ROUNDING * ended.scale;
        // Near the contact distance (`delta`, or the distances' accuracy where that is more),
        // or within rounding of `delta / 2` (where a tolerance of 1e-300 would shrink the
        // steps forever), the certified separation decides.
        if gap - rounding <= self.contact || gap - rounding - 0.5 * self.delta <= rounding {
            let s = g.certify(&ended, &rot12, trans12)?;
            return self.convex_step(&s);
        }
        let near = g.near_leaves(&ended);
        let step = self.whole_bodies_step(gap - rounding, normal);
        (step > 0.0).then(|| StepOutcome::Step {
            dt: step.min(self.window),
            pair: (step < self.window).then_some(near),
            distance: gap,
        })
    }

    /// The step certified by a gap `gap` along `n` between the two whole bodies (their roots'
    /// point sets and motion bounds).
    fn whole_bodies_step(&self, gap: f64, n: Vec3) -> f64 {
        let (a, b) = (&self.bvh1.nodes()[0], &self.bvh2.nodes()[0]);
        let (s1, s2) = (
            PointSet::node(a, self.motion1),
            PointSet::node(b, self.motion2),
        );
        self.step(gap, n, &s1, &s2)
    }

    /// The step certified by the hulls ([`Self::hull`]) and the gap it comes from: GJK's
    /// direction `n` between the hulls (roughly converged, as far from contact), and the gap
    /// along `n` between the meshes' own farthest corners (climbed on a polytope that keeps
    /// every corner of its mesh, else [`crate::bvh::Bvh::support`]), less GJK's rounding
    /// allowance. That gap separates every corner of mesh 1 from every corner of
    /// mesh 2, so every triangle pair, whatever the hulls are: the hull only proposes the
    /// direction. The step is then the whole bodies' ([`Self::whole_bodies_step`]). `(0, 0)`
    /// where there is none; the hulls overlapping drops them for the rest of the query.
    fn hull_step(&mut self) -> (f64, f64) {
        let (rot12, trans12, rot21) = (self.rot12, self.trans12, self.rot21);
        if let Hulls::Untried(m1, m2) = self.hull {
            self.hull = match (m1.outer_polytope(), m2.outer_polytope()) {
                (Some(o1), Some(o2)) => Hulls::On(
                    Gjk::new(
                        o1.mesh,
                        o1.polytope,
                        o2.mesh,
                        o2.polytope,
                        None,
                        WarmSimplex::default(),
                    ),
                    (o1.exact, o2.exact),
                ),
                _ => Hulls::Off,
            };
        }
        let Hulls::On(g, exact) = &mut self.hull else {
            return (0.0, 0.0);
        };
        let Some(ended) = g.run_to(&rot12, trans12, CONVEX_STEP_REL, 4.0 * self.delta) else {
            self.hull = Hulls::Off;
            return (0.0, 0.0);
        };
        let (_, n) = ended.coarse();
        // The farthest corners along `n`: climbed on a polytope that keeps every corner of its
        // mesh (by the hierarchy, a sphere primitive's 500 corners cost 17,000 instructions a
        // side, 37% of that Fetch pair's checks), else searched over the mesh's hierarchy.
        let climbed = if exact.0 || exact.1 {
            g.support(n, &rot12, trans12).map(|w| g.corner_points(&w))
        } else {
            None
        };
        let c1 = match climbed {
            Some((p1, _)) if exact.0 => Some(p1),
            _ => self.bvh1.support(n),
        };
        let c2 = match climbed {
            Some((_, p2)) if exact.1 => Some(p2),
            _ => self.bvh2.support(rot21 * -n),
        };
        let (Some(c1), Some(c2)) = (c1, c2) else {
            return (0.0, 0.0);
        };
        let gap = (rot12 * c2 + trans12).dot(n) - c1.dot(n) - gjk::ROUNDING * ended.scale;
        if gap <= 0.5 * self.delta {
            // Within the tolerance along the hulls' direction: the traversal decides from here.
            self.hull = Hulls::Off;
            return (0.0, 0.0);
        }
        (self.whole_bodies_step(gap, n), gap)
    }

    /// The iteration's outcome from the separation of two convex solids, without a traversal
    /// (`None` where the traversal must decide: the gap is within rounding of `delta / 2`
    /// while the witness pair is not within `delta`). The slab between the solids, of width
    /// at least [`Separation::safe_gap`] across `normal`, is a gap between all of body 1's
    /// points and all of body 2's: the step it certifies with the roots' motion bounds is safe
    /// for every triangle pair, as a node pair's gap is for the pairs below it. The witness
    /// pair's distance is a triangle pair's, so within `delta` it ends the advancement as any
    /// pair would.
    fn convex_step(&mut self, s: &Separation) -> Option<StepOutcome> {
        self.closest = s.pair.distance;
        if s.pair.distance <= self.contact {
            return Some(StepOutcome::Within {
                pair: s.leaves,
                closest: s.certifies(0.0).then_some(s.pair),
            });
        }
        // Within rounding of `delta / 2` the steps would shrink without end (a tolerance of
        // 1e-300): the traversal decides there.
        let margin = s.safe_gap() - 0.5 * self.delta;
        let step = self.whole_bodies_step(s.safe_gap(), s.normal);
        if margin <= gjk::ROUNDING * s.scale || step <= 0.0 {
            self.closest = f64::INFINITY;
            return None;
        }
        Some(if step >= self.window {
            StepOutcome::Step {
                dt: self.window,
                pair: None,
                distance: s.pair.distance,
            }
        } else {
            StepOutcome::Step {
                dt: step,
                pair: Some(s.leaves),
                distance: s.pair.distance,
            }
        })
    }

    /// Sets an iteration's state: the relative pose and the motions' bounds at time `t`,
    /// valid over `[t, t + window]`, and an empty search.
    fn begin(&mut self, t: f64, window: f64, slack: f64) {
        let ((pose1, bound1), (pose2, bound2)) = (
            BodyKinematics::at(self.motion1, t),
            BodyKinematics::at(self.motion2, t),
        );
        let pos12 = pose1.inv_mul(&pose2);
        (self.rot12, self.trans12) = (pos12.rotation, pos12.translation);
        self.rot21 = pos12.rotation.transpose();
        (self.rot1, self.rot2, self.window) = (pose1.rotation, pose2.rotation, window);
        let world_to_mesh1 = pose1.inverse();
        self.columns = ColumnPair::new(self.bvh1, self.bvh2, &pos12);
        self.kin1 = BodyKinematics::in_mesh1(bound1, &world_to_mesh1);
        self.kin2 = BodyKinematics::in_mesh1(bound2, &world_to_mesh1);
        self.t = t;
        // The large projections' record fades by half each iteration: a rule that once gave
        // up for the rest of the query (one projection that did not prune) kept them off where
        // the pairs near contact would have been pruned (docs/BENCHMARKS.md, twenty-eighth
        // session: UR5 free edges 7% fewer instructions, the knots 4 to 12%).
        self.large_projections = (self.large_projections.0 / 2, self.large_projections.1 / 2);
        self.slack = slack;
        self.best = window * (1.0 + slack);
        self.pruned = f64::INFINITY;
        self.best_pair = None;
        self.closest = f64::INFINITY;
        self.hull_floor = 0.0;
        self.shell_tries.set((0, 0));
    }

    /// One iteration at time `t`, with bounds valid over `[t, t + window]` (the step never
    /// exceeds `window`); `slack` trades step length for fewer visited pairs. Not inlined:
    /// inlined into the advancement loop it compiled to 6% more instructions (knot2.8k).
    #[inline(never)]
    pub(crate) fn run(
        &mut self,
        t: f64,
        window: f64,
        slack: f64,
        warm: Option<(u32, u32)>,
    ) -> StepOutcome {
        self.begin(t, window, slack);
        if let Some(out) = self.convex_iteration() {
            return out;
        }
        if self.shells.is_some() && !self.shells_on && !self.shells_given_up && t == self.start {
            // Decide before the first traversal, which without the certificates is the slowest
            // (a ball in its socket: 57 ms of 92), and before the warm pair, which they may
            // certify: probe the nearest pair of a dive.
            let (l1, l2) = self.dive();
            self.shells_on = self.rotation_limited(l1, l2);
        }
        if let Some((l1, l2)) = warm {
            if (l1 as usize) < self.bvh1.leaf_triangles().len()
                && (l2 as usize) < self.bvh2.leaf_triangles().len()
                && !self.certified_leaves(l1, l2)
                && self.leaf_pair(l1, l2)
            {
                return StepOutcome::Within {
                    pair: (l1, l2),
                    closest: None,
                };
            }
        }
        if let (Some(shells), true, true) = (&self.shells, self.shells_on, t == self.start) {
            // A close fit from the start: the whole-query certificate may pay.
            shells.allow_quotient();
        }
        let (nodes1, nodes2) = (self.bvh1.nodes(), self.bvh2.nodes());
        let root = RelativeRss::new(&nodes1[0].rss, &nodes2[0].rss, &self.rot12, self.trans12);
        self.stack.clear();
        self.stack.push((0, 0, self.node_step(0, 0, &root)));
        let mut pops = 0usize;
        while let Some((n1, n2, s)) = self.stack.pop() {
            pops += 1;
            // A traversal that has not ended after a few pairs asks the hulls for their step
            // (most iterations far from contact end sooner, and would only pay for GJK).
            if pops == HULL_AFTER && !matches!(self.hull, Hulls::Off) {
                let (step, gap) = self.hull_step();
                if step >= self.window {
                    return StepOutcome::Step {
                        dt: self.window,
                        pair: self.best_pair,
                        distance: gap.min(self.closest),
                    };
                }
                self.hull_floor = step;
            }
            // The hulls' step is within twice the slack of the best: take it. It is safe for
            // every pair; the rest of the traversal could lengthen the step by at most that
            // much, and costs more than the iterations a shorter step adds (HULL_EXIT).
            if self.best <= (1.0 + HULL_EXIT * self.slack) * self.hull_floor {
                return StepOutcome::Step {
                    dt: self.hull_floor,
                    pair: self.best_pair,
                    distance: self.closest,
                };
            }
            // The step returned is at most the best (or the hulls' floor, known from
            // `HULL_AFTER` pops on): under `abort_below`, the caller stops whatever it is.
            // Not while the rotation certificates are off but may come on after this
            // traversal (below), which then searches again with them.
            if self.best.max(self.hull_floor) < self.abort_below
                && (pops >= HULL_AFTER || matches!(self.hull, Hulls::Off))
                && (self.shells_on || self.shells.is_none() || self.shells_given_up)
            {
                return StepOutcome::Step {
                    dt: 0.0,
                    pair: self.best_pair,
                    distance: self.closest,
                };
            }
            if s * (1.0 + self.slack) >= self.best {
                self.pruned = self.pruned.min(s);
                continue;
            }
            let (a, b): (&Node, &Node) = (&nodes1[n1 as usize], &nodes2[n2 as usize]);
            if a.is_leaf() && b.is_leaf() {
                if self.leaf_pair(a.leaf_position(), b.leaf_position()) {
                    return StepOutcome::Within {
                        pair: (a.leaf_position(), b.leaf_position()),
                        closest: None,
                    };
                }
                continue;
            }
            if !self.shells_on {
                self.expand_lanes(n1, n2);
                continue;
            }
            // With the rotation certificates, the still side is split first: the turning
            // side's ranges are exact at every size, the still side's loosen with size.
            let split_first = match &self.shells {
                Some(sh) if self.shells_on && !a.is_leaf() && !b.is_leaf() => {
                    let (index, node, bvh, other) = if sh.turning_is_1() {
                        (n1, a, self.bvh1, b)
                    } else {
                        (n2, b, self.bvh2, a)
                    };
                    let tris = &bvh.leaf_triangles()[node.leaf_range()];
                    sh.turning_is_1() == sh.split_turning(index, tris, &other.rss)
                }
                _ => !a.is_leaf() && (b.is_leaf() || a.rss.size() >= b.rss.size()),
            };
            let children = if split_first {
                let (c1, c2) = a.children(n1);
                let side = BSide::new(&b.rss, &self.rot12, self.trans12);
                let step = |c: u32| {
                    self.node_step(
                        c,
                        n2,
                        &RelativeRss::from_b_side(&nodes1[c as usize].rss, &side),
                    )
                };
                [(c1, n2, step(c1)), (c2, n2, step(c2))]
            } else {
                let (c1, c2) = b.children(n2);
                let side = ASide::new(&a.rss, &self.rot12, self.trans12);
                let step = |c: u32| {
                    self.node_step(
                        n1,
                        c,
                        &RelativeRss::from_a_side(&side, &nodes2[c as usize].rss),
                    )
                };
                [(n1, c1, step(c1)), (n1, c2, step(c2))]
            };
            // Smaller step (more urgent) is visited first: push it last.
            let [p, q] = children;
            let (first, second) = if p.2 <= q.2 { (p, q) } else { (q, p) };
            for c in [second, first] {
                if c.2 * (1.0 + self.slack) < self.best {
                    self.stack.push(c);
                } else {
                    self.pruned = self.pruned.min(c.2);
                }
            }
        }
        self.give_up_shells();
        if let (Some(_), Some((l1, l2)), false, false) = (
            &self.shells,
            self.best_pair,
            self.shells_on,
            self.shells_given_up,
        ) {
            self.shells_on = self.rotation_limited(l1, l2);
            if self.shells_on && t == self.start {
                // A close fit from the start: the certificates may free the whole window that
                // this pair limited, so search again with them (once: they stay on), rather
                // than take the short step and grow the window back over several iterations
                // (a tapered shaft turning in its bore, whose first probe missed: 6
                // iterations, 6.4 ms). Not later: an ordinary screw's pass that turns them on
                // near its contact would pay for a second traversal (the Panda link's
                // screws, 3% more time).
                return self.run(t, window, slack, None);
            }
        }
        // Both the traversal's step and the hulls' are safe for every pair: the longer is.
        let dt = self
            .best
            .min(self.pruned)
            .min(self.window)
            .max(self.hull_floor);
        if self.hull_floor > 0.0 && dt > HULL_LOOSE * self.hull_floor {
            // The hulls are loose here (a mesh far from convex where they face): GJK would
            // only cost from now on.
            self.hull = Hulls::Off;
        }
        StepOutcome::Step {
            dt,
            pair: self.best_pair,
            distance: self.closest,
        }
    }

    /// Expands the pair `(n1, n2)` (not two leaves): both nodes split when both are internal,
    /// the child pairs bounded four at a time in lanes (as in the distance search), then each
    /// lane's step: the undirected step `(g - delta/2) / (speed1 + speed2)` from the lanes' gap
    /// `g` prunes most pairs cheaply; the survivors get the directional step along the lane's
    /// near-points axis, with the gap along that axis (the volumes' supports, or their
    /// corners' projection for small subtrees). Both steps are certified; the larger is kept.
    fn expand_lanes(&mut self, n1: u32, n2: u32) {
        let (nodes1, nodes2) = (self.bvh1.nodes(), self.bvh2.nodes());
        let Some(e) = Expansion::of(nodes1, n1, nodes2, n2) else {
            return;
        };
        let bounds = self
            .lanes
            .expansion_bounds(&e, nodes1, nodes2, &self.rot12, self.trans12);
        let keep = self.best / (1.0 + self.slack);
        let mut children = [(0u32, 0u32, 0.0f64); 4];
        let mut m = 0;
        // Each child's point set and speed once (a child is in two lanes when both split).
        let sets1 =
            e.a.map(|n| PointSet::node(&nodes1[n as usize], self.motion1));
        let sets2 =
            e.b.map(|n| PointSet::node(&nodes2[n as usize], self.motion2));
        let speeds1 = [self.speed1(&sets1[0]), self.speed1(&sets1[1])];
        let speeds2 = [self.speed2(&sets2[0]), self.speed2(&sets2[1])];
        for &k in e.lanes {
            let (c1, c2) = e.pair(k);
            let (a, b) = (&nodes1[c1 as usize], &nodes2[c2 as usize]);
            let (s1, s2) = (&sets1[k / 2], &sets2[k % 2]);
            let speed = speeds1[k / 2] + speeds2[k % 2];
            let margin = bounds.gap[k] - 0.5 * self.delta;
            let mut step = if margin <= 0.0 {
                0.0
            } else if speed <= 0.0 {
                f64::INFINITY
            } else {
                margin / speed
            };
            if step >= keep {
                self.pruned = self.pruned.min(step);
                continue;
            }
            let u = Vec3::new(bounds.axis[0][k], bounds.axis[1][k], bounds.axis[2][k]);
            if u != Vec3::ZERO {
                let gap = self.gap_along(&a.rss, &b.rss, u);
                step = step.max(self.step(gap, u, s1, s2));
                // The corners' projection, only where the volumes did not prune.
                if let (Some(c), true) = (&self.columns, step < keep) {
                    let size = a.leaf_range().len().max(b.leaf_range().len());
                    if size <= PROJECT_MAX {
                        let projected = c.gap(self.lanes, (c1, a), (c2, b), u);
                        if projected > gap {
                            step = step.max(self.step(projected, u, s1, s2));
                        }
                    } else if size <= LARGE_PROJECT_MAX {
                        step = self.large_projection((c1, a, s1), (c2, b, s2), u, gap, step, keep);
                    }
                }
            }
            if step < keep {
                children[m] = (c1, c2, step);
                m += 1;
            } else {
                self.pruned = self.pruned.min(step);
            }
        }
        let children = &mut children[..m];
        // Largest step first, so that the smallest is on top (insertion sort of at most four).
        for i in 1..children.len() {
            let mut j = i;
            while j > 0 && children[j - 1].2 < children[j].2 {
                children.swap(j - 1, j);
                j -= 1;
            }
        }
        self.stack.extend_from_slice(children);
    }

    /// The step of a lane whose larger subtree is above [`PROJECT_MAX`], raised by projecting
    /// the corners on `u` while such projections pay in this search ([`LARGE_PROJECT_MAX`]).
    /// Kept out of line: most lanes never get here.
    #[inline(never)]
    fn large_projection(
        &mut self,
        (c1, a, s1): (u32, &Node, &PointSet),
        (c2, b, s2): (u32, &Node, &PointSet),
        u: Vec3,
        gap: f64,
        step: f64,
        keep: f64,
    ) -> f64 {
        let (tries, prunes) = self.large_projections;
        let Some(c) = &self.columns else {
            return step;
        };
        if tries > 0 && prunes * LARGE_PROJECT_RATIO < tries {
            return step;
        }
        let projected = c.gap(self.lanes, (c1, a), (c2, b), u);
        let step = if projected > gap {
            step.max(self.step(projected, u, s1, s2))
        } else {
            step
        };
        self.large_projections = (tries + 1, prunes + usize::from(step >= keep));
        step
    }

    /// The gap between volumes `a` (mesh 1) and `b` (mesh 2) along the unit `u` (mesh 1's
    /// frame): `u . (centre_b - centre_a)` less both volumes' supports along `u`.
    #[inline]
    fn gap_along(&self, a: &crate::bvh::Rss, b: &crate::bvh::Rss, u: Vec3) -> f64 {
        let cb = self.rot12 * b.center + self.trans12;
        u.dot(cb - a.center) - a.support(u) - b.support(self.rot21 * u)
    }

    /// A nearby triangle pair (leaf positions) at the current time: from the roots, always into
    /// the child pair of smallest separation.
    fn dive(&self) -> (u32, u32) {
        let (nodes1, nodes2) = (self.bvh1.nodes(), self.bvh2.nodes());
        let (mut n1, mut n2) = (0u32, 0u32);
        loop {
            let (a, b) = (&nodes1[n1 as usize], &nodes2[n2 as usize]);
            if a.is_leaf() && b.is_leaf() {
                return (a.leaf_position(), b.leaf_position());
            }
            let pairs = if !a.is_leaf() && (b.is_leaf() || a.rss.size() >= b.rss.size()) {
                let (c1, c2) = a.children(n1);
                [(c1, n2), (c2, n2)]
            } else {
                let (c1, c2) = b.children(n2);
                [(n1, c1), (n1, c2)]
            };
            // The nearer pair by its volumes' gap, and where both overlap (a close fit, all
            // the way down) by their centres' distance: always taking the first child there
            // ended a tube's dive on the far side of its bore, whose pair the rotation does not
            // limit, and the first traversal ran without the certificates (a taper in its bore
            // 0.8 -> 3.5 ms with its triangles in another order).
            let gap = |(i, j): (u32, u32)| {
                let (a, b) = (&nodes1[i as usize].rss, &nodes2[j as usize].rss);
                let rel = RelativeRss::new(a, b, &self.rot12, self.trans12);
                let apart = a
                    .center
                    .distance_squared(self.rot12 * b.center + self.trans12);
                (rss_separation(a, b, &rel, f64::INFINITY).0, apart)
            };
            (n1, n2) = if gap(pairs[0]) <= gap(pairs[1]) {
                pairs[0]
            } else {
                pairs[1]
            };
        }
    }

    /// Whether the step of the triangle pair that limited this iteration is bound by the spread
    /// of its triangles under rotation (the `|n x w| (R + |w| h rho)` terms of the windowed
    /// bound) more than by the velocity of their centres along the gap: a body turning in a
    /// close fit, which the rotation certificates serve.
    fn rotation_limited(&self, leaf1: u32, leaf2: u32) -> bool {
        let (Path::Rigid(motion1), Path::Rigid(motion2)) = (self.motion1, self.motion2) else {
            return false;
        };
        let t1 = &self.bvh1.leaf_triangles()[leaf1 as usize];
        let body2 = self.bvh2.leaf_triangles()[leaf2 as usize];
        let t2 = body2.map(|p| self.rot12 * p + self.trans12);
        let d = distance_triangle_triangle(t1, &t2);
        if d.distance <= 0.0 {
            return false;
        }
        let n = self.rot1 * ((d.point2 - d.point1) / d.distance);
        let parts = |m: &Motion, n: Vec3, rot: &Mat3, s: &PointSet| {
            let whole = m.directional_bound_window(n, rot, s.center, s.radius, self.window);
            let centre = m.directional_bound_window(n, rot, s.center, 0.0, 0.0);
            (centre, whole - centre)
        };
        let (s1, s2) = (
            PointSet::triangle(t1, self.motion1),
            PointSet::triangle(&body2, self.motion2),
        );
        let (c1, spread1) = parts(motion1, n, &self.rot1, &s1);
        let (c2, spread2) = parts(motion2, -n, &self.rot2, &s2);
        spread1 + spread2 > 4.0 * (c1 + c2).max(0.0)
    }
}

/// `max (p - c) . g` over the triangle `t`'s points `p`: over its corners, since a linear
/// function is largest at a corner.
#[inline]
fn triangle_reach(t: &[Vec3; 3], c: Vec3, g: Vec3) -> f64 {
    (t[0] - c)
        .dot(g)
        .max((t[1] - c).dot(g))
        .max((t[2] - c).dot(g))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::sampling::{rss_point, unit};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random rigid pose: an axis, an angle up to 3 rad, a translation up to 3.
    fn random_pose(rng: &mut ChaCha8Rng) -> Pose {
        Pose::from_axis_angle(
            unit(rng),
            rng.random_range(-3.0..3.0),
            unit(rng) * rng.random_range(0.0..3.0),
        )
    }

    /// A random window `[t, t + h]` of `motion`, its rotation at `t` and its kinematics read in
    /// the body's own frame, as the search reads mesh 1.
    fn random_window(rng: &mut ChaCha8Rng, motion: &Motion) -> (f64, f64, Mat3, Kinematics) {
        let t = rng.random_range(0.0..0.9);
        let h = rng.random_range(0.001..(1.0 - t));
        let rot = motion.pose_at(t).rotation;
        (t, h, rot, Kinematics::new(motion, &rot.transpose()))
    }

    /// Asserts that the body point `p`'s true speed along the world direction `n` (forward
    /// differences of the motion's poses) at a random time of `[t, t + h]` is within `bound`.
    fn assert_within_bound(
        rng: &mut ChaCha8Rng,
        motion: &Motion,
        (t, h): (f64, f64),
        (n, p): (Vec3, Vec3),
        bound: f64,
        case: usize,
    ) {
        let s = t + h * rng.random_range(0.0..1.0);
        let eps = 1e-7;
        let speed = n
            .dot(motion.pose_at(s + eps).transform_point(p) - motion.pose_at(s).transform_point(p))
            / eps;
        assert!(
            speed <= bound + 1e-4 * (1.0 + bound.abs()),
            "case {case}: speed {speed} along n above the bound {bound}"
        );
    }

    /// The rigid bound the step search uses, with a volume's support in place of its bounding
    /// radius, against the true speed of points on the corners, edges and inside of random
    /// swept rectangles, over random windows of translations, interps and screws.
    #[test]
    fn rigid_bound_holds_over_swept_rectangles() {
        let mut rng = ChaCha8Rng::seed_from_u64(31);
        let mut checked = 0;
        for case in 0..600 {
            let (a, b) = (random_pose(&mut rng), random_pose(&mut rng));
            let c = unit(&mut rng) * rng.random_range(0.0..1.5);
            let motion = match case % 3 {
                0 => Motion::translation(
                    a,
                    Pose {
                        rotation: a.rotation,
                        translation: b.translation,
                    },
                ),
                1 => Motion::interp(a, b, c),
                _ => Motion::screw(a, b),
            }
            .expect("motion");
            let (t, h, rot, kin) = random_window(&mut rng, &motion);
            // The volume, body frame.
            let center = unit(&mut rng) * rng.random_range(0.0..2.0);
            let e1 = unit(&mut rng);
            let e2 = e1.cross(unit(&mut rng)).normalize();
            let (h1, h2, r) = (
                rng.random_range(0.0..0.5),
                rng.random_range(0.0..0.5),
                rng.random_range(0.0..0.2),
            );
            let rss = Rss {
                axes: Mat3::from_cols(e1, e2, e1.cross(e2)),
                center,
                half_lengths: [h1, h2],
                radius: r,
            };
            let set = PointSet::volume(&rss, Path::Rigid(&motion));
            let m = unit(&mut rng);
            let bound = kin.bound(
                m,
                set.center - kin.axis_point,
                |g| set.spread().support(g),
                set.rho,
                h,
            );
            for _ in 0..30 {
                let p = rss_point(&mut rng, center, (e1, e2), (h1, h2), r);
                assert_within_bound(&mut rng, &motion, (t, h), (rot * m, p), bound, case);
                checked += 1;
            }
        }
        assert_eq!(checked, 18_000);
    }

    /// The same bound with a triangle's reach over its corners ([`triangle_reach`], what
    /// [`StepSearch::step_triangles`] charges), against the true speed of points on the
    /// corners, edges and inside of random triangles up to 100 times longer than wide, over
    /// random windows of interps, screws and turns.
    #[test]
    fn rigid_bound_holds_over_long_triangles() {
        let mut rng = ChaCha8Rng::seed_from_u64(32);
        let mut checked = 0;
        for case in 0..600 {
            let (a, b) = (random_pose(&mut rng), random_pose(&mut rng));
            let motion = match case % 3 {
                0 => Motion::interp(a, b, unit(&mut rng) * rng.random_range(0.0..1.5)),
                1 => Motion::screw(a, b),
                _ => Motion::turn(
                    a,
                    unit(&mut rng),
                    unit(&mut rng) * rng.random_range(0.1..20.0),
                ),
            }
            .expect("motion");
            let (t, h, rot, kin) = random_window(&mut rng, &motion);
            // A long triangle: a base corner, one far along `u`, one a little across.
            let base = unit(&mut rng) * rng.random_range(0.0..2.0);
            let u = unit(&mut rng);
            let long = rng.random_range(0.1..2.0);
            let across = long * rng.random_range(0.01..0.5);
            let v = u.cross(unit(&mut rng)).normalize();
            let tri = [
                base,
                base + u * long,
                base + u * rng.random_range(0.0..long) + v * across,
            ];
            let set = PointSet::triangle(&tri, Path::Rigid(&motion));
            let m = unit(&mut rng);
            let bound = kin.bound(
                m,
                set.center - kin.axis_point,
                |g| triangle_reach(&tri, set.center, g),
                set.rho,
                h,
            );
            for k in 0..30 {
                let (x, y) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
                let (x, y) = if x + y > 1.0 {
                    (1.0 - x, 1.0 - y)
                } else {
                    (x, y)
                };
                let p = match k {
                    0..=2 => tri[k],
                    3..=5 => tri[k - 3].lerp(tri[(k - 2) % 3], x),
                    _ => tri[0] + (tri[1] - tri[0]) * x + (tri[2] - tri[0]) * y,
                };
                assert_within_bound(&mut rng, &motion, (t, h), (rot * m, p), bound, case);
                checked += 1;
            }
        }
        assert_eq!(checked, 18_000);
    }

    /// The hulls' step between spheres convex but for their triangulation (every corner on the
    /// hull: the farthest corners are climbed on the hulls), one with a triangle inside it
    /// (the hull lacks its corners: they are searched on the mesh), and a convex mesh (its own
    /// polytope): its gap is a lower bound of the meshes' distance and within 10% of it (GJK
    /// stops once its gap is within [`CONVEX_STEP_REL`] of its bound, far from contact), and
    /// over the step no pair comes within `delta / 2` (sampled), on passes of every motion
    /// kind.
    #[test]
    fn the_hulls_step_is_safe_and_tight() {
        use crate::mesh::hull_tests::dented_sphere;
        use crate::query::distance::{distance, DistanceOptions};
        let inner = {
            let s = dented_sphere(3);
            let mut v = s.vertices().to_vec();
            let mut t = s.triangles().to_vec();
            let k = v.len() as u32;
            v.extend([
                Vec3::new(0.3, 0.0, 0.0),
                Vec3::new(0.0, 0.3, 0.1),
                Vec3::ZERO,
            ]);
            t.push([k, k + 1, k + 2]);
            TriMesh::new(v, t).expect("a sphere with a triangle inside")
        };
        let ball = crate::mesh::sphere(1.0, 6, 10).expect("sphere");
        let pairs = [
            (dented_sphere(1), dented_sphere(2), (true, true)),
            (inner, dented_sphere(2), (false, true)),
            (ball, dented_sphere(1), (true, true)),
        ];
        let mut rng = ChaCha8Rng::seed_from_u64(43);
        let delta = 1e-3;
        let mut steps = 0;
        for case in 0..90 {
            let (a, b, exact) = &pairs[case / 30];
            let dir = unit(&mut rng);
            let turn = |rng: &mut ChaCha8Rng, at: Vec3| {
                Pose::from_axis_angle(unit(rng), rng.random_range(-1.0..1.0), at)
            };
            let start = turn(&mut rng, Vec3::ZERO);
            let apart = rng.random_range(2.05..4.0);
            let reach = apart * rng.random_range(0.3..1.2);
            let end = turn(&mut rng, dir * reach);
            let m1 = match case % 3 {
                0 => Motion::translation(
                    start,
                    Pose {
                        rotation: start.rotation,
                        translation: end.translation,
                    },
                ),
                1 => Motion::interp(start, end, unit(&mut rng) * 0.2),
                _ => Motion::screw(start, end),
            }
            .expect("motion");
            let m2 = Motion::stationary(turn(&mut rng, dir * apart));
            let mut search = StepSearch::new(
                a,
                Path::Rigid(&m1),
                b,
                Path::Rigid(&m2),
                (delta, delta),
                WarmSimplex::default(),
            );
            search.begin(0.0, 1.0, 0.1);
            let (step, gap) = search.hull_step();
            assert!(
                matches!(search.hull, Hulls::On(_, e) if e == *exact),
                "case {case}: not the hulls expected"
            );
            let at = |t: f64| {
                distance(
                    a,
                    &m1.pose_at(t),
                    b,
                    &m2.pose_at(t),
                    &DistanceOptions::default(),
                )
                .expect("distance")
                .distance
            };
            let d = at(0.0);
            assert!(
                gap <= d && gap >= 0.9 * d,
                "case {case}: gap {gap}, distance {d}"
            );
            assert!(step > 0.0, "case {case}: no step at distance {d}");
            for k in 0..=100 {
                let t = step.min(1.0) * f64::from(k) / 100.0;
                assert!(
                    at(t) >= 0.5 * delta,
                    "case {case}: within delta/2 at {t} < {step}"
                );
            }
            steps += 1;
        }
        assert_eq!(steps, 90);
    }

    /// The first step of a search that stops under `abort_below` (a robot's frozen check:
    /// `Span::least_first_step`): stopped (a step of 0) only where the whole search's step is
    /// under the threshold, and otherwise the whole search's outcome, on shafts turning in
    /// close bores (the rotation certificates), knots passing each other and balls dropped on
    /// plates, at thresholds around the whole search's step.
    #[test]
    fn a_search_stops_early_only_where_its_step_is_short() {
        use crate::mesh::{plate, revolved, sphere, torus_knot};
        let mut rng = ChaCha8Rng::seed_from_u64(50);
        let still = Motion::stationary(Pose::IDENTITY);
        let knot = torus_knot(60, 12).expect("knot");
        let (mut stopped, mut finished) = (0, 0);
        for case in 0..90 {
            let sides = rng.random_range(16..48);
            let clear = rng.random_range(1e-4..3e-3);
            let (a, b, motion) = match case % 3 {
                0 => (
                    revolved(|_, _| 1.0, 2.0, sides, 3).expect("shaft"),
                    revolved(move |_, _| 1.0 + clear, 3.0, sides, 3).expect("bore"),
                    Motion::turn(
                        Pose::IDENTITY,
                        Vec3::ZERO,
                        Vec3::Z * rng.random_range(0.5..9.0),
                    )
                    .expect("turn"),
                ),
                1 => (
                    knot.clone(),
                    knot.clone(),
                    Motion::interp(
                        Pose::from_axis_angle(unit(&mut rng), 0.5, Vec3::new(-12.0, 0.5, 0.0)),
                        Pose::from_axis_angle(unit(&mut rng), 0.5, Vec3::new(12.0, -0.5, 0.0)),
                        Vec3::ZERO,
                    )
                    .expect("pass"),
                ),
                _ => (
                    sphere(0.3, 8, 16).expect("ball"),
                    plate(2.0, 8).expect("plate"),
                    Motion::translation(
                        Pose::from_axis_angle(Vec3::Z, 0.0, Vec3::new(0.0, 0.0, 0.5)),
                        Pose::from_axis_angle(Vec3::Z, 0.0, Vec3::new(0.1, 0.0, -0.5)),
                    )
                    .expect("drop"),
                ),
            };
            let delta = clear * rng.random_range(0.5..4.0);
            let search = |abort: f64| {
                let path = (Path::Rigid(&motion), Path::Rigid(&still));
                let mut s = StepSearch::new(
                    &a,
                    path.0,
                    &b,
                    path.1,
                    (delta, delta),
                    WarmSimplex::default(),
                );
                s.abort_below = abort;
                match s.run(0.0, 1.0, 0.25, None) {
                    StepOutcome::Step { dt, .. } => Some(dt),
                    StepOutcome::Within { .. } => None,
                }
            };
            let Some(whole) = search(0.0) else {
                continue;
            };
            assert!(whole > 0.0, "case {case}: a free start steps");
            let abort = whole * rng.random_range(0.5..2.0);
            match search(abort) {
                Some(0.0) => {
                    assert!(
                        whole < abort,
                        "case {case}: stopped, its step {whole} >= {abort}"
                    );
                    stopped += 1;
                }
                got => {
                    assert_eq!(got, Some(whole), "case {case}: not stopped, another step");
                    finished += 1;
                }
            }
        }
        assert!(
            stopped >= 10 && finished >= 10,
            "{stopped} stopped, {finished} finished"
        );
    }
}

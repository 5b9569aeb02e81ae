//! The planner's queries on a straight joint-space segment `q(t) = q0 + t (q1 - q0)`:
//! [`time_of_contact`], [`path_is_free`], [`check_configurations`], and their batches.
//!
//! # How a segment is checked
//!
//! 1. **Pairs.** The robot's self pairs (see [`Robot`]) and every (robot object, obstacle) pair.
//! 2. **Swept volumes (temporal culling).** A binary subdivision of `[0, 1]`, down to
//!    [`RobotOptions::cull_depth`] levels (pieces of 1/16 by default), evaluated only where
//!    needed. On a piece `[ta, tb]` an object lies within `v (tb - ta) / 2` of where it is at the
//!    middle time, `v` its largest speed over the segment (the chain bound of `chain.rs`), so if
//!    the two root volumes at the middle time are farther apart than the two growths plus
//!    `delta` (the gap of their world boxes along a world axis, a few comparisons, else the RSS
//!    separating-axis bound), the pair cannot come within `delta` on that piece and the piece
//!    is dropped. When no axis separates the two volumes at the middle time, the whole piece
//!    is kept without splitting it: measured on the MotionBenchMaker Panda bench's 1,470 edges,
//!    the finer tests then culled almost nothing (self pairs on `table_under_pick`: none of
//!    112 tests per edge below the second level), and keeping the piece took 13% fewer
//!    instructions on free edges, 20% on colliding ones, 5% on start-goal edges. Each node's
//!    forward kinematics and placed volumes are computed once and shared by every pair. An
//!    object walks the tree once for all obstacles, carrying down only the obstacles still in
//!    play (one walk per pair cost 3 to 6% more instructions on the Panda and UR5 benches). For
//!    two links the speeds are relative to the deepest body both hang from (the joints they
//!    share move both alike). The finest pieces that remain, merged, are the pair's spans.
//! 3. **Advancement.** Each pair runs the rigid core's conservative advancement (the same step
//!    search, with the chain bound in place of the rigid one) over each of its spans, earliest
//!    span first. For the time of contact, a span that starts after the earliest contact found
//!    so far is skipped and the others stop there; [`path_is_free`] stops at the first contact,
//!    and first probes every candidate pair with exact collision tests at the end and middle
//!    of its spans (a collision found there is real).
//!
//! The answer has the semantics of the rigid query, pair by pair: a contact is reported
//! whenever some checked pair comes closer than `delta / 2` (in particular whenever one
//! collides), never when every pair stays farther apart than `delta`, and the time returned is
//! no later than the first collision.

mod frozen;

use std::sync::Arc;

use super::{chain::ChainPath, Robot, RobotError};
use crate::bvh::{rss_separation, RelativeRss, Rss};
use crate::math::{Pose, Vec3};
use crate::motion::Motion;
use crate::query::collide::collide;
use crate::query::contact_time::probe::{advance_probed, probe_span, Probed, PROBE_AFTER};
use crate::query::contact_time::{
    advance_paths, finish, ContactCache, ContactStatus, Path, Span, Witnesses, NORMAL_RESOLUTION,
};
use crate::TriMesh;

/// The first iteration of a pair's advancement takes its bounds over this fraction of the
/// span: pairs whose step exceeds the window are not visited, and over a shorter window the
/// chain bound is tighter. Measured on the MotionBenchMaker Panda box scene (300 random 0.5 rad
/// edges, `examples/profile_robot.rs`): median free edge 90 us at 1, 45-51 us at 0.5, 48-68 us
/// at 0.25 and below (noisy).
const FIRST_WINDOW: f64 = 0.5;

/// Step slack far from contact and near it (see the rigid query's module docs). Links sweeping
/// past large flat obstacles (shelf walls) have hundreds of triangle pairs with nearly the same
/// step, which an exact search must all visit; a larger far slack takes a shorter step instead.
/// Same measurement, far slack 0.25 / 0.5 / 1 / 2 / 4 / 8: 90th percentile of free edges 370 /
/// 291 / 243 / 195 / 168 / 161 us, colliding medians 298 / 200 / 178 / 150 / 133 / 105 us,
/// free medians 45-49 us throughout.
const FAR_SLACK: f64 = 4.0;
const NEAR_SLACK: f64 = 0.3;

/// Static obstacles the robot is checked against.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    obstacles: Vec<Obstacle>,
}

/// One obstacle: a named mesh at a world pose.
#[derive(Clone, Debug)]
pub struct Obstacle {
    /// Its name (reported in contacts).
    pub name: String,
    /// The mesh (shared: many obstacles may use one mesh).
    pub mesh: Arc<TriMesh>,
    /// Its world pose.
    pub pose: Pose,
    /// Its root volume in the world.
    volume: WorldVolume,
    /// Its motion (stationary), for the advancement.
    motion: Motion,
}

impl Scene {
    /// An empty scene.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds an obstacle.
    pub fn add(&mut self, name: &str, mesh: Arc<TriMesh>, pose: Pose) {
        self.obstacles.push(Obstacle {
            name: name.to_string(),
            motion: Motion::stationary(pose),
            volume: WorldVolume::new(&mesh, &pose),
            mesh,
            pose,
        });
    }

    /// The obstacles.
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }
}

/// Options of the robot queries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobotOptions {
    /// Distance tolerance `delta` (model units, > 0). `None`: `1e-3` times the smallest
    /// bounding radius among the robot's collision objects. As for two bodies, a pair within
    /// the distances' accuracy ([`crate::query::contact_time::DISTANCE_RESOLUTION`] of the
    /// pair's scale) is a contact even where `delta` is smaller.
    pub tolerance: Option<f64>,
    /// Iteration cap of each pair's advancement (>= 1). Default 1000.
    pub max_iterations: usize,
    /// Levels of the binary time subdivision of the culling (module docs; 0 to 20): pieces of
    /// `2^-cull_depth` of the segment at the finest. Default 4. Measured on MotionBenchMaker's
    /// Panda: depth 3 checks random 0.5 rad edges with 0.2 to 17% fewer instructions, but
    /// start-to-goal edges (long, colliding half way) 2 to 4 times slower in three of seven
    /// scenarios: the probes at the spans' ends and middles move with the depth, and where
    /// none lands in the collision the advancement has to converge to it (docs/BENCHMARKS.md,
    /// tenth session).
    pub cull_depth: u32,
    /// Which points a contact reports, as the rigid query's ([`Witnesses`]): by default the two
    /// objects' closest points at the time; [`Witnesses::Contact`] those of the triangle pair
    /// that ended the pair's advancement, without the final exact distance query.
    pub witnesses: Witnesses,
}

impl Default for RobotOptions {
    fn default() -> Self {
        Self {
            tolerance: None,
            max_iterations: 1000,
            cull_depth: 4,
            witnesses: Witnesses::Closest,
        }
    }
}

/// Where and when the robot first comes within the tolerance of itself or an obstacle.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotContact {
    /// Time in `[0, 1]` along the segment, no later than the first collision.
    pub time: f64,
    /// The robot object (link or attached object) of the pair.
    pub object1: String,
    /// The other object: a robot link (self-collision) or an obstacle.
    pub object2: String,
    /// Whether `object2` is part of the robot.
    pub self_collision: bool,
    /// Point of `object1`, world frame: the objects' closest, or the contact pair's
    /// ([`RobotOptions::witnesses`]).
    pub point1: Vec3,
    /// Point of `object2`, world frame, as `point1`.
    pub point2: Vec3,
    /// Unit normal from `object1` to `object2`, world frame (rules of the rigid query).
    pub normal: Vec3,
    /// Distance between `point1` and `point2` (model units, >= 0, at most the tolerance): the
    /// objects' distance at `time` (with [`Witnesses::Contact`], at least it).
    pub distance: f64,
    /// Advancement iterations of the pair that made the contact.
    pub iterations: usize,
    /// [`ContactStatus::StartedInContact`] when in contact at `q0`.
    pub status: ContactStatus,
}

/// A pair to check: robot object `a` and either robot object `b` or obstacle `b`.
#[derive(Clone, Copy, Debug)]
struct Pair {
    a: usize,
    b: usize,
    obstacle: bool,
}

/// Everything one segment needs, built once per query.
struct Segment<'r> {
    robot: &'r Robot,
    scene: &'r Scene,
    v0: Vec<f64>,
    v1: Vec<f64>,
    /// Each object's world path.
    paths: Vec<ChainPath<'r>>,
    /// Each object's world path as a rigid motion, where it is one ([`ChainPath::rigid`]).
    rigid: Vec<Option<Motion>>,
    delta: f64,
    max_iterations: usize,
    /// Levels of the binary time subdivision used by the culling.
    depth: u32,
    /// Which points a contact reports.
    witnesses: Witnesses,
}

/// The robot's body poses and its objects' root volumes in the world at the middle of each
/// culling interval, computed on first use (heap order: node 1 is `[0, 1]`, node `k` has
/// children `2k` and `2k + 1`). Flat arrays filled as needed, so a query allocates a few
/// buffers rather than some per node.
struct VolumeCache {
    /// Per node, where its body poses start in `poses` (`NONE` until computed).
    pose_at: Vec<u32>,
    poses: Vec<Pose>,
    /// Per node and object (`node * objects + object`), its index in `volumes` (`NONE` until
    /// computed).
    volume_at: Vec<u32>,
    volumes: Vec<WorldVolume>,
    /// Joint values at the node being posed.
    q: Vec<f64>,
    /// Per node and joint (`node * joints + joint`), the sine and cosine of the joint's value
    /// at the node's middle, filled when the node is posed.
    trig: Vec<(f64, f64)>,
    /// Per level `L >= 1` and joint (`(L - 1) * joints + joint`), the sine and cosine of the
    /// joint's change over `2^-(L+1)` of the segment: a node's middle is its parent's moved by
    /// that much, so its sines and cosines follow from its parent's by the angle-addition
    /// formulas (one `sin_cos` per joint and level instead of per joint and node).
    level_trig: Vec<(f64, f64)>,
}

const NONE: u32 = u32::MAX;

/// A mesh's root volume placed in the world, with the world box that contains it.
#[derive(Clone, Copy, Debug)]
struct WorldVolume {
    /// The root RSS with world axes and centre.
    rss: Rss,
    /// Its world box (min, max corners).
    bounds: (Vec3, Vec3),
}

impl WorldVolume {
    fn new(mesh: &TriMesh, pose: &Pose) -> Self {
        let root = mesh.bvh().root();
        let rss = Rss {
            axes: pose.rotation * root.axes,
            center: pose.transform_point(root.center),
            ..*root
        };
        let ext = rss.axes.x_axis.abs() * rss.half_lengths[0]
            + rss.axes.y_axis.abs() * rss.half_lengths[1]
            + Vec3::splat(rss.radius);
        Self {
            rss,
            bounds: (rss.center - ext, rss.center + ext),
        }
    }

    /// A lower bound on the distance between the two volumes, exact enough to compare with
    /// `reach`: their boxes' gap along a world axis when it exceeds `reach` (a few comparisons,
    /// and most culled pairs stop there), else the RSS separating-axis bound (which may stop
    /// early once it exceeds `reach`). At most 0 when no axis separates them.
    #[inline]
    fn separation(&self, other: &Self, reach: f64) -> f64 {
        let (a, b) = (&self.bounds, &other.bounds);
        let gap = (a.0 - b.1).max(b.0 - a.1).max_element();
        if gap > reach {
            return gap;
        }
        self.rss_separation(other, reach)
    }

    /// The RSS separating-axis part of [`WorldVolume::separation`].
    #[inline(never)]
    fn rss_separation(&self, other: &Self, reach: f64) -> f64 {
        let rel = RelativeRss::in_common_frame(&self.rss, &other.rss);
        rss_separation(&self.rss, &other.rss, &rel, reach).0
    }
}

fn check_options(options: &RobotOptions) -> Result<(), RobotError> {
    use crate::OptionsError;
    if let Some(t) = options.tolerance {
        if !(t.is_finite() && t > 0.0) {
            return Err(crate::ContactError::Options(OptionsError::OutOfRange {
                name: "tolerance",
                requirement: "must be positive and finite",
                value: t,
            })
            .into());
        }
    }
    if options.max_iterations == 0 {
        return Err(crate::ContactError::Options(OptionsError::OutOfRange {
            name: "max_iterations",
            requirement: "must be at least 1",
            value: 0.0,
        })
        .into());
    }
    if options.cull_depth > 20 {
        return Err(crate::ContactError::Options(OptionsError::OutOfRange {
            name: "cull_depth",
            requirement: "must be at most 20",
            value: options.cull_depth as f64,
        })
        .into());
    }
    Ok(())
}

/// The tolerance the robot queries use with these options.
pub fn robot_tolerance(robot: &Robot, options: &RobotOptions) -> f64 {
    options.tolerance.unwrap_or_else(|| {
        let r = robot
            .objects
            .iter()
            .map(|o| o.mesh.bounding_radius())
            .fold(f64::INFINITY, f64::min);
        if r.is_finite() && r > 0.0 {
            1e-3 * r
        } else {
            1e-9
        }
    })
}

impl<'r> Segment<'r> {
    fn new(
        robot: &'r Robot,
        q0: &[f64],
        q1: &[f64],
        scene: &'r Scene,
        options: &RobotOptions,
    ) -> Result<Self, RobotError> {
        check_options(options)?;
        robot.check_configuration(q0, "q0")?;
        robot.check_configuration(q1, "q1")?;
        let (v0, v1) = (robot.joint_values(q0), robot.joint_values(q1));
        let paths = (0..robot.objects.len())
            .map(|o| robot.object_path(o, &v0, &v1, 0))
            .collect::<Vec<_>>();
        let rigid = paths.iter().map(ChainPath::rigid).collect();
        Ok(Self {
            robot,
            scene,
            v0,
            v1,
            paths,
            rigid,
            delta: robot_tolerance(robot, options),
            max_iterations: options.max_iterations,
            depth: options.cull_depth,
            witnesses: options.witnesses,
        })
    }

    /// An empty culling cache for this segment.
    fn volume_cache(&self) -> VolumeCache {
        let nodes = 2 << self.depth;
        VolumeCache {
            pose_at: vec![NONE; nodes],
            poses: Vec::with_capacity(nodes * self.robot.bodies.len()),
            volume_at: vec![NONE; nodes * self.robot.objects.len()],
            volumes: Vec::with_capacity(nodes * self.robot.objects.len()),
            q: Vec::new(),
            trig: vec![(0.0, 1.0); nodes * self.v0.len()],
            level_trig: (1..=self.depth as i32)
                .flat_map(|level| {
                    let h = 0.5_f64.powi(level + 1);
                    self.v0
                        .iter()
                        .zip(&self.v1)
                        .map(move |(a, b)| (h * (b - a)).sin_cos())
                })
                .collect(),
        }
    }

    /// Robot object `object`'s world volume at the middle of culling node `node`: its index
    /// in `cache.volumes`, computed (with the node's body poses) on first use.
    fn volume(&self, cache: &mut VolumeCache, node: usize, mid: f64, object: usize) -> usize {
        let objects = &self.robot.objects;
        let slot = node * objects.len() + object;
        if cache.volume_at[slot] != NONE {
            return cache.volume_at[slot] as usize;
        }
        if cache.pose_at[node] == NONE {
            cache.q.clear();
            let values = self.v0.iter().zip(&self.v1);
            cache.q.extend(values.map(|(a, b)| a + mid * (b - a)));
            let joints = self.v0.len();
            let parent = node / 2;
            let here = node * joints;
            if node > 1 && cache.pose_at[parent] != NONE {
                let level = (usize::BITS - 1 - node.leading_zeros()) as usize;
                // Left children lie before their parent's middle, right ones after.
                let sign = if node % 2 == 0 { -1.0 } else { 1.0 };
                for j in 0..joints {
                    let (sp, cp) = cache.trig[parent * joints + j];
                    let (sd, cd) = cache.level_trig[(level - 1) * joints + j];
                    let sd = sign * sd;
                    cache.trig[here + j] = (sp * cd + cp * sd, cp * cd - sp * sd);
                }
            } else {
                for (j, q) in cache.q.iter().enumerate() {
                    cache.trig[here + j] = q.sin_cos();
                }
            }
            let start = cache.poses.len();
            cache
                .poses
                .resize(start + self.robot.bodies.len(), Pose::IDENTITY);
            self.robot.body_poses_into(
                &cache.q,
                &cache.trig[here..here + joints],
                &mut cache.poses[start..],
            );
            cache.pose_at[node] = start as u32;
        }
        let o = &objects[object];
        let pose = &cache.poses[cache.pose_at[node] as usize + o.body];
        cache.volumes.push(WorldVolume::new(&o.mesh, pose));
        cache.volume_at[slot] = (cache.volumes.len() - 1) as u32;
        cache.volumes.len() - 1
    }

    /// The spans of `[ta, tb]` (culling node `node` at `level`) where the pair's swept volumes
    /// may meet, appended to `out` (adjacent spans merged).
    #[allow(clippy::too_many_arguments)]
    fn spans(
        &self,
        pair: Pair,
        speeds: (f64, f64),
        cache: &mut VolumeCache,
        node: usize,
        level: u32,
        ta: f64,
        tb: f64,
        out: &mut Vec<(f64, f64)>,
    ) {
        let mid = 0.5 * (ta + tb);
        let half = 0.5 * (tb - ta);
        let a = self.volume(cache, node, mid, pair.a);
        let (b, grow_b) = if pair.obstacle {
            (&self.scene.obstacles[pair.b].volume, 0.0)
        } else {
            let b = self.volume(cache, node, mid, pair.b);
            (&cache.volumes[b], speeds.1 * half)
        };
        let reach = speeds.0 * half + grow_b + self.delta;
        let gap = cache.volumes[a].separation(b, reach);
        if gap > reach {
            return;
        }
        // Volumes that overlap at the middle time keep the whole piece: their halves, a
        // quarter of it away, overlap too or nearly (a link and the next-but-one link, a hand
        // over a table), so splitting costs forward kinematics and tests that cull nothing.
        if level == self.depth || gap <= 0.0 {
            match out.last_mut() {
                Some(last) if last.1 == ta => last.1 = tb,
                _ => out.push((ta, tb)),
            }
            return;
        }
        self.spans(pair, speeds, cache, 2 * node, level + 1, ta, mid, out);
        self.spans(pair, speeds, cache, 2 * node + 1, level + 1, mid, tb, out);
    }

    /// The spans of `[ta, tb]` (culling node `node` at `level`) where robot object `a`'s swept
    /// volume may meet each obstacle of `alive[from..]`, appended to `out` (a span adjacent to
    /// the obstacle's last one, `last[b]`, extends it). One walk down the time tree serves all
    /// obstacles: the object's volume at a node is tested against every obstacle still in
    /// play, and only those neither culled nor kept whole go down to the children.
    #[allow(clippy::too_many_arguments)]
    fn obstacle_spans(
        &self,
        a: usize,
        speed: f64,
        cache: &mut VolumeCache,
        (node, level, ta, tb): (usize, u32, f64, f64),
        alive: &mut Vec<u32>,
        from: usize,
        last: &mut [usize],
        out: &mut Vec<(f64, f64, Pair)>,
    ) {
        let mid = 0.5 * (ta + tb);
        let reach = speed * 0.5 * (tb - ta) + self.delta;
        let index = self.volume(cache, node, mid, a);
        let va = &cache.volumes[index];
        let split = alive.len();
        for i in from..split {
            let b = alive[i] as usize;
            let gap = va.separation(&self.scene.obstacles[b].volume, reach);
            if gap > reach {
                continue;
            }
            // Kept whole as in `spans`.
            if level == self.depth || gap <= 0.0 {
                match out.get_mut(last[b]) {
                    Some(span) if span.1 == ta => span.1 = tb,
                    _ => {
                        last[b] = out.len();
                        out.push((
                            ta,
                            tb,
                            Pair {
                                a,
                                b,
                                obstacle: true,
                            },
                        ));
                    }
                }
            } else {
                alive.push(b as u32);
            }
        }
        if alive.len() > split {
            let children = [(2 * node, ta, mid), (2 * node + 1, mid, tb)];
            for (child, ca, cb) in children {
                let piece = (child, level + 1, ca, cb);
                self.obstacle_spans(a, speed, cache, piece, alive, split, last, out);
            }
        }
        alive.truncate(split);
    }

    /// Every pair with the spans where its swept volumes may meet, earliest span first (pairs
    /// in a fixed order at equal times: self pairs as listed, then obstacle pairs by object and
    /// obstacle).
    fn candidates(&self) -> Vec<(f64, f64, Pair)> {
        let mut cache = self.volume_cache();
        let mut out = Vec::new();
        let mut spans = Vec::new();
        for &(a, b) in &self.robot.self_pairs {
            let pair = Pair {
                a,
                b,
                obstacle: false,
            };
            spans.clear();
            // Two links' distance changes only by their motion relative to the deepest body
            // both hang from: the joints they share move both alike (module docs).
            let common = self.common_joints(pair);
            let speeds = (
                self.paths[a].max_speed_after(common),
                self.paths[b].max_speed_after(common),
            );
            self.spans(pair, speeds, &mut cache, 1, 0, 0.0, 1.0, &mut spans);
            out.extend(spans.iter().map(|&(a, b)| (a, b, pair)));
        }
        let obstacles = self.scene.obstacles.len();
        if obstacles > 0 {
            let mut alive = Vec::with_capacity(obstacles * (self.depth as usize + 2));
            let mut last = vec![usize::MAX; obstacles];
            for a in 0..self.robot.objects.len() {
                alive.clear();
                alive.extend(0..obstacles as u32);
                last.fill(usize::MAX);
                let root = (1, 0, 0.0, 1.0);
                let speed = self.paths[a].max_speed();
                self.obstacle_spans(
                    a, speed, &mut cache, root, &mut alive, 0, &mut last, &mut out,
                );
            }
        }
        let rank = |p: &Pair| {
            if p.obstacle {
                (1, p.a, p.b)
            } else {
                (0, 0, 0)
            }
        };
        // Stable: self pairs keep their order, obstacle pairs are ranked by (object, obstacle).
        out.sort_by(|x, y| {
            x.0.total_cmp(&y.0)
                .then_with(|| rank(&x.2).cmp(&rank(&y.2)))
        });
        out
    }

    /// How many joints, from the root, two robot objects' chains share.
    fn common_joints(&self, pair: Pair) -> usize {
        let (oa, ob) = (&self.robot.objects[pair.a], &self.robot.objects[pair.b]);
        let (ca, cb) = (
            &self.robot.bodies[oa.body].chain,
            &self.robot.bodies[ob.body].chain,
        );
        ca.iter().zip(cb).take_while(|(x, y)| x == y).count()
    }

    /// The pair's two paths: for two robot objects, relative to the deepest body both hang
    /// from (the joints they share move both alike and drop out of the bound), with that
    /// body's index.
    fn pair_paths(&self, pair: Pair) -> (Option<Relative<'r>>, usize) {
        if pair.obstacle {
            return (None, 0);
        }
        let common = self.common_joints(pair);
        if common == 0 {
            return (None, 0);
        }
        let chain = &self.robot.bodies[self.robot.objects[pair.a].body].chain;
        let ancestor = self.robot.joints[chain[common - 1]].child;
        let chains = [
            self.robot.object_path(pair.a, &self.v0, &self.v1, common),
            self.robot.object_path(pair.b, &self.v0, &self.v1, common),
        ];
        let rigid = rigid_pair(chains[0].rigid(), chains[1].rigid());
        (Some(Relative { chains, rigid }), ancestor)
    }

    /// Advances every candidate; `first_only` stops at the first contact found.
    fn run(
        &self,
        first_only: bool,
        warm: &mut Option<&mut RobotCache>,
    ) -> Result<Option<RobotContact>, RobotError> {
        type Found = (f64, Pair, crate::query::contact_time::Ends, ContactCache);
        let mut best: Option<Found> = None;
        let candidates = self.candidates();
        if first_only {
            // A yes/no answer: a pair that collides at the end or the middle of one of its
            // spans settles it at the cost of two exact collision tests, before any
            // advancement. Measured on MotionBenchMaker Panda (10 problems x 20 random 0.5 rad
            // edges + the start-goal edge per scenario, two runs each): colliding random edges
            // 100-440 -> 50-93 us median with the end probe; start-goal edges (which collide
            // half way) 300-1370 -> 100-270 us with the middle one; free edges pay 3-7 us.
            for &(start, end, pair) in &candidates {
                let (relative, _) = self.pair_paths(pair);
                let (m1, p1, m2, p2) = self.meshes(pair, relative.as_ref());
                if let Some(at) = probe_span(m1, p1, m2, p2, start, end) {
                    return Ok(Some(self.contact_at(pair, at, 0)));
                }
            }
        }
        for (start, end, pair) in candidates {
            let limit = best.as_ref().map_or(1.0, |b| b.0);
            if start >= limit {
                break;
            }
            // A link turning fast on a slowly moving parent, past an obstacle: the frozen
            // check may certify the span, or its first part (`query/frozen.rs`).
            let end = end.min(limit);
            let start = self.frozen_until(pair, start, end);
            if start >= end {
                continue;
            }
            let (relative, _) = self.pair_paths(pair);
            let (m1, p1, m2, p2) = self.meshes(pair, relative.as_ref());
            // The exact collision test at the span's start only tells a start in contact
            // apart from a contact found by the first step search (which finds touching
            // meshes too): a yes/no answer does not need it, and a later span's status
            // becomes `Converged` either way.
            let start_free = first_only || start > 0.0;
            let span = self.span((m1, p1, m2, p2), (start, end), self.delta, start_free);
            let key = (pair.a, pair.b, pair.obstacle);
            let mut cache = warm
                .as_ref()
                .and_then(|w| w.pairs.get(&key).copied())
                .unwrap_or_default();
            let found = if first_only {
                // A yes/no answer: the advancement probes a pair that is slow to settle
                // (`probe::advance_probed`; the span's end and middle were probed above).
                match advance_probed(m1, p1, m2, p2, &span, &mut cache)? {
                    Probed::Collides(at) => {
                        return Ok(Some(self.contact_at(pair, at, PROBE_AFTER)))
                    }
                    Probed::Advanced(found) => found,
                }
            } else {
                advance_paths(m1, p1, m2, p2, &span, &mut cache)?
            };
            if let Some(w) = warm.as_mut() {
                w.pairs.insert(key, cache);
            }
            if let Some(ends) = found {
                if first_only {
                    // A yes/no answer needs no witnesses: skip `finish`'s exact distance.
                    return Ok(Some(self.contact_at(pair, ends.time, ends.iterations)));
                }
                if best.as_ref().is_none_or(|b| ends.time < b.0) {
                    best = Some((ends.time, pair, ends, cache));
                }
            }
        }
        Ok(best.map(|(time, pair, mut ends, mut cache)| {
            let (relative, ancestor) = self.pair_paths(pair);
            let (m1, p1, m2, p2) = self.meshes(pair, relative.as_ref());
            if time > 0.0 && ends.status == ContactStatus::StartedInContact {
                ends.status = ContactStatus::Converged;
            }
            let c = finish(m1, p1, m2, p2, ends, &mut cache, self.witnesses);
            // Relative paths give points in the ancestor body's frame.
            let frame = if relative.is_some() {
                let q: Vec<f64> = self
                    .v0
                    .iter()
                    .zip(&self.v1)
                    .map(|(a, b)| a + time * (b - a))
                    .collect();
                self.robot.body_poses_from_values(&q)[ancestor]
            } else {
                Pose::IDENTITY
            };
            RobotContact {
                time,
                object1: self.robot.objects[pair.a].name.clone(),
                object2: if pair.obstacle {
                    self.scene.obstacles[pair.b].name.clone()
                } else {
                    self.robot.objects[pair.b].name.clone()
                },
                self_collision: !pair.obstacle,
                point1: frame.transform_point(c.point1),
                point2: frame.transform_point(c.point2),
                normal: frame.transform_vector(c.normal),
                distance: c.distance,
                iterations: c.iterations,
                status: c.status,
            }
        }))
    }

    /// A pair's advancement over `[start, end]` with tolerance `delta`: the robot's first
    /// window, slacks and iteration cap, the distances' resolution from the scale of the two
    /// meshes where their paths start.
    fn span(
        &self,
        (m1, p1, m2, p2): (&TriMesh, Path<'_>, &TriMesh, Path<'_>),
        (start, end): (f64, f64),
        delta: f64,
        start_free: bool,
    ) -> Span {
        let scale = span_scale((m1, p1, m2, p2), start);
        Span {
            start,
            end,
            delta,
            resolution: NORMAL_RESOLUTION * scale,
            contact: Span::contact(delta, scale),
            max_iterations: self.max_iterations,
            first_window: FIRST_WINDOW,
            slack: (FAR_SLACK, NEAR_SLACK),
            start_free,
            least_first_step: 0.0,
        }
    }

    /// The report of a contact found by a yes/no answer at `time`, by a probe or after
    /// `iterations` of the advancement, without its witnesses (only that it exists matters:
    /// [`path_is_free`] returns `false`).
    fn contact_at(&self, pair: Pair, time: f64, iterations: usize) -> RobotContact {
        RobotContact {
            time,
            object1: self.robot.objects[pair.a].name.clone(),
            object2: String::new(),
            self_collision: !pair.obstacle,
            point1: Vec3::ZERO,
            point2: Vec3::ZERO,
            normal: Vec3::Z,
            distance: 0.0,
            iterations,
            status: ContactStatus::Converged,
        }
    }

    fn meshes<'s>(
        &'s self,
        pair: Pair,
        relative: Option<&'s Relative<'r>>,
    ) -> (&'s TriMesh, Path<'s>, &'s TriMesh, Path<'s>) {
        let a = &self.robot.objects[pair.a];
        let world = |o: usize| match &self.rigid[o] {
            Some(m) => Path::Rigid(m),
            None => Path::Chain(&self.paths[o]),
        };
        if pair.obstacle {
            let o = &self.scene.obstacles[pair.b];
            let link = match &self.rigid[pair.a] {
                Some(m) if m.is_stationary() || o.motion.is_stationary() => Path::Rigid(m),
                _ => Path::Chain(&self.paths[pair.a]),
            };
            return (&a.mesh, link, &o.mesh, Path::Rigid(&o.motion));
        }
        let b = &self.robot.objects[pair.b];
        match relative {
            Some(Relative {
                rigid: Some([ma, mb]),
                ..
            }) => (&a.mesh, Path::Rigid(ma), &b.mesh, Path::Rigid(mb)),
            Some(Relative {
                chains: [pa, pb], ..
            }) => (&a.mesh, Path::Chain(pa), &b.mesh, Path::Chain(pb)),
            None => match rigid_pair(self.rigid[pair.a], self.rigid[pair.b]) {
                Some(_) => (&a.mesh, world(pair.a), &b.mesh, world(pair.b)),
                None => (
                    &a.mesh,
                    Path::Chain(&self.paths[pair.a]),
                    &b.mesh,
                    Path::Chain(&self.paths[pair.b]),
                ),
            },
        }
    }
}

/// The scale of two meshes where their paths start (their bounding radii and distances from
/// the origin), from which an advancement takes its distances' resolution.
fn span_scale((m1, p1, m2, p2): (&TriMesh, Path<'_>, &TriMesh, Path<'_>), start: f64) -> f64 {
    m1.bounding_radius()
        + m2.bounding_radius()
        + p1.pose_at(start).translation.length()
        + p2.pose_at(start).translation.length()
}

/// Two robot objects' paths relative to the deepest body both hang from
/// ([`Segment::pair_paths`]), and the same as rigid motions where [`rigid_pair`] takes them.
struct Relative<'r> {
    chains: [ChainPath<'r>; 2],
    rigid: Option<[Motion; 2]>,
}

/// Two paths as rigid motions when both are rigid and one stands still: the rigid query's
/// rotation certificates then serve a link that turns past the other (a wrist turning near
/// the forearm). Two moving bodies keep their chains (their bound is the same either way).
fn rigid_pair(a: Option<Motion>, b: Option<Motion>) -> Option<[Motion; 2]> {
    match (a, b) {
        (Some(a), Some(b)) if a.is_stationary() || b.is_stationary() => Some([a, b]),
        _ => None,
    }
}

/// First time along `q0 -> q1` at which the robot comes within the tolerance of itself (pairs
/// not allowed to touch) or of an obstacle of `scene` (module docs).
///
/// # Errors
/// [`RobotError::Configuration`] for a configuration of the wrong length or with non-finite
/// values; [`RobotError::Contact`] for bad options or an iteration cap reached.
pub fn time_of_contact(
    robot: &Robot,
    q0: &[f64],
    q1: &[f64],
    scene: &Scene,
    options: &RobotOptions,
) -> Result<Option<RobotContact>, RobotError> {
    Segment::new(robot, q0, q1, scene, options)?.run(false, &mut None)
}

/// Whether the segment `q0 -> q1` is free: `true` when every checked pair stays farther apart
/// than the tolerance, `false` as soon as one comes closer than half of it (exactly
/// `time_of_contact(..).is_none()`, but stopping at the first contact found, which need not
/// be the earliest). A planner's `checkMotion(s1, s2, lastValid)` wants the earliest: use
/// [`time_of_contact`] for that.
///
/// # Errors
/// As [`time_of_contact`].
pub fn path_is_free(
    robot: &Robot,
    q0: &[f64],
    q1: &[f64],
    scene: &Scene,
    options: &RobotOptions,
) -> Result<bool, RobotError> {
    Ok(Segment::new(robot, q0, q1, scene, options)?
        .run(true, &mut None)?
        .is_none())
}

/// The closest triangle pair of every robot pair seen by earlier segment checks: a planner
/// checks many edges from one node, and the pairs' closest features change little between them.
/// Passing one cache to the `_with_cache` queries warm-starts each pair's advancement from its
/// last closest pair (the answers do not depend on it). Valid for one robot and scene.
#[derive(Clone, Debug, Default)]
pub struct RobotCache {
    pairs: std::collections::HashMap<(usize, usize, bool), ContactCache>,
}

/// [`time_of_contact`] warm-started from, and updating, `cache`.
///
/// # Errors
/// As [`time_of_contact`].
pub fn time_of_contact_with_cache(
    robot: &Robot,
    q0: &[f64],
    q1: &[f64],
    scene: &Scene,
    options: &RobotOptions,
    cache: &mut RobotCache,
) -> Result<Option<RobotContact>, RobotError> {
    Segment::new(robot, q0, q1, scene, options)?.run(false, &mut Some(cache))
}

/// [`path_is_free`] warm-started from, and updating, `cache`.
///
/// # Errors
/// As [`path_is_free`].
pub fn path_is_free_with_cache(
    robot: &Robot,
    q0: &[f64],
    q1: &[f64],
    scene: &Scene,
    options: &RobotOptions,
    cache: &mut RobotCache,
) -> Result<bool, RobotError> {
    Ok(Segment::new(robot, q0, q1, scene, options)?
        .run(true, &mut Some(cache))?
        .is_none())
}

/// Whether the robot at `q` collides with itself (pairs not allowed to touch) or with an
/// obstacle: exact triangle intersection (touching counts), no tolerance.
///
/// # Errors
/// [`RobotError::Configuration`] for a bad configuration.
pub fn in_collision(robot: &Robot, q: &[f64], scene: &Scene) -> Result<bool, RobotError> {
    robot.check_configuration(q, "q")?;
    let poses = robot.body_poses(q);
    let objects = &robot.objects;
    // Each object's world box when a pair first needs it: a colliding configuration stops at
    // its first colliding pair, before most boxes are needed (callgrind, 300 random
    // configurations of example-robot-data's robots: Tiago dual 15%, B1 7%, Panda 4% fewer
    // instructions, none more).
    let mut boxes: Vec<Option<(Vec3, Vec3)>> = vec![None; objects.len()];
    let mut bounds = |i: usize| {
        *boxes[i].get_or_insert_with(|| {
            WorldVolume::new(&objects[i].mesh, &poses[objects[i].body]).bounds
        })
    };
    for &(a, b) in &robot.self_pairs {
        if boxes_meet(&bounds(a), &bounds(b))
            && collide(
                &objects[a].mesh,
                &poses[objects[a].body],
                &objects[b].mesh,
                &poses[objects[b].body],
            )
        {
            return Ok(true);
        }
    }
    for (a, o) in objects.iter().enumerate() {
        for obs in &scene.obstacles {
            if boxes_meet(&bounds(a), &obs.volume.bounds)
                && collide(&o.mesh, &poses[o.body], &obs.mesh, &obs.pose)
            {
                return Ok(true);
            }
        }
    }
    Ok(false)
}

/// [`in_collision`] for every configuration, in parallel; results in input order.
///
/// # Errors
/// The first bad configuration, before anything is checked.
pub fn check_configurations(
    robot: &Robot,
    qs: &[Vec<f64>],
    scene: &Scene,
) -> Result<Vec<bool>, RobotError> {
    use rayon::prelude::*;
    for (i, q) in qs.iter().enumerate() {
        robot.check_configuration(q, &format!("{i}"))?;
    }
    qs.par_iter()
        .map(|q| in_collision(robot, q, scene))
        .collect()
}

/// [`time_of_contact`] for every segment `(q0, q1)`, in parallel; results in input order,
/// identical to the single calls. Options are checked first; each segment's own error (a bad
/// configuration, an iteration cap) is its entry.
///
/// # Errors
/// Bad options.
#[allow(clippy::type_complexity)]
pub fn time_of_contact_batch(
    robot: &Robot,
    segments: &[(Vec<f64>, Vec<f64>)],
    scene: &Scene,
    options: &RobotOptions,
) -> Result<Vec<Result<Option<RobotContact>, RobotError>>, RobotError> {
    use rayon::prelude::*;
    check_options(options)?;
    Ok(segments
        .par_iter()
        .map(|(a, b)| time_of_contact(robot, a, b, scene, options))
        .collect())
}

/// [`path_is_free`] for every segment, in parallel; results in input order.
///
/// # Errors
/// Bad options.
pub fn path_is_free_batch(
    robot: &Robot,
    segments: &[(Vec<f64>, Vec<f64>)],
    scene: &Scene,
    options: &RobotOptions,
) -> Result<Vec<Result<bool, RobotError>>, RobotError> {
    use rayon::prelude::*;
    check_options(options)?;
    Ok(segments
        .par_iter()
        .map(|(a, b)| path_is_free(robot, a, b, scene, options))
        .collect())
}

fn boxes_meet(a: &(Vec3, Vec3), b: &(Vec3, Vec3)) -> bool {
    a.0.x <= b.1.x
        && b.0.x <= a.1.x
        && a.0.y <= b.1.y
        && b.0.y <= a.1.y
        && a.0.z <= b.1.z
        && b.0.z <= a.1.z
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The culling's poses (sines and cosines carried from parent to child nodes) against
    /// forward kinematics at each node's middle, on a chain with revolute, prismatic and mimic
    /// joints.
    #[test]
    fn culling_poses_match_forward_kinematics() {
        let link = |n: &str| {
            format!("<link name='{n}'><collision><geometry><box size='0.1 0.2 0.3'/></geometry></collision></link>")
        };
        let joint = |n: &str, kind: &str, p: &str, c: &str, axis: &str, extra: &str| {
            format!(
                "<joint name='{n}' type='{kind}'><parent link='{p}'/><child link='{c}'/>\
                 <origin xyz='0.1 0.2 0.3' rpy='0.3 -0.2 0.5'/><axis xyz='{axis}'/>\
                 <limit lower='-3' upper='3' effort='1' velocity='1'/>{extra}</joint>"
            )
        };
        let xml = format!(
            "<robot name='r'>{}{}{}{}{}{}{}{}</robot>",
            link("a"),
            link("b"),
            link("c"),
            link("d"),
            joint("j1", "revolute", "a", "b", "0 0 1", ""),
            joint("j2", "prismatic", "b", "c", "0.6 0 0.8", ""),
            joint("j3", "revolute", "c", "d", "1 2 -1", ""),
            link("e")
                + &joint(
                    "j4",
                    "revolute",
                    "d",
                    "e",
                    "0 1 0",
                    "<mimic joint='j1' multiplier='-1.5' offset='0.2'/>"
                ),
        );
        let robot = Robot::from_urdf_str(&xml, None, &[]).expect("model");
        let scene = Scene::new();
        let (q0, q1) = ([0.4, -0.2, 2.5], [-2.9, 0.3, -1.0]);
        let segment =
            Segment::new(&robot, &q0, &q1, &scene, &RobotOptions::default()).expect("segment");
        let mut cache = segment.volume_cache();
        let bodies = robot.bodies.len();
        for node in 1..(2usize << segment.depth) {
            let level = usize::BITS - 1 - node.leading_zeros();
            let width = 0.5_f64.powi(level as i32);
            let mid = (node as f64 - (1 << level) as f64 + 0.5) * width;
            segment.volume(&mut cache, node, mid, 0);
            let start = cache.pose_at[node] as usize;
            let q: Vec<f64> = q0.iter().zip(&q1).map(|(a, b)| a + mid * (b - a)).collect();
            let expected = robot.body_poses(&q);
            for (got, want) in cache.poses[start..start + bodies].iter().zip(&expected) {
                let rot = (got.rotation - want.rotation).to_cols_array();
                let err = rot.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
                assert!(err < 1e-13, "node {node}: rotation off by {err}");
                assert!((got.translation - want.translation).length() < 1e-13);
            }
        }
    }
}

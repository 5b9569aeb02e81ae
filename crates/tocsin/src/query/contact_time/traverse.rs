//! One C2A iteration: the largest step `dt` certified safe by the two hierarchies at time `t`.
//!
//! Invariant: every node pair left unvisited has a certified step `s` with
//! `s (1 + slack) >= best`, and the step returned is `best / (1 + slack)`, so it is safe for
//! every triangle pair. A triangle pair within `delta` ends the search.

use crate::bvh::{rss_separation, ASide, BSide, Bvh, Node, RelativeRss};
use crate::math::{Mat3, Pose, Vec3};
use crate::motion::Motion;
use crate::query::distance::distance_triangle_triangle;
use crate::TriMesh;

/// What one iteration found.
pub(crate) enum StepOutcome {
    /// A triangle pair (leaf positions) is within the tolerance at the current time.
    Within { pair: (u32, u32) },
    /// A safe step, the triangle pair that limited it (if any) and the smallest triangle-pair
    /// distance seen (an upper bound of the meshes' distance; infinite if none was evaluated).
    Step {
        dt: f64,
        pair: Option<(u32, u32)>,
        distance: f64,
    },
}

pub(crate) struct StepSearch<'a> {
    bvh1: &'a Bvh,
    bvh2: &'a Bvh,
    motion1: &'a Motion,
    motion2: &'a Motion,
    delta: f64,
    // Per-iteration state.
    rot12: Mat3,
    trans12: Vec3,
    /// Mesh 1's rotation at the current time: mesh-1 frame to world.
    rot1: Mat3,
    /// Mesh 2's world rotation at the current time.
    rot2: Mat3,
    /// Length of the time window the bounds are valid for (steps never exceed it).
    window: f64,
    best: f64,
    best_pair: Option<(u32, u32)>,
    closest: f64,
    slack: f64,
    stack: Vec<(u32, u32, f64)>,
}

/// A set of body points for the motion bounds: a ball (body frame) and a bound `rho` on the
/// points' distance from the motion's rotation axis.
struct PointSet {
    center: Vec3,
    radius: f64,
    rho: f64,
}

impl PointSet {
    /// A node's volume: its RSS centre and bounding radius (on demand: a query touches few nodes).
    #[inline]
    fn node(node: &Node, motion: &Motion) -> Self {
        let (center, radius) = (node.rss.center, node.rss.bounding_radius());
        Self {
            center,
            radius,
            rho: motion.axis_distance(center) + radius,
        }
    }

    /// A triangle: its centroid, the farthest corner, and the largest corner axis distance.
    #[inline]
    fn triangle(t: &[Vec3; 3], motion: &Motion) -> Self {
        let center = (t[0] + t[1] + t[2]) / 3.0;
        let radius = t.iter().fold(0.0_f64, |m, &p| m.max((p - center).length()));
        let rho = t
            .iter()
            .fold(0.0_f64, |m, &p| m.max(motion.axis_distance(p)));
        Self {
            center,
            radius,
            rho,
        }
    }
}

impl<'a> StepSearch<'a> {
    pub(crate) fn new(
        mesh1: &'a TriMesh,
        motion1: &'a Motion,
        mesh2: &'a TriMesh,
        motion2: &'a Motion,
        delta: f64,
    ) -> Self {
        Self {
            bvh1: mesh1.bvh(),
            bvh2: mesh2.bvh(),
            motion1,
            motion2,
            delta,
            rot12: Mat3::IDENTITY,
            trans12: Vec3::ZERO,
            rot1: Mat3::IDENTITY,
            rot2: Mat3::IDENTITY,
            window: 1.0,
            best: 0.0,
            best_pair: None,
            closest: f64::INFINITY,
            slack: 0.0,
            stack: Vec::with_capacity(64),
        }
    }

    /// Safe step for a gap `gap` along the mesh-1-frame unit direction `n` (from body 1 to
    /// body 2) between the point sets `s1` (of body 1) and `s2` (of body 2). Each body's speed
    /// along the gap is the smaller of its whole-motion bound and its bound over the window.
    #[inline]
    fn step(&self, gap: f64, n: Vec3, s1: &PointSet, s2: &PointSet) -> f64 {
        let margin = gap - 0.5 * self.delta;
        if margin <= 0.0 {
            return 0.0;
        }
        let n_world = self.rot1 * n;
        let (m1, m2) = (self.motion1, self.motion2);
        let mu1 = m1
            .directional_bound(n_world, s1.rho)
            .min(m1.directional_bound_window(
                n_world,
                &self.rot1,
                s1.center,
                s1.radius,
                self.window,
            ));
        let mu2 = m2
            .directional_bound(-n_world, s2.rho)
            .min(m2.directional_bound_window(
                -n_world,
                &self.rot2,
                s2.center,
                s2.radius,
                self.window,
            ));
        let mu = mu1 + mu2;
        if mu <= 0.0 {
            f64::INFINITY
        } else {
            margin / mu
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
        let mu_max = self.motion1.speed_bound(s1.rho) + self.motion2.speed_bound(s2.rho);
        let cutoff = 0.5 * self.delta + mu_max * self.best / (1.0 + self.slack);
        let (gap, axis) = rss_separation(&a.rss, &b.rss, rel, cutoff);
        self.step(gap, a.rss.axes * axis, &s1, &s2)
    }

    /// Evaluates a triangle pair: `true` when it is within the tolerance.
    fn leaf_pair(&mut self, leaf1: u32, leaf2: u32) -> bool {
        let t1 = &self.bvh1.leaf_triangles()[leaf1 as usize];
        let body2 = self.bvh2.leaf_triangles()[leaf2 as usize];
        let t2 = body2.map(|p| self.rot12 * p + self.trans12);
        let d = distance_triangle_triangle(t1, &t2);
        self.closest = self.closest.min(d.distance);
        if d.distance <= self.delta {
            return true;
        }
        let (s1, s2) = (
            PointSet::triangle(t1, self.motion1),
            PointSet::triangle(&body2, self.motion2),
        );
        let n = (d.point2 - d.point1) / d.distance;
        let s = self.step(d.distance, n, &s1, &s2);
        if s < self.best {
            self.best = s;
            self.best_pair = Some((leaf1, leaf2));
        }
        false
    }

    /// One iteration at time `t`, with bounds valid over `[t, t + window]` (the step never
    /// exceeds `window`); `slack` trades step length for fewer visited pairs.
    pub(crate) fn run(
        &mut self,
        t: f64,
        window: f64,
        slack: f64,
        warm: Option<(u32, u32)>,
    ) -> StepOutcome {
        let (pose1, pose2): (Pose, Pose) = (self.motion1.pose_at(t), self.motion2.pose_at(t));
        let pos12 = pose1.inv_mul(&pose2);
        (self.rot12, self.trans12) = (pos12.rotation, pos12.translation);
        (self.rot1, self.rot2, self.window) = (pose1.rotation, pose2.rotation, window);
        self.slack = slack;
        self.best = window * (1.0 + slack);
        self.best_pair = None;
        self.closest = f64::INFINITY;
        if let Some((l1, l2)) = warm {
            if (l1 as usize) < self.bvh1.leaf_triangles().len()
                && (l2 as usize) < self.bvh2.leaf_triangles().len()
                && self.leaf_pair(l1, l2)
            {
                return StepOutcome::Within { pair: (l1, l2) };
            }
        }
        let (nodes1, nodes2) = (self.bvh1.nodes(), self.bvh2.nodes());
        let root = RelativeRss::new(&nodes1[0].rss, &nodes2[0].rss, &self.rot12, self.trans12);
        self.stack.clear();
        self.stack.push((0, 0, self.node_step(0, 0, &root)));
        while let Some((n1, n2, s)) = self.stack.pop() {
            if s * (1.0 + self.slack) >= self.best {
                continue;
            }
            let (a, b): (&Node, &Node) = (&nodes1[n1 as usize], &nodes2[n2 as usize]);
            if a.is_leaf() && b.is_leaf() {
                if self.leaf_pair(a.leaf_position(), b.leaf_position()) {
                    return StepOutcome::Within {
                        pair: (a.leaf_position(), b.leaf_position()),
                    };
                }
                continue;
            }
            let split_first = !a.is_leaf() && (b.is_leaf() || a.rss.size() >= b.rss.size());
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
                }
            }
        }
        StepOutcome::Step {
            dt: self.best / (1.0 + self.slack),
            pair: self.best_pair,
            distance: self.closest,
        }
    }
}

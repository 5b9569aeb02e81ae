//! The distance branch and bound, in mesh 1's frame.
//!
//! Invariant: every node pair left unvisited has a lower bound `lb` with
//! `lb * (1 + rel) + abs >= best - 2 slack` (or was cut by the early stop), so at the end the
//! best triangle pair found is within the requested error of the true minimum, plus
//! `2 slack = 2e-13` of the scene's scale: pairs tied with the best (parallel faces of CAD
//! models) are not all visited.
//!
//! Order: first a greedy dive from the roots to one triangle pair (into the child pair of
//! smallest bound, ties to the nearest centres), so that the cutoff is finite from the start
//! (without it, three quarters of the corner projections below were made against an infinite
//! cutoff, before the first triangle pair; the dive takes 9% of the instructions off the
//! knot34k workload). Then best-first (smallest bound first, a binary heap) until a triangle
//! pair has been evaluated or [`HEAP_CAP`] pairs wait, which finds a close upper bound, or until
//! a pair of small subtrees ([`PLUNGE_MAX`]) whose volumes overlap reaches the top: all such
//! pairs are tied at bound 0, so the queue's order says nothing among them (at 0.01 R most pairs
//! near the contact are such ties, and the dive's pair is 2 to 12 times the minimum away), and
//! that pair is searched to the bottom at once for a close cutoff (22% fewer instructions at
//! 0.01 R on the `bench/compare_fcl.py` poses, 7 and 18% on two other sets of 16); then the
//! waiting pairs in queue order, each searched depth-first, nearest child first, which keeps
//! node accesses local and the queue small. Measured on knot34k at random poses, the
//! best-first start halves the node pairs of a plain depth-first search (8% above the
//! best-first optimum). A threshold test ([`Stop::AtOrBelow`]) is depth-first from the start.
//! Two internal nodes are split together, so each expansion bounds four child pairs in one
//! 4-lane evaluation ([`crate::bvh::Lanes4`]).
//!
//! Near the leaves the volumes, not the order, limit the pruning: a triangle fills half of its
//! bounding rectangle, and a patch of a few triangles a little more. So a child pair whose
//! subtrees both hold at most [`PROJECT_MAX`] triangles is also bounded by projecting the
//! subtrees' points (corners, or distinct vertices) on the near-points axis of its volumes
//! ([`DistanceSearch::projected_gap`]).
//! On knot34k at random poses this halves (0.01 R) to quarters (1 R) the node pairs expanded,
//! and the triangle pairs evaluated drop from 79 / 153 / 380 to about 30 / 50 / 65 per query.

use super::distance_triangle_triangle::distance_triangle_triangle;
use super::{DistanceOptions, DistanceResult};
use crate::bvh::{
    both_at_most, rss_separation, Bvh, ColumnPair, Expansion, Lanes4, Node, RelativeRss,
    PROJECT_MAX,
};
use crate::math::{Mat3, Pose, Vec3};
use crate::mesh::TriMesh;
use std::collections::BinaryHeap;

/// When a search may stop before the minimum is proven.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Stop {
    /// Only when the minimum (within the error bounds) is proven.
    Never,
    /// As soon as a pair at or below this distance is found.
    AtOrBelow(f64),
}

/// The best triangle pair found so far; points in mesh 1's frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Best {
    pub distance: f64,
    pub point1: Vec3,
    pub point2: Vec3,
    pub leaf1: u32,
    pub leaf2: u32,
}

/// Largest best-first queue before the search turns depth-first. Measured on the knot34k
/// workload of `examples/profile_distance.rs` (instructions): 256 costs 10% more, 512 5% more,
/// 2048 2% more; with no cap (switch at the first triangle pair only) the 1R poses took 20%
/// longer.
const HEAP_CAP: usize = 1024;

/// Largest subtrees (triangles, on both sides) of a pair with overlapping volumes that ends the
/// best-first phase, searched to the bottom at once (see [`DistanceSearch::run`]). Measured on
/// the knot34k poses of `bench/compare_fcl.py` (instructions per query at 0.01 R, with
/// 0.1 R and 1 R unchanged): none 546k; 4: 549k; 8: 504k; 16: 424k; 32: 460k; 64: 467k.
const PLUNGE_MAX: usize = 16;

pub(crate) struct DistanceSearch<'a> {
    bvh1: &'a Bvh,
    bvh2: &'a Bvh,
    rot12: Mat3,
    trans12: Vec3,
    rel: f64,
    abs: f64,
    stop: Stop,
    /// Absolute slack subtracted from every bound, covering rounding in the relative transform.
    slack: f64,
    /// Both meshes' corner columns, for [`Self::projected_gap`] (`None` when either has none).
    columns: Option<ColumnPair<'a>>,
    best: Best,
    /// [`Self::compute_cutoff`] for the current best.
    cut: f64,
    stack: Vec<(u32, u32, f64)>,
    heap: BinaryHeap<Pending>,
    /// [`HEAP_CAP`] for the minimum, 0 (depth-first at once) for a threshold test; other
    /// values in tests.
    heap_cap: usize,
    lanes: Lanes4,
}

/// A node pair waiting in the best-first queue, ordered by its bound (the smallest is the
/// greatest), stored as the bits of `lb + slack >= 0`, which order like the values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Pending {
    key: std::cmp::Reverse<u64>,
    n1: u32,
    n2: u32,
}

impl Pending {
    #[inline]
    fn new(lb: f64, slack: f64, n1: u32, n2: u32) -> Self {
        Self {
            key: std::cmp::Reverse((lb + slack).max(0.0).to_bits()),
            n1,
            n2,
        }
    }

    #[inline]
    fn lb(&self, slack: f64) -> f64 {
        f64::from_bits(self.key.0) - slack
    }

    /// Whether the pair's volumes may overlap (its bound is 0, like all such pairs).
    #[inline]
    fn overlapping(&self) -> bool {
        self.key.0 == 0
    }
}

impl<'a> DistanceSearch<'a> {
    pub(crate) fn new(
        mesh1: &'a TriMesh,
        mesh2: &'a TriMesh,
        pos12: &Pose,
        options: &DistanceOptions,
        stop: Stop,
    ) -> Self {
        let scale = pos12.translation.length()
            + mesh1.bounding_radius()
            + mesh2.bounding_radius()
            + mesh1.bvh().root().center.length()
            + mesh2.bvh().root().center.length();
        let mut search = Self {
            bvh1: mesh1.bvh(),
            bvh2: mesh2.bvh(),
            rot12: pos12.rotation,
            trans12: pos12.translation,
            rel: options.relative_error,
            abs: options.absolute_error,
            stop,
            slack: 1e-13 * scale,
            columns: ColumnPair::new(mesh1.bvh(), mesh2.bvh(), pos12),
            best: Best {
                distance: f64::INFINITY,
                point1: Vec3::ZERO,
                point2: Vec3::ZERO,
                leaf1: 0,
                leaf2: 0,
            },
            cut: f64::INFINITY,
            stack: Vec::with_capacity(64),
            heap: BinaryHeap::with_capacity(64),
            // A threshold test wants any pair below its threshold soon: depth-first dives to
            // one (knot34k at 0.1R: 4 us, against 43 us with the best-first start).
            heap_cap: match stop {
                Stop::Never => HEAP_CAP,
                Stop::AtOrBelow(_) => 0,
            },
            lanes: Lanes4::detect(),
        };
        search.cut = search.compute_cutoff();
        search
    }

    pub(crate) fn best(&self) -> &Best {
        &self.best
    }

    /// The result in the world frame, given mesh 1's pose.
    pub(crate) fn result(&self, pose1: &Pose) -> DistanceResult {
        DistanceResult {
            distance: self.best.distance,
            point1: pose1.transform_point(self.best.point1),
            point2: pose1.transform_point(self.best.point2),
            triangle1: self.bvh1.triangle_index(self.best.leaf1),
            triangle2: self.bvh2.triangle_index(self.best.leaf2),
        }
    }

    /// Bound below which a pair is still worth visiting (`NEG_INFINITY` once the search is done);
    /// cached, since it changes only with the best pair.
    #[inline]
    fn cutoff(&self) -> f64 {
        self.cut
    }

    fn compute_cutoff(&self) -> f64 {
        let improve = (self.best.distance - self.abs) / (1.0 + self.rel);
        match self.stop {
            // A pair whose bound exceeds the threshold cannot answer "within".
            Stop::AtOrBelow(t) if self.best.distance <= t => f64::NEG_INFINITY,
            Stop::AtOrBelow(t) => improve.min(t.next_up()),
            // Nothing is below 0: a contact ends the search.
            Stop::Never if improve <= 0.0 => f64::NEG_INFINITY,
            // A pair that could only improve by the rounding slack is a tie: skip it.
            Stop::Never => improve - 2.0 * self.slack,
        }
    }

    /// Lower bound for the pair `(n1, n2)` whose relative frame is `rel`.
    #[inline]
    fn bound(&self, n1: u32, n2: u32, rel: &RelativeRss, cutoff: f64) -> f64 {
        let a = &self.bvh1.nodes()[n1 as usize].rss;
        let b = &self.bvh2.nodes()[n2 as usize].rss;
        rss_separation(a, b, rel, cutoff + self.slack).0 - self.slack
    }

    /// A lower bound on the distance between the triangles of two small subtrees: their
    /// corners projected on `axis` (unit, mesh 1's frame; the near-points axis of their
    /// volumes, which runs from `a` towards `b`). The volumes' rectangles overhang their
    /// triangles (a triangle fills half of its rectangle), so the corners themselves are often
    /// farther apart along that axis. One-sided: `min(u . q) - max(u . p)` over `q` in `b`, `p`
    /// in `a` bounds the distance for any unit `u`, and along the near-points axis `b` lies on
    /// the positive side (the other side was never the larger on the knot34k poses of
    /// `examples/profile_poses.rs` nor in the tests, and computing it cost 3% of the searches'
    /// instructions). Computed from the `f32` corner columns, less their rounding bound;
    /// `NEG_INFINITY` for meshes without columns.
    fn projected_gap(&self, (i, a): (u32, &Node), (j, b): (u32, &Node), axis: Vec3) -> f64 {
        match &self.columns {
            Some(c) => c.gap(self.lanes, (i, a), (j, b), axis),
            None => f64::NEG_INFINITY,
        }
    }

    /// [`Self::leaf_pair`] of the triangles of two leaf nodes.
    fn leaf_nodes(&mut self, n1: u32, n2: u32) {
        let (l1, l2) = (
            self.bvh1.nodes()[n1 as usize].leaf_position(),
            self.bvh2.nodes()[n2 as usize].leaf_position(),
        );
        self.leaf_pair(l1, l2);
    }

    fn leaf_pair(&mut self, leaf1: u32, leaf2: u32) {
        let t1 = &self.bvh1.leaf_triangles()[leaf1 as usize];
        let t2 = self.bvh2.leaf_triangles()[leaf2 as usize].map(|p| self.rot12 * p + self.trans12);
        let d = distance_triangle_triangle(t1, &t2);
        if d.distance < self.best.distance {
            self.best = Best {
                distance: d.distance,
                point1: d.point1,
                point2: d.point2,
                leaf1,
                leaf2,
            };
            self.cut = self.compute_cutoff();
        }
    }

    /// Runs the search, first evaluating `warm` (a pair of leaf positions) when given.
    pub(crate) fn run(&mut self, warm: Option<(u32, u32)>) {
        if let Some((l1, l2)) = warm {
            if (l1 as usize) < self.bvh1.leaf_triangles().len()
                && (l2 as usize) < self.bvh2.leaf_triangles().len()
            {
                self.leaf_pair(l1, l2);
            }
        }
        self.stack.clear();
        self.heap.clear();
        if self.best.distance == f64::INFINITY {
            self.dive();
        }
        let (root1, root2) = (&self.bvh1.nodes()[0].rss, &self.bvh2.nodes()[0].rss);
        let lb = self.bound(
            0,
            0,
            &RelativeRss::new(root1, root2, &self.rot12, self.trans12),
            f64::INFINITY,
        );
        self.heap.push(Pending::new(lb, self.slack, 0, 0));
        while let Some(p) = self.heap.pop() {
            let lb = p.lb(self.slack);
            if lb >= self.cutoff() {
                // Everything left in the queue is bounded at least as high.
                self.heap.clear();
                return;
            }
            if p.overlapping() && self.small_pair(p.n1, p.n2) {
                self.depth_first(p.n1, p.n2, lb);
                break;
            }
            if self.expand(p.n1, p.n2, true) || self.heap.len() >= self.heap_cap {
                break;
            }
        }
        // The rest in queue order, each pair's subtree depth-first, nearest child first.
        while let Some(p) = self.heap.pop() {
            let lb = p.lb(self.slack);
            if lb >= self.cutoff() {
                break;
            }
            self.depth_first(p.n1, p.n2, lb);
        }
        self.heap.clear();
    }

    /// Whether both subtrees of a pair hold at most [`PLUNGE_MAX`] triangles.
    #[inline]
    fn small_pair(&self, n1: u32, n2: u32) -> bool {
        let (a, b) = (
            &self.bvh1.nodes()[n1 as usize],
            &self.bvh2.nodes()[n2 as usize],
        );
        both_at_most(a, b, PLUNGE_MAX)
    }

    /// Searches the pair `(n1, n2)` (bound `lb`) to the bottom, depth-first, nearest child
    /// first.
    fn depth_first(&mut self, n1: u32, n2: u32, lb: f64) {
        self.stack.push((n1, n2, lb));
        while let Some((n1, n2, lb)) = self.stack.pop() {
            if lb < self.cutoff() {
                self.expand(n1, n2, false);
            }
        }
    }

    /// A first triangle pair, for a finite cutoff from the start: from the roots down, always
    /// into the child pair of smallest bound (one expansion per level).
    fn dive(&mut self) {
        let (nodes1, nodes2) = (self.bvh1.nodes(), self.bvh2.nodes());
        let (mut n1, mut n2) = (0, 0);
        while let Some(e) = Expansion::of(nodes1, n1, nodes2, n2) {
            let bounds = self
                .lanes
                .expansion_bounds(&e, nodes1, nodes2, &self.rot12, self.trans12);
            // Ties go to the pair with the nearest centres, computed only for tied lanes:
            // volumes that overlap (bound 0), and bounds within the rounding slack of each
            // other (parallel faces: by the last bits of their bounds the dive drifted to
            // pairs that overlap less and less, and ended 20 times the minimum away).
            let centres = |k: usize| {
                let (c1, c2) = e.pair(k);
                let (a, b) = (&nodes1[c1 as usize].rss, &nodes2[c2 as usize].rss);
                (a.center - (self.rot12 * b.center + self.trans12)).length_squared()
            };
            let tie = 2.0 * self.slack;
            let mut k = e.lanes[0];
            let mut k_centres = None;
            for &j in &e.lanes[1..] {
                if bounds.gap[j] < bounds.gap[k] - tie {
                    (k, k_centres) = (j, None);
                } else if bounds.gap[j] <= bounds.gap[k] + tie {
                    let current = *k_centres.get_or_insert_with(|| centres(k));
                    let other = centres(j);
                    if other < current {
                        (k, k_centres) = (j, Some(other));
                    }
                }
            }
            (n1, n2) = e.pair(k);
        }
        self.leaf_nodes(n1, n2);
    }

    /// Evaluates the pair `(n1, n2)`: the triangle pair of two leaves (returns true), or the
    /// bounds of its child pairs, queued (on the heap or the stack) where they may improve the
    /// best. Two internal nodes are split together: four child pairs, one 4-lane bound.
    fn expand(&mut self, n1: u32, n2: u32, to_heap: bool) -> bool {
        let (nodes1, nodes2) = (self.bvh1.nodes(), self.bvh2.nodes());
        let Some(e) = Expansion::of(nodes1, n1, nodes2, n2) else {
            self.leaf_nodes(n1, n2);
            return true;
        };
        let bounds = self
            .lanes
            .expansion_bounds(&e, nodes1, nodes2, &self.rot12, self.trans12);
        let cutoff = self.cutoff();
        let mut queued = [(0u32, 0u32, 0.0f64); 4];
        let mut m = 0;
        for &k in e.lanes {
            let mut lb = bounds.gap[k] - self.slack;
            if lb < cutoff {
                let (c1, c2) = e.pair(k);
                let (a, b) = (&nodes1[c1 as usize], &nodes2[c2 as usize]);
                // Where the volumes touch, the axis is degenerate and the projection seldom
                // prunes; it is skipped there.
                if bounds.gap[k] > 0.0 && both_at_most(a, b, PROJECT_MAX) {
                    let axis = Vec3::new(bounds.axis[0][k], bounds.axis[1][k], bounds.axis[2][k]);
                    lb = lb.max(self.projected_gap((c1, a), (c2, b), axis) - self.slack);
                    if lb >= cutoff {
                        continue;
                    }
                }
                queued[m] = (c1, c2, lb);
                m += 1;
            }
        }
        let queued = &mut queued[..m];
        if to_heap {
            let slack = self.slack;
            for &(n1, n2, lb) in queued.iter() {
                self.heap.push(Pending::new(lb, slack, n1, n2));
            }
        } else {
            // Farthest first, so that the nearest is on top (insertion sort of at most four).
            for i in 1..queued.len() {
                let mut j = i;
                while j > 0 && queued[j - 1].2 < queued[j].2 {
                    queued.swap(j - 1, j);
                    j -= 1;
                }
            }
            self.stack.extend_from_slice(queued);
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh;

    /// Every switch point from best-first to depth-first (at once, after 1 or 4 queued pairs, at the
    /// first triangle pair) gives the brute-force minimum over all triangle pairs.
    #[test]
    fn every_switch_point_finds_the_minimum() {
        let knot = mesh::torus_knot(60, 8).unwrap_or_else(|e| unreachable!("{e}"));
        let tris = knot.bvh().leaf_triangles();
        for k in 0..6 {
            let axis = Vec3::new(0.3, 1.0, 0.2 * k as f64);
            let offset = Vec3::new(1.0, 0.4, 0.1 * k as f64) * (2.0 + 1.5 * k as f64);
            let pose = Pose::from_axis_angle(axis, 0.4 + k as f64, offset);
            let moved: Vec<[Vec3; 3]> = tris
                .iter()
                .map(|t| t.map(|p| pose.transform_point(p)))
                .collect();
            let brute = tris
                .iter()
                .flat_map(|a| {
                    moved
                        .iter()
                        .map(|b| distance_triangle_triangle(a, b).distance)
                })
                .fold(f64::INFINITY, f64::min);
            for cap in [0, 1, 4, HEAP_CAP] {
                let opts = DistanceOptions::default();
                let mut search = DistanceSearch::new(&knot, &knot, &pose, &opts, Stop::Never);
                search.heap_cap = cap;
                search.run(None);
                let d = search.best().distance;
                assert!(
                    (d - brute).abs() <= 1e-12 * (1.0 + brute),
                    "cap {cap}: {d} vs {brute}"
                );
            }
        }
    }
}

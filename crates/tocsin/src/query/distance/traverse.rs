//! The distance branch and bound, in mesh 1's frame.
//!
//! Invariant: every node pair left unvisited has a lower bound `lb` with
//! `lb * (1 + rel) + abs >= best - 2 slack` (or was cut by the early stop), so at the end the
//! best triangle pair found is within the requested error of the true minimum, plus
//! `2 slack = 2e-13` of the scene's scale: pairs tied with the best (parallel faces of CAD
//! models) are not all visited.

use super::distance_triangle_triangle::distance_triangle_triangle;
use super::{DistanceOptions, DistanceResult};
use crate::bvh::{rss_separation, ASide, BSide, Bvh, RelativeRss};
use crate::math::{Mat3, Pose, Vec3};
use crate::mesh::TriMesh;

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
    best: Best,
    stack: Vec<(u32, u32, f64)>,
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
        Self {
            bvh1: mesh1.bvh(),
            bvh2: mesh2.bvh(),
            rot12: pos12.rotation,
            trans12: pos12.translation,
            rel: options.relative_error,
            abs: options.absolute_error,
            stop,
            slack: 1e-13 * scale,
            best: Best {
                distance: f64::INFINITY,
                point1: Vec3::ZERO,
                point2: Vec3::ZERO,
                leaf1: 0,
                leaf2: 0,
            },
            stack: Vec::with_capacity(64),
        }
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

    /// Bound below which a pair is still worth visiting (`NEG_INFINITY` once the search is done).
    #[inline]
    fn cutoff(&self) -> f64 {
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
        let (root1, root2) = (&self.bvh1.nodes()[0].rss, &self.bvh2.nodes()[0].rss);
        let lb = self.bound(
            0,
            0,
            &RelativeRss::new(root1, root2, &self.rot12, self.trans12),
            f64::INFINITY,
        );
        self.stack.push((0, 0, lb));
        let (nodes1, nodes2) = (self.bvh1.nodes(), self.bvh2.nodes());
        while let Some((n1, n2, lb)) = self.stack.pop() {
            let cutoff = self.cutoff();
            if lb >= cutoff {
                continue;
            }
            let (a, b) = (&nodes1[n1 as usize], &nodes2[n2 as usize]);
            if a.is_leaf() && b.is_leaf() {
                self.leaf_pair(a.leaf_position(), b.leaf_position());
                continue;
            }
            // Split the larger volume (or the one that is not a leaf).
            let split_first = !a.is_leaf() && (b.is_leaf() || a.rss.size() >= b.rss.size());
            // The side that stays is transformed once for both children.
            let (p, q, lp, lq);
            if split_first {
                let (c1, c2) = a.children(n1);
                let side = BSide::new(&b.rss, &self.rot12, self.trans12);
                let rel = |c: u32| RelativeRss::from_b_side(&nodes1[c as usize].rss, &side);
                (p, q) = ((c1, n2), (c2, n2));
                lp = self.bound(c1, n2, &rel(c1), cutoff);
                lq = self.bound(c2, n2, &rel(c2), cutoff);
            } else {
                let (c1, c2) = b.children(n2);
                let side = ASide::new(&a.rss, &self.rot12, self.trans12);
                let rel = |c: u32| RelativeRss::from_a_side(&side, &nodes2[c as usize].rss);
                (p, q) = ((n1, c1), (n1, c2));
                lp = self.bound(n1, c1, &rel(c1), cutoff);
                lq = self.bound(n1, c2, &rel(c2), cutoff);
            }
            // Push the farther first so that the nearer is visited first.
            let (near, far) = if lp <= lq {
                ((p, lp), (q, lq))
            } else {
                ((q, lq), (p, lp))
            };
            if far.1 < cutoff {
                self.stack.push((far.0 .0, far.0 .1, far.1));
            }
            if near.1 < cutoff {
                self.stack.push((near.0 .0, near.0 .1, near.1));
            }
        }
    }
}

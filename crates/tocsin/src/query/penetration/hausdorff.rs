//! Hausdorff distance between two polygon soups (their surfaces), exact within a user error
//! bound: the one-sided `h(A, B) = max over a in A of d(a, B)`, and the symmetric
//! `max(h(A, B), h(B, A))`.
//!
//! Branch and bound over pieces of A (Tang, Lee and Kim 2009 cull with the hierarchies in the
//! same spirit): a lower bound `L` is the largest `d(a, B)` found at points `a` of A's surface
//! (one exact point-to-mesh distance per piece: the centroid of the triangle in the middle of
//! a node's leaf range, or of a (sub)triangle), and each piece of A keeps an upper bound on
//! `d(a, B)` over the piece; pieces whose bound is at most `L + e` are dropped, the largest
//! bound is split first. When the largest bound left is at most `L + e`, the true value lies in
//! `[L, L + e]` and `L` is returned with its witness points.
//!
//! Upper bounds: the distance to a set is 1-Lipschitz, so a node of A whose volume has centre
//! `o` and bounding radius `r` has `d(a, B) <= d(p, B) + |p - o| + r` for its sampled point
//! `p`, and a triangle with centroid `c` and corners within `r` of it has
//! `d(a, B) <= d(c, B) + r`. And the distance to one triangle `B_j` of B is convex and
//! 1-Lipschitz: over a node's volume (its rectangle grown by its radius) `d(a, B) <= d(a, B_j)`
//! is at most the largest `d(., B_j)` at the rectangle's corners plus the radius, and over a
//! triangle `T` (and the four sub-triangles it is split into, recursively)
//! `max over T of d(., B) = max over T of min_j d(., B_j) <= min_j max over T of d(., B_j)`,
//! the maximum of each `d(., B_j)` over `T` being at a corner. Tighter, since the eighteenth
//! session: each `d(., B_j)` is at most the interpolation of its corner values, so
//! `max over T of d(., B)` is at most the largest over `T` of the smallest of those linear
//! functions (`surface::envelope_bound`, the lower envelope: at a corner or where two or three
//! cross). The triangles of B tried for `j`: the one closest to the piece's sampled point, the
//! two its parent tried (neighbouring points have neighbouring closest triangles) and, for the
//! parts of a split, the three other parts' closest ones (spread over the parent, they are
//! near where the others are not). Where one triangle of B lies under all of `T` (two parallel
//! plates) this is exact at once, where the Lipschitz bound would need `(size / e)^2` pieces.
//!
//! One exact distance per piece, not four (corners and centroid) as before: 2.3 times faster
//! on the benchmark's knot against a moved copy, the same values (docs/BENCHMARKS.md, ninth
//! session).
//!
//! A whole triangle of A that its candidates leave above `L + e` is also bounded by the
//! nearest triangle of B and its vertex neighbours, one at a time (`surface::ring_bound`):
//! where B is A moved a little (a simplified or perturbed copy: the benchmark's hard case,
//! every point near the maximum), the moved copy of the triangle is among them, and bounds it
//! by the move, about the maximum, without splitting it (knot2.8k against its copy moved by
//! (0.3, 0.1, 0.05), instructions per symmetric query at errors 1e-2 / 1e-3 / 1e-4 R: 67.5M /
//! 114.6M / 132.4M -> 63.0M / 80.5M / 82.8M; against turned copies, where it seldom settles a
//! piece, 7.8M / 10.3M / 10.7M -> 7.8M / 10.4M / 10.9M; the ring's envelope with the other
//! candidates instead of each ring triangle alone was no tighter and cost more). Sub-triangles
//! do not try it: their parent did.
//!
//! Against such a copy no node bigger than a few triangles is ever settled by its probe (the
//! volume's radius stays far above the error), and the probes of the nodes above the
//! triangles were most of the work. The search counts, per size class of node (log2 of its
//! triangle count), how many of its probes settled the node; once a class has `SKIP_AFTER` (16)
//! probes and fewer than one in `SKIP_RATE` (16) settled, its nodes are no longer probed: a child
//! keeps its parent's bound (it is part of the parent) and is split when it comes up; skipped
//! nodes add no count, so the decision holds for the rest of the query (knot2.8k
//! against the copy moved by (0.3, 0.1, 0.05), one-thread instructions per symmetric query at
//! 1e-2 / 1e-3 / 1e-4 R: 62.5M / 79.9M / 82.2M -> 52.2M / 67.0M / 66.6M; knot34k at 1e-2 /
//! 1e-4 R 13M and 24M fewer; against a copy turned by 0.5 rad, where the probes settle a
//! quarter to 60% of the nodes of up to 127 triangles and next to nothing is skipped, 7.48M /
//! 9.86M / 10.36M -> 7.63M / 10.05M / 10.54M, the same with skipping turned off: the
//! bookkeeping and the code's layout; the same distances).
//!
//! A piece is first bounded by its parent's two triangles of B alone, before its exact
//! distance: a triangle or a part of one by their envelope, an internal node by the largest
//! distance from its rectangle's corners to either plus its radius (both convex bounds). Where
//! that settles the piece, its exact distance is never computed: the distances to B of
//! neighbouring points are carried by the same triangles, and the pieces far below the maximum
//! are most of a surface. A node settled so counts as a settled probe of its size class (the
//! class's other nodes are worth probing); a class whose parent bounds seldom settle stops
//! computing them, as with the probes. One-thread instructions per symmetric query (knot2.8k;
//! 1e-2 / 1e-3 / 1e-4 R): against the copy moved by (0.3, 0.1, 0.05) 47.6M / 59.3M / 62.7M ->
//! 41.8M / 51.4M / 58.0M, against the copy turned by 0.5 rad 7.42M / 9.64M / 10.13M -> 5.92M /
//! 8.33M / 8.85M; knot11k (1e-2 / 1e-4 R): moved 72.2M / 150.6M -> 64.3M / 132.2M, turned by
//! 0.5 rad 8.02M / 14.80M -> 5.83M / 10.91M, by 1.5 rad 4.38M / 6.96M -> 3.48M / 5.19M. Without
//! counting the nodes it settles as settled probes, the moved copy's skipping flipped on one
//! class and cost 11% more at 1e-3 R.
//!
//! A node's probe samples the centroid of the triangle in the middle of its leaf range; where
//! that triangle is a child of the node, the child's piece takes the probe's distance (plus the
//! rounding between the two placements of the centroid) instead of computing it again (the
//! moved copy 52.2M / 67.0M / 66.6M -> 47.6M / 59.3M / 62.7M, the turned one 7.63M / 10.05M /
//! 10.54M -> 7.42M / 9.64M / 10.12M; knot34k against the moved copy at 1e-4 R 10M fewer; the
//! same distances and bounds).
//!
//! Copies (thirtieth session). Where B has A's triangle list (the same mesh at another pose, which
//! is how a pose error is measured, or a copy whose vertices moved: a deformation, a smoothing),
//! each point of A has a corresponding point of B (the same barycentric combination of the same
//! vertex indices), so its distance to B is at most how far that moved: a triangle's largest
//! corner move, and for the same vertices a node's rigid move (`surface::Copies`, shared with the
//! pointwise depth). A piece is bounded by the smaller of that and its other bounds, and settled
//! by it before any exact distance. Against a moved copy every point is near the maximum and the
//! other bounds only settle pieces near the error's size, while this one is the maximum's value
//! wherever the move is a translation (`examples/profile_hausdorff.rs`, knot2.8k, one thread,
//! symmetric, instructions at 1e-2 / 1e-3 / 1e-4 R: moved by (0.3, 0.1, 0.05) 41.6M / 50.9M /
//! 57.8M -> 0.27M / 0.71M / 10.6M; turned by 0.02 rad and moved by 5% R 39.1M / 49.7M / 53.5M ->
//! 0.54M / 9.6M / 15.4M; turned by 0.5 rad 5.66M / 9.37M / 9.88M -> 4.82M / 7.88M / 8.41M). The
//! bound takes the place of the others' ranking where it is smaller: on the bunny moved by the
//! same (a fifth of its radius: most of its surface lies well below the move, which bounds only
//! the pieces near the maximum and ties the others' ranking) 9.26M / 12.2M / 13.4M -> 0.72M /
//! 13.3M / 14.9M, the finer errors 9 and 11% dearer; ranking nodes by their other bounds instead
//! made the bunny 9.1M / 13.7M at the finer errors but the knot 0.91M / 24.0M
//! (docs/BENCHMARKS.md). Meshes with other triangle lists (a simplified copy) do not have it.
//!
//! Against a copy only translated (the same vertices, `R = I`), every point moved by `t`, the
//! copy bound is `|t|` everywhere, and the search ends once the lower bound is within the error
//! of it; nearly every point is near the maximum but few within a fine error of it, so the
//! search sampled most of the surface to find one. But the corner `a` of A farthest along `t`
//! reaches it: the copy lies behind the plane `x . t = a . t - |t|^2`, so every point of it is
//! at least `|t|` from `a`, and the Hausdorff distance is `|t|` exactly. The search samples
//! that corner first (found by a branch and bound over A's hierarchy, [`Bvh::support`]; an
//! exact distance, so the lower bound stays attained) and ends at the root at any error:
//! symmetric, at 1e-2 / 1e-3 / 1e-4 R, knot2.8k 0.27M / 0.62M / 0.96M -> 0.06M instructions,
//! knot34k 0.12M / 4.2M / 4.2M -> 0.09M, the bunny 0.76M / 7.6M / 15.0M -> 0.05M (the
//! thirtieth session sampled the centroids of the 16 triangles facing the move after 8 pieces
//! instead; docs/BENCHMARKS.md). Turned copies do not have it.

use std::collections::BinaryHeap;

use crate::bvh::{Bvh, Node};
use crate::error::OptionsError;
use crate::math::{Pose, Vec3};
use crate::query::penetration::surface::{
    corner_bound, envelope_bound, node_probe, point_to_mesh, rectangle_corners, ring_bound, split4,
    Copies, Ranked,
};
use crate::TriMesh;

/// Node probes of one size class (see [`OneSided::probes`]) counted before the class may be
/// skipped.
const SKIP_AFTER: u32 = 16;
/// A size class whose probes settled fewer than one in this many is skipped.
const SKIP_RATE: u32 = 16;

#[cfg(test)]
thread_local! {
    /// Whether unpromising node probes are skipped (the tests compare the answers without).
    static SKIPS: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
    /// Node probes skipped on this thread.
    static SKIPPED: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    /// Searches against a translated copy that sampled the triangles facing the move.
    static SEEDED: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    /// Pieces settled or bounded by the correspondence bounds on this thread.
    static COPY_USED: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// The Hausdorff distance found and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HausdorffResult {
    /// A value attained by a point of the surface (model units, >= 0): `d(point1, other mesh)`,
    /// at most the true Hausdorff distance and at least it minus the error bound.
    pub distance: f64,
    /// An upper bound on the true Hausdorff distance (model units; `distance <= true <=
    /// upper_bound`,
    /// `upper_bound - distance <= max_error`).
    pub upper_bound: f64,
    /// The point realising `distance`, on the mesh it is measured from (world frame).
    pub point1: Vec3,
    /// Its closest point on the other mesh (world frame).
    pub point2: Vec3,
    /// Whether `point1` is on mesh 1 (the one-sided distance from mesh 1 to mesh 2 realises
    /// the value); `false` when the symmetric distance is realised from mesh 2.
    pub from_first: bool,
}

/// A piece of A waiting: a node of A's hierarchy or a (sub)triangle, ranked by its upper
/// bound, with the leaf positions of the two triangles of B its bound used (its pieces try
/// them again: neighbouring points have neighbouring closest triangles).
type Piece = Ranked<(PieceKind, [u32; 2])>;

enum PieceKind {
    /// A node, with its probe's exact distance (model units; at the centroid of the triangle
    /// in the middle of its leaf range) where it was probed.
    Node(u32, Option<f64>),
    /// A (sub)triangle, with its bound by the corresponding points of B ([`Copies`];
    /// infinite without).
    Triangle([Vec3; 3], f64),
}

/// The one-sided search from A to B, both in B's frame (A's points mapped by `a_to_b`).
struct OneSided<'a> {
    a: &'a Bvh,
    /// B's triangles at the corresponding points of A's, where B is a copy of A ([`Copies`]).
    copies: Option<Copies<'a>>,
    b: &'a Bvh,
    /// B itself, for its triangles' vertex neighbours.
    b_mesh: &'a TriMesh,
    /// The error bound the search runs to.
    max_error: f64,
    a_to_b: Pose,
    lower: f64,
    witness: (Vec3, Vec3),
    /// The largest upper bound of a piece dropped for being within the error of `lower`.
    dropped: f64,
    /// Per size class of node (the floor of log2 of its triangle count): nodes probed, and
    /// how many of those the probe settled (bounded within the error of `lower`).
    probes: [(u32, u32); 32],
    /// Per size class of node: internal nodes bounded by their parent's two triangles of B
    /// ([`Self::parent_bound`]), and how many of those that bound settled.
    parent_bounds: [(u32, u32); 32],
}

impl OneSided<'_> {
    /// The bound of a node of A (its volume `rss`) by B's corresponding points ([`Copies`]);
    /// infinite where there are none.
    fn copy_bound(&self, rss: &crate::bvh::Rss) -> f64 {
        self.copies.as_ref().map_or(f64::INFINITY, |c| c.node(rss))
    }

    /// Drops a piece whose correspondence bound `copy` is within the error of the lower bound.
    fn settle_by_copy(&mut self, copy: f64) {
        #[cfg(test)]
        COPY_USED.with(|n| n.set(n.get() + 1));
        self.dropped = self.dropped.max(copy);
    }

    /// Keeps a piece worth splitting, or records the bound of one that is not.
    fn keep(&mut self, heap: &mut BinaryHeap<Piece>, p: Piece) {
        if p.upper > self.lower + self.max_error {
            heap.push(p);
        } else {
            self.dropped = self.dropped.max(p.upper);
        }
    }

    /// Exact `d(p, B)` at a surface point of A, raising the lower bound; the search tries the
    /// triangle of B at leaf position `warm` first (the parent piece's nearest: the heap pops
    /// pieces from all over A, so the last query's is seldom near).
    fn sample(&mut self, p: Vec3, warm: u32) -> (f64, u32) {
        let (d, q, leaf) = point_to_mesh(self.b, p, warm);
        if d > self.lower {
            self.lower = d;
            self.witness = (p, q);
        }
        (d, leaf)
    }

    /// A node's piece ([`node_probe`]: one exact distance, at the centroid of its middle
    /// triangle, and the bounds it gives); `tried` are the parent's two triangles of B. A leaf
    /// that was its parent's middle triangle takes the parent probe's distance `known` at its
    /// centroid instead of computing it again (the probe's nearest triangle is `tried[0]`).
    fn node_piece(&mut self, i: u32, tried: [u32; 2], known: Option<f64>) -> Piece {
        let node = &self.a.nodes()[i as usize];
        if node.is_leaf() {
            let corners = self.a.leaf_triangles()[node.leaf_position() as usize];
            let t = corners.map(|p| self.a_to_b.transform_point(p));
            let copy = self.copies.as_ref().map_or(f64::INFINITY, |c| {
                c.triangle(self.a.triangle_index(node.leaf_position()), &t)
            });
            if copy <= self.lower + self.max_error {
                #[cfg(test)]
                COPY_USED.with(|n| n.set(n.get() + 1));
                return Piece {
                    upper: copy,
                    item: (PieceKind::Triangle(t, copy), tried),
                };
            }
            let Some(d) = known else {
                return self.triangle_piece(t, copy, tried);
            };
            // The probe's point is the same centroid placed the other way round: to rounding.
            let p = self
                .a_to_b
                .transform_point((corners[0] + corners[1] + corners[2]) / 3.0);
            let c = (t[0] + t[1] + t[2]) / 3.0;
            let dc = d + (p - c).length();
            let leaf = tried[0];
            return self.bounded((t, copy), dc, leaf, tried, &[leaf, tried[1]], true);
        }
        let probe = node_probe(self.a, &self.a_to_b, self.b, i, tried);
        if probe.distance > self.lower {
            self.lower = probe.distance;
            self.witness = (probe.point, probe.closest);
        }
        self.record(node.leaf_range().len(), probe.upper);
        let copy = self.copy_bound(&node.rss);
        #[cfg(test)]
        if copy < probe.upper {
            COPY_USED.with(|n| n.set(n.get() + 1));
        }
        Piece {
            upper: probe.upper.min(copy).max(probe.distance),
            item: (
                PieceKind::Node(i, Some(probe.distance)),
                [probe.leaf, tried[0]],
            ),
        }
    }

    /// A (sub)triangle's piece: the envelope of the parent's two triangles of B `tried` when
    /// that settles it; else one exact distance, at its centroid, and the smaller of the two
    /// bounds.
    fn triangle_piece(&mut self, t: [Vec3; 3], copy: f64, tried: [u32; 2]) -> Piece {
        // The parent's triangles alone may settle it, without the exact distance.
        let pre = envelope_bound(self.b, &t, &tried);
        if pre <= self.lower + self.max_error {
            return Piece {
                upper: pre,
                item: (PieceKind::Triangle(t, copy), tried),
            };
        }
        let c = (t[0] + t[1] + t[2]) / 3.0;
        let (dc, leaf) = self.sample(c, tried[0]);
        self.bounded(
            (t, copy),
            dc,
            leaf,
            tried,
            &[leaf, tried[0], tried[1]],
            true,
        )
    }

    /// A (sub)triangle's piece from its centroid's distance `dc` and nearest triangle `leaf`:
    /// the smaller of the Lipschitz bound and the envelope over `candidates`; with `ring` (a
    /// whole triangle of A), where that does not settle the piece, also [`ring_bound`] over
    /// `leaf` and its vertex neighbours; never above `copy`, the bound by B's corresponding
    /// points ([`Copies`]).
    fn bounded(
        &self,
        (t, copy): ([Vec3; 3], f64),
        dc: f64,
        leaf: u32,
        tried: [u32; 2],
        candidates: &[u32],
        ring: bool,
    ) -> Piece {
        let c = (t[0] + t[1] + t[2]) / 3.0;
        let r = t.iter().fold(0.0_f64, |m, p| m.max((*p - c).length()));
        let mut upper = (dc + r).min(envelope_bound(self.b, &t, candidates));
        #[cfg(test)]
        if copy < upper {
            COPY_USED.with(|n| n.set(n.get() + 1));
        }
        upper = upper.min(copy);
        if ring && upper > self.lower + self.max_error {
            upper = upper.min(ring_bound(self.b_mesh, &t, leaf));
        }
        Piece {
            upper: upper.max(dc),
            item: (PieceKind::Triangle(t, copy), [leaf, tried[0]]),
        }
    }

    /// The bound of an internal node from its parent's two triangles of B `tried`, without an
    /// exact distance: the distance to one triangle is convex and 1-Lipschitz, so over the
    /// volume it is at most its largest value at the rectangle's corners plus the radius.
    /// `None` when that settles the node (it is dropped, and counts as a settled probe of its
    /// size class: the class's other nodes are worth probing); else the bound, infinite where
    /// it was not computed: once a size class has [`SKIP_AFTER`] such bounds and fewer than one
    /// in [`SKIP_RATE`] settled, its nodes skip it.
    fn parent_bound(&mut self, node: &Node, tried: [u32; 2]) -> Option<f64> {
        let class = size_class(node.leaf_range().len());
        let (bounded, settled) = self.parent_bounds[class];
        if bounded >= SKIP_AFTER && settled * SKIP_RATE < bounded {
            return Some(f64::INFINITY);
        }
        let corners = rectangle_corners(&node.rss, &self.a_to_b);
        let bound = corner_bound(self.b, &corners, &tried) + node.rss.radius;
        let settles = bound <= self.lower + self.max_error;
        self.parent_bounds[class].0 += 1;
        self.parent_bounds[class].1 += u32::from(settles);
        if settles {
            self.record(node.leaf_range().len(), bound);
            self.dropped = self.dropped.max(bound);
            return None;
        }
        Some(bound)
    }

    /// Counts a probe of a node of `triangles` triangles that bounded it by `upper`.
    fn record(&mut self, triangles: usize, upper: f64) {
        let (probed, settled) = &mut self.probes[size_class(triangles)];
        *probed += 1;
        *settled += u32::from(upper <= self.lower + self.max_error);
    }

    /// Whether nodes of size class `class` go unprobed: at least [`SKIP_AFTER`] probed, and
    /// fewer than one in [`SKIP_RATE`] of those settled.
    fn unpromising(&self, class: usize) -> bool {
        #[cfg(test)]
        if !SKIPS.with(|c| c.get()) {
            return false;
        }
        let (probed, settled) = self.probes[class];
        probed >= SKIP_AFTER && settled * SKIP_RATE < probed
    }

    /// Against a copy only translated by `t` (the same vertices, B = A - t in B's frame, where
    /// A's points sit), no distance exceeds `|t|`, and the corner of A farthest along `t`
    /// reaches it: every point `x` of B has `x . t <= a . t - |t|^2` for that corner `a`, so
    /// `|a - x| >= |t|`. That corner ([`Bvh::support`], a branch and bound over A's hierarchy)
    /// is sampled (an exact distance, so the lower bound stays attained), which raises the lower
    /// bound to the copy bound, and the search ends at once at any error.
    fn seed_translated(&mut self, t: Vec3) {
        #[cfg(test)]
        SEEDED.with(|n| n.set(n.get() + 1));
        if let Some(a) = self.a.support(t) {
            let p = self.a_to_b.transform_point(a);
            self.sample(p, 0);
        }
    }

    fn run(&mut self) -> f64 {
        let mut heap = BinaryHeap::new();
        if let Some(t) = self.copies.as_ref().and_then(Copies::translation) {
            self.seed_translated(t);
        }
        let root = self.node_piece(0, [0, 0], None);
        heap.push(root);
        while let Some(piece) = heap.pop() {
            if piece.upper <= self.lower + self.max_error {
                // The largest bound left is within the error: done.
                return piece.upper.max(self.lower).max(self.dropped);
            }
            let (item, tried) = piece.item;
            match item {
                PieceKind::Node(i, probed) => {
                    let nodes = self.a.nodes();
                    let parent = &nodes[i as usize];
                    let middle = parent.leaf_range().start + parent.leaf_range().len() / 2;
                    let (l, r) = parent.children(i);
                    for c in [l, r] {
                        let node = &nodes[c as usize];
                        if !node.is_leaf() {
                            let copy = self.copy_bound(&node.rss);
                            if copy <= self.lower + self.max_error {
                                self.settle_by_copy(copy);
                                continue;
                            }
                        }
                        let pre = if node.is_leaf() {
                            f64::INFINITY
                        } else {
                            match self.parent_bound(node, tried) {
                                Some(bound) => bound,
                                None => continue,
                            }
                        };
                        let p = if !node.is_leaf()
                            && self.unpromising(size_class(node.leaf_range().len()))
                        {
                            // The probes of this size settle next to nothing here: the child
                            // keeps its parent's bound (it is part of the parent), unprobed.
                            #[cfg(test)]
                            SKIPPED.with(|n| n.set(n.get() + 1));
                            Piece {
                                upper: piece.upper.min(pre).min(self.copy_bound(&node.rss)),
                                item: (PieceKind::Node(c, None), tried),
                            }
                        } else {
                            let own = node.is_leaf() && node.leaf_position() as usize == middle;
                            self.node_piece(c, tried, probed.filter(|_| own))
                        };
                        self.keep(&mut heap, p);
                    }
                }
                PieceKind::Triangle(t, copy) => {
                    // The parts that the parent's triangles do not settle are sampled first,
                    // then bounded with each other's nearest triangles of B among the
                    // candidates too (spread over the parent, they tighten the envelope).
                    let subs = split4(t);
                    let pre = subs.map(|sub| envelope_bound(self.b, &sub, &tried));
                    let mut sampled = [(0.0, tried[0]); 4];
                    for (k, sub) in subs.iter().enumerate() {
                        if pre[k] > self.lower + self.max_error {
                            sampled[k] = self.sample((sub[0] + sub[1] + sub[2]) / 3.0, tried[0]);
                        }
                    }
                    for (k, sub) in subs.into_iter().enumerate() {
                        if pre[k] <= self.lower + self.max_error {
                            self.dropped = self.dropped.max(pre[k]);
                            continue;
                        }
                        let (dc, leaf) = sampled[k];
                        let mut candidates = [leaf; 6];
                        (candidates[1], candidates[2]) = (tried[0], tried[1]);
                        let mut n = 3;
                        for (j, &(_, l)) in sampled.iter().enumerate() {
                            if j != k {
                                candidates[n] = l;
                                n += 1;
                            }
                        }
                        let p = self.bounded((sub, copy), dc, leaf, tried, &candidates, false);
                        self.keep(&mut heap, p);
                    }
                }
            }
        }
        self.lower.max(self.dropped)
    }
}

/// A node's size class: the floor of log2 of its triangle count (0 to 31).
fn size_class(triangles: usize) -> usize {
    (usize::BITS - 1 - triangles.max(1).leading_zeros()).min(31) as usize
}

/// The Hausdorff distance from `mesh1` to `mesh2` (one-sided, `max over a in mesh1 of
/// d(a, mesh2)`), or with `symmetric` the larger of both directions, within `max_error`
/// (model units, > 0; module docs). A mesh against itself at another pose, or against a
/// copy with the same triangle list, is bounded by how far corresponding points moved, which
/// makes a pose error quick to measure.
///
/// A `max_error` below the distances' accuracy
/// ([`crate::query::contact_time::DISTANCE_RESOLUTION`] of the radii plus the poses' distances
/// from the origin) is raised to it: below it the search could not end.
///
/// # Errors
/// [`OptionsError`] when `max_error` is not positive and finite.
pub fn hausdorff_distance(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    max_error: f64,
    symmetric: bool,
) -> Result<HausdorffResult, OptionsError> {
    if !(max_error.is_finite() && max_error > 0.0) {
        return Err(OptionsError::OutOfRange {
            name: "max_error",
            requirement: "must be positive and finite",
            value: max_error,
        });
    }
    let max_error = super::resolved_error(max_error, (mesh1, pose1), (mesh2, pose2));
    let one = |a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose, from_first: bool| {
        let a_to_b = pb.inv_mul(pa);
        let mut s = OneSided {
            a: a.bvh(),
            copies: Copies::new(a, b, &a_to_b),
            b: b.bvh(),
            b_mesh: b,
            max_error,
            a_to_b,
            lower: 0.0,
            witness: (Vec3::ZERO, Vec3::ZERO),
            dropped: 0.0,
            probes: [(0, 0); 32],
            parent_bounds: [(0, 0); 32],
        };
        let upper = s.run();
        HausdorffResult {
            distance: s.lower,
            upper_bound: upper.max(s.lower),
            point1: pb.transform_point(s.witness.0),
            point2: pb.transform_point(s.witness.1),
            from_first,
        }
    };
    if !symmetric {
        return Ok(one(mesh1, pose1, mesh2, pose2, true));
    }
    // The two directions are independent searches: on two threads when rayon has them.
    let (forward, backward) = rayon::join(
        || one(mesh1, pose1, mesh2, pose2, true),
        || one(mesh2, pose2, mesh1, pose1, false),
    );
    Ok(HausdorffResult {
        upper_bound: forward.upper_bound.max(backward.upper_bound),
        ..if backward.distance > forward.distance {
            backward
        } else {
            forward
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh;

    /// Two answers to one query, each within the error `e` and both holding the true value
    /// (their intervals `[distance, upper_bound]` overlap).
    fn agree(a: &HausdorffResult, b: &HausdorffResult, e: f64, label: &str) {
        for h in [a, b] {
            assert!(
                h.upper_bound - h.distance <= e * (1.0 + 1e-9),
                "{label}: {h:?}"
            );
        }
        assert!(
            a.distance.max(b.distance) <= a.upper_bound.min(b.upper_bound) * (1.0 + 1e-12),
            "{label}: {a:?} against {b:?}"
        );
    }

    /// Skipping unpromising node probes changes no answer beyond the error bound: on a knot
    /// against a copy moved a little (where the probes are skipped) and against a turned copy,
    /// one-sided, at errors of 1e-2 and 1e-3 of the radius, with and without skipping, each
    /// interval `[distance, upper_bound]` is within the error and the two overlap (both hold
    /// the true value); and the moved copy does skip probes.
    #[test]
    fn skipped_probes_change_no_answer() {
        let m = mesh::torus_knot(100, 8).expect("knot");
        let r = m.bounding_radius();
        let poses = [
            Pose::from_axis_angle(Vec3::X, 0.0, Vec3::new(0.3, 0.1, 0.05)),
            Pose::from_axis_angle(
                Vec3::new(0.3, 1.0, -0.2).normalize(),
                0.5,
                Vec3::new(0.6, -0.3, 0.74).normalize() * (0.05 * r),
            ),
        ];
        for (k, pose) in poses.iter().enumerate() {
            for rel in [1e-2, 1e-3] {
                let e = rel * r;
                let run = |skip: bool| {
                    // The correspondence bounds settle the moved copy before any skipping:
                    // off, it stands for a perturbed copy with other triangles.
                    crate::query::penetration::surface::COPIES.with(|c| c.set(false));
                    SKIPS.with(|c| c.set(skip));
                    SKIPPED.with(|c| c.set(0));
                    let h = hausdorff_distance(&m, &Pose::IDENTITY, &m, pose, e, false)
                        .expect("hausdorff");
                    SKIPS.with(|c| c.set(true));
                    crate::query::penetration::surface::COPIES.with(|c| c.set(true));
                    (h, SKIPPED.with(|c| c.get()))
                };
                let ((with, skipped), (without, none)) = (run(true), run(false));
                assert_eq!(none, 0);
                if k == 0 {
                    assert!(skipped > 0, "no probe skipped against the moved copy");
                }
                agree(&with, &without, e, &format!("pose {k}, error {rel}"));
            }
        }
    }

    /// The correspondence bounds change no answer beyond the error bound, and they are what
    /// ends the search against a copy: the same knot moved, the same knot moved and turned a
    /// little, a separately built equal knot (the same values in other memory), and a copy with
    /// the same triangles whose vertices moved by up to 1% of the radius; one-sided and
    /// symmetric, at errors of 1e-2 and 1e-3 of the radius, with and without the bounds: each
    /// interval `[distance, upper_bound]` within the error, the two overlapping, and pieces
    /// settled or bounded by them. A knot against a different knot has no correspondence.
    #[test]
    fn copy_bounds_change_no_answer() {
        let m = mesh::torus_knot(100, 8).expect("knot");
        let r = m.bounding_radius();
        let rebuilt = mesh::torus_knot(100, 8).expect("knot");
        // Seeded offsets of every vertex, up to 1% of the radius per coordinate.
        let perturbed = crate::query::penetration::surface::tests::jittered(&m, 0.01 * r, 7);
        let moved = Pose::from_translation(Vec3::new(0.3, 0.1, 0.05));
        let turned = Pose::from_axis_angle(
            Vec3::new(0.3, 1.0, -0.2).normalize(),
            0.02,
            Vec3::new(0.6, -0.3, 0.74).normalize() * (0.05 * r),
        );
        let cases: [(&TriMesh, Pose); 4] = [
            (&m, moved),
            (&m, turned),
            (&rebuilt, moved),
            (
                &perturbed,
                Pose::from_translation(Vec3::new(0.05, 0.0, 0.02)),
            ),
        ];
        for (k, (b, pose)) in cases.iter().enumerate() {
            for rel in [1e-2, 1e-3] {
                for symmetric in [false, true] {
                    let e = rel * r;
                    // On one thread: the switch and the count are per thread, and a
                    // symmetric search joins its two directions.
                    let run = |copies: bool| {
                        crate::query::penetration::surface::tests::one_thread().install(|| {
                            crate::query::penetration::surface::COPIES.with(|c| c.set(copies));
                            COPY_USED.with(|c| c.set(0));
                            let h = hausdorff_distance(&m, &Pose::IDENTITY, b, pose, e, symmetric)
                                .expect("hausdorff");
                            crate::query::penetration::surface::COPIES.with(|c| c.set(true));
                            (h, COPY_USED.with(|c| c.get()))
                        })
                    };
                    let ((with, settled), (without, none)) = (run(true), run(false));
                    assert_eq!(none, 0);
                    assert!(
                        settled > 0,
                        "case {k}, error {rel}: the copy bounded nothing"
                    );
                    agree(&with, &without, e, &format!("case {k}, error {rel}"));
                }
            }
            // The bound exists for every case, and not for a different knot.
            let to_b = pose.inv_mul(&Pose::IDENTITY);
            assert!(Copies::new(&m, b, &to_b).is_some(), "case {k}");
            assert_eq!(
                Copies::new(&m, b, &to_b).is_some_and(|c| c.rigid.is_some()),
                k < 3,
                "case {k}"
            );
        }
        let other = mesh::torus_knot(101, 8).expect("knot");
        assert!(Copies::new(&m, &other, &moved).is_none());
    }

    /// The bounds hold at every point: the largest move of a triangle's corners bounds the
    /// distance of seeded points of it to the copy, and a node's rigid bound every corner
    /// of its triangles' moves.
    #[test]
    fn copy_bounds_hold_pointwise() {
        let m = mesh::torus_knot(40, 6).expect("knot");
        let pose = Pose::from_axis_angle(
            Vec3::new(0.2, 1.0, -0.4).normalize(),
            0.3,
            Vec3::new(-0.1, 0.2, 0.0),
        );
        let a_to_b = pose;
        let copies = Copies::new(&m, &m, &a_to_b).expect("the same mesh corresponds");
        let bvh = m.bvh();
        for (i, node) in bvh.nodes().iter().enumerate() {
            let bound = copies.node(&node.rss);
            for leaf in node.leaf_range() {
                let t = bvh.leaf_triangles()[leaf].map(|p| a_to_b.transform_point(p));
                let tri = copies.triangle(bvh.triangle_index(leaf as u32), &t);
                assert!(tri <= bound * (1.0 + 1e-12), "node {i}: {tri} > {bound}");
                for (u, v) in [(0.2, 0.3), (0.6, 0.1), (1.0 / 3.0, 1.0 / 3.0)] {
                    let p = t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
                    let (d, _, _) = crate::query::penetration::surface::point_to_mesh(bvh, p, 0);
                    assert!(d <= tri, "leaf {leaf}: {d} > {tri}");
                }
            }
        }
    }

    /// Against a copy only translated, at a fine error, the search samples the corner farthest
    /// along the move, which reaches the move's length, and ends with the same answer as
    /// without the correspondence bounds (and without that sample); against a turned copy it
    /// does not sample it.
    #[test]
    fn translated_copies_sample_the_corner_farthest_along_the_move() {
        let m = mesh::torus_knot(100, 8).expect("knot");
        let e = 1e-4 * m.bounding_radius();
        let turned = Pose::from_axis_angle(Vec3::Z, 0.01, Vec3::new(0.3, 0.1, 0.05));
        for (k, pose) in [Pose::from_translation(Vec3::new(0.3, 0.1, 0.05)), turned]
            .iter()
            .enumerate()
        {
            let run = |copies: bool| {
                crate::query::penetration::surface::tests::one_thread().install(|| {
                    crate::query::penetration::surface::COPIES.with(|c| c.set(copies));
                    SEEDED.with(|c| c.set(0));
                    let h = hausdorff_distance(&m, &Pose::IDENTITY, &m, pose, e, true)
                        .expect("hausdorff");
                    crate::query::penetration::surface::COPIES.with(|c| c.set(true));
                    (h, SEEDED.with(|c| c.get()))
                })
            };
            let ((with, seeded), (without, none)) = (run(true), run(false));
            assert_eq!(none, 0);
            assert_eq!(seeded > 0, k == 0, "pose {k}: {seeded} seeded searches");
            agree(&with, &without, e, &format!("pose {k}"));
            if k == 0 {
                let t = pose.translation.length();
                assert!(
                    (with.distance - t).abs() <= 1e-14 && (with.upper_bound - t).abs() <= 1e-14
                );
            }
        }
    }
}

//! Hausdorff distance between two polygon soups (their surfaces), exact within a user error
//! bound: the one-sided `h(A, B) = max over a in A of d(a, B)`, and the symmetric
//! `max(h(A, B), h(B, A))`.
//!
//! Branch and bound over pieces of A (Tang, Lee and Kim 2009 cull with the hierarchies in the
//! same spirit): a lower bound `L` is the largest `d(a, B)` found at points `a` of A's surface
//! (triangle corners and centroids, from exact point-to-mesh distances), and each piece of A
//! keeps an upper bound on `d(a, B)` over the piece; pieces whose bound is at most `L + e` are
//! dropped, the largest bound is split first. When the largest bound left is at most `L + e`,
//! the true value lies in `[L, L + e]` and `L` is returned with its witness points.
//!
//! Upper bounds: a hierarchy node of A with centre `c` and bounding radius `r` has
//! `d(a, B) <= d(c, B) + r` (the distance to a set is 1-Lipschitz), and, the node's volume being
//! its rectangle grown by its radius, `d(a, B) <= d(a, B_j) <=` the largest `d(., B_j)` at the
//! rectangle's corners plus the radius, for any triangle `B_j` of B (convex and 1-Lipschitz;
//! the triangles nearest the centre and a corner are tried). A triangle `T` of A (and
//! the four sub-triangles it is split into, recursively) has, besides that,
//! `max over T of d(., B) = max over T of min_j d(., B_j) <= min_j max over T of d(., B_j)`, and
//! each `d(., B_j)` (distance to one triangle of B) is convex, so its maximum over `T` is at
//! a corner: any triangle `j` of B gives the bound `max_corners d(corner, B_j)`. The triangles
//! of B closest to `T`'s corners are tried: where one triangle of B lies under all of `T` (two
//! parallel plates) this is exact at once, where the Lipschitz bound would need `(size / e)^2`
//! pieces.

use std::collections::BinaryHeap;

use crate::bvh::{Bvh, Rss};
use crate::error::OptionsError;
use crate::math::{Pose, Vec3};
use crate::query::distance::distance_triangle_triangle;
use crate::TriMesh;

/// The Hausdorff distance found and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HausdorffResult {
    /// A value attained by a point of the surface: `d(point1, other mesh)`, at most the true
    /// Hausdorff distance and at least it minus the error bound.
    pub distance: f64,
    /// An upper bound on the true Hausdorff distance (`distance <= true <= upper_bound`,
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

/// Distance from `p` (B's frame) to B, below `cutoff` when it is; the closest point and the
/// triangle's leaf position. `warm` is a leaf tried first.
fn point_to_mesh(bvh: &Bvh, p: Vec3, warm: u32) -> (f64, Vec3, u32) {
    let nodes = bvh.nodes();
    let tris = bvh.leaf_triangles();
    let point = [p; 3];
    let w = (warm as usize).min(tris.len() - 1);
    let first = distance_triangle_triangle(&point, &tris[w]);
    let (mut best, mut closest, mut leaf) = (first.distance, first.point2, w as u32);
    let mut stack: Vec<(u32, f64)> = vec![(0, rss_point_bound(&nodes[0].rss, p))];
    while let Some((i, lb)) = stack.pop() {
        if lb >= best {
            continue;
        }
        let node = &nodes[i as usize];
        if node.is_leaf() {
            let pos = node.leaf_position();
            let d = distance_triangle_triangle(&point, &tris[pos as usize]);
            if d.distance < best {
                (best, closest, leaf) = (d.distance, d.point2, pos);
            }
            continue;
        }
        let (l, r) = node.children(i);
        let (bl, br) = (
            rss_point_bound(&nodes[l as usize].rss, p),
            rss_point_bound(&nodes[r as usize].rss, p),
        );
        // Nearer child on top.
        if bl <= br {
            stack.push((r, br));
            stack.push((l, bl));
        } else {
            stack.push((l, bl));
            stack.push((r, br));
        }
    }
    (best, closest, leaf)
}

/// A lower bound on the distance from `p` to the volume.
#[inline]
fn rss_point_bound(rss: &Rss, p: Vec3) -> f64 {
    let q = rss.axes.transpose() * (p - rss.center);
    let dx = (q.x.abs() - rss.half_lengths[0]).max(0.0);
    let dy = (q.y.abs() - rss.half_lengths[1]).max(0.0);
    ((dx * dx + dy * dy + q.z * q.z).sqrt() - rss.radius).max(0.0)
}

/// A piece of A waiting: a node of A's hierarchy or a (sub)triangle, with its upper bound.
struct Piece {
    upper: f64,
    kind: PieceKind,
}

enum PieceKind {
    Node(u32),
    Triangle([Vec3; 3]),
}

impl PartialEq for Piece {
    fn eq(&self, other: &Self) -> bool {
        self.upper == other.upper
    }
}
impl Eq for Piece {}
impl PartialOrd for Piece {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Piece {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.upper.total_cmp(&other.upper)
    }
}

/// The one-sided search from A to B, both in B's frame (A's points mapped by `a_to_b`).
struct OneSided<'a> {
    a: &'a Bvh,
    b: &'a Bvh,
    a_to_b: Pose,
    lower: f64,
    witness: (Vec3, Vec3),
    warm: u32,
    /// The largest upper bound of a piece dropped for being within the error of `lower`.
    dropped: f64,
}

impl OneSided<'_> {
    /// Keeps a piece worth splitting, or records the bound of one that is not.
    fn keep(&mut self, heap: &mut BinaryHeap<Piece>, p: Piece, max_error: f64) {
        if p.upper > self.lower + max_error {
            heap.push(p);
        } else {
            self.dropped = self.dropped.max(p.upper);
        }
    }

    /// Exact `d(p, B)` at a surface point of A, raising the lower bound.
    fn sample(&mut self, p: Vec3) -> (f64, u32) {
        let (d, q, leaf) = point_to_mesh(self.b, p, self.warm);
        self.warm = leaf;
        if d > self.lower {
            self.lower = d;
            self.witness = (p, q);
        }
        (d, leaf)
    }

    /// A node's piece: its volume's centre and bounding radius.
    fn node_piece(&mut self, i: u32) -> Piece {
        let node = &self.a.nodes()[i as usize];
        if node.is_leaf() {
            let t = self.a.leaf_triangles()[node.leaf_position() as usize]
                .map(|p| self.a_to_b.transform_point(p));
            return self.triangle_piece(t);
        }
        let rss = &node.rss;
        let c = self.a_to_b.transform_point(rss.center);
        let (d, _, leaf) = point_to_mesh(self.b, c, self.warm);
        self.warm = leaf;
        // A point of the node's surface keeps the lower bound moving.
        let first = self.a.leaf_triangles()[node.leaf_range().start][0];
        let (_, first_leaf) = self.sample(self.a_to_b.transform_point(first));
        // The volume is its rectangle grown by its radius, and the distance to one triangle
        // of B is convex and 1-Lipschitz: over the volume it is at most its largest value at
        // the rectangle's corners plus the radius.
        let (e0, e1) = (
            rss.axes.x_axis * rss.half_lengths[0],
            rss.axes.y_axis * rss.half_lengths[1],
        );
        let corners = [
            rss.center + e0 + e1,
            rss.center + e0 - e1,
            rss.center - e0 + e1,
            rss.center - e0 - e1,
        ]
        .map(|p| self.a_to_b.transform_point(p));
        let tris = self.b.leaf_triangles();
        let mut upper = d + rss.bounding_radius();
        for j in [leaf, first_leaf] {
            let bj = &tris[j as usize];
            let worst = corners
                .iter()
                .map(|p| distance_triangle_triangle(&[*p; 3], bj).distance)
                .fold(0.0_f64, f64::max);
            upper = upper.min(worst + rss.radius);
        }
        Piece {
            upper,
            kind: PieceKind::Node(i),
        }
    }

    /// A (sub)triangle's piece: corners and centroid sampled, the smaller of the two bounds.
    fn triangle_piece(&mut self, t: [Vec3; 3]) -> Piece {
        let mut leaves = [0u32; 3];
        let mut corner_max: f64 = 0.0;
        for k in 0..3 {
            let (d, leaf) = self.sample(t[k]);
            leaves[k] = leaf;
            corner_max = corner_max.max(d);
        }
        let c = (t[0] + t[1] + t[2]) / 3.0;
        let (dc, _) = self.sample(c);
        let r = t.iter().fold(0.0_f64, |m, p| m.max((*p - c).length()));
        let mut upper = dc + r;
        let tris = self.b.leaf_triangles();
        for &j in &leaves {
            let bj = &tris[j as usize];
            let worst = t
                .iter()
                .map(|p| distance_triangle_triangle(&[*p; 3], bj).distance)
                .fold(0.0_f64, f64::max);
            upper = upper.min(worst);
        }
        Piece {
            upper: upper.max(corner_max),
            kind: PieceKind::Triangle(t),
        }
    }

    fn run(&mut self, max_error: f64) -> f64 {
        let mut heap = BinaryHeap::new();
        let root = self.node_piece(0);
        heap.push(root);
        while let Some(piece) = heap.pop() {
            if piece.upper <= self.lower + max_error {
                // The largest bound left is within the error: done.
                return piece.upper.max(self.lower).max(self.dropped);
            }
            match piece.kind {
                PieceKind::Node(i) => {
                    let (l, r) = self.a.nodes()[i as usize].children(i);
                    for c in [l, r] {
                        let p = self.node_piece(c);
                        self.keep(&mut heap, p, max_error);
                    }
                }
                PieceKind::Triangle(t) => {
                    let m = [
                        (t[0] + t[1]) * 0.5,
                        (t[1] + t[2]) * 0.5,
                        (t[2] + t[0]) * 0.5,
                    ];
                    for sub in [
                        [t[0], m[0], m[2]],
                        [m[0], t[1], m[1]],
                        [m[2], m[1], t[2]],
                        [m[0], m[1], m[2]],
                    ] {
                        let p = self.triangle_piece(sub);
                        self.keep(&mut heap, p, max_error);
                    }
                }
            }
        }
        self.lower.max(self.dropped)
    }
}

/// The Hausdorff distance from `mesh1` to `mesh2` (one-sided, `max over a in mesh1 of
/// d(a, mesh2)`), or with `symmetric` the larger of both directions, within `max_error`
/// (model units, > 0; module docs).
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
    let one = |a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose, from_first: bool| {
        let mut s = OneSided {
            a: a.bvh(),
            b: b.bvh(),
            a_to_b: pb.inv_mul(pa),
            lower: 0.0,
            witness: (Vec3::ZERO, Vec3::ZERO),
            warm: 0,
            dropped: 0.0,
        };
        let upper = s.run(max_error);
        HausdorffResult {
            distance: s.lower,
            upper_bound: upper.max(s.lower),
            point1: pb.transform_point(s.witness.0),
            point2: pb.transform_point(s.witness.1),
            from_first,
        }
    };
    let forward = one(mesh1, pose1, mesh2, pose2, true);
    if !symmetric {
        return Ok(forward);
    }
    let backward = one(mesh2, pose2, mesh1, pose1, false);
    Ok(HausdorffResult {
        upper_bound: forward.upper_bound.max(backward.upper_bound),
        ..if backward.distance > forward.distance {
            backward
        } else {
            forward
        }
    })
}

//! Pointwise penetration depth (Tang, Lee and Kim, SIGGRAPH 2009): the deepest interpenetrating
//! points. The parts of each surface that lie inside the other body (by the winding number,
//! [`super::winding`]) are measured against the other surface; the depth is the largest
//! distance from such a point to the other surface (the Hausdorff distance from the inside parts
//! to it), within an error bound, with the two points that realise it.
//!
//! The search is the Hausdorff distance's (`hausdorff.rs`) restricted to inside points: samples
//! raise the lower bound only where they are inside the other body, and a piece (a node of the
//! hierarchy, whose bounding ball is tested, then a triangle split in four) that does not meet
//! the other surface (its distance to it is positive) lies on one side of it, decided at its
//! centre: outside pieces are dropped (a whole subtree at once), inside ones keep their upper
//! bounds. For closed meshes that is exact; for soups with
//! holes, where the winding number varies without crossing the surface, a piece is classified by
//! its centroid (said on [`pointwise_penetration`]).

use std::collections::BinaryHeap;

use crate::error::OptionsError;
use crate::math::{Pose, Vec3};
use crate::query::penetration::surface::{
    corner_bound, point_to_mesh, split4, triangle_meets_mesh, Ranked,
};
use crate::query::penetration::winding::inside;
use crate::TriMesh;

/// The deepest interpenetrating points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointwisePenetration {
    /// Depth attained (model units, >= 0; 0 when no part of either surface is inside the other).
    pub depth: f64,
    /// Upper bound on the true pointwise depth (model units; `depth <= true <= upper_bound`).
    pub upper_bound: f64,
    /// The deepest point found, on the surface of the body it belongs to (world frame).
    pub point1: Vec3,
    /// Its closest point on the other surface (world frame).
    pub point2: Vec3,
    /// Whether `point1` is on mesh 1 (inside mesh 2); `false`: on mesh 2 inside mesh 1.
    pub from_first: bool,
}

/// A (sub)triangle of A waiting, ranked by its upper bound, with the two triangles of B its
/// bound tried and whether it is known to be inside B without meeting its surface.
type Piece = Ranked<([Vec3; 3], [u32; 2], bool)>;

/// One direction: the parts of A inside B, measured against B's surface (all in B's frame).
struct Inside<'a> {
    b_mesh: &'a TriMesh,
    lower: f64,
    witness: (Vec3, Vec3),
    dropped: f64,
    /// The last closest triangle of B (neighbouring queries start from it).
    warm: u32,
}

impl Inside<'_> {
    fn inside(&self, p: Vec3) -> bool {
        inside(self.b_mesh, p)
    }

    /// Samples `p` (a point of A): raises the lower bound if it is inside B. Returns the
    /// distance to B and the leaf position of B's closest triangle.
    fn sample(&mut self, p: Vec3) -> (f64, u32) {
        let (d, q, leaf) = point_to_mesh(self.b_mesh.bvh(), p, self.warm);
        self.warm = leaf;
        if d > self.lower && self.inside(p) {
            self.lower = d;
            self.witness = (p, q);
        }
        (d, leaf)
    }

    /// The piece's upper bound, or `None` when it lies outside B (it does not meet B's surface
    /// and its centroid is outside). One exact point distance, at the centroid; the convex-corner
    /// bound tries B's triangles nearest the piece and its centroid and the two its parent
    /// tried (`tried`), which the piece passes on. `clear`: the piece is known to lie inside B
    /// without meeting its surface (a part of such a piece, or of such a node), so neither is
    /// tested again.
    fn piece(&mut self, t: [Vec3; 3], tried: [u32; 2], clear: bool) -> Option<Piece> {
        let c = (t[0] + t[1] + t[2]) / 3.0;
        let meets = if clear {
            None
        } else {
            let meets = triangle_meets_mesh(self.b_mesh.bvh(), &t, self.warm);
            if meets.is_none() && !self.inside(c) {
                return None;
            }
            meets
        };
        let (dc, leaf) = self.sample(c);
        let near = meets.unwrap_or(leaf);
        let r = t.iter().fold(0.0_f64, |m, p| m.max((*p - c).length()));
        // As in the Hausdorff search: the convex-corner bound.
        let candidates = [near, leaf, tried[0], tried[1]];
        let upper = (dc + r).min(corner_bound(self.b_mesh.bvh(), &t, &candidates));
        Some(Piece {
            upper: upper.max(dc),
            item: (t, [leaf, near], meets.is_none()),
        })
    }

    fn run(&mut self, a: &TriMesh, a_to_b: &Pose, max_error: f64) -> f64 {
        let mut heap = BinaryHeap::new();
        // A's hierarchy first: a node whose bounding ball does not meet B's surface lies on
        // one side of it (the ball is connected), decided at its centre; outside nodes are
        // dropped whole, the triangles of inside ones are pieces known to be clear of B's
        // surface (no further test), those of the others become pieces tested on their own.
        let (nodes, tris) = (a.bvh().nodes(), a.bvh().leaf_triangles());
        let mut stack = vec![(0u32, false)];
        let mut leaf = 0;
        while let Some((i, mut clear)) = stack.pop() {
            let node = &nodes[i as usize];
            if !clear {
                let c = a_to_b.transform_point(node.rss.center);
                let (d, _, near) = point_to_mesh(self.b_mesh.bvh(), c, self.warm);
                (self.warm, leaf) = (near, near);
                if d > node.rss.bounding_radius() {
                    if !self.inside(c) {
                        continue;
                    }
                    clear = true;
                }
            }
            if node.is_leaf() {
                let t = tris[node.leaf_position() as usize].map(|p| a_to_b.transform_point(p));
                if let Some(p) = self.piece(t, [leaf, self.warm], clear) {
                    heap.push(p);
                }
                continue;
            }
            let (l, r) = node.children(i);
            stack.push((l, clear));
            stack.push((r, clear));
        }
        while let Some(piece) = heap.pop() {
            if piece.upper <= self.lower + max_error {
                return piece.upper.max(self.lower).max(self.dropped);
            }
            let (t, tried, clear) = piece.item;
            for sub in split4(t) {
                if let Some(p) = self.piece(sub, tried, clear) {
                    if p.upper > self.lower + max_error {
                        heap.push(p);
                    } else {
                        self.dropped = self.dropped.max(p.upper);
                    }
                }
            }
        }
        self.lower.max(self.dropped)
    }
}

/// The pointwise penetration depth of two placed meshes, within `max_error` (module docs):
/// the largest distance from a point of one surface inside the other body to the other
/// surface. Inside is the winding number's (magnitude above 1/2); a piece of a surface that
/// does not meet the other surface is classified by its centroid, exact for closed meshes.
///
/// # Errors
/// [`OptionsError`] when `max_error` is not positive and finite.
pub fn pointwise_penetration(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    max_error: f64,
) -> Result<PointwisePenetration, OptionsError> {
    if !(max_error.is_finite() && max_error > 0.0) {
        return Err(OptionsError::OutOfRange {
            name: "max_error",
            requirement: "must be positive and finite",
            value: max_error,
        });
    }
    let one = |a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose| {
        let mut s = Inside {
            b_mesh: b,
            lower: 0.0,
            witness: (Vec3::ZERO, Vec3::ZERO),
            dropped: 0.0,
            warm: 0,
        };
        let upper = s.run(a, &pb.inv_mul(pa), max_error);
        (
            s.lower,
            upper.max(s.lower),
            pb.transform_point(s.witness.0),
            pb.transform_point(s.witness.1),
        )
    };
    // The two directions are independent searches: on two threads when rayon has them.
    let (f, b) = rayon::join(
        || one(mesh1, pose1, mesh2, pose2),
        || one(mesh2, pose2, mesh1, pose1),
    );
    let (win, from_first) = if b.0 > f.0 { (b, false) } else { (f, true) };
    Ok(PointwisePenetration {
        depth: win.0,
        upper_bound: f.1.max(b.1),
        point1: win.2,
        point2: win.3,
        from_first,
    })
}

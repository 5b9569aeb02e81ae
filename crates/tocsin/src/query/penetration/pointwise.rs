//! Pointwise penetration depth (Tang, Lee and Kim, SIGGRAPH 2009): the deepest interpenetrating
//! points. The parts of each surface that lie inside the other body (by the winding number,
//! [`super::winding`]) are measured against the other surface; the depth is the largest
//! distance from such a point to the other surface (the Hausdorff distance from the inside parts
//! to it), within an error bound, with the two points that realise it.
//!
//! The search is the Hausdorff distance's (`hausdorff.rs`) restricted to inside points: samples
//! (the centroids of pieces known to be inside the other body without meeting its surface)
//! raise the lower bound, and a piece (a node of the
//! hierarchy, whose bounding ball is tested, then a triangle split in four) that does not meet
//! the other surface lies on one side of it: outside pieces are dropped (a whole subtree at
//! once), inside ones keep their upper bounds.
//!
//! The side is constant on a connected set that does not meet the surface (for a closed mesh
//! the winding number only changes across it), so one winding number serves several pieces:
//! - a node's ball that misses the surface, and a piece's centroid at distance `d` from it,
//!   carry a free ball (a ball that misses the surface) with the side of its centre; a search
//!   remembers the last few, and a new free ball that overlaps one takes its side (the union of
//!   two overlapping free balls is connected and misses the surface);
//! - the four parts of a split triangle pairwise share a corner, so those of them that miss the
//!   surface share one side;
//! - so do any two pieces that share a corner and both miss the surface (A's triangles around
//!   a vertex, a split part and its neighbours): a search remembers the side at the corners of
//!   the pieces it classified (a table of 1,024 entries keyed by the corner's coordinates),
//!   and a piece with a remembered corner takes that side (nineteenth session: -10 to -18% at
//!   1% of the radius, +1 to +3% at 20%).
//!
//! A small node (up to `NEAR_LEAVES` triangles) whose ball meets the surface is not opened at
//! once but queued whole, bounded without an exact distance (its ball meets the surface, so every
//! point of it is within twice its radius of it, and the corner bound on the triangle its ball
//! met): at deep penetrations most such nodes near the intersection never need opening once the
//! lower bound is known (knot34k at 20% of the radius: -61% instructions; +4 to +8% at 1%).
//! So is a single triangle whose ball meets the surface, bounded by twice its ball's radius
//! and its farthest corner's distance to the triangle the ball met, and probed only if that is
//! not within the error when it comes up (nineteenth session: knot2.8k at 20% -23%).
//!
//! A triangle piece's convex bound is the lower envelope of its candidate triangles' corner
//! distances (`surface::envelope_bound`, as in the Hausdorff search), and the four parts of a
//! split are probed first, then bounded with each other's nearest triangles among the
//! candidates too.
//!
//! Where B has A's triangle list (the same mesh at another pose, or a copy whose vertices
//! moved), every piece is also bounded by how far its points' corresponding points of B are
//! (`surface::Copies`, as in the Hausdorff search; thirtieth session). Against the copy moved by
//! (0.3, 0.1, 0.05) (knot2.8k, one thread, instructions at 1e-2 / 1e-3 / 1e-4 R): 44.4M / 59.8M
//! / 82.2M -> 4.0M / 9.6M / 71.5M; at 1e-4 R the bound settles pieces only once an inside
//! point within the error of the maximum is found, and the classification of the surface
//! near the other is most of the work.
//!
//! On the benchmark's shallow penetrations this took 28-39% of the instructions off, then
//! the node walk's test became a bounded ball query (stops at the first triangle within the
//! ball) and a piece's intersection test and centroid distance one traversal: 25-37% more
//! (docs/BENCHMARKS.md, eighteenth session). For closed meshes the classification is exact;
//! for soups with holes, where the winding number varies without crossing the surface, a piece
//! is classified by the winding number at a point connected to it without crossing the
//! surface (its centroid, a sibling's, or the centre of an overlapping free ball; said on
//! [`pointwise_penetration`]).

use std::collections::BinaryHeap;

use crate::bvh::Node;
use crate::error::OptionsError;
use crate::math::{Pose, Vec3};
use crate::query::penetration::surface::{
    ball_meets_mesh, corner_bound, envelope_bound, node_probe, rectangle_corners, ring_bound,
    split4, triangle_probe, Copies, Ranked,
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

/// A piece of A waiting, ranked by its upper bound, with the two triangles of B its bound
/// tried.
type Piece = Ranked<(PieceKind, [u32; 2])>;

enum PieceKind {
    /// A node of A's hierarchy known to lie inside B without meeting its surface.
    Inside(u32),
    /// A small node of A's hierarchy, or a leaf, whose ball meets B's surface, bounded whole
    /// (a leaf is probed when popped).
    Near(u32),
    /// A (sub)triangle, whether it is known to lie inside B without meeting its surface, and
    /// its bound by B's corresponding points ([`Copies`]; infinite without).
    Triangle([Vec3; 3], bool, f64),
}

/// A node of A with at most this many triangles whose ball meets B's surface is bounded whole
/// (and opened when that bound is not within the error), a larger one opened at once.
const NEAR_LEAVES: usize = 8;

/// How many classified free balls a search remembers (the most recent).
const KNOWN: usize = 32;

/// One direction: the parts of A inside B, measured against B's surface (all in B's frame).
struct Inside<'a> {
    b_mesh: &'a TriMesh,
    /// B's points corresponding to A's, where B has A's triangle list ([`Copies`]).
    copies: Option<Copies<'a>>,
    lower: f64,
    /// The error bound the search runs to: a whole triangle's bound that is not within it of
    /// `lower` also tries [`ring_bound`], as in the Hausdorff search (knot2.8k against its copy
    /// moved by (0.3, 0.1, 0.05), instructions per query at 1e-2 / 1e-3 / 1e-4 R: 47.5M /
    /// 87.4M / 103.5M -> 43.0M / 58.7M / 82.1M; the grid's poses at 1% / 5% / 20% of the
    /// radius, knot2.8k +3.5% / +3.4% / -1.1%, duck +3.7% / +3.0% / -1.4%).
    max_error: f64,
    witness: (Vec3, Vec3),
    dropped: f64,
    /// The last closest triangle of B (neighbouring queries start from it).
    warm: u32,
    /// Recently classified free balls: centre, radius (no point of B's surface nearer to the
    /// centre), whether the centre is inside B. Unset entries have a NaN centre.
    known: [(Vec3, f64, bool); KNOWN],
    next: usize,
    /// Sides of corners of pieces that miss B's surface (module docs), a direct-mapped table
    /// keyed by the corner's coordinates (B's frame, bit for bit): 0 unset, 1 outside, 2
    /// inside.
    corners: Vec<([u64; 3], u8)>,
}

/// Entries of a search's corner table ([`Inside::corners`]), a power of two.
const CORNERS: usize = 1024;
const _: () = assert!(CORNERS.is_power_of_two());

/// The slot of a point in the corner table (the top bits of a multiplicative hash of its
/// coordinates), and its key.
fn corner_slot(p: Vec3) -> (usize, [u64; 3]) {
    let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let h = (key[0] ^ key[1].rotate_left(21) ^ key[2].rotate_left(42))
        .wrapping_mul(0x9E37_79B9_7F4A_7C15);
    ((h >> (64 - CORNERS.trailing_zeros())) as usize, key)
}

/// The triangle of A's leaf `node`, in B's frame.
fn placed_leaf(a: &TriMesh, a_to_b: &Pose, node: &Node) -> [Vec3; 3] {
    a.bvh().leaf_triangles()[node.leaf_position() as usize].map(|p| a_to_b.transform_point(p))
}

impl<'a> Inside<'a> {
    /// A search of the parts of A inside `b_mesh`, nothing known yet.
    fn new(b_mesh: &'a TriMesh, max_error: f64) -> Self {
        Self {
            b_mesh,
            copies: None,
            lower: 0.0,
            max_error,
            witness: (Vec3::ZERO, Vec3::ZERO),
            dropped: 0.0,
            warm: 0,
            known: [(Vec3::NAN, 0.0, false); KNOWN],
            next: 0,
            corners: vec![([0; 3], 0); CORNERS],
        }
    }

    /// The bound of node `node` of A by B's corresponding points ([`Copies::node`]; infinite
    /// without).
    fn node_copy(&self, node: &Node) -> f64 {
        self.copies
            .as_ref()
            .map_or(f64::INFINITY, |c| c.node(&node.rss))
    }

    /// The bound of A's leaf `node`, placed at `t` in B's frame, by B's corresponding points
    /// ([`Copies::triangle`]; infinite without).
    fn leaf_copy(&self, a: &TriMesh, node: &Node, t: &[Vec3; 3]) -> f64 {
        self.copies.as_ref().map_or(f64::INFINITY, |c| {
            c.triangle(a.bvh().triangle_index(node.leaf_position()), t)
        })
    }

    /// The side of a piece that misses B's surface, if one of its corners lies on a piece
    /// classified before that also missed it (the two pieces share that point, so their union
    /// is connected and misses the surface).
    fn corner_side(&self, t: &[Vec3; 3]) -> Option<bool> {
        t.iter().find_map(|&p| {
            let (slot, key) = corner_slot(p);
            match self.corners[slot] {
                (k, side) if side != 0 && k == key => Some(side == 2),
                _ => None,
            }
        })
    }

    /// Remembers the side of a piece that misses B's surface at its corners.
    fn remember_corners(&mut self, t: &[Vec3; 3], inside: bool) {
        for &p in t {
            let (slot, key) = corner_slot(p);
            self.corners[slot] = (key, 1 + u8::from(inside));
        }
    }

    /// Whether the piece `t`, which misses B's surface, is inside B: from a remembered corner,
    /// else [`Self::side`] at `c`, free of the surface within `free`; remembered at its corners
    /// and with its free ball either way.
    fn piece_side(&mut self, t: &[Vec3; 3], c: Vec3, free: f64) -> bool {
        let s = match self.corner_side(t) {
            Some(s) => {
                self.remember_ball(c, free, s);
                s
            }
            None => self.side(c, free),
        };
        self.remember_corners(t, s);
        s
    }

    /// Whether `c` is inside B, where the open ball of radius `free` about `c` does not meet
    /// B's surface. The side is constant on a connected set that does not meet the surface
    /// (module docs), so a remembered free ball that overlaps this one answers for it; else the
    /// winding number decides and the ball is remembered.
    fn side(&mut self, c: Vec3, free: f64) -> bool {
        for &(k, r, s) in &self.known {
            let reach = r + free;
            if (k - c).length_squared() < reach * reach {
                return s;
            }
        }
        let s = inside(self.b_mesh, c);
        self.remember_ball(c, free, s);
        s
    }

    /// Remembers a free ball (centre, radius) and the side of its centre.
    fn remember_ball(&mut self, c: Vec3, free: f64, inside: bool) {
        self.known[self.next] = (c, free, inside);
        self.next = (self.next + 1) % KNOWN;
    }

    /// The piece's upper bound, or `None` when it lies outside B (it does not meet B's surface
    /// and its side is outside). One probe of B: whether the piece meets B's surface and the
    /// exact distance of its centroid (a sample when the piece is inside); the envelope bound
    /// tries B's triangles nearest the piece and its centroid and the two its parent
    /// tried (`tried`), which the piece passes on. `clear`: the piece is known to lie inside B
    /// without meeting its surface (a part of such a piece, or of such a node), so neither is
    /// tested again. `siblings`: the side of the pieces split from the same parent that do not
    /// meet B's surface, once one of them is classified (the four parts of a split pairwise
    /// share a corner, so any two of them that miss the surface form a connected set missing it).
    fn piece(
        &mut self,
        (t, copy): ([Vec3; 3], f64),
        tried: [u32; 2],
        clear: bool,
        siblings: &mut Option<bool>,
    ) -> Option<Piece> {
        let (mut piece, dc) = self.probed((t, copy), tried, clear, siblings)?;
        self.bound(&mut piece, dc, &tried);
        if piece.upper > self.lower + self.max_error {
            if let (PieceKind::Triangle(t, _, _), [leaf, _]) = &piece.item {
                piece.upper = piece.upper.min(ring_bound(self.b_mesh, t, *leaf)).max(dc);
            }
        }
        Some(piece)
    }

    /// [`Self::piece`] before its convex bound: the piece with only the Lipschitz bound, and
    /// its centroid's distance to B.
    fn probed(
        &mut self,
        (t, copy): ([Vec3; 3], f64),
        tried: [u32; 2],
        clear: bool,
        siblings: &mut Option<bool>,
    ) -> Option<(Piece, f64)> {
        let c = (t[0] + t[1] + t[2]) / 3.0;
        let r = t.iter().fold(0.0_f64, |m, p| m.max((*p - c).length()));
        let (dc, q, leaf, meets) = triangle_probe(self.b_mesh.bvh(), &t, c, r, !clear, tried);
        self.warm = leaf;
        if !clear && meets.is_none() && *siblings == Some(false) {
            return None;
        }
        // The centroid's side: known for clear pieces and for pieces off the surface whose
        // sibling was classified; else decided here (pieces off the surface). A piece that
        // meets the surface is not a sample: its side would cost a winding number, and the
        // lower bound comes from the pieces inside next to it (1-4% fewer instructions).
        if !clear && meets.is_none() {
            let s = match *siblings {
                Some(s) => {
                    self.remember_corners(&t, s);
                    s
                }
                None => self.piece_side(&t, c, dc),
            };
            *siblings = Some(s);
            if !s {
                return None;
            }
        }
        if dc > self.lower && meets.is_none() {
            self.lower = dc;
            self.witness = (c, q);
        }
        let near = meets.unwrap_or(leaf);
        let piece = Piece {
            upper: (dc + r).min(copy).max(dc),
            item: (PieceKind::Triangle(t, meets.is_none(), copy), [leaf, near]),
        };
        Some((piece, dc))
    }

    /// A triangle piece's convex bound (as in the Hausdorff search, the lower envelope of its
    /// candidate triangles' corner distances): its own two triangles of B and `more`. `dc`: its
    /// centroid's distance (the bound is never below it).
    fn bound(&self, piece: &mut Piece, dc: f64, more: &[u32]) {
        if let (PieceKind::Triangle(t, _, _), [leaf, near]) = &piece.item {
            let mut candidates = [*near; 6];
            candidates[1] = *leaf;
            for (k, &m) in more.iter().take(4).enumerate() {
                candidates[2 + k] = m;
            }
            let n = 2 + more.len().min(4);
            let e = envelope_bound(self.b_mesh.bvh(), t, &candidates[..n]);
            piece.upper = piece.upper.min(e).max(dc);
        }
    }

    /// The four parts of a triangle piece: probed first, then bounded with each other's
    /// nearest triangles of B among the candidates too (spread over the parent, they tighten
    /// the envelope: 2 to 14% fewer instructions than each part's own candidates alone).
    fn split(
        &mut self,
        (t, copy): ([Vec3; 3], f64),
        tried: [u32; 2],
        clear: bool,
    ) -> [Option<Piece>; 4] {
        let mut siblings = None;
        let mut parts = [None, None, None, None];
        for (k, sub) in split4(t).into_iter().enumerate() {
            parts[k] = self.probed((sub, copy), tried, clear, &mut siblings);
        }
        let nearest: [Option<u32>; 4] =
            std::array::from_fn(|k| parts[k].as_ref().map(|(p, _)| p.item.1[0]));
        let mut out = [None, None, None, None];
        for (k, part) in parts.into_iter().enumerate() {
            let Some((mut p, dc)) = part else { continue };
            let mut more = [tried[0]; 4];
            let mut n = 1;
            for (j, l) in nearest.iter().enumerate() {
                if let (Some(l), true) = (l, j != k) {
                    more[n] = *l;
                    n += 1;
                }
            }
            self.bound(&mut p, dc, &more[..n]);
            out[k] = Some(p);
        }
        out
    }

    /// A node of A known to lie inside B without meeting its surface, whole: the Hausdorff
    /// search's node bound ([`node_probe`]), its sample a point inside B. Its triangles are
    /// only visited when that bound is not within the error of the lower bound.
    fn inside_node(&mut self, a: &TriMesh, a_to_b: &Pose, i: u32, tried: [u32; 2]) -> Piece {
        let probe = node_probe(a.bvh(), a_to_b, self.b_mesh.bvh(), i, tried);
        if probe.distance > self.lower {
            self.lower = probe.distance;
            self.witness = (probe.point, probe.closest);
        }
        let copy = self.node_copy(&a.bvh().nodes()[i as usize]);
        Piece {
            upper: probe.upper.min(copy).max(probe.distance),
            item: (PieceKind::Inside(i), [probe.leaf, tried[0]]),
        }
    }

    /// The two children of inside node `i`: inside nodes, or clear triangle pieces at the leaves.
    fn open_inside(
        &mut self,
        a: &TriMesh,
        a_to_b: &Pose,
        i: u32,
        tried: [u32; 2],
    ) -> [Option<Piece>; 2] {
        let nodes = a.bvh().nodes();
        let (l, r) = nodes[i as usize].children(i);
        [l, r].map(|c| {
            let node = &nodes[c as usize];
            if node.is_leaf() {
                let t = placed_leaf(a, a_to_b, node);
                self.piece((t, self.leaf_copy(a, node, &t)), tried, true, &mut None)
            } else {
                Some(self.inside_node(a, a_to_b, c, tried))
            }
        })
    }

    /// What a `Near` piece (node `i`, the triangles of B its bound tried) holds, once its
    /// bound is not within the error: a leaf's triangle probed, or a node's two children
    /// opened, starting from the triangle its ball met.
    fn open_near(
        &mut self,
        a: &TriMesh,
        a_to_b: &Pose,
        i: u32,
        tried: [u32; 2],
    ) -> [Option<Piece>; 2] {
        let node = &a.bvh().nodes()[i as usize];
        if node.is_leaf() {
            let t = placed_leaf(a, a_to_b, node);
            let copy = self.leaf_copy(a, node, &t);
            return [self.piece((t, copy), tried, false, &mut None), None];
        }
        self.warm = tried[0];
        let (l, r) = node.children(i);
        // Both children are small nodes or leaves: none is pushed to open later.
        let mut unused = Vec::new();
        [l, r].map(|c| self.open(a, a_to_b, c, &mut unused))
    }

    /// Queues a piece worth splitting, or records the bound of one that is not.
    fn keep(&mut self, heap: &mut BinaryHeap<Piece>, p: Piece) {
        if p.upper > self.lower + self.max_error {
            heap.push(p);
        } else {
            self.dropped = self.dropped.max(p.upper);
        }
    }

    /// Node `i` of A, not yet classified: its ball is tested against B's surface. A ball that
    /// misses it lies on one side (outside: dropped; inside: a clear piece); a leaf whose ball
    /// meets it is a triangle piece tested on its own, a small node ([`NEAR_LEAVES`] triangles
    /// or fewer) a `Near` piece bounded whole, a larger one is opened (`stack`).
    fn open(&mut self, a: &TriMesh, a_to_b: &Pose, i: u32, stack: &mut Vec<u32>) -> Option<Piece> {
        let node = &a.bvh().nodes()[i as usize];
        let c = a_to_b.transform_point(node.rss.center);
        let leaf = node.is_leaf().then(|| placed_leaf(a, a_to_b, node));
        // The last triangle of B a ball met starts the test, and the piece's bounds.
        let clear = match ball_meets_mesh(self.b_mesh.bvh(), c, node.rss.corner_radius(), self.warm)
        {
            Err(near) => {
                self.warm = near;
                false
            }
            Ok(free) => {
                // A triangle clear of the surface may have a corner whose side is known.
                let is_in = match &leaf {
                    Some(t) => self.piece_side(t, c, free),
                    None => self.side(c, free),
                };
                if !is_in {
                    return None;
                }
                true
            }
        };
        let tried = [self.warm; 2];
        if let Some(t) = leaf {
            let copy = self.leaf_copy(a, node, &t);
            if clear {
                return self.piece((t, copy), tried, true, &mut None);
            }
            // Its ball meets B's surface, so every point of it is within twice the ball's
            // radius of that surface, and within its farthest corner's distance of the
            // triangle the ball met (the distance to one triangle is convex). Queued with
            // that bound, it is only probed if the bound is still above the lower bound when
            // it comes up: at 20% of the radius most such triangles never are (knot2.8k -23%
            // instructions, 1-4% more at 1%, where nearly all are).
            let upper = (2.0 * node.rss.corner_radius())
                .min(corner_bound(self.b_mesh.bvh(), &t, &tried[..1]))
                .min(copy);
            return Some(Piece {
                upper,
                item: (PieceKind::Near(i), tried),
            });
        }
        if clear {
            return Some(self.inside_node(a, a_to_b, i, tried));
        }
        if node.leaf_range().len() <= NEAR_LEAVES {
            // Its ball meets B's surface, so its centre is within its radius `r` of B and every
            // point of it within `2 r`; and the distance to the triangle it met is convex: the
            // corner bound over its rectangle, plus its radius. No exact distance: a bound
            // covering the parts outside B too, valid for the inside ones.
            let rss = &node.rss;
            let corners = rectangle_corners(rss, a_to_b);
            let upper = (2.0 * rss.corner_radius())
                .min(corner_bound(self.b_mesh.bvh(), &corners, &tried[..1]) + rss.radius)
                .min(self.node_copy(node));
            return Some(Piece {
                upper,
                item: (PieceKind::Near(i), tried),
            });
        }
        let (l, r) = node.children(i);
        stack.push(l);
        stack.push(r);
        None
    }

    fn run(&mut self, a: &TriMesh, a_to_b: &Pose) -> f64 {
        let mut heap = BinaryHeap::new();
        // A's hierarchy first: a node whose bounding ball does not meet B's surface lies on
        // one side of it (the ball is connected), decided at its centre; outside nodes are
        // dropped whole, inside ones become pieces known to be clear of B's surface (whole
        // nodes, bounded as the Hausdorff search bounds them, split only when that bound is not
        // within the error); small nodes near B's surface are bounded whole too, larger ones
        // opened (`open`).
        let mut stack = vec![0u32];
        while let Some(i) = stack.pop() {
            if let Some(p) = self.open(a, a_to_b, i, &mut stack) {
                heap.push(p);
            }
        }
        while let Some(piece) = heap.pop() {
            if piece.upper <= self.lower + self.max_error {
                return piece.upper.max(self.lower).max(self.dropped);
            }
            match piece.item {
                (PieceKind::Inside(i), tried) => {
                    for p in self.open_inside(a, a_to_b, i, tried).into_iter().flatten() {
                        self.keep(&mut heap, p);
                    }
                }
                (PieceKind::Near(i), tried) => {
                    for p in self.open_near(a, a_to_b, i, tried).into_iter().flatten() {
                        self.keep(&mut heap, p);
                    }
                }
                (PieceKind::Triangle(t, clear, copy), tried) => {
                    for p in self.split((t, copy), tried, clear).into_iter().flatten() {
                        self.keep(&mut heap, p);
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
/// does not meet the other surface is classified at a point connected to it without crossing
/// the other surface (its centroid or a neighbour's, module docs), exact for closed meshes.
///
/// A `max_error` below the distances' accuracy
/// ([`crate::query::contact_time::DISTANCE_RESOLUTION`] of the radii plus the poses' distances
/// from the origin) is raised to it: below it the search could not end.
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
    let max_error = super::resolved_error(max_error, (mesh1, pose1), (mesh2, pose2));
    let one = |a: &TriMesh, pa: &Pose, b: &TriMesh, pb: &Pose| {
        let a_to_b = pb.inv_mul(pa);
        let mut s = Inside::new(b, max_error);
        s.copies = Copies::new(a, b, &a_to_b);
        let upper = s.run(a, &a_to_b);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh;
    use crate::query::penetration::surface::tests::{barycentric_grid, brute_distance};

    /// Distance from `p` to every triangle of `b`, the smallest (brute force).
    fn brute(b: &TriMesh, p: Vec3) -> f64 {
        brute_distance(b.bvh().leaf_triangles(), p)
    }

    /// Every piece's upper bound holds over dense samples of the piece, against brute-force
    /// distances to the other surface: triangles (whole and split), inside nodes and the small
    /// nodes near the surface bounded whole, on a knot and turned copies overlapping it deeply
    /// and shallowly, and a ball mostly inside a larger one. Every piece the search makes is
    /// checked, nodes opened down to their triangles, triangles split once.
    #[test]
    fn every_piece_bound_holds_over_dense_samples() {
        let knot = mesh::torus_knot(60, 6).expect("knot");
        let ball = mesh::sphere(0.8, 12, 24).expect("sphere");
        let socket = mesh::sphere(1.0, 10, 20).expect("sphere");
        let mut cases = Vec::new();
        for case in [0, 3] {
            let angle = 0.15 * (case + 1) as f64;
            let shift = Vec3::new(0.1 * case as f64, 0.35, -0.05 * case as f64);
            let pose = Pose::from_axis_angle(Vec3::new(0.3, 1.0, -0.2).normalize(), angle, shift);
            cases.push((&knot, &knot, pose));
        }
        // A ball mostly inside a larger one: whole nodes inside.
        for shift in [0.1, 0.4] {
            cases.push((
                &ball,
                &socket,
                Pose::from_translation(Vec3::new(shift, 0.0, 0.0)),
            ));
        }
        // Inside nodes, near nodes, near leaves, triangles.
        let mut kinds = [0usize; 4];
        for (case, &(a, b, pose2)) in cases.iter().enumerate() {
            let (nodes, tris) = (a.bvh().nodes(), a.bvh().leaf_triangles());
            // A at the origin, B at `pose2`; B's frame.
            let a_to_b = pose2.inv_mul(&Pose::IDENTITY);
            // No error: every whole triangle above the lower bound tries `ring_bound` too.
            let mut s = Inside::new(b, 0.0);
            s.copies = Copies::new(a, b, &a_to_b);
            let mut pieces = Vec::new();
            let mut stack = vec![0u32];
            while let Some(i) = stack.pop() {
                if let Some(p) = s.open(a, &a_to_b, i, &mut stack) {
                    pieces.push((p, 0));
                }
            }
            while let Some((p, depth)) = pieces.pop() {
                let points: Vec<Vec3> = match &p.item.0 {
                    PieceKind::Inside(i) | PieceKind::Near(i) => nodes[*i as usize]
                        .leaf_range()
                        .flat_map(|k| {
                            barycentric_grid(&tris[k].map(|q| a_to_b.transform_point(q)), 4)
                        })
                        .collect(),
                    PieceKind::Triangle(t, _, _) => barycentric_grid(t, 6),
                };
                let worst = points.iter().map(|q| brute(b, *q)).fold(0.0, f64::max);
                assert!(
                    worst <= p.upper + 1e-12,
                    "case {case}: a sample at {worst} above the bound {}",
                    p.upper
                );
                if depth == 1 {
                    // Split pieces once.
                    continue;
                }
                let tried = p.item.1;
                match p.item.0 {
                    PieceKind::Inside(i) => {
                        kinds[0] += 1;
                        for q in s.open_inside(a, &a_to_b, i, tried).into_iter().flatten() {
                            pieces.push((q, depth));
                        }
                    }
                    PieceKind::Near(i) => {
                        kinds[if nodes[i as usize].is_leaf() { 2 } else { 1 }] += 1;
                        for q in s.open_near(a, &a_to_b, i, tried).into_iter().flatten() {
                            pieces.push((q, depth));
                        }
                    }
                    PieceKind::Triangle(t, clear, copy) => {
                        kinds[3] += 1;
                        for q in s.split((t, copy), tried, clear).into_iter().flatten() {
                            pieces.push((q, depth + 1));
                        }
                    }
                }
            }
        }
        // Every kind of piece was made and checked.
        assert!(
            kinds.iter().all(|&k| k > 10),
            "pieces checked by kind: {kinds:?}"
        );
    }

    /// The correspondence bounds ([`Copies`]) change no answer beyond the error bound: a knot
    /// against itself moved, moved and turned a little, and against a copy with the same
    /// triangles whose vertices moved by up to 1% of the radius, at errors of 1e-2 and 1e-3 of
    /// the radius, with and without the bounds: each interval `[depth, upper_bound]` within the
    /// error and the two overlapping.
    #[test]
    fn copy_bounds_change_no_answer() {
        use crate::query::penetration::surface::{tests::one_thread, COPIES};
        let m = mesh::torus_knot(80, 8).expect("knot");
        let r = m.bounding_radius();
        let perturbed = crate::query::penetration::surface::tests::jittered(&m, 0.01 * r, 7);
        let cases: [(&TriMesh, Pose); 3] = [
            (&m, Pose::from_translation(Vec3::new(0.3, 0.1, 0.0))),
            (
                &m,
                Pose::from_axis_angle(
                    Vec3::new(0.3, 1.0, -0.2).normalize(),
                    0.02,
                    Vec3::new(0.2, -0.1, 0.1),
                ),
            ),
            (
                &perturbed,
                Pose::from_translation(Vec3::new(0.1, 0.05, 0.0)),
            ),
        ];
        for (k, (b, pose)) in cases.iter().enumerate() {
            for rel in [1e-2, 1e-3] {
                let e = rel * r;
                // On one thread: the switch is per thread, and the two directions are joined.
                let run = |copies: bool| {
                    one_thread().install(|| {
                        COPIES.with(|c| c.set(copies));
                        let p = pointwise_penetration(&m, &Pose::IDENTITY, b, pose, e);
                        COPIES.with(|c| c.set(true));
                        p.expect("pointwise")
                    })
                };
                let (with, without) = (run(true), run(false));
                for p in [&with, &without] {
                    assert!(
                        p.upper_bound - p.depth <= e * (1.0 + 1e-9),
                        "case {k}: {p:?}"
                    );
                    assert!(p.depth > 0.0, "case {k}: no inside point found");
                }
                assert!(
                    with.depth.max(without.depth)
                        <= with.upper_bound.min(without.upper_bound) * (1.0 + 1e-12),
                    "case {k}, error {rel}: {with:?} against {without:?}"
                );
            }
        }
    }
}

//! The bounding volume hierarchy: a binary tree of [`Rss`] volumes in one flat array.
//!
//! Layout (preorder): node `i` with `n` triangles owns the `2n - 1` entries from `i`; its left
//! child is `i + 1` and its right child is `node.right`. Each leaf holds exactly one triangle,
//! stored by its position in [`Bvh::leaf_triangles`] (the triangles' corners are copied there in
//! leaf order, so traversal never chases vertex indices). Everything is in the mesh's frame.

mod build;
pub(crate) mod eigen;
mod projection;
mod rss;
mod rss4;
#[cfg(target_arch = "x86_64")]
mod rss4_avx2;

/// A small seeded generator for the unit tests of the hierarchy (uniform in [0, 1)).
#[cfg(test)]
pub(crate) struct TestRng(pub u64);

#[cfg(test)]
impl TestRng {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

pub(crate) use projection::ColumnPair;
pub use rss::Rss;
pub(crate) use rss::{rss_separation, ASide, BSide, RelativeRss, SplitSpread};
pub(crate) use rss4::{LaneBounds, Lanes4};

/// The child pairs of expanding the node pair `(n1, n2)` when not both are leaves: each
/// internal node of the two is split, so the pairs are the product of two nodes per side (a leaf
/// stands for itself, twice). Lane `2 i + j` of a 4-lane bound pairs `a[i]` with `b[j]`;
/// `lanes` lists the distinct pairs. Shared by the distance search and `collide`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Expansion {
    pub a: [u32; 2],
    pub b: [u32; 2],
    pub lanes: &'static [usize],
}

impl Expansion {
    /// The expansion of `(n1, n2)`, or `None` when both are leaves (a triangle pair).
    #[inline]
    pub(crate) fn of(nodes1: &[Node], n1: u32, nodes2: &[Node], n2: u32) -> Option<Self> {
        let (a, b) = (&nodes1[n1 as usize], &nodes2[n2 as usize]);
        match (a.is_leaf(), b.is_leaf()) {
            (true, true) => None,
            (false, false) => {
                let ((a1, a2), (b1, b2)) = (a.children(n1), b.children(n2));
                Some(Self {
                    a: [a1, a2],
                    b: [b1, b2],
                    lanes: &[0, 1, 2, 3],
                })
            }
            (false, true) => {
                let (a1, a2) = a.children(n1);
                Some(Self {
                    a: [a1, a2],
                    b: [n2, n2],
                    lanes: &[0, 2],
                })
            }
            (true, false) => {
                let (b1, b2) = b.children(n2);
                Some(Self {
                    a: [n1, n1],
                    b: [b1, b2],
                    lanes: &[0, 1],
                })
            }
        }
    }

    /// The node pair of lane `k`.
    #[inline]
    pub(crate) fn pair(&self, k: usize) -> (u32, u32) {
        (self.a[k / 2], self.b[k % 2])
    }
}

use crate::math::Vec3;

/// One node of the hierarchy.
#[derive(Clone, Copy, Debug)]
pub struct Node {
    /// The bounding volume, mesh frame.
    pub rss: Rss,
    /// Index of the right child, or 0 for a leaf (the root is never a right child).
    right: u32,
    /// Leaf position of the subtree's first triangle (for a leaf, its own triangle's).
    first: u32,
    /// Number of triangles in the subtree (1 for a leaf); they are the leaf positions from
    /// `first`.
    count: u32,
}

impl Node {
    /// Whether the node is a leaf (holds one triangle).
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.right == 0
    }

    /// The two children, for an internal node at index `index`.
    #[inline]
    pub fn children(&self, index: u32) -> (u32, u32) {
        (index + 1, self.right)
    }

    /// For a leaf, the position of its triangle in [`Bvh::leaf_triangles`].
    #[inline]
    pub fn leaf_position(&self) -> u32 {
        self.first
    }

    /// The leaf positions of the subtree's triangles (in [`Bvh::leaf_triangles`]).
    #[inline]
    pub fn leaf_range(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }
}

/// A bounding volume hierarchy of rectangle swept spheres over a mesh's triangles.
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Corners of the triangles in leaf order (mesh frame).
    leaf_corners: Vec<[Vec3; 3]>,
    /// The same corners in `f32` columns, for projecting a subtree's corners on an axis in
    /// vector lanes (`None` when the mesh is too large for `f32`).
    corner_columns: Option<CornerColumns>,
    /// Original index of each triangle in leaf order.
    leaf_ids: Vec<u32>,
}

impl Bvh {
    /// Builds the hierarchy top-down (principal-axis split at the mean of the centroids).
    /// `triangles` must be non-empty with indices in range (checked by `TriMesh`).
    pub(crate) fn build(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Self {
        build::build(vertices, triangles, triangles.len() <= build::REFINE_MAX)
    }

    /// As [`Self::build`], without turning small meshes' rectangles to their edge directions
    /// (for a hierarchy that is barely searched: a convex hull's, `TriMesh::hull`).
    pub(crate) fn build_unrefined(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Self {
        build::build(vertices, triangles, false)
    }

    /// All nodes, root first.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The root node.
    pub fn root(&self) -> &Rss {
        &self.nodes[0].rss
    }

    /// The triangles' corners in leaf order (mesh frame).
    pub fn leaf_triangles(&self) -> &[[Vec3; 3]] {
        &self.leaf_corners
    }

    /// The corners in `f32` columns, when the mesh's extent allows it.
    #[inline]
    pub(crate) fn corner_columns(&self) -> Option<&CornerColumns> {
        self.corner_columns.as_ref()
    }

    /// The original triangle index of the triangle at leaf position `position`.
    #[inline]
    pub fn triangle_index(&self, position: u32) -> usize {
        self.leaf_ids[position as usize] as usize
    }

    /// A triangle corner farthest along `direction` (mesh frame; any length): depth first over
    /// the hierarchy, the larger child first, a subtree dropped where its volume's support
    /// along `direction` (the rectangle's corners' and the sphere's) is no farther than the
    /// best corner found. A volume's rounding can only drop a corner tied with the best to a
    /// few units in the last place. `None` for a direction that is not finite.
    pub fn support(&self, direction: Vec3) -> Option<Vec3> {
        if !direction.is_finite() {
            return None;
        }
        let reach = |r: &Rss| r.center.dot(direction) + r.spread().support(direction);
        let mut best = (f64::NEG_INFINITY, None);
        // Room for a balanced hierarchy's depth at once: grown one push at a time, the stack
        // was reallocated about three times a call (callgrind, a Fetch's self-collision).
        let mut stack = Vec::with_capacity(64);
        stack.push(0u32);
        while let Some(i) = stack.pop() {
            let node = &self.nodes[i as usize];
            if reach(&node.rss) <= best.0 {
                continue;
            }
            if node.is_leaf() {
                for v in self.leaf_corners[node.leaf_position() as usize] {
                    let along = v.dot(direction);
                    if along > best.0 || best.1.is_none() {
                        best = (along, Some(v));
                    }
                }
                continue;
            }
            let (l, r) = node.children(i);
            let (near, far) =
                if reach(&self.nodes[l as usize].rss) >= reach(&self.nodes[r as usize].rss) {
                    (l, r)
                } else {
                    (r, l)
                };
            stack.push(far);
            stack.push(near);
        }
        best.1
    }
}

impl Bvh {
    /// Whether some triangle corner lies farther than `level` along `direction` (mesh frame;
    /// any length): depth first over the hierarchy, a subtree dropped where its volume's
    /// support along `direction` is at most `level`. The test a plane needs to be a supporting
    /// plane (the convex polytope test), which visits only the nodes reaching past the plane.
    pub(crate) fn reaches_beyond(&self, direction: Vec3, level: f64) -> bool {
        let reach = |r: &Rss| r.center.dot(direction) + r.spread().support(direction);
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let i = stack[top];
            let node = &self.nodes[i as usize];
            if reach(&node.rss) <= level {
                continue;
            }
            if node.is_leaf() {
                let corners = &self.leaf_corners[node.leaf_position() as usize];
                if corners.iter().any(|v| v.dot(direction) > level) {
                    return true;
                }
                continue;
            }
            let (l, r) = node.children(i);
            if top + 2 > stack.len() {
                // Deeper than any hierarchy built here: the exhaustive answer.
                return self
                    .leaf_corners
                    .iter()
                    .flatten()
                    .any(|v| v.dot(direction) > level);
            }
            stack[top] = r;
            stack[top + 1] = l;
            top += 2;
        }
        false
    }
}

/// Child pairs whose subtrees both hold at most this many triangles are also bounded, in the
/// distance search, by projecting their corners. Measured on the knot34k workload of
/// `examples/profile_distance.rs`, in instructions of the searches (callgrind; timings on
/// this machine are noisy): 64: 1,062M; 128: 905M; 256: 821M; 512: 772M. Interleaved timings
/// (minimum of 5, 0.01 / 0.1 / 1 R, us) put 256 ahead of 128 (47 / 41 / 36 against
/// 45 / 46 / 47) and gave 512 no clear gain at 0.01 R, where the larger projections prune
/// least; before the greedy dive, 256 had been slower than 128 at 0.01 R.
pub(crate) const PROJECT_MAX: usize = 256;

/// Subtree pairs larger than [`PROJECT_MAX`] (up to this many triangles on the larger side) are
/// also bounded by projecting their corners in the step search, for as long as that pays: the
/// first such projection is made, and later ones while at least one in `LARGE_PROJECT_RATIO`
/// pruned its pair, in a record that halves at every iteration (such subtrees keep their
/// distinct vertices too). Two links a centimetre apart (UR5's base and upper arm, 578 and
/// 1,176 triangles) are then told apart near the roots; intertwined meshes (the knots) stop
/// trying after a miss until the next iteration. Until the twenty-eighth session the record
/// spanned the whole query, so that one early miss turned the projections off for good: the
/// halving took 7% off UR5's free edges and 4 to 12% off the knots (instructions).
/// Measured in instructions (fifteenth session; always projecting up to 512 / 1,024: box_ur5
/// 54.5M -> 40.7M / 32.5M but knot2.8k 135.8M -> 150.9M / 164.4M): with this rule box_ur5
/// 54.3M -> 38.6M, the Panda bench's free edges 450.4M -> 438.1M, knot2.8k and knot34k +1%
/// (134.5M -> 136.3M, 272.8M -> 274.9M), colliding and start-goal edges unchanged.
pub(crate) const LARGE_PROJECT_MAX: usize = 1024;

/// Whether the subtrees of `a` and `b` both hold at most `max` triangles (the projection's
/// size test: the distance search, the step search and `collide`).
#[inline]
pub(crate) fn both_at_most(a: &Node, b: &Node, max: usize) -> bool {
    a.leaf_range().len() <= max && b.leaf_range().len() <= max
}

/// Three coordinate columns.
type Columns = [Vec<f32>; 3];

/// For each vertex, the first index of a vertex at exactly the same position (bitwise, with
/// `-0.0` and `0.0` alike), found by sorting the indices by position (in parallel).
pub(crate) fn same_position(vertices: &[Vec3]) -> Vec<u32> {
    use rayon::prelude::*;
    let key = |v: &Vec3| [v.x + 0.0, v.y + 0.0, v.z + 0.0].map(f64::to_bits);
    let mut order: Vec<u32> = (0..vertices.len() as u32).collect();
    order.par_sort_unstable_by_key(|&i| (key(&vertices[i as usize]), i));
    let mut same: Vec<u32> = (0..vertices.len() as u32).collect();
    for run in order.chunk_by(|&a, &b| key(&vertices[a as usize]) == key(&vertices[b as usize])) {
        for &i in run {
            same[i as usize] = run[0];
        }
    }
    same
}

/// Subtrees of more triangles than this (up to [`LARGE_PROJECT_MAX`]) also keep their distinct
/// vertices, when that saves at least a third of the corners.
const DISTINCT_MIN: usize = 16;

/// The leaf triangles' corners as `f32` coordinates relative to `origin`, by column (x, y, z;
/// corner `j` of leaf position `i` at `3 i + j`): a subtree's corners are contiguous, and half
/// the bytes of `f64` let eight of them be projected per vector instruction. Larger subtrees
/// also keep their distinct vertices (a shared vertex is a corner of about six triangles).
#[derive(Clone, Debug)]
pub(crate) struct CornerColumns {
    /// The point the coordinates are relative to (mesh frame).
    pub origin: Vec3,
    columns: Columns,
    /// The distinct vertices of some subtrees, by column, relative to `origin`.
    distinct: Columns,
    /// Per node: the start and length of its distinct vertices in `distinct` (length 0: none).
    distinct_ranges: Vec<[u32; 2]>,
    /// A bound on the error of a projection computed from these columns on a unit axis in
    /// `f32`: storing each coordinate and rounding the axis cost at most `2^-24` relative each,
    /// the three-term sum at most `3 * 2^-24` of the sum of magnitudes, so in all under
    /// `5.1 * 2^-24 = 3.1e-7` times the largest distance of a corner from `origin`; this uses
    /// `4e-7` of it, plus `1e-37` for results near `f32`'s underflow.
    pub error: f64,
}

impl CornerColumns {
    /// Columns for `corners` about `origin`, or `None` when a corner is farther than `1e30`
    /// from it (past that, `f32` products could overflow).
    pub(crate) fn new(corners: &[[Vec3; 3]], origin: Vec3) -> Option<Self> {
        use rayon::prelude::*;
        // In parallel (a million triangles: 40 ms on one thread); the maximum does not depend
        // on the order.
        let reach = corners
            .par_iter()
            .map(|c| c.iter().fold(0.0_f64, |m, p| m.max((*p - origin).length())))
            .reduce(|| 0.0, f64::max);
        if !reach.is_finite() || reach > 1e30 {
            return None;
        }
        let column = |k: usize| {
            let mut column = vec![0.0_f32; 3 * corners.len()];
            column.par_chunks_mut(3).zip(corners).for_each(|(out, c)| {
                for (o, p) in out.iter_mut().zip(c) {
                    *o = (p[k] - origin[k]) as f32;
                }
            });
            column
        };
        Some(Self {
            origin,
            columns: [column(0), column(1), column(2)],
            distinct: [Vec::new(), Vec::new(), Vec::new()],
            distinct_ranges: Vec::new(),
            error: 4e-7 * reach + 1e-37,
        })
    }

    /// Adds the distinct vertices of the subtrees of more than [`DISTINCT_MIN`] and at most
    /// [`LARGE_PROJECT_MAX`] triangles (`ids`: original triangle index per leaf position;
    /// `triangles` index `vertices`), where that saves at least a third of their corners.
    /// Vertices are told apart by position, not by index: many files repeat each shared vertex
    /// per face (the MotionBenchMaker Panda's OBJ links: 900 vertices for 300 triangles, 152
    /// positions), and a soup without shared positions saves nothing. The points are copied
    /// from the corner columns, so the error bound holds.
    pub(crate) fn add_distinct(
        &mut self,
        nodes: &[Node],
        ids: &[u32],
        triangles: &[[u32; 3]],
        vertices: &[Vec3],
    ) {
        use rayon::prelude::*;
        let same = same_position(vertices);
        let vertex_count = vertices.len();
        // The triangles' vertices (the first index at each position) in leaf order (one gather
        // here), read in order below next to the corner columns, which hold their coordinates.
        let leaf_triangles: Vec<[u32; 3]> = ids
            .par_iter()
            .map(|&id| triangles[id as usize].map(|v| same[v as usize]))
            .collect();
        let eligible: Vec<u32> = (0..nodes.len() as u32)
            .into_par_iter()
            .filter(|&i| {
                (DISTINCT_MIN + 1..=LARGE_PROJECT_MAX).contains(&(nodes[i as usize].count as usize))
            })
            .collect();
        // In parallel over runs of nodes, each with its own marks; then concatenated in order.
        let run = eligible.len().div_ceil(rayon::current_num_threads()).max(1);
        let columns = &self.columns;
        let parts: Vec<(Vec<(u32, u32)>, Columns)> = eligible
            .par_chunks(run)
            .map(|chunk| {
                let mut seen = vec![u32::MAX; vertex_count];
                let room: usize = chunk
                    .iter()
                    .map(|&i| 3 * nodes[i as usize].count as usize)
                    .sum();
                let mut points: Columns = [0, 1, 2].map(|_| Vec::with_capacity(room));
                let mut ranges = Vec::with_capacity(chunk.len());
                for &i in chunk {
                    let node = &nodes[i as usize];
                    let start = points[0].len();
                    for p in node.leaf_range() {
                        for (j, v) in leaf_triangles[p].into_iter().enumerate() {
                            if seen[v as usize] != i {
                                seen[v as usize] = i;
                                for k in 0..3 {
                                    points[k].push(columns[k][3 * p + j]);
                                }
                            }
                        }
                    }
                    let len = points[0].len() - start;
                    if 3 * len > 2 * 3 * node.count as usize {
                        points.iter_mut().for_each(|c| c.truncate(start));
                    } else {
                        ranges.push((i, start as u32));
                    }
                }
                (ranges, points)
            })
            .collect();
        self.distinct_ranges = (0..nodes.len()).into_par_iter().map(|_| [0, 0]).collect();
        let total: usize = parts.iter().map(|(_, p)| p[0].len()).sum();
        self.distinct
            .iter_mut()
            .for_each(|c| c.reserve_exact(total));
        for (ranges, points) in parts {
            let base = self.distinct[0].len() as u32;
            let total = points[0].len() as u32;
            for (k, &(i, start)) in ranges.iter().enumerate() {
                let end = ranges.get(k + 1).map_or(total, |r| r.1);
                self.distinct_ranges[i as usize] = [base + start, end - start];
            }
            for (column, part) in self.distinct.iter_mut().zip(points) {
                column.extend_from_slice(&part);
            }
        }
    }

    /// The columns of points covering node `index`'s triangles: its distinct vertices where
    /// kept, else its triangles' corners.
    #[inline]
    pub(crate) fn points(&self, index: u32, node: &Node) -> [&[f32]; 3] {
        match self.distinct_ranges.get(index as usize) {
            Some(&[start, len]) if len > 0 => {
                rows(&self.distinct, start as usize..(start + len) as usize)
            }
            _ => self.columns(node.leaf_range()),
        }
    }

    /// The x, y and z columns of the corners of the triangles at the leaf positions `range`.
    #[inline]
    pub(crate) fn columns(&self, range: std::ops::Range<usize>) -> [&[f32]; 3] {
        rows(&self.columns, 3 * range.start..3 * range.end)
    }
}

/// The entries `range` of each of three columns.
#[inline]
fn rows(columns: &Columns, range: std::ops::Range<usize>) -> [&[f32]; 3] {
    let [x, y, z] = columns;
    [&x[range.clone()], &y[range.clone()], &z[range]]
}

#[cfg(test)]
mod support_tests {
    use super::TestRng;
    use crate::math::Vec3;
    use crate::{mesh, TriMesh};

    /// The hierarchy's support corner reaches as far along the direction as the farthest of
    /// all corners (brute force), on random soups with degenerate and repeated triangles at
    /// tiny, unit and huge scales, and on a knot.
    #[test]
    fn support_reaches_the_farthest_corner() {
        let mut rng = TestRng(7);
        let mut meshes = vec![mesh::torus_knot(100, 8).expect("knot")];
        for (k, scale) in [1e-9, 1.0, 1e9].into_iter().enumerate() {
            let mut v: Vec<Vec3> = (0..60)
                .map(|_| Vec3::new(rng.next(), rng.next(), rng.next()) * scale)
                .collect();
            v.push(v[0]); // a repeated vertex
            let mut t: Vec<[u32; 3]> = (0..40)
                .map(|_| {
                    let mut i = || (rng.next() * 61.0) as u32 % 61;
                    let (a, b) = (i(), i());
                    [a, b, (a + 1 + k as u32) % 61]
                })
                .collect();
            t.push([0, 0, 0]); // a point
            t.push([1, 2, 1]); // a segment
            t.push(t[0]); // a repeated triangle
            meshes.push(TriMesh::new(v, t).expect("soup"));
        }
        for m in &meshes {
            let corners = m.bvh().leaf_triangles();
            for _ in 0..50 {
                let d = Vec3::new(rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5);
                let brute = corners
                    .iter()
                    .flatten()
                    .map(|v| v.dot(d))
                    .fold(f64::NEG_INFINITY, f64::max);
                let got = m.bvh().support(d).expect("a finite direction");
                assert!(corners.iter().flatten().any(|v| *v == got));
                assert_eq!(got.dot(d), brute, "direction {d}");
            }
        }
        assert!(meshes[0]
            .bvh()
            .support(Vec3::new(f64::NAN, 0.0, 1.0))
            .is_none());
    }
}

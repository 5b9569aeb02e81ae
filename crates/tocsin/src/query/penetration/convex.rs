//! The exact translational penetration depth of two convex polytopes.
//!
//! For convex `A` and `B` overlapping, the depth is the distance from the origin to the
//! boundary of the Minkowski difference `A - B`, that is the smallest, over unit directions
//! `n`, of the overlap `o(n) = max_a n.a - min_b n.b` (moving `B` by `o(n) n` makes `n` a
//! separating direction, and no shorter translation separates them). The minimum
//! of this support-function difference is reached at a facet normal of the Minkowski
//! difference, and those are face normals of `A`, face normals of `B`, or cross products of an
//! edge of `A` with an edge of `B`; so the candidates are finite and the minimum over them is
//! exact (to rounding).
//!
//! **EPA first.** Where both meshes are convex to 1e-12 of their size and either has more than
//! 8 corners, EPA (`query/penetration/epa.rs`) answers first when its certificate holds
//! (the depth between a polytope inside the Minkowski difference and a support along its
//! nearest face's normal, within 1e-11 of the size): it visits only the faces near the deepest
//! direction, where the candidates below are all bounded. On 470 random overlapping pairs it
//! answered every one, equal to the candidates' depth to 1e-12 of the size; 3,000-point hulls
//! 255 -> 39 to 44 us (docs/BENCHMARKS.md, thirty-ninth session).
//!
//! **Which candidates, found on the Gauss map.** The Gauss map puts each face at its outward
//! normal on the unit sphere, each edge on the arc between its two faces' normals, and each
//! vertex on the region of directions it is the support of. Every face of `A` gives a facet of
//! `A - B` (normal `n_A`, with `B`'s support along `-n_A`), and so does every face of `B`
//! (normal `-n_B`); an edge pair gives one only where the edge of `A`'s arc crosses the edge of
//! `B`'s arc negated, and then the facet's normal is the crossing point, along `e_A x e_B`, and
//! its overlap is `n.(p_A - p_B)` with `p_A` and `p_B` any corners of the two edges (each edge
//! is its body's support there). So:
//!
//! - *Supports by climbing.* A support along `d` is found by walking the mesh's edges to a
//!   neighbour with a larger `d.p` until none has one, each face's search starting where that
//!   of an adjacent face ended (its parent in a breadth-first order over the faces). On a
//!   convex surface a corner with no larger neighbour is a support: its triangles cover a
//!   neighbourhood of it, so its edges span the cone the polytope lies in from there. Not for
//!   a corner inside a flat face (its edges span only the face's plane): a walk that ends at
//!   one on a face turned away from `d` takes the support by a loop over every corner
//!   instead.
//! - *Bounds before climbs.* Any corner `q` of `B` gives `h_B(-m) >= -m.q`, so a face of `A`
//!   (normal `m`, corner `p`) has an overlap of at least `m.(p - q)`; a face whose bound, from
//!   the support found for the nearest face above it in the breadth-first tree, already reaches
//!   the best overlap so far is not climbed (nor are the faces of `B`, the same way). An arc
//!   of `A` with corner `p` has, at every normal `n` on it, an overlap of at least `n.(p - q)`
//!   for the corner `q` of either face, so at least `mid.(p - q) - r |p - q|` with `mid` its
//!   midpoint and `r` its ends' distance from it; an arc whose bound reaches the best is not
//!   looked up. Only what lies near the deepest directions is searched: on two hulls of 1,000
//!   points (3,992 faces) 84 faces were climbed.
//! - *Crossing pairs from a grid.* `B`'s arcs are bucketed once, in `B`'s frame, in a uniform
//!   grid over the cube around the sphere (cells about as wide as its mean arc, each arc in
//!   every cell of its box, widened by how far the arc bows out of its chord); each arc of `A`,
//!   turned into `B`'s frame, is tested only against the arcs in the cells of its own box.
//! - *Arcs within one region skipped.* The climbed faces' supports on the other body say in
//!   which region of its Gauss map each face normal lies. An arc of `A` whose two ends have
//!   the same support on `B` lies in that one region (the regions are convex, the arcs geodesics
//!   shorter than a half circle) and crosses none of `B`'s arcs: it is not tested. Where an
//!   end lies on a region's border, the support taken is one of the regions it touches, and an
//!   arc that then stays in that region's closure meets the other arcs only at its end, a face
//!   normal, already a candidate.
//! - *The crossing test.* Arcs `(a, b)` and `(c, d)`, each shorter than a half circle, cross
//!   when `c` and `d` lie on opposite sides of the plane through `a` and `b` (normal `u`, along
//!   the first edge), `a` and `b` on opposite sides of the plane through `c` and `d` (normal
//!   `w`, along the second edge), and the point where arc `cd` meets the great circle of `ab`,
//!   `y = |d.u| c + |c.u| d`, is on arc `ab` and not its antipode. The two great circles meet in
//!   `+-x` only, `x` on arc `ab` has `x.(a + b) > 0` and `-x` has it negative, so the last
//!   condition is `y.(a + b) > 0`, and `y` gives the facet normal's sign. The test keeps every
//!   pair within rounding (1e-12) of crossing; one kept needlessly is within rounding of a
//!   crossing, so its overlap is within rounding of a true facet's. Where rounding leaves the
//!   sign open, both signs are taken with climbed supports, whose overlaps are never below the
//!   depth.
//!
//! Edges between two coplanar triangles (a triangulated face's diagonals) have a point for an
//! arc and are left out (a facet there has a face's normal, already a candidate), and coplanar
//! triangles give one face. A closed mesh with a degenerate triangle, or two faces back to back
//! (a flat mesh), has no Gauss map here: such a pair takes every face normal with both signs
//! and every edge pair, their overlaps by loops over every corner (the path the tests hold the
//! Gauss map's against).
//!
//! A mesh counts as a convex polytope when it is closed (every edge shared by exactly two
//! triangles) and every vertex lies behind every non-degenerate face's plane (within 1e-9 of
//! its size; on a mesh convex only to that, a climb may stop as far short of a support, and
//! the depth be off by as much). The candidates give up for the local search beyond
//! [`MAX_TESTS`] crossing tests (two prisms of many sides turned across each other have a
//! Minkowski difference of about `E_A E_B` facets: at 500 sides the candidates take 18 ms, at
//! 5,000 they give up; EPA answers both first, the latter in 0.25 ms) or, without Gauss maps,
//! beyond [`MAX_WORK`] for `(F_A + F_B + E_A E_B)(V_A + V_B)`.

use std::collections::{HashMap, VecDeque};

use crate::math::{Pose, Vec3};
use crate::TriMesh;

/// Largest `candidates x vertices` the exact path takes on without Gauss maps (above it, the
/// local search).
pub const MAX_WORK: usize = 50_000_000;

/// Most crossing tests the exact path makes with Gauss maps before it gives up for the local
/// search. Two prisms of 5,000 sides turned across each other spend 26 ms before giving up
/// (375 ms at 50 million); the local search then takes 185 ms (where EPA's certified answer
/// comes first, 0.25 ms: `epa.rs`).
pub const MAX_TESTS: usize = 10_000_000;

/// A mesh, its polytope and its pose (world).
pub(crate) type Placed<'a> = (&'a TriMesh, &'a Polytope, &'a Pose);

/// Pairs of meshes with at most this many corners each skip EPA's certified answer
/// ([`super::epa`]) for the candidates.
const EPA_MIN_VERTICES: usize = 8;

/// What the crossing test and the flat-corner test count as zero (unit vectors).
const ROUNDING: f64 = 1e-12;

/// A convex polytope (body frame): the candidates over every edge pair, and its Gauss map.
#[derive(Clone, Debug)]
pub(crate) struct Polytope {
    /// Every non-degenerate triangle's outward normal.
    normals: Vec<Vec3>,
    /// Every edge's unit direction.
    edges: Vec<Vec3>,
    /// `None` where a degenerate triangle or two faces back to back leave an edge without a
    /// proper arc (module docs).
    gauss: Option<GaussMap>,
    /// Whether every corner lies behind every face's plane within [`STRICT`] of the mesh's size
    /// (not only within the 1e-9 the polytope test admits): the distance's GJK path
    /// ([`crate::query::distance::gjk`]) trusts its climbed supports only then.
    strict: bool,
    /// Each corner's triangles, by leaf position: `.1[.0[v]..][..(.0[v + 1] - .0[v])]`.
    corner_leaves: (Vec<u32>, Vec<u32>),
}

/// What the strict convexity test ([`Polytope::strict`]) admits beyond a face's plane, a
/// fraction of the mesh's bounding radius: about the rounding of a convex hull's coordinates.
pub(crate) const STRICT: f64 = 1e-12;

impl Polytope {
    /// The corner of `vertices` (the mesh's, body frame) farthest along `d`, climbed over the
    /// mesh's edges from `start` (module docs); `None` without a Gauss map or unless the mesh is
    /// convex to [`STRICT`].
    #[inline]
    pub(crate) fn climb(&self, vertices: &[Vec3], d: Vec3, start: u32) -> Option<u32> {
        match &self.gauss {
            Some(g) if self.strict => Some(g.support(vertices, d, start)),
            _ => None,
        }
    }

    /// Whether [`Self::climb`] answers (a Gauss map, convex to [`STRICT`]).
    #[inline]
    pub(crate) fn climbs(&self) -> bool {
        self.strict && self.gauss.is_some()
    }

    /// The leaf positions of the triangles at corner `v`.
    #[inline]
    pub(crate) fn corner_leaves(&self, v: u32) -> &[u32] {
        let (offsets, leaves) = &self.corner_leaves;
        &leaves[offsets[v as usize] as usize..offsets[v as usize + 1] as usize]
    }
}

/// A convex polytope's Gauss map (body frame) and what the supports are climbed on.
#[derive(Clone, Debug)]
struct GaussMap {
    /// One outward normal per face (coplanar triangles joined), one of its corners, and its
    /// parent face (earlier, adjacent), in breadth-first order over the triangles.
    faces: Vec<(Vec3, u32, u32)>,
    /// Every edge between two faces that are not coplanar.
    arcs: Vec<Arc>,
    /// `arcs` bucketed by where they lie on the sphere.
    grid: Grid,
    /// The corners' neighbours: `neighbors[offsets[v]..offsets[v + 1]]`.
    offsets: Vec<u32>,
    neighbors: Vec<u32>,
    /// A corner whose triangles are coplanar (inside a face): their normal.
    flat: Vec<Option<Vec3>>,
}

/// An edge's arc on the Gauss map: its two faces' outward unit normals, its unit direction,
/// one of its corners, and the two faces (indices into [`GaussMap::faces`]).
#[derive(Clone, Copy, Debug)]
struct Arc {
    from: Vec3,
    to: Vec3,
    edge: Vec3,
    corner: u32,
    faces: [u32; 2],
    /// The arc's midpoint, and how far its points are from it at most (its ends' distance).
    mid: Vec3,
    spread: f64,
}

impl Arc {
    /// The arc's box on the sphere: its ends' box, widened by how far the arc bows out of its
    /// chord (`1 - cos(angle / 2)`) and by rounding.
    fn bounds(&self) -> (Vec3, Vec3) {
        let bow = 1.0 - (0.5 * (1.0 + self.from.dot(self.to))).max(0.0).sqrt() + 1e-9;
        (
            self.from.min(self.to) - Vec3::splat(bow),
            self.from.max(self.to) + Vec3::splat(bow),
        )
    }

    /// The arc turned by `r`, its corner kept.
    fn turned(&self, r: &crate::math::Mat3) -> Self {
        Self {
            from: *r * self.from,
            to: *r * self.to,
            edge: *r * self.edge,
            mid: *r * self.mid,
            ..*self
        }
    }
}

/// A uniform grid of `n^3` cells over `[-1, 1]^3`.
#[derive(Clone, Copy, Debug)]
struct Cells {
    n: usize,
    size: f64,
}

impl Cells {
    /// The cell index of a coordinate, clamped into the grid.
    #[inline]
    fn index(&self, x: f64) -> usize {
        // Truncation is the floor of a non-negative number (and `floor` a library call here).
        (((x + 1.0) / self.size).max(0.0) as usize).min(self.n - 1)
    }

    /// Calls `f` with every cell that the box `(lo, hi)` meets.
    #[inline]
    fn each(&self, (lo, hi): (Vec3, Vec3), mut f: impl FnMut(usize)) {
        let n = self.n;
        for i in self.index(lo.x)..=self.index(hi.x) {
            for j in self.index(lo.y)..=self.index(hi.y) {
                for k in self.index(lo.z)..=self.index(hi.z) {
                    f((i * n + j) * n + k);
                }
            }
        }
    }
}

/// Arcs bucketed by a uniform grid, each in every cell its box meets:
/// `items[offsets[c]..offsets[c + 1]]` for cell `c`.
#[derive(Clone, Debug)]
struct Grid {
    cells: Cells,
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl Grid {
    /// The grid for `arcs`: cells about as wide as their mean chord (at most 32 a side), halved
    /// in number a side while the arcs would take more than [`Self::budget`] places (long arcs
    /// among short ones, such as the caps' of a prism of many sides, each cover many cells).
    fn new(arcs: &[Arc]) -> Self {
        let mean =
            arcs.iter().map(|a| (a.to - a.from).length()).sum::<f64>() / arcs.len().max(1) as f64;
        let mut n = if mean > 0.0 {
            ((2.0 / mean) as usize).clamp(1, 32)
        } else {
            1
        };
        let shape = |n: usize| Cells {
            n,
            size: 2.0 / n as f64,
        };
        let too_many = |cells: Cells| {
            let mut places = 0usize;
            arcs.iter().any(|a| {
                cells.each(a.bounds(), |_| places += 1);
                places > Self::budget(arcs.len())
            })
        };
        while n > 1 && too_many(shape(n)) {
            n /= 2;
        }
        let cells = shape(n);
        // Counted into offsets[c + 1], summed, then filled from each cell's front.
        let mut offsets = vec![0u32; n * n * n + 1];
        for a in arcs {
            cells.each(a.bounds(), |c| offsets[c + 1] += 1);
        }
        for c in 1..offsets.len() {
            offsets[c] += offsets[c - 1];
        }
        let mut items = vec![0; offsets[n * n * n] as usize];
        let mut next = offsets.clone();
        for (k, a) in arcs.iter().enumerate() {
            cells.each(a.bounds(), |c| {
                items[next[c] as usize] = k as u32;
                next[c] += 1;
            });
        }
        Self {
            cells,
            offsets,
            items,
        }
    }

    /// The most places the arcs may take: 32 per arc and a million more.
    fn budget(arcs: usize) -> usize {
        32 * arcs + (1 << 20)
    }

    /// The arcs (indices) bucketed in cell `c`.
    #[inline]
    fn cell(&self, c: usize) -> &[u32] {
        &self.items[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }
}

impl GaussMap {
    /// The corner of `vertices` (body frame) farthest along `d`, climbed from `start` (module
    /// docs).
    #[inline]
    fn support(&self, vertices: &[Vec3], d: Vec3, start: u32) -> u32 {
        let mut v = start as usize;
        let mut best = d.dot(vertices[v]);
        loop {
            let mut next = v;
            for &u in &self.neighbors[self.offsets[v] as usize..self.offsets[v + 1] as usize] {
                let s = d.dot(vertices[u as usize]);
                if s > best {
                    (best, next) = (s, u as usize);
                }
            }
            if next == v {
                break;
            }
            v = next;
        }
        match self.flat[v] {
            // Inside a face turned away from `d`: not a support (module docs).
            Some(m) if m.dot(d) < 0.0 => {
                (0..vertices.len())
                    .filter(|&u| self.offsets[u] < self.offsets[u + 1])
                    .fold((f64::NEG_INFINITY, v), |(b, w), u| {
                        let s = d.dot(vertices[u]);
                        if s > b {
                            (s, u)
                        } else {
                            (b, w)
                        }
                    })
                    .1 as u32
            }
            _ => v as u32,
        }
    }
}

/// The mesh as a convex polytope, or `None` when it is open or not convex.
pub(crate) fn polytope(mesh: &TriMesh) -> Option<Polytope> {
    let v = mesh.vertices();
    // Every face's plane with all the used vertices on one side, first: a non-convex mesh
    // (the usual case) fails at its first faces, before the edges are hashed (knot34k: the
    // edge hashing was about 40M instructions of its first penetration depth). The farthest
    // corner beyond a plane comes from the hierarchy ([`crate::bvh::Bvh::support`]), which
    // visits the nodes near the plane only: a loop over every vertex for every face made the
    // test O(F V), 0.11 s for a sphere of 16,128 triangles.
    let scale = mesh.bounding_radius().max(f64::MIN_POSITIVE);
    let (eps, strict_eps) = (1e-9 * scale, STRICT * scale);
    let mut strict = true;
    let bvh = mesh.bvh();
    let mut normals = Vec::new();
    // Each triangle's outward normal, `None` for a degenerate one.
    let mut outward = Vec::with_capacity(mesh.num_triangles());
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|i| v[i as usize]);
        let Some(n) = (b - a).cross(c - a).try_normalize() else {
            outward.push(None);
            continue;
        };
        // Whether a corner lies beyond the plane through `a`, widened by `e`, along `d`.
        let beyond = |d: Vec3, e: f64| bvh.reaches_beyond(d, d.dot(a) + e);
        let n = if !beyond(n, strict_eps) {
            n
        } else if !beyond(-n, strict_eps) {
            -n
        } else {
            strict = false;
            if !beyond(n, eps) {
                n
            } else if !beyond(-n, eps) {
                -n
            } else {
                return None;
            }
        };
        normals.push(n);
        outward.push(Some(n));
    }
    // Then closed: every edge in exactly two triangles, no triangle with a repeated corner.
    // The triangles beside each edge (at most two kept; a third makes it not closed).
    let mut beside: HashMap<(u32, u32), (u32, [usize; 2])> = HashMap::new();
    for (k, t) in mesh.triangles().iter().enumerate() {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            if a == b {
                return None;
            }
            let entry = beside.entry((a.min(b), a.max(b))).or_insert((0, [k; 2]));
            if entry.0 < 2 {
                entry.1[entry.0 as usize] = k;
            }
            entry.0 += 1;
        }
    }
    if beside.values().any(|&(c, _)| c != 2) {
        return None;
    }
    // Sorted, so that the same mesh always gives the same lists (the hash map's order is
    // random): ties between equal candidates then always resolve alike.
    let mut beside: Vec<_> = beside.into_iter().collect();
    beside.sort_unstable_by_key(|&(edge, _)| edge);
    let edges = beside
        .iter()
        .filter_map(|&((a, b), _)| (v[b as usize] - v[a as usize]).try_normalize())
        .collect();
    let gauss = gauss_map(mesh, &outward, &beside);
    // Each corner's triangles, by leaf position (the witnesses of a GJK simplex).
    let mut counts = vec![0u32; v.len() + 1];
    for t in mesh.triangles() {
        for &i in t {
            counts[i as usize + 1] += 1;
        }
    }
    for i in 0..v.len() {
        counts[i + 1] += counts[i];
    }
    let mut leaves = vec![0u32; counts[v.len()] as usize];
    let mut fill = counts.clone();
    for leaf in 0..mesh.num_triangles() as u32 {
        for &i in &mesh.triangles()[bvh.triangle_index(leaf)] {
            leaves[fill[i as usize] as usize] = leaf;
            fill[i as usize] += 1;
        }
    }
    Some(Polytope {
        normals,
        edges,
        gauss,
        strict,
        corner_leaves: (counts, leaves),
    })
}

/// The Gauss map of a closed convex mesh whose triangles have the outward normals `outward`
/// and whose edges have the triangles `beside` them, or `None` where an edge has no proper
/// arc (module docs).
#[allow(clippy::type_complexity)]
fn gauss_map(
    mesh: &TriMesh,
    outward: &[Option<Vec3>],
    beside: &[((u32, u32), (u32, [usize; 2]))],
) -> Option<GaussMap> {
    let v = mesh.vertices();
    let coplanar = |m: Vec3, n: Vec3| m.cross(n).length() <= ROUNDING && m.dot(n) > 0.0;
    // Coplanar triangles joined into faces (union-find over the edges between them).
    let mut face: Vec<u32> = (0..outward.len() as u32).collect();
    let root = |face: &mut [u32], k: usize| super::union_root(face, k as u32) as usize;
    let mut arcs = Vec::with_capacity(beside.len());
    let mut next_to: Vec<Vec<usize>> = vec![Vec::new(); outward.len()];
    for &((a, b), (_, [k1, k2])) in beside {
        next_to[k1].push(k2);
        next_to[k2].push(k1);
        let (from, to) = (outward[k1]?, outward[k2]?);
        if coplanar(from, to) {
            let (r1, r2) = (root(&mut face, k1), root(&mut face, k2));
            face[r1] = r2 as u32;
        } else if from.dot(to) > -1.0 + 1e-9 {
            let edge = (v[b as usize] - v[a as usize]).try_normalize()?;
            let mid = (from + to).normalize();
            arcs.push(Arc {
                from,
                to,
                edge,
                corner: a,
                // Triangles for now, faces below.
                faces: [k1 as u32, k2 as u32],
                mid,
                spread: (from - mid).length(),
            });
        } else {
            return None;
        }
    }
    // The faces in breadth-first order over the triangles, each with a corner and the face
    // whose triangle reached it first (its parent, an earlier face: their normals are near).
    let mut faces = Vec::new();
    let mut index = vec![u32::MAX; outward.len()];
    let mut seen = vec![false; outward.len()];
    for first in 0..outward.len() {
        if seen[first] {
            continue;
        }
        seen[first] = true;
        let mut queue = VecDeque::from([(first, first)]);
        while let Some((k, from)) = queue.pop_front() {
            let r = root(&mut face, k);
            if index[r] == u32::MAX {
                index[r] = faces.len() as u32;
                let parent = index[root(&mut face, from)].min(index[r]);
                faces.push((outward[r]?, mesh.triangles()[k][0], parent));
            }
            for &j in &next_to[k] {
                if !seen[j] {
                    seen[j] = true;
                    queue.push_back((j, k));
                }
            }
        }
    }
    for arc in &mut arcs {
        arc.faces = arc.faces.map(|k| index[root(&mut face, k as usize)]);
    }
    // The corners' neighbours, and which corners lie inside a face.
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); v.len()];
    let mut flat: Vec<Option<Option<Vec3>>> = vec![None; v.len()];
    for (k, t) in mesh.triangles().iter().enumerate() {
        let n = outward[k]?;
        for i in 0..3 {
            let (p, q) = (t[i], t[(i + 1) % 3]);
            lists[p as usize].push(q);
            lists[q as usize].push(p);
            let f = &mut flat[p as usize];
            *f = match *f {
                None => Some(Some(n)),
                Some(Some(m)) if coplanar(m, n) => Some(Some(m)),
                _ => Some(None),
            };
        }
    }
    let mut offsets = Vec::with_capacity(v.len() + 1);
    let mut neighbors = Vec::new();
    offsets.push(0u32);
    for list in &mut lists {
        list.sort_unstable();
        list.dedup();
        neighbors.extend_from_slice(list);
        offsets.push(neighbors.len() as u32);
    }
    let grid = Grid::new(&arcs);
    Some(GaussMap {
        faces,
        arcs,
        grid,
        offsets,
        neighbors,
        flat: flat.into_iter().map(Option::flatten).collect(),
    })
}

/// Whether arc `a` (of `A`) and arc `b` negated (of `-B`) cross, within rounding (module docs):
/// the crossing's side of the facet normal `e_A x e_B`, `+1.0` or `-1.0`, `0.0` when rounding
/// leaves it open, `None` when they do not cross.
#[inline]
fn crossing(a: &Arc, b: &Arc) -> Option<f64> {
    let opposite =
        |x: f64, y: f64| !((x > ROUNDING && y > ROUNDING) || (x < -ROUNDING && y < -ROUNDING));
    // Arc of -B: from -b.from to -b.to; the plane through a's arc has normal a.edge.
    let (c, d) = (-b.from, -b.to);
    let (cu, du) = (c.dot(a.edge), d.dot(a.edge));
    if !opposite(cu, du) {
        return None;
    }
    if !opposite(a.from.dot(b.edge), a.to.dot(b.edge)) {
        return None;
    }
    let y = c * du.abs() + d * cu.abs();
    if y.dot(a.from + a.to) < -ROUNDING {
        return None;
    }
    let side = y.dot(a.edge.cross(b.edge));
    Some(if side > ROUNDING {
        1.0
    } else if side < -ROUNDING {
        -1.0
    } else {
        0.0
    })
}

/// The exact depth of convex `b` (placed by `pose_b`) into convex `a`: the overlap, the unit
/// direction to move `b` along, and the two support points (world), or `None` when the work
/// would be too much ([`MAX_TESTS`], [`MAX_WORK`]).
pub(crate) fn exact_depth(
    a: &TriMesh,
    pa: &Polytope,
    pose_a: &Pose,
    b: &TriMesh,
    pb: &Polytope,
    pose_b: &Pose,
) -> Option<(f64, Vec3, Vec3, Vec3)> {
    // Two boxes (8 corners each) are answered sooner by their few candidates (3 us against
    // EPA's 5; docs/BENCHMARKS.md, thirty-ninth session).
    let small = a.num_vertices() <= EPA_MIN_VERTICES && b.num_vertices() <= EPA_MIN_VERTICES;
    if !small && pa.climbs() && pb.climbs() {
        if let Some(found) = super::epa::depth((a, pa, pose_a), (b, pb, pose_b)) {
            return Some(found);
        }
    }
    exact_depth_without_epa((a, pa, pose_a), (b, pb, pose_b))
}

/// [`exact_depth`] by the candidates alone, without EPA's certified answer first (the oracle of
/// EPA's tests).
pub(crate) fn exact_depth_without_epa(
    (a, pa, pose_a): Placed<'_>,
    (b, pb, pose_b): Placed<'_>,
) -> Option<(f64, Vec3, Vec3, Vec3)> {
    match (&pa.gauss, &pb.gauss) {
        (Some(ga), Some(gb)) => gauss_depth(a, ga, pose_a, b, gb, pose_b),
        _ => every_pair_depth((a, pa, pose_a), (b, pb, pose_b)),
    }
}

/// [`exact_depth`] on the Gauss maps (module docs), in `b`'s frame, the result turned into the
/// world.
fn gauss_depth(
    a: &TriMesh,
    ga: &GaussMap,
    pose_a: &Pose,
    b: &TriMesh,
    gb: &GaussMap,
    pose_b: &Pose,
) -> Option<(f64, Vec3, Vec3, Vec3)> {
    let rel = pose_b.inv_mul(pose_a);
    let back = rel.rotation.transpose();
    let (va, vb) = (a.vertices(), b.vertices());
    // (overlap, normal, A's point, B's point), `b`'s frame.
    let mut best = (f64::INFINITY, Vec3::Z, Vec3::ZERO, Vec3::ZERO);
    fn keep(best: &mut (f64, Vec3, Vec3, Vec3), o: f64, n: Vec3, p: Vec3, q: Vec3) {
        if o < best.0 {
            *best = (o, n, p, q);
        }
    }
    // Each body's corners in the other's frame, once: the bounds below are then dot products.
    let va_in_b: Vec<Vec3> = va.iter().map(|&p| rel.transform_point(p)).collect();
    let to_a = rel.inverse();
    let vb_in_a: Vec<Vec3> = vb.iter().map(|&q| to_a.transform_point(q)).collect();
    // Both supports climbed along `n` (`b`'s frame), from corners `start`.
    let climbed = |n: Vec3, (sa, sb): (u32, u32)| {
        let ia = ga.support(va, back * n, sa);
        let ib = gb.support(vb, -n, sb);
        let (p, q) = (va_in_b[ia as usize], vb[ib as usize]);
        (n.dot(p - q), p, q, ib)
    };
    // A face's overlap is bounded from below without climbing by any corner of the other body
    // (module docs): from the support climbed for the nearest face above it in the
    // breadth-first tree. Those whose bound reaches the best overlap so far are not climbed,
    // and pass that corner on to their children.
    let scale = {
        let (ra, rb) = (a.bvh().root(), b.bvh().root());
        ra.corner_radius()
            + rb.corner_radius()
            + (rel.transform_point(ra.center) - rb.center).length()
    };
    let margin = ROUNDING * scale;
    // Per face of `A`: the corner of `B` its bound and its climb start from, and whether it
    // was climbed (that corner then its support along `-m`). Bounds in `A`'s frame.
    let mut near_b = vec![gb.faces.first().map_or(0, |f| f.1); ga.faces.len()];
    let mut climbed_a = vec![false; ga.faces.len()];
    for (k, &(n, corner, parent)) in ga.faces.iter().enumerate() {
        let from = near_b[parent as usize];
        near_b[k] = from;
        let bound = n.dot(va[corner as usize] - vb_in_a[from as usize]);
        if k > 0 && bound - margin >= best.0 {
            continue;
        }
        let m = rel.rotation * n;
        let (o, p, q, ib) = climbed(m, (corner, from));
        (near_b[k], climbed_a[k]) = (ib, true);
        keep(&mut best, o, m, p, q);
    }
    // The same for the faces of `B` (facet normal `-m`), with corners of `A`, in `B`'s frame.
    let mut near_a = vec![ga.faces.first().map_or(0, |f| f.1); gb.faces.len()];
    for (k, &(m, corner, parent)) in gb.faces.iter().enumerate() {
        let from = near_a[parent as usize];
        near_a[k] = from;
        let bound = (-m).dot(va_in_b[from as usize] - vb[corner as usize]);
        if k > 0 && bound - margin >= best.0 {
            continue;
        }
        // The facet normal -m: A's support along -m, B's along m (its own face).
        let ia = ga.support(va, -(back * m), from);
        let ib = gb.support(vb, m, corner);
        let (p, q) = (va_in_b[ia as usize], vb[ib as usize]);
        near_a[k] = ia;
        keep(&mut best, (-m).dot(p - q), -m, p, q);
    }
    let mut stamp = vec![u32::MAX; gb.arcs.len()];
    let mut tests = 0usize;
    for (k, x) in ga.arcs.iter().enumerate() {
        let [f0, f1] = x.faces.map(|f| f as usize);
        // Both ends in one region of `-B`'s Gauss map: no crossing (module docs).
        if climbed_a[f0] && climbed_a[f1] && near_b[f0] == near_b[f1] {
            continue;
        }
        // Over the whole arc, from its faces' corners of `B` (module docs), in `A`'s frame.
        let bound = [near_b[f0], near_b[f1]]
            .into_iter()
            .map(|j| {
                let w = va[x.corner as usize] - vb_in_a[j as usize];
                x.mid.dot(w) - x.spread * w.length()
            })
            .fold(f64::NEG_INFINITY, f64::max);
        if bound - margin >= best.0 {
            continue;
        }
        let p = va_in_b[x.corner as usize];
        let x = x.turned(&rel.rotation);
        // `B`'s arcs are bucketed where they are; those of `-B` near `x` are where `-x` is.
        let (lo, hi) = x.bounds();
        gb.grid.cells.each((-hi, -lo), |c| {
            for &j in gb.grid.cell(c) {
                if stamp[j as usize] == k as u32 {
                    continue;
                }
                stamp[j as usize] = k as u32;
                tests += 1;
                let y = &gb.arcs[j as usize];
                let Some(side) = crossing(&x, y) else {
                    continue;
                };
                let Some(n) = x.edge.cross(y.edge).try_normalize() else {
                    continue;
                };
                if side != 0.0 {
                    // Crossing arcs make the two edges the supports along `n`, and their
                    // points' overlap is the candidate's. Where rounding declared a crossing
                    // that is not one (nearly parallel edges: two coincident pancakes 1e6
                    // wide and 20 thick got an overlap of 0 against a depth of 20), they are
                    // not supports and that overlap can fall below the depth: a candidate
                    // that would become the best has its supports climbed.
                    let (n, q) = (n * side, vb[y.corner as usize]);
                    if n.dot(p - q) < best.0 {
                        let (o, p, q, _) = climbed(n, (x.corner, y.corner));
                        keep(&mut best, o, n, p, q);
                    }
                } else {
                    for n in [n, -n] {
                        let (o, p, q, _) = climbed(n, (x.corner, y.corner));
                        keep(&mut best, o, n, p, q);
                    }
                }
            }
        });
        if tests > MAX_TESTS {
            return None;
        }
    }
    let (o, n, p, q) = best;
    Some((
        o,
        pose_b.rotation * n,
        pose_b.transform_point(p),
        pose_b.transform_point(q),
    ))
}

/// [`exact_depth`] over every triangle normal with both signs and every edge pair, each
/// overlap by loops over every corner: for meshes without a Gauss map, and the oracle of the
/// tests.
fn every_pair_depth(
    (a, pa, pose_a): Placed<'_>,
    (b, pb, pose_b): Placed<'_>,
) -> Option<(f64, Vec3, Vec3, Vec3)> {
    let candidates = pa.normals.len() + pb.normals.len() + pa.edges.len() * pb.edges.len();
    if candidates.saturating_mul(a.num_vertices() + b.num_vertices()) > MAX_WORK {
        return None;
    }
    let va: Vec<Vec3> = a
        .vertices()
        .iter()
        .map(|p| pose_a.transform_point(*p))
        .collect();
    let vb: Vec<Vec3> = b
        .vertices()
        .iter()
        .map(|p| pose_b.transform_point(*p))
        .collect();
    let overlap = |n: Vec3| {
        let (mut best_a, mut sa) = (f64::NEG_INFINITY, Vec3::ZERO);
        for p in &va {
            let s = n.dot(*p);
            if s > best_a {
                (best_a, sa) = (s, *p);
            }
        }
        let (mut best_b, mut sb) = (f64::INFINITY, Vec3::ZERO);
        for p in &vb {
            let s = n.dot(*p);
            if s < best_b {
                (best_b, sb) = (s, *p);
            }
        }
        (best_a - best_b, sa, sb)
    };
    let mut best = (f64::INFINITY, Vec3::Z, Vec3::ZERO, Vec3::ZERO);
    let mut consider = |n: Vec3| {
        for n in [n, -n] {
            let (o, sa, sb) = overlap(n);
            if o < best.0 {
                best = (o, n, sa, sb);
            }
        }
    };
    for n in &pa.normals {
        consider(pose_a.rotation * *n);
    }
    for n in &pb.normals {
        consider(pose_b.rotation * *n);
    }
    for ea in &pa.edges {
        let ea = pose_a.rotation * *ea;
        for eb in &pb.edges {
            if let Some(n) = ea.cross(pose_b.rotation * *eb).try_normalize() {
                consider(n);
            }
        }
    }
    Some(best)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::math::Mat3;
    use crate::mesh;
    use crate::motion::sampling::unit;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::collections::HashMap;

    /// A convex mesh under a random linear map (boxes, coarse UV spheres and cylinders,
    /// stretched and sheared: still convex, with every kind of dihedral angle).
    pub(crate) fn random_convex(rng: &mut ChaCha8Rng) -> TriMesh {
        let base = match rng.random_range(0..5) {
            0 => mesh::box_mesh(Vec3::new(0.5, 0.3, 0.8)).expect("box"),
            1 => mesh::sphere(0.6, rng.random_range(2..7), rng.random_range(3..10)).expect("ball"),
            2 => mesh::cylinder(0.4, 1.0).expect("cylinder"),
            3 => mesh::box_mesh(Vec3::new(0.9, 0.05, 0.4)).expect("slab"),
            _ => gridded_box(rng.random_range(2..5), Vec3::new(0.6, 0.4, 0.5)),
        };
        let mut map = Mat3::IDENTITY;
        // Each axis stretched and sheared three times in four: the others keep faces parallel
        // to other shapes' faces.
        let stretched: Vec<usize> = (0..3).filter(|_| rng.random_range(0..4) > 0).collect();
        for k in stretched {
            let column = Vec3::new(
                rng.random_range(-0.3..0.3),
                rng.random_range(-0.3..0.3),
                rng.random_range(-0.3..0.3),
            ) + Vec3::new(
                f64::from(u8::from(k == 0)),
                f64::from(u8::from(k == 1)),
                f64::from(u8::from(k == 2)),
            ) * rng.random_range(0.3..1.5);
            match k {
                0 => map.x_axis = column,
                1 => map.y_axis = column,
                _ => map.z_axis = column,
            }
        }
        let vertices = base.vertices().iter().map(|p| map * *p).collect();
        TriMesh::new(vertices, base.triangles().to_vec()).expect("mapped mesh")
    }

    /// A box of half extents `h` whose faces are `n x n` grids of squares, two triangles each:
    /// corners inside faces (flat) and along edges (collinear).
    pub(crate) fn gridded_box(n: u32, h: Vec3) -> TriMesh {
        let mut index = HashMap::new();
        let mut vertices = Vec::new();
        let mut corner = |p: [u32; 3]| {
            *index.entry(p).or_insert_with(|| {
                let f = |i: u32, e: f64| (2.0 * f64::from(i) / f64::from(n) - 1.0) * e;
                vertices.push(Vec3::new(f(p[0], h.x), f(p[1], h.y), f(p[2], h.z)));
                (vertices.len() - 1) as u32
            })
        };
        let mut triangles = Vec::new();
        for axis in 0..3 {
            for side in [0, n] {
                for i in 0..n {
                    for j in 0..n {
                        let at = |di: u32, dj: u32| {
                            let mut p = [0; 3];
                            p[axis] = side;
                            p[(axis + 1) % 3] = i + di;
                            p[(axis + 2) % 3] = j + dj;
                            p
                        };
                        let q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)].map(&mut corner);
                        triangles.push([q[0], q[1], q[2]]);
                        triangles.push([q[0], q[2], q[3]]);
                    }
                }
            }
        }
        TriMesh::new(vertices, triangles).expect("gridded box")
    }

    /// A rotation that is a random multiple of a quarter turn about a coordinate axis, or a
    /// random one.
    pub(crate) fn rotation(rng: &mut ChaCha8Rng, axis_aligned: bool) -> Pose {
        if axis_aligned {
            let axis = [Vec3::X, Vec3::Y, Vec3::Z][rng.random_range(0..3)];
            let turns = f64::from(rng.random_range(0..4u8));
            Pose::from_axis_angle(axis, turns * std::f64::consts::FRAC_PI_2, Vec3::ZERO)
        } else {
            Pose::from_axis_angle(unit(rng), rng.random_range(0.0..3.0), Vec3::ZERO)
        }
    }

    /// Every edge pair, as before the Gauss-map test: the oracle.
    fn all_pairs(p: &Polytope) -> Polytope {
        Polytope {
            gauss: None,
            ..p.clone()
        }
    }

    /// The Gauss map drops only candidates that give no facet: on 600 random overlapping or
    /// nearly touching pairs of convex meshes (coarse spheres, boxes, cylinders, boxes with
    /// gridded faces, most stretched and sheared, a quarter turned by quarter turns only), the
    /// depth equals that over every candidate with loops over every corner to 1e-12 relative,
    /// the sign (overlap or not) agrees on every pair, the points are the supports along the
    /// direction, and the crossing test keeps under 5% of the edge pairs.
    #[test]
    fn crossing_test_keeps_every_facet() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut overlapping, mut kept, mut all) = (0, 0usize, 0usize);
        for case in 0..600 {
            let (a, b) = (random_convex(&mut rng), random_convex(&mut rng));
            let (pa, pb) = (
                a.convex_polytope().expect("convex a"),
                b.convex_polytope().expect("convex b"),
            );
            let (ga, gb) = (
                pa.gauss.as_ref().expect("a Gauss map"),
                pb.gauss.as_ref().expect("a Gauss map"),
            );
            // A quarter with quarter turns: parallel faces, arcs through each other's ends.
            let aligned = case % 4 == 0;
            let pose_a = rotation(&mut rng, aligned);
            let reach = rng.random_range(0.0..1.6);
            let pose_b = Pose {
                translation: unit(&mut rng) * reach,
                ..rotation(&mut rng, aligned)
            };
            let fast =
                exact_depth_without_epa((&a, pa, &pose_a), (&b, pb, &pose_b)).expect("small");
            let slow = exact_depth(&a, &all_pairs(pa), &pose_a, &b, &all_pairs(pb), &pose_b)
                .expect("small");
            assert_eq!(
                fast.0 > 0.0,
                slow.0 > 0.0,
                "case {case}: {} vs {}",
                fast.0,
                slow.0
            );
            if slow.0 > 0.0 {
                overlapping += 1;
                assert!(
                    (fast.0 - slow.0).abs() <= 1e-12 * slow.0.max(1e-3),
                    "case {case}: {} vs {}",
                    fast.0,
                    slow.0
                );
                // The direction is a unit vector, and the points are the supports along it
                // whose gap is the overlap.
                let n = fast.1;
                assert!((n.length() - 1.0).abs() < 1e-12);
                let reach_a = a
                    .vertices()
                    .iter()
                    .map(|&p| n.dot(pose_a.transform_point(p)));
                let reach_b = b
                    .vertices()
                    .iter()
                    .map(|&p| n.dot(pose_b.transform_point(p)));
                assert!((n.dot(fast.2) - reach_a.fold(f64::MIN, f64::max)).abs() < 1e-12);
                assert!((n.dot(fast.3) - reach_b.fold(f64::MAX, f64::min)).abs() < 1e-12);
                assert!((n.dot(fast.2 - fast.3) - fast.0).abs() < 1e-12);
            }
            all += pa.edges.len() * pb.edges.len();
            for x in &ga.arcs {
                let x = x.turned(&pose_a.rotation);
                for y in &gb.arcs {
                    kept += usize::from(crossing(&x, &y.turned(&pose_b.rotation)).is_some());
                }
            }
        }
        assert!(overlapping >= 300, "{overlapping} overlapping pairs");
        assert!(kept * 20 < all, "{kept} of {all} edge pairs kept");
    }

    /// An arc's box holds every point of the arc, the bow out of its chord included (arcs of
    /// up to nearly a half turn).
    #[test]
    fn arc_bounds_hold_the_arc() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..2000 {
            let (from, to) = (unit(&mut rng), unit(&mut rng));
            if from.dot(to) < -1.0 + 1e-6 {
                continue;
            }
            let arc = Arc {
                from,
                to,
                edge: Vec3::X,
                corner: 0,
                faces: [0, 1],
                mid: Vec3::X,
                spread: 0.0,
            };
            let (lo, hi) = arc.bounds();
            for k in 0..=100 {
                let s = f64::from(k) / 100.0;
                let p = (from * (1.0 - s) + to * s).normalize();
                assert!(
                    p.cmpge(lo).all() && p.cmple(hi).all(),
                    "{p} outside {lo} {hi}"
                );
            }
        }
    }

    /// A climb that ends inside a flat face turned away from the direction (every neighbour
    /// as far along it) takes the support from every corner: from the centre of a gridded
    /// box's top face, downwards, the support is on the bottom face.
    #[test]
    fn climb_off_a_flat_face() {
        let cube = gridded_box(2, Vec3::splat(0.5));
        let g = cube
            .convex_polytope()
            .and_then(|p| p.gauss.as_ref())
            .expect("Gauss map");
        let top = cube
            .vertices()
            .iter()
            .position(|&p| p == Vec3::new(0.0, 0.0, 0.5))
            .expect("centre of the top face") as u32;
        assert!(g.flat[top as usize].is_some());
        let down = g.support(cube.vertices(), -Vec3::Z, top);
        assert_eq!(cube.vertices()[down as usize].z, -0.5);
        // Upwards, the climb stays on the top face.
        let up = g.support(cube.vertices(), Vec3::Z, top);
        assert_eq!(cube.vertices()[up as usize].z, 0.5);
    }

    /// A prism of `n` sides (radius 1, height 2), its caps fanned from their centres (corners
    /// inside a face).
    pub(crate) fn prism(n: u32) -> TriMesh {
        let mut vertices = vec![Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 1.0)];
        for k in 0..n {
            let t = std::f64::consts::TAU * f64::from(k) / f64::from(n);
            vertices.push(Vec3::new(t.cos(), t.sin(), -1.0));
            vertices.push(Vec3::new(t.cos(), t.sin(), 1.0));
        }
        let mut triangles = Vec::new();
        for k in 0..n {
            let (b0, t0) = (2 + 2 * k, 3 + 2 * k);
            let (b1, t1) = (2 + 2 * ((k + 1) % n), 3 + 2 * ((k + 1) % n));
            triangles.extend([[0, b1, b0], [1, t0, t1], [b0, b1, t1], [b0, t1, t0]]);
        }
        TriMesh::new(vertices, triangles).expect("prism")
    }

    /// Prisms of many sides: the caps' long arcs among the sides' short ones. At 5,000 sides
    /// the grid stays within its budget and a box across a side gets its depth; at 64 sides,
    /// turned across each other, the depth equals that over every candidate.
    #[test]
    fn prisms_of_many_sides() {
        let big = prism(5000);
        let pb = big.convex_polytope().expect("convex");
        let g = pb.gauss.as_ref().expect("Gauss map");
        assert!(g.grid.items.len() <= Grid::budget(g.arcs.len()));
        // A box across its side: the depth is how far the box must go out through the side
        // (0.9 - 0.2 + 0.3 = 1, within the polygon's 2e-7 of the circle), along +x.
        let cube = mesh::box_mesh(Vec3::splat(0.2)).expect("box");
        let pc = cube.convex_polytope().expect("convex");
        let at = Pose::from_axis_angle(Vec3::Z, 0.0, Vec3::new(0.9, 0.0, 0.0));
        let d = exact_depth(&big, pb, &Pose::IDENTITY, &cube, pc, &at).expect("an answer");
        assert!((d.0 - 0.3).abs() < 1e-6 && d.1.x > 0.999_999, "{d:?}");
        let small = prism(64);
        let p = small.convex_polytope().expect("convex");
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        for case in 0..20 {
            let pose_b = Pose {
                translation: unit(&mut rng) * 0.8,
                ..rotation(&mut rng, case % 2 == 0)
            };
            let fast = exact_depth_without_epa((&small, p, &Pose::IDENTITY), (&small, p, &pose_b))
                .expect("small");
            let (every, at) = (all_pairs(p), Pose::IDENTITY);
            let slow = exact_depth(&small, &every, &at, &small, &every, &pose_b).expect("small");
            assert!(slow.0 > 0.0, "case {case}: apart");
            assert!(
                (fast.0 - slow.0).abs() <= 1e-12 * slow.0,
                "case {case}: {} vs {}",
                fast.0,
                slow.0
            );
        }
    }

    /// Many short arcs and some nearly half circles (each of which covers most of a fine grid):
    /// the grid coarsens until the places stay within the budget, and every arc is in every
    /// cell its box meets.
    #[test]
    fn grid_budget_with_long_arcs_among_short_ones() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let arc = |from: Vec3, to: Vec3| {
            let mid = (from + to).normalize();
            Arc {
                from,
                to,
                edge: from.cross(to).normalize(),
                corner: 0,
                faces: [0, 1],
                mid,
                spread: (from - mid).length(),
            }
        };
        let mut arcs = Vec::new();
        for _ in 0..100_000 {
            let from = unit(&mut rng);
            arcs.push(arc(from, (from + unit(&mut rng) * 1e-3).normalize()));
        }
        for _ in 0..2_000 {
            let from = unit(&mut rng);
            let side = from.cross(unit(&mut rng)).normalize();
            arcs.push(arc(from, (-from + side * 0.05).normalize()));
        }
        let grid = Grid::new(&arcs);
        assert!(
            grid.items.len() <= Grid::budget(arcs.len()),
            "{}",
            grid.items.len()
        );
        assert!(grid.cells.n < 32);
        for (k, a) in arcs.iter().enumerate().step_by(97) {
            grid.cells
                .each(a.bounds(), |c| assert!(grid.cell(c).contains(&(k as u32))));
        }
    }

    /// A box's face diagonals are coplanar edges and have no arc; a flat closed mesh (two
    /// faces back to back) has none at all and takes every edge pair.
    #[test]
    fn coplanar_and_flat_meshes() {
        let cube = mesh::box_mesh(Vec3::splat(0.5)).expect("box");
        let p = cube.convex_polytope().expect("convex");
        assert_eq!(p.edges.len(), 18);
        assert_eq!(
            p.gauss.as_ref().map(|g| (g.faces.len(), g.arcs.len())),
            Some((6, 12))
        );
        let flat = TriMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            vec![[0, 1, 2], [0, 2, 1]],
        )
        .expect("flat");
        let q = flat
            .convex_polytope()
            .expect("a flat closed mesh is convex");
        assert!(q.gauss.is_none());
        let turned = Pose::from_axis_angle(Vec3::X, 0.3, Vec3::new(0.1, 0.1, 0.0));
        let d = exact_depth(&cube, p, &Pose::IDENTITY, &flat, q, &turned).expect("small");
        let e =
            exact_depth(&cube, &all_pairs(p), &Pose::IDENTITY, &flat, q, &turned).expect("small");
        assert_eq!(d.0, e.0);
        assert!(d.0 > 0.0);
    }

    /// Pancakes (UV spheres flattened to 1e-3 to 1e-7 of their width, a million units wide)
    /// against a copy of themselves, coincident, shifted a little or turned a little: nearly
    /// parallel edges whose arcs rounding declared crossing gave the coincident pair an overlap
    /// of 0 (depth 20 at 1e-5; found by fuzzing). The Gauss map's answer and the whole depth
    /// equal the every-pair oracle's.
    #[test]
    fn coincident_and_nearly_coincident_pancakes() {
        for (rings, segments, thickness) in [
            (4, 8, 1e-5),
            (8, 16, 1e-5),
            (8, 16, 1e-3),
            (8, 16, 1e-7),
            (6, 12, 1e-4),
        ] {
            let ball = mesh::sphere(1.0, rings, segments).expect("sphere");
            let v = ball
                .vertices()
                .iter()
                .map(|p| Vec3::new(p.x, p.y, p.z * thickness) * 1e6)
                .collect();
            let pancake = TriMesh::new(v, ball.triangles().to_vec()).expect("pancake");
            let p = pancake.convex_polytope().expect("convex");
            // The flattest has no Gauss map (its sides are too thin to tell apart): the whole
            // depth is still compared.
            assert!(p.gauss.is_some() || thickness < 1e-6);
            for other in [
                Pose::IDENTITY,
                Pose::from_translation(Vec3::new(3.0, -2.0, 0.5 * thickness * 1e6)),
                Pose::from_axis_angle(Vec3::new(0.3, 0.1, 1.0), 1e-6, Vec3::ZERO),
                Pose::from_axis_angle(Vec3::X, 1e-9, Vec3::new(0.0, 0.0, 1e-3)),
            ] {
                let id = Pose::IDENTITY;
                let oracle = every_pair_depth((&pancake, p, &id), (&pancake, p, &other))
                    .expect("small")
                    .0;
                let gauss = exact_depth_without_epa((&pancake, p, &id), (&pancake, p, &other))
                    .expect("small")
                    .0;
                let whole = exact_depth(&pancake, p, &id, &pancake, p, &other)
                    .expect("small")
                    .0;
                for d in [gauss, whole] {
                    assert!(
                        (d - oracle).abs() <= 1e-9 * oracle,
                        "{rings} {segments} {thickness:e} {other:?}: {d} against {oracle}"
                    );
                }
                assert!(oracle > 0.4 * thickness * 1e6);
            }
        }
    }
}

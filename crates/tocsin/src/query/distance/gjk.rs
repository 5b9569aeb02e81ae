//! The distance between two convex polytopes by GJK (Gilbert, Johnson and Keerthi 1988), with
//! the answer certified and given by a triangle pair, as the hierarchy search gives it.
//!
//! Meshes that pass the convex polytope test ([`crate::query::penetration::convex`]) bound
//! convex solids `A` and `B`. While the solids are apart, their closest points lie on their
//! surfaces, so the meshes' distance is the solids' distance, the distance from the origin to
//! the Minkowski difference `C = A - B`. GJK finds it by a sequence of simplices whose corners
//! are supports of `C`, `s_C(d) = s_A(d) - s_B(-d)`, each support climbed over the mesh's edges
//! from where the last one ended ([`Polytope::climb`]): a few steps per support, against a
//! search over every triangle pair's volumes.
//!
//! **The certificate.** GJK ends with `v`, the closest point of its last simplex to the origin,
//! and `w = s_C(-v)`. Every point `c` of `C` has `v.c >= v.w`, so with `u = v / |v|` the gap
//! `L = u.w` bounds the distance from below: `L` is the width of the slab between the two
//! solids across the unit normal `n = -u` (from body 1 to body 2), `min_B n.b - max_A n.a`.
//! The simplex's corners on each body give the triangles holding its witness points; their
//! exact distance `d` ([`distance_triangle_triangle`]) is one triangle pair's, so it bounds the
//! meshes' distance from above. The answer is that pair when `d - L` is within the allowed
//! error (for an exact query [`ROUNDING`] of the coordinates' size): the distance the
//! hierarchy would return, to that. Any unit direction gives such a slab; the one used is
//! rebuilt from the simplex ([`Gjk::certify`]: a triangle's normal, or `v` without its
//! component along a segment), since `v` itself is a small difference of large coordinates
//! near contact, and a gap across its direction was off by 1e-10 of the size at a gap of 1e-6.
//! Otherwise (the solids overlap, which the meshes need not:
//! a ball inside a closed socket; a simplex that rounding stalled; a climb that stopped short)
//! the caller searches the hierarchies as for any soup.
//!
//! The climb is trusted only on meshes convex to [`crate::query::penetration::convex::STRICT`]
//! of their size (every corner behind every face's plane to that): on those a climbed corner
//! is a support to about that much, which [`ROUNDING`] covers. The polytope test is made on a
//! mesh's first query and kept; it costs about a build of the hierarchy (28 ms for a sphere of
//! 16,128 triangles), so meshes above [`GJK_MAX_VERTICES`] corners are not tested for it here.
//!
//! The continuous collision's step search uses the same separation: the slab's width along
//! its normal certifies a step for the two whole bodies, as a node pair's gap does for its two
//! volumes ([`crate::query::contact_time`]); far from contact the slab across `v` serves
//! ([`Ended::coarse`]), from a GJK stopped early ([`Gjk::run_to`]). Where the solids overlap,
//! GJK's tetrahedron holding the origin starts the penetration depth's EPA
//! ([`crate::query::penetration`]). Meshes already tested (by a penetration depth, or
//! [`TriMesh::is_convex`]) take the path whatever their size.

use super::{distance_triangle_triangle, TrianglePairDistance};
use crate::math::{Mat3, Vec3};
use crate::query::penetration::convex::Polytope;
use crate::query::penetration::surface::point_to_mesh;
use crate::TriMesh;

/// Meshes with more corners than this are not tested for convexity by the distance queries
/// (the test's cost, module docs); those already tested (by a penetration depth or
/// [`TriMesh::is_convex`]) still take the GJK path.
pub const GJK_MAX_VERTICES: usize = 4096;

/// The certificate's allowance for rounding, a fraction of the coordinates' size (the bodies'
/// radii plus their distance apart).
pub const ROUNDING: f64 = 1e-11;

/// Most GJK iterations before the path gives up for the hierarchy search (on polytopes GJK
/// ends in a few; this only stops rounding from cycling).
const MAX_ITERATIONS: usize = 64;

/// Both meshes as convex polytopes whose supports can be climbed, or `None`.
pub(crate) fn polytopes<'a>(
    mesh1: &'a TriMesh,
    mesh2: &'a TriMesh,
) -> Option<(&'a Polytope, &'a Polytope)> {
    let small = |m: &TriMesh| m.num_vertices() <= GJK_MAX_VERTICES || m.has_convex_polytope();
    if !(small(mesh1) && small(mesh2)) {
        return None;
    }
    let p1 = mesh1.convex_polytope().filter(|p| p.climbs())?;
    let p2 = mesh2.convex_polytope().filter(|p| p.climbs())?;
    Some((p1, p2))
}

/// Two convex solids apart, as GJK left them (mesh 1's frame).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Separation {
    /// The slab's width across `normal`: a lower bound of the distance (module docs).
    pub gap: f64,
    /// Unit normal from body 1 to body 2.
    pub normal: Vec3,
    /// The triangles (leaf positions) holding the witness points.
    pub leaves: (u32, u32),
    /// Their exact distance and closest points: an upper bound of the distance.
    pub pair: TrianglePairDistance,
    /// The size the rounding is measured against (radii plus the distance apart).
    pub scale: f64,
}

impl Separation {
    /// Whether the pair's distance is within `allowed` (plus rounding) of the gap, so that it
    /// is the meshes' distance to that.
    #[inline]
    pub(crate) fn certifies(&self, allowed: f64) -> bool {
        self.pair.distance - self.gap <= allowed + ROUNDING * self.scale
    }

    /// The gap less the rounding allowance: a lower bound of the distance that holds to the
    /// last bit.
    #[inline]
    pub(crate) fn safe_gap(&self) -> f64 {
        self.gap - ROUNDING * self.scale
    }
}

/// Where GJK ended on a mesh pair: its last simplex's corners (index pairs into the two meshes'
/// vertices), the next query's start on nearby poses. Carried by the distance and contact
/// caches.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct WarmSimplex {
    ids: [(u32, u32); 3],
    size: u8,
}

/// Where GJK ended: its last simplex (corners and weights), `v` (the simplex's nearest point to
/// the origin) and `v.w` for the last support `w` along `-v`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ended {
    corners: [Corner; 3],
    weights: [f64; 3],
    size: usize,
    v: Vec3,
    vw: f64,
    /// The size the rounding is measured against (radii plus the distance apart).
    pub scale: f64,
}

impl Ended {
    /// The slab's width across `v`'s direction and the unit normal from body 1 to body 2: a
    /// lower bound of the distance (every `c` of C has `v.c >= v.w`), exact to the rounding of
    /// a dot product, though less tight than [`Gjk::certify`]'s near contact.
    pub(crate) fn coarse(&self) -> (f64, Vec3) {
        let len = self.v.length();
        (self.vw / len, -self.v / len)
    }
}

/// A corner of a GJK simplex: the point of `C` and the two mesh corners giving it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Corner {
    /// The point of `C = A - B` (mesh 1's frame).
    pub w: Vec3,
    /// Mesh 1's corner.
    pub a: u32,
    /// Mesh 2's corner.
    pub b: u32,
}

/// GJK between two convex meshes, keeping where the last supports were found (the next query
/// on nearby poses climbs from there).
pub(crate) struct Gjk<'a> {
    mesh1: &'a TriMesh,
    poly1: &'a Polytope,
    mesh2: &'a TriMesh,
    poly2: &'a Polytope,
    /// The last support corners of mesh 1 and mesh 2.
    starts: (u32, u32),
    /// The last query's final simplex, the next one's start.
    last: WarmSimplex,
    /// Where the last query found the solids overlapping: a tetrahedron of C holding the
    /// origin (the penetration depth's start).
    inside: Option<[Corner; 4]>,
}

impl<'a> Gjk<'a> {
    /// GJK on two meshes' polytopes ([`polytopes`]), starting from `simplex` (a last query's,
    /// when its indices are in range) or else from the corners of the triangle pair `warm`
    /// (leaf positions) when given.
    pub(crate) fn new(
        mesh1: &'a TriMesh,
        poly1: &'a Polytope,
        mesh2: &'a TriMesh,
        poly2: &'a Polytope,
        warm: Option<(u32, u32)>,
        simplex: WarmSimplex,
    ) -> Self {
        let (n1, n2) = (mesh1.num_vertices() as u32, mesh2.num_vertices() as u32);
        let in_range = simplex.ids[..usize::from(simplex.size)]
            .iter()
            .all(|&(a, b)| a < n1 && b < n2);
        let last = if in_range {
            simplex
        } else {
            WarmSimplex::default()
        };
        let corner = |m: &TriMesh, leaf: u32| {
            let i = m
                .bvh()
                .triangle_index(leaf.min(m.num_triangles() as u32 - 1));
            m.triangles()[i][0]
        };
        let starts = match warm {
            Some((l1, l2)) => (corner(mesh1, l1), corner(mesh2, l2)),
            None => (mesh1.triangles()[0][0], mesh2.triangles()[0][0]),
        };
        Self {
            mesh1,
            poly1,
            mesh2,
            poly2,
            starts,
            last,
            inside: None,
        }
    }

    /// Where the last query ended, for a cache.
    pub(crate) fn warm(&self) -> WarmSimplex {
        self.last
    }

    /// The tetrahedron of C holding the origin where the last query found the solids
    /// overlapping.
    pub(crate) fn tetrahedron(&self) -> Option<[Corner; 4]> {
        self.inside
    }

    /// The support corner of `C = A - B` along `d` (mesh 1's frame), mesh 2 placed by
    /// `(rot12, trans12)`.
    #[inline]
    pub(crate) fn support(&mut self, d: Vec3, rot12: &Mat3, trans12: Vec3) -> Option<Corner> {
        let (v1, v2) = (self.mesh1.vertices(), self.mesh2.vertices());
        let a = self.poly1.climb(v1, d, self.starts.0)?;
        let b = self
            .poly2
            .climb(v2, rot12.transpose() * -d, self.starts.1)?;
        self.starts = (a, b);
        let w = v1[a as usize] - (*rot12 * v2[b as usize] + trans12);
        Some(Corner { w, a, b })
    }

    /// The two mesh corners giving `c`, each in its own mesh's frame.
    #[inline]
    pub(crate) fn corner_points(&self, c: &Corner) -> (Vec3, Vec3) {
        (
            self.mesh1.vertices()[c.a as usize],
            self.mesh2.vertices()[c.b as usize],
        )
    }

    /// The separation of the two solids with mesh 2 placed by `(rot12, trans12)` in mesh 1's
    /// frame, or `None` when they overlap (or GJK stalls: module docs). The caller checks
    /// [`Separation::certifies`] before taking the pair as the distance.
    pub(crate) fn separation(&mut self, rot12: &Mat3, trans12: Vec3) -> Option<Separation> {
        let ended = self.run(rot12, trans12)?;
        self.certify(&ended, rot12, trans12)
    }

    /// The full separation from where GJK ended: the gap across the simplex's accurate
    /// direction (`v`'s loses accuracy as `|v|` shrinks, being a small difference of large
    /// coordinates: at a gap of 1e-6 of the size, 1e-10 of it), and the witness pair.
    pub(crate) fn certify(
        &mut self,
        ended: &Ended,
        rot12: &Mat3,
        trans12: Vec3,
    ) -> Option<Separation> {
        let simplex = &ended.corners[..ended.size];
        let u = Self::accurate_direction(simplex, ended.v);
        let w = self.support(-u, rot12, trans12)?;
        Some(self.finish(
            (rot12, trans12),
            simplex,
            &ended.weights[..ended.size],
            (u, u.dot(w.w)),
            ended.scale,
        ))
    }

    /// A triangle pair (leaf positions) at GJK's last supports: near the closest features,
    /// for a warm start, without the witness search.
    pub(crate) fn near_leaves(&self, ended: &Ended) -> (u32, u32) {
        let c = &ended.corners[0];
        (
            self.poly1.corner_leaves(c.a)[0],
            self.poly2.corner_leaves(c.b)[0],
        )
    }

    /// GJK itself: where it ended, or `None` when the solids overlap or it stalls.
    pub(crate) fn run(&mut self, rot12: &Mat3, trans12: Vec3) -> Option<Ended> {
        self.run_to(rot12, trans12, 0.0, f64::INFINITY)
    }

    /// [`Self::run`], ending as soon as the gap `v.w / |v|` is at least `floor` and within
    /// `rel` of `|v|` (a lower bound of the distance within that fraction of an upper bound:
    /// what a step far from contact needs), or when it has converged.
    pub(crate) fn run_to(
        &mut self,
        rot12: &Mat3,
        trans12: Vec3,
        rel: f64,
        floor: f64,
    ) -> Option<Ended> {
        self.inside = None;
        let (r1, r2) = (self.mesh1.bounding_radius(), self.mesh2.bounding_radius());
        let centre2 = *rot12 * self.mesh2.bvh().root().center + trans12;
        let scale = r1 + r2 + (centre2 - self.mesh1.bvh().root().center).length();
        let (v1, v2) = (self.mesh1.vertices(), self.mesh2.vertices());
        let corner = |(a, b): (u32, u32)| Corner {
            w: v1[a as usize] - (*rot12 * v2[b as usize] + trans12),
            a,
            b,
        };
        let first = corner(self.starts);
        let mut simplex = [first; 4];
        let mut size = 1;
        let mut weights = [1.0, 0.0, 0.0, 0.0];
        let mut v = first.w;
        // Warm: the last query's simplex, its corners at the new pose (on nearby poses the
        // nearest features change little, and GJK ends in one or two iterations instead of a
        // dozen on hulls of 1,000 points near contact).
        let (last_ids, last_size) = (self.last.ids, usize::from(self.last.size));
        if last_size > 1 {
            let mut warm = [first; 4];
            for (slot, &ids) in warm.iter_mut().zip(&last_ids[..last_size]) {
                *slot = corner(ids);
            }
            if let Some(nearest) = closest_on_simplex(&warm[..last_size], None) {
                (simplex, weights, size, v) = kept(&warm[..last_size], nearest);
            }
        }
        let tiny = 1e-13 * scale;
        let mut last = f64::INFINITY;
        for _ in 0..MAX_ITERATIONS {
            let vv = v.length_squared();
            if vv <= tiny * tiny {
                return None;
            }
            let w = self.support(-v, rot12, trans12)?;
            // No point of C is closer along `v` than `w`: the gap, and the end when it is
            // within rounding of `|v|`, or the corner is already in the simplex.
            let vw = v.dot(w.w);
            // Or `|v|` no longer shrinks: a support coplanar with the simplex's face, along a
            // `v` whose direction rounding has tilted, would otherwise come back forever.
            let repeated = simplex[..size].iter().any(|c| c.a == w.a && c.b == w.b);
            let stalled = vv >= last;
            last = vv;
            let close = vv - vw <= rel * vv && vw >= floor * vv.sqrt();
            if close || repeated || stalled || vv - vw <= 1e-14 * scale * vv.sqrt() {
                let mut ids = [(0, 0); 3];
                for (slot, c) in ids.iter_mut().zip(&simplex[..size]) {
                    *slot = (c.a, c.b);
                }
                self.last = WarmSimplex {
                    ids,
                    size: size as u8,
                };
                let mut corners = [first; 3];
                corners[..size].copy_from_slice(&simplex[..size]);
                let mut lambda = [0.0; 3];
                lambda[..size].copy_from_slice(&weights[..size]);
                return Some(Ended {
                    corners,
                    weights: lambda,
                    size,
                    v,
                    vw,
                    scale,
                });
            }
            simplex[size] = w;
            size += 1;
            let nearest = closest_on_simplex(&simplex[..size], Some(size - 1))?;
            (simplex, weights, size, v) = kept(&simplex[..size], nearest);
            if size == 4 {
                // The origin is inside the tetrahedron: the solids overlap.
                self.last = WarmSimplex::default();
                self.inside = Some(simplex);
                return None;
            }
        }
        None
    }

    /// The unit direction from the origin towards C's nearest point `v`, rebuilt from the
    /// simplex: a triangle's normal (a face of C; a cross product of differences of the size
    /// of the bodies keeps full accuracy); for a segment (an edge of C), `v`'s direction with
    /// its component along the edge removed, since a tilt along the edge changes the gap to
    /// first order and one about it only to second; `v` itself for a corner.
    fn accurate_direction(simplex: &[Corner], v: Vec3) -> Vec3 {
        let u = v.normalize();
        match simplex {
            [a, b, c] => match (b.w - a.w).cross(c.w - a.w).try_normalize() {
                Some(n) if n.dot(a.w) < 0.0 => -n,
                Some(n) => n,
                None => u,
            },
            [a, b] => match (b.w - a.w).try_normalize() {
                Some(e) => (u - e * u.dot(e)).try_normalize().unwrap_or(u),
                None => u,
            },
            _ => u,
        }
    }

    /// The separation from GJK's last simplex (its corners and weights), the unit direction
    /// `u` from the origin towards C and the gap `L` across it.
    fn finish(
        &self,
        (rot12, trans12): (&Mat3, Vec3),
        simplex: &[Corner],
        weights: &[f64],
        (u, gap): (Vec3, f64),
        scale: f64,
    ) -> Separation {
        let normal = -u;
        let (v1, v2) = (self.mesh1.vertices(), self.mesh2.vertices());
        let point1: Vec3 = simplex
            .iter()
            .zip(weights)
            .map(|(c, &l)| v1[c.a as usize] * l)
            .sum();
        let point2: Vec3 = simplex
            .iter()
            .zip(weights)
            .map(|(c, &l)| v2[c.b as usize] * l)
            .sum();
        let leaf1 = holding(self.mesh1, self.poly1, simplex.iter().map(|c| c.a), point1);
        let leaf2 = holding(self.mesh2, self.poly2, simplex.iter().map(|c| c.b), point2);
        let t1 = &self.mesh1.bvh().leaf_triangles()[leaf1 as usize];
        // Mesh 2's triangle placed as the hierarchy search places it.
        let t2 = self.mesh2.bvh().leaf_triangles()[leaf2 as usize].map(|p| *rot12 * p + trans12);
        Separation {
            gap,
            normal,
            leaves: (leaf1, leaf2),
            pair: distance_triangle_triangle(t1, &t2),
            scale,
        }
    }
}

/// The triangle (leaf position) of `mesh` at the corners `corners` (body frame) nearest to
/// `point`: a triangle with every distinct corner among them when there is one (the point is
/// on the feature they span), else the nearest by the point's distance.
fn holding(
    mesh: &TriMesh,
    poly: &Polytope,
    corners: impl Iterator<Item = u32> + Clone,
    point: Vec3,
) -> u32 {
    let mut distinct = [0u32; 3];
    let mut n = 0;
    for c in corners {
        if !distinct[..n].contains(&c) && n < 3 {
            distinct[n] = c;
            n += 1;
        }
    }
    let first = poly.corner_leaves(distinct[0]);
    let tri_corners = |leaf: u32| {
        let t = mesh.triangles()[mesh.bvh().triangle_index(leaf)];
        distinct[..n].iter().all(|c| t.contains(c))
    };
    if let Some(&leaf) = first.iter().find(|&&l| tri_corners(l)) {
        return leaf;
    }
    // A flat face's corners can span a segment or triangle across other triangles of the
    // face: the point's nearest triangle, from the hierarchy.
    point_to_mesh(mesh.bvh(), point, first[0]).2
}

/// The simplex reduced to the face holding its nearest point (`closest_on_simplex`'s answer:
/// the point, the face's corners as a bit mask, the weights indexed like `s`): the face's
/// corners first, their weights, how many, and the point.
fn kept(
    s: &[Corner],
    (point, mask, lambda): (Vec3, u32, [f64; 4]),
) -> ([Corner; 4], [f64; 4], usize, Vec3) {
    let mut corners = [s[0]; 4];
    let mut weights = [0.0; 4];
    let mut k = 0;
    for (i, c) in s.iter().enumerate() {
        if mask & (1 << i) != 0 {
            corners[k] = *c;
            weights[k] = lambda[i];
            k += 1;
        }
    }
    (corners, weights, k, point)
}

/// The point of the simplex's hull nearest the origin, which corners span the face holding it
/// (a bit mask) and its weights (indexed like the simplex): the nearest of the origin's
/// projections on the faces' affine hulls that fall inside their faces (the nearest point lies
/// inside some face, where it is that face's projection; every candidate is a point of the
/// hull). A corner is always a candidate. With `with`, only the faces holding that corner (a new
/// support: GJK's next nearest point lies on a face holding it, being nearer than the last).
/// The first face, by decreasing size, whose projection is inside it and no other corner
/// improves on is the answer at once.
fn closest_on_simplex(s: &[Corner], with: Option<usize>) -> Option<(Vec3, u32, [f64; 4])> {
    // Faces by decreasing size: a face whose projection falls inside it and from which no
    // other corner leads nearer (`x.(w_j - x) >= 0`: the hull's nearest point, by convexity)
    // ends the search; without one to rounding, the nearest candidate.
    const ORDER: [&[u32]; 5] = [
        &[],
        &[1],
        &[3, 1, 2],
        &[7, 3, 5, 6, 1, 2, 4],
        &[15, 7, 11, 13, 14, 3, 5, 6, 9, 10, 12, 1, 2, 4, 8],
    ];
    let n = s.len();
    let mut best: Option<(f64, Vec3, u32, [f64; 4])> = None;
    for &mask in ORDER[n] {
        if with.is_some_and(|i| mask & (1 << i) == 0) {
            continue;
        }
        let mut idx = [0usize; 4];
        let mut k = 0;
        for (i, slot) in (0..n).filter(|i| mask & (1 << i) != 0).zip(0..) {
            idx[slot] = i;
            k += 1;
        }
        let Some(lambda) = project(s, &idx[..k]) else {
            continue;
        };
        let mut weights = [0.0; 4];
        let mut point = Vec3::ZERO;
        for (j, &i) in idx[..k].iter().enumerate() {
            weights[i] = lambda[j];
            point += s[i].w * lambda[j];
        }
        let d = point.length_squared();
        if (0..n).all(|j| mask & (1 << j) != 0 || point.dot(s[j].w - point) >= 0.0) {
            return Some((point, mask, weights));
        }
        if best.is_none_or(|b| d < b.0) {
            best = Some((d, point, mask, weights));
        }
    }
    best.map(|(_, p, m, w)| (p, m, w))
}

/// The weights of the origin's projection on the affine hull of the corners `idx`, when it
/// falls inside their hull (every weight positive) and the corners are independent.
fn project(s: &[Corner], idx: &[usize]) -> Option<[f64; 4]> {
    let p0 = s[idx[0]].w;
    let k = idx.len() - 1;
    if k == 0 {
        return Some([1.0, 0.0, 0.0, 0.0]);
    }
    let mut e = [Vec3::ZERO; 3];
    for (j, &i) in idx[1..].iter().enumerate() {
        e[j] = s[i].w - p0;
    }
    // Normal equations: G mu = -E^T p0.
    let mut g = [[0.0f64; 3]; 3];
    let mut r = [0.0f64; 3];
    for i in 0..k {
        for j in 0..k {
            g[i][j] = e[i].dot(e[j]);
        }
        r[i] = -e[i].dot(p0);
    }
    let mu = solve(&g, &r, k)?;
    let mut lambda = [0.0; 4];
    lambda[0] = 1.0 - mu[..k].iter().sum::<f64>();
    lambda[1..=k].copy_from_slice(&mu[..k]);
    lambda[..=k].iter().all(|&l| l > 0.0).then_some(lambda)
}

/// Solves the `k x k` (1 to 3) symmetric system `g x = r`, or `None` when it is singular to
/// rounding.
fn solve(g: &[[f64; 3]; 3], r: &[f64; 3], k: usize) -> Option<[f64; 3]> {
    let scale = (0..k).map(|i| g[i][i]).fold(0.0, f64::max);
    match k {
        1 => (g[0][0] > 0.0).then(|| [r[0] / g[0][0], 0.0, 0.0]),
        2 => {
            let det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
            (det > 1e-14 * scale * scale).then(|| {
                [
                    (r[0] * g[1][1] - g[0][1] * r[1]) / det,
                    (g[0][0] * r[1] - r[0] * g[1][0]) / det,
                    0.0,
                ]
            })
        }
        _ => {
            let m = Mat3::from_cols(
                Vec3::new(g[0][0], g[1][0], g[2][0]),
                Vec3::new(g[0][1], g[1][1], g[2][1]),
                Vec3::new(g[0][2], g[1][2], g[2][2]),
            );
            let det = m.determinant();
            (det.abs() > 1e-14 * scale * scale * scale).then(|| {
                let x = m.inverse() * Vec3::new(r[0], r[1], r[2]);
                [x.x, x.y, x.z]
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pose;
    use crate::mesh;
    use crate::motion::sampling::unit;
    use crate::query::distance::traverse::{DistanceSearch, Stop};
    use crate::query::distance::{distance, within_distance, DistanceOptions, DistanceResult};
    use crate::query::penetration::convex::tests::{gridded_box, random_convex, rotation};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The hierarchy search alone: the oracle.
    fn searched(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose) -> DistanceResult {
        let pos12 = p1.inv_mul(p2);
        let options = DistanceOptions::default();
        let mut search = DistanceSearch::new(m1, m2, &pos12, &options, Stop::Never);
        search.run(None);
        search.result(p1)
    }

    /// The certified separation, when the GJK path answers.
    fn gjk(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose) -> Option<Separation> {
        let (q1, q2) = polytopes(m1, m2)?;
        let pos12 = p1.inv_mul(p2);
        Gjk::new(m1, q1, m2, q2, None, WarmSimplex::default())
            .separation(&pos12.rotation, pos12.translation)
            .filter(|s| s.certifies(0.0))
    }

    /// The point's distance from the mesh's triangle `k` (world frame, the mesh at `pose`).
    fn off_triangle(m: &TriMesh, pose: &Pose, k: usize, p: Vec3) -> f64 {
        let t = m.triangle(k).map(|v| pose.transform_point(v));
        distance_triangle_triangle(&t, &[p; 3]).distance
    }

    /// On 1,500 random pairs of convex meshes (boxes, coarse spheres, cylinders, gridded
    /// boxes, stretched and sheared; a third turned by quarter turns only, so that faces and
    /// edges are parallel), placed far apart, near (gaps of 1e-3 to 1e-12 of the size,
    /// made exact by moving one body along the normal), touching and overlapping, the distance
    /// equals the hierarchy search's to rounding, its points lie on the triangles it names,
    /// and GJK answered every pair apart by more than rounding but a few (where they touch to
    /// rounding, the hierarchy answers).
    #[test]
    fn agrees_with_the_hierarchy_search() {
        let mut rng = ChaCha8Rng::seed_from_u64(41);
        let (mut separated, mut answered, mut worst) = (0, 0, 0.0f64);
        for case in 0..1500 {
            let (a, b) = (random_convex(&mut rng), random_convex(&mut rng));
            let pa = rotation(&mut rng, case % 3 == 0);
            let mut pb = rotation(&mut rng, case % 3 == 0);
            let reach = a.bounding_radius() + b.bounding_radius();
            pb.translation = unit(&mut rng) * reach * rng.random_range(0.3..2.0);
            let gap = [f64::NAN, 1e-3, 1e-6, 1e-9, 1e-12, 0.0][case % 6];
            if !gap.is_nan() {
                let d = searched(&a, &pa, &b, &pb);
                if d.distance == 0.0 {
                    continue;
                }
                let n = (d.point2 - d.point1) / d.distance;
                pb.translation -= n * (d.distance - gap * reach);
            }
            let slow = searched(&a, &pa, &b, &pb);
            let fast = distance(&a, &pa, &b, &pb, &DistanceOptions::default()).expect("ok");
            let scale = reach + pb.translation.length();
            let error = (fast.distance - slow.distance).abs() / scale;
            worst = worst.max(error);
            assert!(error <= ROUNDING, "case {case}: {fast:?} against {slow:?}");
            assert!((fast.point2 - fast.point1).length() - fast.distance <= 1e-12 * scale);
            assert!(off_triangle(&a, &pa, fast.triangle1, fast.point1) <= 1e-12 * scale);
            assert!(off_triangle(&b, &pb, fast.triangle2, fast.point2) <= 1e-12 * scale);
            if slow.distance > 1e-13 * scale {
                separated += 1;
                answered += usize::from(gjk(&a, &pa, &b, &pb).is_some());
            }
        }
        eprintln!("GJK answered {answered} of {separated} separated pairs; worst {worst:e}");
        assert!(separated > 1000 && answered * 100 >= separated * 98);
    }

    /// The allowed error and the threshold query take the same path and keep their promises.
    #[test]
    fn options_and_threshold() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..300 {
            let (a, b) = (random_convex(&mut rng), random_convex(&mut rng));
            let pa = rotation(&mut rng, false);
            let mut pb = rotation(&mut rng, false);
            let reach = a.bounding_radius() + b.bounding_radius();
            pb.translation = unit(&mut rng) * reach * rng.random_range(0.5..2.0);
            let exact = searched(&a, &pa, &b, &pb).distance;
            let options = DistanceOptions {
                relative_error: 0.1,
                absolute_error: 1e-3,
            };
            let d = distance(&a, &pa, &b, &pb, &options).expect("ok").distance;
            assert!(d >= exact - 1e-12 * reach && d <= exact * 1.1 + 1e-3 + 1e-12 * reach);
            for threshold in [exact * 0.999, exact * 1.001, exact + 1e-12 * reach] {
                let within = within_distance(&a, &pa, &b, &pb, threshold).expect("ok");
                if (threshold - exact).abs() > 1e-11 * reach {
                    assert_eq!(within, exact <= threshold, "{exact} against {threshold}");
                }
            }
        }
    }

    /// Where the GJK path must not answer, the hierarchy does: a ball inside a closed socket
    /// (the solids overlap, the surfaces are apart), a convex mesh with a degenerate
    /// triangle (no Gauss map), one convex only to 1e-10 of its size (not to the strict
    /// test), and meshes that touch.
    #[test]
    fn falls_back_where_it_must() {
        let ball = mesh::sphere(1.0, 8, 16).expect("ball");
        let socket = mesh::sphere(1.01, 8, 16).expect("socket");
        let id = Pose::IDENTITY;
        assert!(gjk(&ball, &id, &socket, &id).is_none());
        let d = distance(&ball, &id, &socket, &id, &DistanceOptions::default()).expect("ok");
        assert_eq!(d, searched(&ball, &id, &socket, &id));
        assert!(d.distance > 0.009 && d.distance < 0.0101);

        // A box with one face's diagonal split at its midpoint: a degenerate triangle.
        let cube = mesh::box_mesh(Vec3::splat(0.5)).expect("box");
        let mut vertices = cube.vertices().to_vec();
        let mut triangles = cube.triangles().to_vec();
        let [p, q, r] = triangles[0];
        vertices.push((vertices[p as usize] + vertices[r as usize]) * 0.5);
        let m = vertices.len() as u32 - 1;
        triangles[0] = [p, q, m];
        triangles.push([q, r, m]);
        triangles.push([r, p, m]);
        let split = TriMesh::new(vertices.clone(), triangles.clone()).expect("split");
        let far = Pose::from_axis_angle(Vec3::Z, 0.3, Vec3::new(2.0, 0.4, 0.1));
        assert!(gjk(&split, &id, &cube, &far).is_none());
        let d = distance(&split, &id, &cube, &far, &DistanceOptions::default()).expect("ok");
        assert_eq!(d, searched(&split, &id, &cube, &far));

        // A corner inside a gridded face pushed 1e-10 into the box (a dimple): convex to the
        // polytope test's 1e-9, not to the strict one.
        let grid = gridded_box(2, Vec3::splat(0.5));
        let mut dimpled = grid.vertices().to_vec();
        let centre = dimpled
            .iter()
            .position(|p| (*p - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-12)
            .expect("a face centre");
        dimpled[centre].x -= 1e-10;
        let dimpled = TriMesh::new(dimpled, grid.triangles().to_vec()).expect("dimpled");
        assert!(dimpled.convex_polytope().is_some());
        assert!(gjk(&dimpled, &id, &cube, &far).is_none());
        assert!(gjk(&grid, &id, &cube, &far).is_some());

        // Touching face to face, and a gridded box against a box turned a quarter.
        let touching = Pose::from_axis_angle(Vec3::Z, 0.0, Vec3::new(1.0, 0.2, 0.1));
        let d = distance(&cube, &id, &cube, &touching, &DistanceOptions::default()).expect("ok");
        assert_eq!(d.distance, 0.0);
        let grid = gridded_box(3, Vec3::new(0.5, 0.5, 0.5));
        let quarter = Pose::from_axis_angle(
            Vec3::Z,
            std::f64::consts::FRAC_PI_2,
            Vec3::new(1.5, 0.0, 0.0),
        );
        let d = distance(&grid, &id, &cube, &quarter, &DistanceOptions::default()).expect("ok");
        assert!((d.distance - 0.5).abs() < 1e-14);
        assert!(gjk(&grid, &id, &cube, &quarter).is_some());
    }

    /// Meshes above [`GJK_MAX_VERTICES`] corners are not tested for convexity by the queries,
    /// but take the path once tested ([`TriMesh::is_convex`]).
    #[test]
    fn large_meshes_once_tested() {
        let big = mesh::sphere(1.0, 64, 128).expect("sphere");
        assert!(big.num_vertices() > GJK_MAX_VERTICES);
        assert!(polytopes(&big, &big).is_none());
        assert!(big.is_convex());
        assert!(polytopes(&big, &big).is_some());
        let far = Pose::from_axis_angle(Vec3::X, 0.4, Vec3::new(2.5, 0.3, 0.0));
        let fast = distance(
            &big,
            &Pose::IDENTITY,
            &big,
            &far,
            &DistanceOptions::default(),
        );
        let slow = searched(&big, &Pose::IDENTITY, &big, &far);
        assert!((fast.expect("ok").distance - slow.distance).abs() < 1e-14);
    }

    /// At 1e-9 and 1e9 of the unit size, and 1e9 away from the origin, the answer is the
    /// hierarchy's to rounding of those coordinates.
    #[test]
    fn tiny_and_huge_scales() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for (size, offset) in [(1e-9, 0.0), (1e9, 0.0), (1.0, 1e9), (1e-6, 1e3)] {
            for _ in 0..40 {
                let scaled = |m: TriMesh| {
                    let v = m.vertices().iter().map(|p| *p * size).collect();
                    TriMesh::new(v, m.triangles().to_vec()).expect("scaled")
                };
                let (a, b) = (
                    scaled(random_convex(&mut rng)),
                    scaled(random_convex(&mut rng)),
                );
                let mut pa = rotation(&mut rng, false);
                pa.translation = Vec3::splat(offset);
                let mut pb = rotation(&mut rng, false);
                let reach = a.bounding_radius() + b.bounding_radius();
                pb.translation = pa.translation + unit(&mut rng) * reach * 1.2;
                let slow = searched(&a, &pa, &b, &pb);
                let fast = distance(&a, &pa, &b, &pb, &DistanceOptions::default()).expect("ok");
                let scale = reach + offset;
                assert!(
                    (fast.distance - slow.distance).abs() <= ROUNDING * scale,
                    "{size} {offset}: {fast:?} {slow:?}"
                );
            }
        }
    }
}

//! What the Hausdorff and pointwise-depth searches share: the distance from a point to a mesh
//! and whether a triangle meets it (small searches over its RSS hierarchy), the convex-corner
//! upper bound, the split of a triangle in four, and the max-heap order of pieces by upper
//! bound.

use crate::bvh::{Bvh, Rss};
use crate::math::{Pose, Vec3};
use crate::query::distance::{
    intersect_triangle_triangle, project_inside_triangle, triangle_normal,
};
use crate::TriMesh;

/// A lower bound on the distance from `p` to the volume.
#[inline]
pub(crate) fn rss_point_bound(rss: &Rss, p: Vec3) -> f64 {
    let q = rss.axes.transpose() * (p - rss.center);
    let dx = (q.x.abs() - rss.half_lengths[0]).max(0.0);
    let dy = (q.y.abs() - rss.half_lengths[1]).max(0.0);
    ((dx * dx + dy * dy + q.z * q.z).sqrt() - rss.radius).max(0.0)
}

/// Closest point of the triangle `t` to `p` (any triangle: degenerate ones are their edges).
/// By the Voronoi regions of the corners, then the edges, then the face, each decided from
/// dot products with the two edges at a corner (the textbook order, e.g. Ericson's Real-Time
/// Collision Detection 5.1.5); 1.5x fewer instructions than projecting on the plane first and
/// testing the three edges. Thin and degenerate triangles take the plane projection first.
#[inline]
pub(crate) fn closest_on_triangle(p: Vec3, t: &[Vec3; 3]) -> Vec3 {
    let [a, b, c] = *t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    // The region tests below cancel in products of dot products; on thin triangles (the sine
    // of the angle at `a` under 1e-3) that noise could pick a wrong region, so those take the
    // projection on the plane first.
    let nn = ab.cross(ac).length_squared();
    if nn.is_nan() || nn <= 1e-6 * ab.length_squared() * ac.length_squared() {
        return closest_on_thin(p, t);
    }
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    // `va + vb + vc` is `|ab x ac|^2`, well away from 0 here.
    let sum = va + vb + vc;
    a + ab * (vb / sum) + ac * (vc / sum)
}

/// [`closest_on_triangle`] for thin and degenerate triangles: the nearest of the three edges'
/// closest points and the projection on the plane where it falls inside (on a sliver the plane's
/// normal is poorly determined, so the projection is only a candidate).
fn closest_on_thin(p: Vec3, t: &[Vec3; 3]) -> Vec3 {
    let on_edge = |a: Vec3, b: Vec3| {
        let e = b - a;
        let ee = e.length_squared();
        let s = if ee > 0.0 {
            ((p - a).dot(e) / ee).clamp(0.0, 1.0)
        } else {
            0.0
        };
        a + e * s
    };
    let face = triangle_normal(t).and_then(|n| project_inside_triangle(p, t, n));
    [
        Some(on_edge(t[0], t[1])),
        Some(on_edge(t[1], t[2])),
        Some(on_edge(t[2], t[0])),
        face,
    ]
    .into_iter()
    .flatten()
    .min_by(|x, y| {
        (*x - p)
            .length_squared()
            .total_cmp(&(*y - p).length_squared())
    })
    .unwrap_or(t[0])
}

/// Runs `f` with this thread's scratch stack, empty: the searches below run thousands of times
/// a query, and a vector allocated and freed by each was 2.5 to 4% of a Hausdorff query's
/// instructions. A nested call (there is none) would find it borrowed and use a vector of its
/// own.
fn with_stack<R>(f: impl FnOnce(&mut Vec<(u32, f64)>) -> R) -> R {
    thread_local! {
        static STACK: std::cell::RefCell<Vec<(u32, f64)>> = const { std::cell::RefCell::new(Vec::new()) };
    }
    STACK.with(|cell| match cell.try_borrow_mut() {
        Ok(mut stack) => {
            stack.clear();
            f(&mut stack)
        }
        Err(_) => f(&mut Vec::new()),
    })
}

/// The squared lower bound of [`rss_point_bound`]: the searches below compare squares.
#[inline]
fn point_bound2(rss: &Rss, p: Vec3) -> f64 {
    let b = rss_point_bound(rss, p);
    b * b
}

/// Pushes two children with their bounds so that the nearer is popped first.
#[inline]
fn push_nearer_last(stack: &mut Vec<(u32, f64)>, a: (u32, f64), b: (u32, f64)) {
    let (near, far) = if a.1 <= b.1 { (a, b) } else { (b, a) };
    stack.push(far);
    stack.push(near);
}

/// Exact distance from the point `p` to the mesh of `bvh`, both in that mesh's frame: the
/// distance, the closest point on the mesh and the leaf position of its triangle. `warm` (a
/// leaf position) is tried first. The point against triangle kernel ([`closest_on_triangle`])
/// at the leaves, lower bounds compared squared; it took the triangle pair distance with a
/// degenerate triangle before, 15% slower in all.
pub(crate) fn point_to_mesh(bvh: &Bvh, p: Vec3, warm: u32) -> (f64, Vec3, u32) {
    let nodes = bvh.nodes();
    let tris = bvh.leaf_triangles();
    let w = (warm as usize).min(tris.len() - 1);
    let first = closest_on_triangle(p, &tris[w]);
    let (mut best2, mut closest, mut leaf) = ((first - p).length_squared(), first, w as u32);
    let bound2 = |i: u32| point_bound2(&nodes[i as usize].rss, p);
    with_stack(|stack| {
        stack.push((0u32, bound2(0)));
        while let Some((i, lb2)) = stack.pop() {
            if best2 <= 0.0 {
                break;
            }
            if lb2 >= best2 {
                continue;
            }
            let node = &nodes[i as usize];
            if node.is_leaf() {
                let q = closest_on_triangle(p, &tris[node.leaf_position() as usize]);
                let d2 = (q - p).length_squared();
                if d2 < best2 {
                    (best2, closest, leaf) = (d2, q, node.leaf_position());
                }
                continue;
            }
            let (l, r) = node.children(i);
            push_nearer_last(stack, (l, bound2(l)), (r, bound2(r)));
        }
    });
    (best2.sqrt(), closest, leaf)
}

/// Whether the mesh of `bvh` comes within `r` of `c` (both in that mesh's frame): `Err` with
/// the leaf position of a triangle that does, else `Ok` with a lower bound on the distance
/// from `c` to the mesh, at least `r` (the smallest bound of a pruned volume or distance of a
/// tested triangle). Nodes farther than `r` are pruned, and the search stops at the first
/// triangle within `r`, where an exact distance would go on; `warm` (a leaf position) is
/// tried first.
pub(crate) fn ball_meets_mesh(bvh: &Bvh, c: Vec3, r: f64, warm: u32) -> Result<f64, u32> {
    let nodes = bvh.nodes();
    let tris = bvh.leaf_triangles();
    let w = (warm as usize).min(tris.len() - 1);
    let r2 = r * r;
    let d2 = (closest_on_triangle(c, &tris[w]) - c).length_squared();
    if d2 <= r2 {
        return Err(w as u32);
    }
    let mut free2 = d2;
    with_stack(|stack| {
        stack.push((0u32, 0.0));
        while let Some((i, _)) = stack.pop() {
            let node = &nodes[i as usize];
            let b = rss_point_bound(&node.rss, c);
            let b2 = b * b;
            if b2 > r2 {
                free2 = free2.min(b2);
                continue;
            }
            if node.is_leaf() {
                let d2 = (closest_on_triangle(c, &tris[node.leaf_position() as usize]) - c)
                    .length_squared();
                if d2 <= r2 {
                    return Err(node.leaf_position());
                }
                free2 = free2.min(d2);
                continue;
            }
            let (l, rr) = node.children(i);
            stack.push((rr, 0.0));
            stack.push((l, 0.0));
        }
        Ok(free2.sqrt())
    })
}

/// A triangle's probe of the mesh of `bvh` (both in that mesh's frame): the exact distance
/// from its centroid `c` to the mesh, the closest point and its triangle's leaf position (as
/// [`point_to_mesh`]), and with `test_meets`, whether the triangle touches or crosses the
/// mesh, with the leaf position of a triangle it meets (the exact triangle test of `collide`; `r` bounds
/// the triangle's corners about `c`). One traversal for both: a node is visited while it may
/// hold a nearer point or, until a meeting triangle is found, lies within `r` of `c`. The
/// triangles at the leaf positions `warm` are tried first: the first for the distance, the
/// second for the intersection.
pub(crate) fn triangle_probe(
    bvh: &Bvh,
    t: &[Vec3; 3],
    c: Vec3,
    r: f64,
    test_meets: bool,
    warm: [u32; 2],
) -> (f64, Vec3, u32, Option<u32>) {
    let nodes = bvh.nodes();
    let tris = bvh.leaf_triangles();
    let [w, wm] = warm.map(|w| (w as usize).min(tris.len() - 1));
    let first = closest_on_triangle(c, &tris[w]);
    let (mut best2, mut closest, mut leaf) = ((first - c).length_squared(), first, w as u32);
    let mut meets = None;
    let mut open = test_meets;
    if open && intersect_triangle_triangle(t, &tris[wm]) {
        (meets, open) = (Some(wm as u32), false);
    }
    let r2 = r * r;
    let bound2 = |i: u32| point_bound2(&nodes[i as usize].rss, c);
    with_stack(|stack| {
        stack.push((0u32, bound2(0)));
        while let Some((i, lb2)) = stack.pop() {
            let wanted = lb2 < best2 || (open && lb2 <= r2);
            if !wanted {
                continue;
            }
            let node = &nodes[i as usize];
            if node.is_leaf() {
                let tri = &tris[node.leaf_position() as usize];
                if lb2 < best2 {
                    let q = closest_on_triangle(c, tri);
                    let d2 = (q - c).length_squared();
                    if d2 < best2 {
                        (best2, closest, leaf) = (d2, q, node.leaf_position());
                    }
                }
                if open && lb2 <= r2 && intersect_triangle_triangle(t, tri) {
                    (meets, open) = (Some(node.leaf_position()), false);
                }
                continue;
            }
            let (l, rr) = node.children(i);
            push_nearer_last(stack, (l, bound2(l)), (rr, bound2(rr)));
        }
    });
    (best2.sqrt(), closest, leaf, meets)
}

/// An upper bound on the distance to the mesh over the convex hull of `corners`: the distance
/// to one triangle of the mesh is convex, so over the hull it peaks at a corner, and it bounds
/// the distance to the mesh; the triangles at the leaf positions `leaves` are tried.
pub(crate) fn corner_bound(bvh: &Bvh, corners: &[Vec3], leaves: &[u32]) -> f64 {
    let tris = bvh.leaf_triangles();
    leaves
        .iter()
        .enumerate()
        // A triangle listed twice is tried once.
        .filter(|&(k, j)| !leaves[..k].contains(j))
        .map(|(_, &j)| {
            corners
                .iter()
                .map(|p| (closest_on_triangle(*p, &tris[j as usize]) - *p).length_squared())
                .fold(0.0_f64, f64::max)
                .sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// An upper bound on the distance to the mesh over the triangle `t`, at most [`corner_bound`]'s:
/// with `D[k][m]` the distance from corner `m` to the candidate triangle `k` (the leaf positions
/// `leaves`, up to four), a point `x = sum_m l_m t_m` of `t` has `d(x, mesh) <= d(x, B_k) <=
/// sum_m l_m D[k][m]` for every `k` (each `d(., B_k)` is convex), so the bound is the largest
/// over the barycentric simplex of the smallest of those linear functions: at a corner, where
/// two of them cross on an edge, or where three cross inside (the lower envelope of linear
/// functions is concave and piecewise linear, so its maximum is at such a vertex). Where the
/// candidates are each near a different part of `t` this is tighter than the best single one.
pub(crate) fn envelope_bound(bvh: &Bvh, t: &[Vec3; 3], leaves: &[u32]) -> f64 {
    let tris = bvh.leaf_triangles();
    let mut d = [[0.0_f64; 3]; 6];
    let mut n = 0;
    for (k, &j) in leaves.iter().enumerate() {
        if n == 6 || leaves[..k].contains(&j) {
            continue;
        }
        for m in 0..3 {
            d[n][m] = (closest_on_triangle(t[m], &tris[j as usize]) - t[m]).length();
        }
        n += 1;
    }
    let d = &d[..n];
    let value = |l: [f64; 3]| {
        d.iter()
            .map(|row| row[0] * l[0] + row[1] * l[1] + row[2] * l[2])
            .fold(f64::INFINITY, f64::min)
    };
    // The single best candidate's bound (its largest corner), which the envelope never exceeds.
    let single = d
        .iter()
        .map(|row| row[0].max(row[1]).max(row[2]))
        .fold(f64::INFINITY, f64::min);
    let mut best = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        .map(value)
        .into_iter()
        .fold(0.0_f64, f64::max);
    for a in 0..n {
        for b in (a + 1)..n {
            // On each edge (corners m, m2): where candidates a and b cross.
            for (m, m2) in [(0, 1), (1, 2), (2, 0)] {
                let (ga, gb) = (d[a][m] - d[a][m2], d[b][m] - d[b][m2]);
                let den = ga - gb;
                if den != 0.0 {
                    let s = (d[b][m2] - d[a][m2]) / den;
                    if s > 0.0 && s < 1.0 {
                        let mut l = [0.0; 3];
                        (l[m], l[m2]) = (s, 1.0 - s);
                        best = best.max(value(l));
                    }
                }
            }
            // Inside: where a, b and a third c cross (two equations in l0, l1; l2 = 1 - l0 - l1).
            for c in (b + 1)..n {
                let row = |k: usize| [d[k][0] - d[k][2], d[k][1] - d[k][2], d[k][2]];
                let (ra, rb, rc) = (row(a), row(b), row(c));
                // (ra - rb) . (l0, l1) = rb[2] - ra[2], and the same for a, c.
                let (p0, p1, q) = (ra[0] - rb[0], ra[1] - rb[1], rb[2] - ra[2]);
                let (r0, r1, w) = (ra[0] - rc[0], ra[1] - rc[1], rc[2] - ra[2]);
                let det = p0 * r1 - p1 * r0;
                if det != 0.0 {
                    let l0 = (q * r1 - p1 * w) / det;
                    let l1 = (p0 * w - q * r0) / det;
                    let l2 = 1.0 - l0 - l1;
                    if l0 > 0.0 && l1 > 0.0 && l2 > 0.0 {
                        best = best.max(value([l0, l1, l2]));
                    }
                }
            }
        }
    }
    // A relative margin for the rounding of the crossings, never above the single bound.
    (best * (1.0 + 1e-12)).min(single)
}

/// An upper bound on `d(x, B)` over a piece `t` of A that its candidates did not settle: the
/// smallest, over `leaf` (the triangle of B nearest the piece's centroid) and its vertex
/// neighbours, of the farthest distance from the piece's corners to that triangle (the distance
/// to one triangle is convex: its largest value over `t` is at a corner). Where B is A moved a
/// little (a simplified or perturbed copy), the moved copy of a triangle of A lies a triangle
/// or two from the nearest one, and bounds the whole piece by the move (docs/BENCHMARKS.md,
/// twenty-third session).
pub(crate) fn ring_bound(b: &TriMesh, t: &[Vec3; 3], leaf: u32) -> f64 {
    let tris = b.bvh().leaf_triangles();
    let mut best2 = f64::INFINITY;
    for &j in std::iter::once(&leaf).chain(b.leaf_neighbours().of(leaf)) {
        let tj = &tris[j as usize];
        // The farthest corner's squared distance, given up once it is not the smallest.
        let mut far2 = 0.0_f64;
        for p in t {
            far2 = far2.max((closest_on_triangle(*p, tj) - *p).length_squared());
            if far2 >= best2 {
                break;
            }
        }
        best2 = best2.min(far2);
    }
    best2.sqrt()
}

/// A node of A's hierarchy probed from B (B's frame, A's points mapped by `a_to_b`): one exact
/// distance, at the centroid of the triangle in the middle of the node's leaf range (the leaves
/// are in split order, so it lies where the node's two halves meet, near its centre), and the
/// upper bound on the distance to B over the node's volume it gives.
pub(crate) struct NodeProbe {
    /// Upper bound on `d(a, B)` over the node's volume.
    pub upper: f64,
    /// The sampled point (a point of A's surface) and its exact distance to B.
    pub point: Vec3,
    pub distance: f64,
    /// Its closest point on B and that triangle's leaf position.
    pub closest: Vec3,
    pub leaf: u32,
}

/// The four corners of a volume's rectangle, placed by `pose`: `centre + e0 + e1`, `+ e0 - e1`,
/// `- e0 + e1`, `- e0 - e1` with `e0`, `e1` its half-length axes.
pub(crate) fn rectangle_corners(rss: &Rss, pose: &Pose) -> [Vec3; 4] {
    let (e0, e1) = (
        rss.axes.x_axis * rss.half_lengths[0],
        rss.axes.y_axis * rss.half_lengths[1],
    );
    [
        rss.center + e0 + e1,
        rss.center + e0 - e1,
        rss.center - e0 + e1,
        rss.center - e0 - e1,
    ]
    .map(|p| pose.transform_point(p))
}

/// Probes node `i` of `a` from `b` (see [`NodeProbe`]); `tried`: the parent's two triangles of
/// B (the first starts the exact distance). Every point of the volume is within
/// `|p - centre| + r` of the sampled point `p` (the distance to B is 1-Lipschitz); and the
/// volume is its rectangle grown by its radius, while the distance to one triangle of B is
/// convex and 1-Lipschitz: over the volume it is at most its largest value at the rectangle's
/// corners plus the radius.
pub(crate) fn node_probe(a: &Bvh, a_to_b: &Pose, b: &Bvh, i: u32, tried: [u32; 2]) -> NodeProbe {
    let node = &a.nodes()[i as usize];
    let rss = &node.rss;
    let range = node.leaf_range();
    let middle = a.leaf_triangles()[range.start + range.len() / 2];
    let p = a_to_b.transform_point((middle[0] + middle[1] + middle[2]) / 3.0);
    let (d, q, leaf) = point_to_mesh(b, p, tried[0]);
    let centre = a_to_b.transform_point(rss.center);
    let corners = rectangle_corners(rss, a_to_b);
    let candidates = [leaf, tried[0], tried[1]];
    let upper = (d + (p - centre).length() + rss.corner_radius())
        .min(corner_bound(b, &corners, &candidates) + rss.radius);
    NodeProbe {
        upper,
        point: p,
        distance: d,
        closest: q,
        leaf,
    }
}

/// The four triangles of the midpoint split.
pub(crate) fn split4(t: [Vec3; 3]) -> [[Vec3; 3]; 4] {
    let m = [
        (t[0] + t[1]) * 0.5,
        (t[1] + t[2]) * 0.5,
        (t[2] + t[0]) * 0.5,
    ];
    [
        [t[0], m[0], m[2]],
        [m[0], t[1], m[1]],
        [m[2], m[1], t[2]],
        [m[0], m[1], m[2]],
    ]
}

#[cfg(test)]
thread_local! {
    /// Whether the correspondence bounds are used ([`Copies`]; the tests compare without).
    pub(crate) static COPIES: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// Where B holds, for every triangle of A, a triangle over the vertices of the same indices
/// (the same triangle list: the same mesh at another pose, or a copy whose vertices moved): a
/// point `x = sum l_k a_k` of a triangle of A then has the point `sum l_k b_k` of B, so
/// `d(x, B) <= |sum l_k (a_k - b_k)| <= max_k |a_k - b_k|`, the largest move of its corners
/// (a norm of an affine function is convex: its maximum over the triangle is at a corner).
/// Where the vertices are the same too (the same mesh), every point `x` of A's frame moves by
/// `(R - I) x + t` (`a_to_b = (R, t)`), so a node whose points lie within `rho` of its centre
/// `c` moves by at most `|(R - I) c + t| + |R - I| rho` (the Frobenius norm, at least the
/// operator norm), with no pass over its triangles.
pub(crate) struct Copies<'a> {
    /// A's triangles (vertex indices), which are B's too.
    triangles: &'a [[u32; 3]],
    /// B's vertices, B's frame.
    b_vertices: &'a [Vec3],
    /// With the same vertices: `R - I` of `a_to_b`, its Frobenius norm, and `t`.
    pub(crate) rigid: Option<(crate::math::Mat3, f64, Vec3)>,
}

impl<'a> Copies<'a> {
    /// The correspondence of A (`a`) onto B (`b`) placed by `a_to_b`, where B's triangle list
    /// is A's (`None` otherwise).
    pub(crate) fn new(a: &'a TriMesh, b: &'a TriMesh, a_to_b: &Pose) -> Option<Self> {
        #[cfg(test)]
        if !COPIES.with(|c| c.get()) {
            return None;
        }
        if a.num_vertices() != b.num_vertices() || !same(a.triangles(), b.triangles()) {
            return None;
        }
        let rigid = same(a.vertices(), b.vertices()).then(|| {
            let m = a_to_b.rotation - crate::math::Mat3::IDENTITY;
            let frobenius =
                (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared())
                    .sqrt();
            (m, frobenius, a_to_b.translation)
        });
        Some(Self {
            triangles: a.triangles(),
            b_vertices: b.vertices(),
            rigid,
        })
    }

    /// The move, where B has A's vertices and A is only translated onto it (`R = I` exactly).
    pub(crate) fn translation(&self) -> Option<Vec3> {
        match self.rigid {
            Some((_, 0.0, t)) => Some(t),
            _ => None,
        }
    }

    /// The bound over A's triangle `index` whose corners, in B's frame, are `t`: the largest
    /// move of a corner, plus a rounding margin.
    pub(crate) fn triangle(&self, index: usize, t: &[Vec3; 3]) -> f64 {
        let ids = self.triangles[index];
        (0..3).fold(0.0_f64, |m, k| {
            let b = self.b_vertices[ids[k] as usize];
            let d = (t[k] - b).length();
            m.max(d + ROUNDING * (t[k].length() + b.length()))
        })
    }

    /// The bound over a node of A (`rss` in A's frame) when B has A's vertices; infinite
    /// otherwise.
    pub(crate) fn node(&self, rss: &crate::bvh::Rss) -> f64 {
        match self.rigid {
            Some((m, frobenius, t)) => {
                let c = rss.center;
                let rho = rss.corner_radius();
                let moved = m * c + t;
                moved.length() + frobenius * rho + ROUNDING * (moved.length() + c.length() + rho)
            }
            None => f64::INFINITY,
        }
    }
}

/// Relative rounding margin of the correspondence bounds ([`Copies`]): a few units in the last
/// place of the coordinates they subtract.
const ROUNDING: f64 = 8.0 * f64::EPSILON;

/// Whether two slices are equal (the same memory, or the same values).
fn same<T: PartialEq>(a: &[T], b: &[T]) -> bool {
    a.len() == b.len() && (std::ptr::eq(a.as_ptr(), b.as_ptr()) || a == b)
}

/// A piece waiting in a max-heap, ordered by its upper bound.
pub(crate) struct Ranked<T> {
    pub upper: f64,
    pub item: T,
}

impl<T> PartialEq for Ranked<T> {
    fn eq(&self, other: &Self) -> bool {
        self.upper == other.upper
    }
}
impl<T> Eq for Ranked<T> {}
impl<T> PartialOrd for Ranked<T> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl<T> Ord for Ranked<T> {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.upper.total_cmp(&other.upper)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::motion::sampling::unit;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A copy of `m` with its triangle list and every vertex moved by a seeded offset of length
    /// up to `size` in a random direction.
    pub(crate) fn jittered(m: &TriMesh, size: f64, seed: u64) -> TriMesh {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let vertices: Vec<Vec3> = m
            .vertices()
            .iter()
            .map(|v| *v + unit(&mut rng) * (size * rng.random_range(0.0..1.0)))
            .collect();
        TriMesh::new(vertices, m.triangles().to_vec()).expect("a valid copy")
    }

    /// A pool of one thread, for tests whose switches and counts are per thread.
    pub(crate) fn one_thread() -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("a pool of one thread")
    }

    /// Distance from `p` to the triangle by its candidate critical points: the three edges'
    /// (clamped projections, corners) and the interior one from the Gram system, written
    /// apart from [`closest_on_triangle`].
    pub(crate) fn oracle_distance(p: Vec3, t: &[Vec3; 3]) -> f64 {
        let segment = |a: Vec3, b: Vec3| {
            let d = b - a;
            let l = d.length_squared();
            let mut best = (p - a).length().min((p - b).length());
            if l > 0.0 {
                let s = (p - a).dot(d) / l;
                if s > 0.0 && s < 1.0 {
                    best = best.min((p - (a + d * s)).length());
                }
            }
            best
        };
        let mut best = segment(t[0], t[1])
            .min(segment(t[1], t[2]))
            .min(segment(t[2], t[0]));
        let (e0, e1, w) = (t[1] - t[0], t[2] - t[0], p - t[0]);
        let (a, b, c) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
        let det = a * c - b * b;
        if det > 1e-12 * a * c {
            let (r0, r1) = (w.dot(e0), w.dot(e1));
            let u = (c * r0 - b * r1) / det;
            let v = (a * r1 - b * r0) / det;
            if u >= 0.0 && v >= 0.0 && u + v <= 1.0 {
                best = best.min((p - (t[0] + e0 * u + e1 * v)).length());
            }
        }
        best
    }

    /// Distance from `p` to the nearest of `tris`, brute force over [`oracle_distance`].
    pub(crate) fn brute_distance(tris: &[[Vec3; 3]], p: Vec3) -> f64 {
        tris.iter()
            .map(|t| oracle_distance(p, t))
            .fold(f64::INFINITY, f64::min)
    }

    /// Barycentric grid of `k + 1` points a side over the triangle (corners included).
    pub(crate) fn barycentric_grid(t: &[Vec3; 3], k: usize) -> Vec<Vec3> {
        let mut out = Vec::new();
        for u in 0..=k {
            for v in 0..=(k - u) {
                let (s, r) = (u as f64 / k as f64, v as f64 / k as f64);
                out.push(t[0] + (t[1] - t[0]) * s + (t[2] - t[0]) * r);
            }
        }
        out
    }

    /// `ring_bound` holds over dense samples of the piece against brute-force distances to the
    /// other mesh (random triangles near a knot, and the knot's own triangles moved a little
    /// and turned), and against a copy moved by `v` it bounds most triangles by `|v|`: the
    /// moved copy of each is among the neighbours of its centroid's nearest triangle.
    #[test]
    fn ring_bound_holds_and_finds_the_moved_copy() {
        let knot = crate::mesh::torus_knot(40, 6).expect("knot");
        let bvh = knot.bvh();
        let tris = bvh.leaf_triangles();
        let brute = |p: Vec3| brute_distance(tris, p);
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let v = Vec3::new(0.05, -0.02, 0.03);
        let turn = Pose::from_axis_angle(Vec3::new(0.2, 1.0, 0.3), 0.05, v);
        let mut by_move = 0;
        for case in 0..240 {
            let t: [Vec3; 3] = match case % 3 {
                0 => {
                    let c = unit(&mut rng) * rng.random_range(0.0..6.0);
                    let size = rng.random_range(0.05..1.0);
                    [0, 1, 2].map(|_| c + unit(&mut rng) * size)
                }
                1 => tris[rng.random_range(0..tris.len())].map(|p| p + v),
                _ => tris[rng.random_range(0..tris.len())].map(|p| turn.transform_point(p)),
            };
            let c = (t[0] + t[1] + t[2]) / 3.0;
            let leaf = point_to_mesh(bvh, c, 0).2;
            let bound = ring_bound(&knot, &t, leaf);
            for x in barycentric_grid(&t, 10) {
                let dx = brute(x);
                assert!(
                    dx <= bound + 1e-12,
                    "case {case}: {dx} above the bound {bound}"
                );
            }
            if case % 3 == 1 && bound <= v.length() * (1.0 + 1e-9) {
                by_move += 1;
            }
        }
        assert!(by_move >= 60, "bounded by the move on {by_move} of 80");
    }

    /// The envelope bound holds over dense samples of the triangle against brute-force
    /// distances to the mesh, never exceeds the best single candidate's bound, and is tighter
    /// than it on a fair share of cases: random triangles near a knot, up to four candidates
    /// among the knot's triangles nearest the triangle's corners and centroid.
    #[test]
    fn envelope_bound_holds_and_is_tighter() {
        let knot = crate::mesh::torus_knot(30, 5).expect("knot");
        let bvh = knot.bvh();
        let tris = bvh.leaf_triangles();
        let brute = |p: Vec3| brute_distance(tris, p);
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let (mut tighter, cases) = (0, 300);
        for case in 0..cases {
            let c = unit(&mut rng) * rng.random_range(0.0..6.0);
            let size = rng.random_range(0.05..1.5);
            let t = [0, 1, 2].map(|_| c + unit(&mut rng) * size);
            let nearest = |p: Vec3| point_to_mesh(bvh, p, 0).2;
            let mut leaves = vec![
                nearest(t[0]),
                nearest(t[1]),
                nearest(t[2]),
                nearest((t[0] + t[1] + t[2]) / 3.0),
            ];
            leaves.truncate(1 + case % 4);
            let bound = envelope_bound(bvh, &t, &leaves);
            let single = corner_bound(bvh, &t, &leaves);
            assert!(bound <= single, "case {case}: {bound} above {single}");
            for x in barycentric_grid(&t, 12) {
                let dx = brute(x);
                assert!(
                    dx <= bound + 1e-12,
                    "case {case}: {dx} above the bound {bound}"
                );
            }
            if bound < single * (1.0 - 1e-3) {
                tighter += 1;
            }
        }
        assert!(tighter > cases / 10, "tighter on {tighter} of {cases}");
    }

    /// The closest point against the oracle: random triangles and points at scales from 1e-6
    /// to 1e6, slivers, collinear and repeated corners, points on the plane, at corners and on
    /// edges; the point returned lies on the triangle (its distance to it is 0 by the oracle).
    #[test]
    fn closest_on_triangle_against_its_oracle() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for case in 0..20_000 {
            let scale = 10f64.powi(rng.random_range(-6..=6));
            let corner = |rng: &mut ChaCha8Rng| unit(rng) * rng.random_range(0.0..1.0) * scale;
            let mut t = [corner(&mut rng), corner(&mut rng), corner(&mut rng)];
            match case % 8 {
                0 => t[2] = t[0] + (t[1] - t[0]) * rng.random_range(-0.5..1.5), // collinear
                1 => t[1] = t[0],                                               // repeated
                2 => t = [t[0]; 3],                                             // a point
                3 => t[2] = t[1] + unit(&mut rng) * 1e-9 * scale,               // sliver
                _ => {}
            }
            let n = (t[1] - t[0]).cross(t[2] - t[0]);
            let mut p = corner(&mut rng) * 2.0;
            match case % 5 {
                // On the plane.
                0 if n.length_squared() > 0.0 => p -= n * (n.dot(p - t[0]) / n.length_squared()),
                1 => p = t[case % 3],
                2 => p = t[0] + (t[1] - t[0]) * rng.random_range(0.0..1.0),
                _ => {}
            }
            let q = closest_on_triangle(p, &t);
            let (got, want) = ((q - p).length(), oracle_distance(p, &t));
            let tol = 1e-9 * scale;
            assert!(
                (got - want).abs() <= tol,
                "case {case}: {got} against {want} for {p:?} and {t:?}"
            );
            assert!(
                oracle_distance(q, &t) <= tol,
                "case {case}: {q:?} off {t:?}"
            );
        }
    }
}

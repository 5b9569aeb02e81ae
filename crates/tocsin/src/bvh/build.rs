//! Top-down construction, in parallel over subtrees (rayon), into the preorder flat array.
//!
//! Each node: vertex covariance of its triangles -> principal axes -> RSS fit -> split the
//! triangles by the mean centroid along the first axis, or another where slivers span the node
//! ([`split_axis`]); half and half when that leaves a side empty, e.g. duplicated triangles.
//! The triangles' corners are partitioned in place with their ids, so every pass reads memory
//! in order and the array ends in leaf order. Subtree
//! sizes are known in advance (`2n - 1`), so the two children write disjoint slices and the
//! result does not depend on the thread count.

use super::eigen::principal_axes;
use super::{Bvh, CornerColumns, Node, Rss, SplitSpread};
use crate::math::Vec3;
use rayon::prelude::*;

/// Subtrees with fewer triangles than this are built on the current thread.
const PARALLEL_THRESHOLD: usize = 4096;

/// Meshes of at most this many triangles (boxes, primitives, small parts: the obstacles of a
/// robot's scene) get their rectangles turned to the best of their edge directions (see
/// [`refine_in_plane`]).
pub(super) const REFINE_MAX: usize = 256;

pub(super) fn build(vertices: &[Vec3], triangles: &[[u32; 3]], refine: bool) -> Bvh {
    // The large arrays are filled in parallel: most of their cost is the kernel providing
    // fresh pages (the node array of a million triangles is 272 MB), which then happens on
    // every thread; filling them on one thread took 0.2 s of the 1M build.
    let mut corners: Vec<[Vec3; 3]> = triangles
        .par_iter()
        .map(|t| t.map(|i| vertices[i as usize]))
        .collect();
    let mut ids: Vec<u32> = (0..triangles.len() as u32).collect();
    let placeholder = Node {
        rss: Rss {
            axes: Default::default(),
            center: Vec3::ZERO,
            half_lengths: [0.0; 2],
            radius: 0.0,
        },
        right: 0,
        first: 0,
        count: 0,
    };
    let mut nodes: Vec<Node> = (0..2 * triangles.len() - 1)
        .into_par_iter()
        .map(|_| placeholder)
        .collect();
    build_subtree(&mut corners, &mut ids, &mut nodes, 0, 0, refine);
    let mut corner_columns = CornerColumns::new(&corners, nodes[0].rss.center);
    if let Some(c) = corner_columns.as_mut() {
        c.add_distinct(&nodes, &ids, triangles, vertices);
    }
    Bvh {
        nodes,
        corner_columns,
        leaf_corners: corners,
        leaf_ids: ids,
    }
}

/// Builds the subtree over `corners` (with their `ids`) into `nodes`
/// (`nodes.len() == 2 * corners.len() - 1`), whose first entry has global index `base`;
/// `offset` is the global leaf position of `corners[0]`.
fn build_subtree(
    corners: &mut [[Vec3; 3]],
    ids: &mut [u32],
    nodes: &mut [Node],
    base: usize,
    offset: usize,
    refine: bool,
) {
    let n = corners.len();
    if n == 1 {
        let axes = triangle_axes(&corners[0])
            .unwrap_or_else(|| principal_axes(mean_covariance(corners).1));
        let rss = Rss::fit(axes, corners[0].into_iter());
        nodes[0] = Node {
            rss,
            right: 0,
            first: offset as u32,
            count: 1,
        };
        return;
    }
    let (mean, cov) = mean_covariance(corners);
    // The closed form everywhere (Jacobi only where the largest eigenvalue repeats): on the
    // 1M-triangle knot it builds in 0.81 s instead of 0.92 s with Jacobi at internal nodes,
    // and the distance searches on knot34k visit the same number of pairs.
    let axes = principal_axes(cov);
    let (mut rss, spread) = Rss::fit_triangles(axes, corners);
    if refine {
        rss = refine_in_plane(rss, corners);
    }
    let split_axis = axes.col(split_axis(&spread));
    let threshold = 3.0 * split_axis.dot(mean);
    let n_left = match partition(corners, ids, |c| {
        split_axis.dot(c[0] + c[1] + c[2]) < threshold
    }) {
        0 => n / 2,
        k if k == n => n / 2,
        k => k,
    };
    let right = base + 2 * n_left;
    nodes[0] = Node {
        rss,
        right: right as u32,
        first: offset as u32,
        count: n as u32,
    };
    let (left_nodes, right_nodes) = nodes[1..].split_at_mut(2 * n_left - 1);
    let (left_corners, right_corners) = corners.split_at_mut(n_left);
    let (left_ids, right_ids) = ids.split_at_mut(n_left);
    let mut left =
        move || build_subtree(left_corners, left_ids, left_nodes, base + 1, offset, refine);
    let mut right = move || {
        build_subtree(
            right_corners,
            right_ids,
            right_nodes,
            right,
            offset + n_left,
            refine,
        )
    };
    if n >= PARALLEL_THRESHOLD {
        rayon::join(left, right);
    } else {
        left();
        right();
    }
}

/// Which of the node's principal axes to split along (0 is the first): the first, unless the
/// triangles reach at least twice as far along it as their centroids spread (slivers spanning
/// a segment of a tube, whose halves would each span the segment again), and another axis has
/// its centroids spread at least twice as far as the triangles reach along it; of two such,
/// the one where the centroids spread most. The factors of two keep ordinary meshes, and fans
/// of long thin triangles around a pole, on the first axis (docs/BENCHMARKS.md, ninth
/// session, has the measurements).
fn split_axis(spread: &SplitSpread) -> usize {
    let (c, r) = (spread.centroids, spread.reach);
    if r.x < 2.0 * c.x {
        return 0;
    }
    let fits = |k: usize| c[k] >= 2.0 * r[k];
    match (fits(1), fits(2)) {
        (true, true) if c.z > c.y => 2,
        (true, _) => 1,
        (false, true) => 2,
        (false, false) => 0,
    }
}

/// A leaf's frame: the longest edge, the in-plane perpendicular, the normal. The rectangle
/// along the longest edge is the smallest around a triangle (twice its area: the feet of the
/// other corner's altitude fall on that edge), where principal axes gave 2.13 times on
/// average on the knots, and it needs no eigenvalues. `None` for a triangle without area.
fn triangle_axes(t: &[Vec3; 3]) -> Option<crate::math::Mat3> {
    let edges = [t[1] - t[0], t[2] - t[1], t[0] - t[2]];
    let longest = edges
        .into_iter()
        .max_by(|a, b| a.length_squared().total_cmp(&b.length_squared()))?;
    let normal = edges[0].cross(edges[1]);
    let (area2, edge2) = (normal.length(), longest.length_squared());
    // Area well above rounding at this edge length, else the normal is noise; coordinates
    // near f64's range may overflow here, and then the principal axes (which scale) decide.
    if !area2.is_finite() || !edge2.is_finite() || area2 <= 1e-12 * edge2 {
        return None;
    }
    let x = longest.normalize();
    let z = normal.normalize();
    Some(crate::math::Mat3::from_cols(x, z.cross(x), z))
}

/// In-place partition of `corners` and `ids` together: moves the triangles satisfying `pred`
/// to the front, returns their count.
fn partition(
    corners: &mut [[Vec3; 3]],
    ids: &mut [u32],
    pred: impl Fn(&[Vec3; 3]) -> bool,
) -> usize {
    let mut k = 0;
    for i in 0..corners.len() {
        if pred(&corners[i]) {
            corners.swap(i, k);
            ids.swap(i, k);
            k += 1;
        }
    }
    k
}

/// The rectangle turned in its plane to the triangle edge direction that gives the smallest
/// volume. The corners' covariance of a triangulated box is not symmetric (each face's diagonal
/// breaks it), so its principal axes come out turned: a 1.2 x 2 m table top got a rectangle
/// 6 degrees off, 2.1 x 1.4 m, whose corners reach 10 cm past the table's, and the robot
/// checks beside it lost their cheap prunes (a link 20 cm away had a root gap of 0). An edge
/// direction of a box face is the box's own axis. Quadratic in the node size, so only for
/// small meshes.
///
/// Each edge direction, in the triangles' order, is fitted ([`Rss::fit`]) and kept when its
/// volume is smaller than the best so far, unless a lower bound of its volume already reaches
/// the best: the result is the same, to the bit, as fitting every direction. With the normal
/// fixed, the fit's radius, its centre along the normal and each corner's allowance for the
/// round ends do not depend on the direction in the plane, so they are worked out once, and a
/// direction's bound costs two 2-D dot products per corner, the corners farthest out first,
/// left as soon as the volume so far reaches the best. The bound allows for the rounding in
/// which it differs from the fit (a thousand times that rounding), and takes each corner's
/// allowance from above. Fitting every direction took 22 of a Fetch's 28 ms to load
/// (docs/BENCHMARKS.md, forty-second session).
fn refine_in_plane(rss: Rss, corners: &[[Vec3; 3]]) -> Rss {
    let normal = rss.axes.z_axis;
    let (e1, e2) = (rss.axes.x_axis, rss.axes.y_axis);
    let mut points: Vec<[f64; 3]> = corners
        .iter()
        .flatten()
        .map(|p| [e1.dot(*p), e2.dot(*p), normal.dot(*p)])
        .collect();
    // The corners farthest from the centre in the plane first: the extents along a direction
    // reach near their final values within the first few.
    let centre = rss.axes.transpose() * rss.center;
    let reach = |p: &[f64; 3]| (p[0] - centre.x).powi(2) + (p[1] - centre.y).powi(2);
    points.sort_unstable_by(|p, q| reach(q).total_cmp(&reach(p)));
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p[2]), hi.max(p[2]))
        });
    // What the bound's coordinates may differ from the fit's by: far above a few units in the
    // last place of the largest corner.
    let slop = 1e-12
        * corners
            .iter()
            .flatten()
            .fold(0.0_f64, |m, p| m.max(p.length()));
    let (radius, cz) = (0.5 * (hi - lo), 0.5 * (hi + lo));
    // Each corner's allowance for the round ends, from above: the fit's radius and the
    // corner's offset along the normal are within `slop` of these.
    let allowance: Vec<f64> = points
        .iter()
        .map(|p| {
            let (r, dz) = (radius + slop, ((p[2] - cz).abs() - slop).max(0.0));
            (r * r - dz * dz).max(0.0).sqrt() * std::f64::consts::FRAC_1_SQRT_2
        })
        .collect();
    let lower_bound = |(x0, x1, y0, y1): (f64, f64, f64, f64)| {
        volume_of(
            0.5 * (x1 - x0 - 2.0 * slop).max(0.0),
            0.5 * (y1 - y0 - 2.0 * slop).max(0.0),
            (radius - slop).max(0.0),
        )
    };
    let mut best = rss;
    let mut best_volume = rss_volume(&rss);
    for u in in_plane_directions(normal, corners) {
        let v = normal.cross(u);
        let (u1, u2, v1, v2) = (u.dot(e1), u.dot(e2), v.dot(e1), v.dot(e2));
        let mut extents = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        let mut beaten = false;
        for (k, (p, &s)) in points.iter().zip(&allowance).enumerate() {
            let (x, y) = (u1 * p[0] + u2 * p[1], v1 * p[0] + v2 * p[1]);
            extents = (
                extents.0.min(x + s),
                extents.1.max(x - s),
                extents.2.min(y + s),
                extents.3.max(y - s),
            );
            // The extents only grow with more corners: the volume so far is a bound.
            if k % 8 == 7 && lower_bound(extents) >= best_volume {
                beaten = true;
                break;
            }
        }
        if beaten || lower_bound(extents) >= best_volume {
            continue;
        }
        let axes = crate::math::Mat3::from_cols(u, v, normal);
        let candidate = Rss::fit(axes, corners.iter().flatten().copied());
        let volume = rss_volume(&candidate);
        if volume < best_volume {
            (best, best_volume) = (candidate, volume);
        }
    }
    best
}

/// The triangles' edge directions projected into the plane across `normal`, in the triangles'
/// order (unit; each edge as its triangle runs, so a shared edge gives both signs).
fn in_plane_directions(normal: Vec3, corners: &[[Vec3; 3]]) -> impl Iterator<Item = Vec3> + '_ {
    corners.iter().flat_map(move |c| {
        [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])]
            .into_iter()
            .filter_map(move |(a, b)| {
                let e = b - a;
                let along = e - normal * e.dot(normal);
                // An edge (nearly) along the normal gives no direction in the plane: its
                // projection would be rounding noise, and the axes would not be orthonormal.
                if along.length() <= 1e-6 * e.length() {
                    return None;
                }
                along.try_normalize()
            })
    })
}

/// A swept sphere rectangle's volume from its half lengths and radius.
fn volume_of(l0: f64, l1: f64, radius: f64) -> f64 {
    8.0 * l0 * l1 * radius + 2.0 * std::f64::consts::PI * radius * radius * (l0 + l1)
}

/// [`volume_of`] a volume.
fn rss_volume(r: &Rss) -> f64 {
    volume_of(r.half_lengths[0], r.half_lengths[1], r.radius)
}

/// Mean and covariance of all corners (accumulated about the first corner, for precision far
/// from the origin).
fn mean_covariance(corners: &[[Vec3; 3]]) -> (Vec3, [[f64; 3]; 3]) {
    let origin = corners[0][0];
    let mut s = Vec3::ZERO;
    let (mut xx, mut xy, mut xz, mut yy, mut yz, mut zz) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for &p in corners.iter().flatten() {
        let q = p - origin;
        s += q;
        xx += q.x * q.x;
        xy += q.x * q.y;
        xz += q.x * q.z;
        yy += q.y * q.y;
        yz += q.y * q.z;
        zz += q.z * q.z;
    }
    let count = 3.0 * corners.len() as f64;
    let m = s / count;
    let cov = [
        [
            xx / count - m.x * m.x,
            xy / count - m.x * m.y,
            xz / count - m.x * m.z,
        ],
        [
            xy / count - m.x * m.y,
            yy / count - m.y * m.y,
            yz / count - m.y * m.z,
        ],
        [
            xz / count - m.x * m.z,
            yz / count - m.y * m.z,
            zz / count - m.z * m.z,
        ],
    ];
    (m + origin, cov)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The refinement as it was first written, every candidate fitted in 3-D: the oracle.
    fn refine_by_fitting_every_edge(rss: Rss, corners: &[[Vec3; 3]]) -> Rss {
        let normal = rss.axes.z_axis;
        let mut best = rss;
        for u in in_plane_directions(normal, corners) {
            let axes = crate::math::Mat3::from_cols(u, normal.cross(u), normal);
            let candidate = Rss::fit(axes, corners.iter().flatten().copied());
            if rss_volume(&candidate) < rss_volume(&best) {
                best = candidate;
            }
        }
        best
    }

    /// Whether `r` holds `p`, to `slack`.
    fn holds(r: &Rss, p: Vec3, slack: f64) -> bool {
        let q = r.axes.transpose() * (p - r.center);
        let dx = (q.x.abs() - r.half_lengths[0]).max(0.0);
        let dy = (q.y.abs() - r.half_lengths[1]).max(0.0);
        (dx * dx + dy * dy + q.z * q.z).sqrt() <= r.radius + slack
    }

    /// On boxes turned at random, triangulated soups and small meshes far from the origin, the
    /// refined volume holds every corner and is the one fitting every edge direction in 3-D
    /// finds, to the bit (never larger than the principal axes' volume).
    #[test]
    fn the_refinement_matches_fitting_every_edge() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let mut meshes: Vec<Vec<[Vec3; 3]>> = Vec::new();
        for k in 0..40 {
            let half = Vec3::new(
                rng.random_range(0.01..2.0),
                rng.random_range(0.01..2.0),
                rng.random_range(0.001..1.0),
            );
            let b = crate::mesh::box_mesh(half).expect("box");
            let turn = crate::math::Pose::from_axis_angle(
                Vec3::new(rng.random(), rng.random(), rng.random()).normalize(),
                rng.random_range(-3.0..3.0),
                Vec3::splat(if k % 4 == 0 { 1e6 } else { 0.0 }),
            );
            meshes.push(
                b.triangles()
                    .iter()
                    .map(|t| t.map(|i| turn.transform_point(b.vertices()[i as usize])))
                    .collect(),
            );
        }
        // Soups: thick, nearly flat, exactly flat far from the origin, and on a coarse grid
        // (parallel edges and equal volumes, where the first of equals must be the one kept).
        for k in 0..120 {
            let n = rng.random_range(1..60);
            meshes.push(
                (0..n)
                    .map(|_| {
                        [(); 3].map(|_| {
                            let (x, y, z) = (
                                rng.random_range(-1.0..1.0),
                                rng.random_range(-0.5..0.5),
                                rng.random::<f64>(),
                            );
                            match k % 4 {
                                0 => Vec3::new(x, y, z),
                                1 => Vec3::new(x, y, 0.01 * z),
                                2 => Vec3::new(x + 1e4, y, 0.0),
                                _ => (Vec3::new(x, y, z) * 4.0).round() / 4.0,
                            }
                        })
                    })
                    .collect(),
            );
        }
        let knot = crate::mesh::torus_knot(20, 4).expect("knot");
        meshes.push(
            (0..knot.num_triangles())
                .map(|i| knot.triangle(i))
                .collect(),
        );
        for (m, corners) in meshes.iter().enumerate() {
            let (_, cov) = mean_covariance(corners);
            let (start, _) = Rss::fit_triangles(principal_axes(cov), corners);
            let fast = refine_in_plane(start, corners);
            let slow = refine_by_fitting_every_edge(start, corners);
            let scale = corners
                .iter()
                .flatten()
                .fold(0.0_f64, |s, p| s.max(p.abs().max_element()));
            for p in corners.iter().flatten() {
                assert!(
                    holds(&fast, *p, 1e-12 * scale),
                    "mesh {m}: a corner outside"
                );
            }
            assert_eq!(fast, slow, "mesh {m}: not the exhaustive search's volume");
            assert!(
                rss_volume(&fast) <= rss_volume(&start),
                "mesh {m}: above the start's"
            );
        }
    }
}

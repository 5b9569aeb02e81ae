//! What the Hausdorff and pointwise-depth searches share: the distance from a point or a
//! triangle to a mesh (a small search over its RSS hierarchy), the convex-corner upper bound,
//! the split of a triangle in four, and the max-heap order of pieces by upper bound.

use crate::bvh::{Bvh, Rss};
use crate::math::Vec3;
use crate::query::distance::distance_triangle_triangle;

/// A lower bound on the distance from `p` to the volume.
#[inline]
pub(crate) fn rss_point_bound(rss: &Rss, p: Vec3) -> f64 {
    let q = rss.axes.transpose() * (p - rss.center);
    let dx = (q.x.abs() - rss.half_lengths[0]).max(0.0);
    let dy = (q.y.abs() - rss.half_lengths[1]).max(0.0);
    ((dx * dx + dy * dy + q.z * q.z).sqrt() - rss.radius).max(0.0)
}

/// Exact distance from the triangle `t` (a point when its corners are equal) to the mesh of
/// `bvh`, both in that mesh's frame: the distance, the closest point on the mesh (meaningful
/// for a point) and the leaf position of the closest triangle. `warm` (a leaf position) is tried
/// first; the search stops once a distance of 0 is found (nothing is closer).
pub(crate) fn triangle_to_mesh(bvh: &Bvh, t: &[Vec3; 3], warm: u32) -> (f64, Vec3, u32) {
    let nodes = bvh.nodes();
    let tris = bvh.leaf_triangles();
    let c = (t[0] + t[1] + t[2]) / 3.0;
    let r = t.iter().fold(0.0_f64, |m, p| m.max((*p - c).length()));
    let w = (warm as usize).min(tris.len() - 1);
    let first = distance_triangle_triangle(t, &tris[w]);
    let (mut best, mut closest, mut leaf) = (first.distance, first.point2, w as u32);
    // Each entry carries its lower bound, computed once, when its parent is expanded.
    let bound = |i: u32| rss_point_bound(&nodes[i as usize].rss, c) - r;
    let mut stack = vec![(0u32, bound(0))];
    while let Some((i, lb)) = stack.pop() {
        if best <= 0.0 {
            break;
        }
        if lb >= best {
            continue;
        }
        let node = &nodes[i as usize];
        if node.is_leaf() {
            let d = distance_triangle_triangle(t, &tris[node.leaf_position() as usize]);
            if d.distance < best {
                (best, closest, leaf) = (d.distance, d.point2, node.leaf_position());
            }
            continue;
        }
        let (l, rr) = node.children(i);
        let (bl, br) = (bound(l), bound(rr));
        // Nearer child on top.
        if bl <= br {
            stack.push((rr, br));
            stack.push((l, bl));
        } else {
            stack.push((l, bl));
            stack.push((rr, br));
        }
    }
    (best, closest, leaf)
}

/// An upper bound on the distance to the mesh over the convex hull of `corners`: the distance
/// to one triangle of the mesh is convex, so over the hull it peaks at a corner, and it bounds
/// the distance to the mesh; the triangles at the leaf positions `leaves` are tried.
pub(crate) fn corner_bound(bvh: &Bvh, corners: &[Vec3], leaves: &[u32]) -> f64 {
    let tris = bvh.leaf_triangles();
    leaves
        .iter()
        .map(|&j| {
            corners
                .iter()
                .map(|p| distance_triangle_triangle(&[*p; 3], &tris[j as usize]).distance)
                .fold(0.0_f64, f64::max)
        })
        .fold(f64::INFINITY, f64::min)
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

//! Top-down construction, in parallel over subtrees (rayon), into the preorder flat array.
//!
//! Each node: vertex covariance of its triangles -> principal axes -> RSS fit -> split the
//! triangles by the mean centroid along the first axis (half and half when that leaves a side
//! empty, e.g. duplicated triangles). Subtree sizes are known in advance (`2n - 1`), so the two
//! children write disjoint slices and the result does not depend on the thread count.

use super::eigen::principal_axes;
use super::{Bvh, Node, Rss};
use crate::math::Vec3;

/// Subtrees with fewer triangles than this are built on the current thread.
const PARALLEL_THRESHOLD: usize = 4096;

pub(super) fn build(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Bvh {
    let corners: Vec<[Vec3; 3]> =
        triangles.iter().map(|t| t.map(|i| vertices[i as usize])).collect();
    let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
    let placeholder = Node {
        rss: Rss { axes: Default::default(), center: Vec3::ZERO, half_lengths: [0.0; 2], radius: 0.0 },
        right: 0,
        leaf: 0,
    };
    let mut nodes = vec![placeholder; 2 * triangles.len() - 1];
    build_subtree(&corners, &mut order, &mut nodes, 0, 0);
    let leaf_corners = order.iter().map(|&i| corners[i as usize]).collect();
    Bvh { nodes, leaf_corners, leaf_ids: order }
}

/// Builds the subtree over `order` into `nodes` (`nodes.len() == 2 * order.len() - 1`), whose
/// first entry has global index `base`; `offset` is the global position of `order[0]`.
fn build_subtree(
    corners: &[[Vec3; 3]],
    order: &mut [u32],
    nodes: &mut [Node],
    base: usize,
    offset: usize,
) {
    let n = order.len();
    let (mean, cov) = mean_covariance(corners, order);
    if n == 1 {
        let c = corners[order[0] as usize];
        let rss = Rss::fit(principal_axes(cov), c.into_iter());
        nodes[0] = Node { rss, right: 0, leaf: offset as u32 };
        return;
    }
    let axes = principal_axes(cov);
    let rss = Rss::fit(axes, order.iter().flat_map(|&i| corners[i as usize]));
    let split_axis = axes.x_axis;
    let threshold = split_axis.dot(mean);
    let n_left = match partition(order, |i| {
        let c = corners[i as usize];
        split_axis.dot(c[0] + c[1] + c[2]) < 3.0 * threshold
    }) {
        0 => n / 2,
        k if k == n => n / 2,
        k => k,
    };
    let right = base + 2 * n_left;
    nodes[0] = Node { rss, right: right as u32, leaf: 0 };
    let (left_nodes, right_nodes) = nodes[1..].split_at_mut(2 * n_left - 1);
    let (left_order, right_order) = order.split_at_mut(n_left);
    if n >= PARALLEL_THRESHOLD {
        rayon::join(
            || build_subtree(corners, left_order, left_nodes, base + 1, offset),
            || build_subtree(corners, right_order, right_nodes, right, offset + n_left),
        );
    } else {
        build_subtree(corners, left_order, left_nodes, base + 1, offset);
        build_subtree(corners, right_order, right_nodes, right, offset + n_left);
    }
}

/// In-place partition: moves the entries satisfying `pred` to the front, returns their count.
fn partition(order: &mut [u32], pred: impl Fn(u32) -> bool) -> usize {
    let mut k = 0;
    for i in 0..order.len() {
        if pred(order[i]) {
            order.swap(i, k);
            k += 1;
        }
    }
    k
}

/// Sum of the points and sum of their outer products, relative to `origin`.
fn moments(points: &[Vec3], origin: Vec3) -> (Vec3, [[f64; 3]; 3]) {
    let mut s = Vec3::ZERO;
    let mut m = [[0.0; 3]; 3];
    for &p in points {
        let q = p - origin;
        s += q;
        for (r, row) in m.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v += q[r] * q[c];
            }
        }
    }
    (s, m)
}

/// Mean and covariance of all triangle corners of `order` (computed about the first corner, for
/// precision far from the origin).
fn mean_covariance(corners: &[[Vec3; 3]], order: &[u32]) -> (Vec3, [[f64; 3]; 3]) {
    let origin = corners[order[0] as usize][0];
    let mut s = Vec3::ZERO;
    let mut m = [[0.0; 3]; 3];
    for &i in order {
        let (si, mi) = moments(&corners[i as usize], origin);
        s += si;
        for r in 0..3 {
            for c in 0..3 {
                m[r][c] += mi[r][c];
            }
        }
    }
    let count = 3.0 * order.len() as f64;
    let mean = s / count;
    for r in 0..3 {
        for c in 0..3 {
            m[r][c] = m[r][c] / count - mean[r] * mean[c];
        }
    }
    (mean + origin, m)
}

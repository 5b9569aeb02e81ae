//! Whether two meshes intersect: any triangle pair touching or overlapping (coplanar overlaps
//! included), optionally listing all such pairs.
//!
//! Traversal of the two RSS hierarchies in mesh 1's frame; a node pair is skipped when a
//! separating axis shows a positive gap (beyond a rounding slack, so touching is never
//! skipped). Leaves use [`intersect_triangle_triangle`]. No OBB is kept: see ARCHITECTURE.md.

use crate::bvh::{rss_separation, Lanes4, RelativeRss, Rss};
use crate::math::Pose;
use crate::mesh::TriMesh;
use crate::query::distance::intersect_triangle_triangle;

/// Whether `mesh1` at `pose1` and `mesh2` at `pose2` intersect or touch.
pub fn collide(mesh1: &TriMesh, pose1: &Pose, mesh2: &TriMesh, pose2: &Pose) -> bool {
    let mut found = false;
    traverse(mesh1, pose1, mesh2, pose2, &mut |_, _| {
        found = true;
        false
    });
    found
}

/// [`collide`] for every `(pose1, pose2)` in `poses`, in parallel (rayon); results in input
/// order, identical to the single queries.
pub fn collide_batch(mesh1: &TriMesh, mesh2: &TriMesh, poses: &[(Pose, Pose)]) -> Vec<bool> {
    use rayon::prelude::*;
    poses
        .par_iter()
        .map(|(p1, p2)| collide(mesh1, p1, mesh2, p2))
        .collect()
}

/// All intersecting (or touching) triangle pairs `[triangle of mesh 1, triangle of mesh 2]`,
/// sorted.
pub fn collide_pairs(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
) -> Vec<[usize; 2]> {
    let mut pairs = Vec::new();
    traverse(mesh1, pose1, mesh2, pose2, &mut |i, j| {
        pairs.push([i, j]);
        true
    });
    pairs.sort_unstable();
    pairs
}

/// Calls `on_pair` for intersecting triangle pairs until it returns false.
///
/// A pair is on the stack only once its volumes are known to overlap (within the slack); when
/// two internal volumes meet, both are split and the four child pairs bounded together.
fn traverse(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    on_pair: &mut dyn FnMut(usize, usize) -> bool,
) {
    let pos12 = pose1.inv_mul(pose2);
    let (rot12, trans12) = (pos12.rotation, pos12.translation);
    let (bvh1, bvh2) = (mesh1.bvh(), mesh2.bvh());
    let (nodes1, nodes2) = (bvh1.nodes(), bvh2.nodes());
    let scale = trans12.length()
        + mesh1.bounding_radius()
        + mesh2.bounding_radius()
        + bvh1.root().center.length()
        + bvh2.root().center.length();
    let slack = 1e-13 * scale;
    let apart = |a: &Rss, b: &Rss, rel: &RelativeRss| rss_separation(a, b, rel, slack).0 > slack;
    if apart(
        &nodes1[0].rss,
        &nodes2[0].rss,
        &RelativeRss::new(&nodes1[0].rss, &nodes2[0].rss, &rot12, trans12),
    ) {
        return;
    }
    let lanes = Lanes4::detect();
    let mut stack: Vec<(u32, u32)> = vec![(0, 0)];
    while let Some((n1, n2)) = stack.pop() {
        let (a, b) = (&nodes1[n1 as usize], &nodes2[n2 as usize]);
        if a.is_leaf() && b.is_leaf() {
            let t1 = &bvh1.leaf_triangles()[a.leaf_position() as usize];
            let t2 = bvh2.leaf_triangles()[b.leaf_position() as usize].map(|p| rot12 * p + trans12);
            if intersect_triangle_triangle(t1, &t2)
                && !on_pair(
                    bvh1.triangle_index(a.leaf_position()),
                    bvh2.triangle_index(b.leaf_position()),
                )
            {
                return;
            }
            continue;
        }
        // Two internal nodes are split together: four child pairs, one 4-lane bound. Lane
        // 2 i + j pairs an[i] with bn[j]; with one internal node, half the lanes repeat.
        const ALL: &[usize] = &[0, 1, 2, 3];
        let (an, bn, used): ([u32; 2], [u32; 2], &[usize]) = match (a.is_leaf(), b.is_leaf()) {
            (false, false) => {
                let ((a1, a2), (b1, b2)) = (a.children(n1), b.children(n2));
                ([a1, a2], [b1, b2], ALL)
            }
            (false, _) => {
                let (a1, a2) = a.children(n1);
                ([a1, a2], [n2, n2], &[0, 2])
            }
            _ => {
                let (b1, b2) = b.children(n2);
                ([n1, n1], [b1, b2], &[0, 1])
            }
        };
        let (a0, a1) = (&nodes1[an[0] as usize].rss, &nodes1[an[1] as usize].rss);
        let (b0, b1) = (&nodes2[bn[0] as usize].rss, &nodes2[bn[1] as usize].rss);
        let bounds = lanes.bounds([a0, a1], [b0, b1], &rot12, trans12);
        // Pushed last first, so that the first child pair is visited first.
        for &k in used.iter().rev() {
            if bounds[k] <= slack {
                stack.push((an[k / 2], bn[k % 2]));
            }
        }
    }
}

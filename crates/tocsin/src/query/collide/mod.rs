//! Whether two meshes intersect: any triangle pair touching or overlapping (coplanar overlaps
//! included), optionally listing all such pairs.
//!
//! Traversal of the two RSS hierarchies in mesh 1's frame; a node pair is skipped when a
//! separating axis shows a positive gap (beyond a rounding slack, so touching is never
//! skipped). Leaves use [`intersect_triangle_triangle`]. No OBB is kept: see ARCHITECTURE.md.

use crate::bvh::{rss_separation, Expansion, Lanes4, RelativeRss, Rss};
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
        let Some(e) = Expansion::of(nodes1, n1, nodes2, n2) else {
            let (l1, l2) = (
                nodes1[n1 as usize].leaf_position(),
                nodes2[n2 as usize].leaf_position(),
            );
            let t1 = &bvh1.leaf_triangles()[l1 as usize];
            let t2 = bvh2.leaf_triangles()[l2 as usize].map(|p| rot12 * p + trans12);
            if intersect_triangle_triangle(t1, &t2)
                && !on_pair(bvh1.triangle_index(l1), bvh2.triangle_index(l2))
            {
                return;
            }
            continue;
        };
        // Two internal nodes are split together: four child pairs, one 4-lane bound.
        let bounds = lanes
            .expansion_bounds(&e, nodes1, nodes2, &rot12, trans12)
            .gap;
        // Pushed last first, so that the first child pair is visited first.
        for &k in e.lanes.iter().rev() {
            if bounds[k] <= slack {
                stack.push(e.pair(k));
            }
        }
    }
}

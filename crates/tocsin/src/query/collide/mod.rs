//! Whether two meshes intersect: any triangle pair touching or overlapping (coplanar overlaps
//! included), optionally listing all such pairs.
//!
//! Traversal of the two RSS hierarchies in mesh 1's frame; a node pair is skipped when a
//! separating axis shows a positive gap (beyond a rounding slack, so touching is never
//! skipped), or, for small subtrees, when their corners projected on the pair's near-points
//! axis are apart by more than that slack after the corner columns' rounding bound (the
//! triangles are the hulls of their corners). Leaves use [`intersect_triangle_triangle`]. No
//! OBB is kept: see ARCHITECTURE.md.

use crate::bvh::{
    both_at_most, rss_separation, ColumnPair, Expansion, Lanes4, RelativeRss, Rss, PROJECT_MAX,
};
use crate::math::{Pose, Vec3};
use crate::mesh::TriMesh;
use crate::query::distance::intersect_triangle_triangle;

/// Whether `mesh1` at `pose1` and `mesh2` at `pose2` intersect or touch.
pub fn collide(mesh1: &TriMesh, pose1: &Pose, mesh2: &TriMesh, pose2: &Pose) -> bool {
    intersecting_leaves(mesh1, pose1, mesh2, pose2, None).is_some()
}

/// [`collide`] that names the intersecting pair it found (leaf positions of the two
/// hierarchies), trying `hint` (such a pair from a nearby configuration) first: the
/// penetration depth's samples along a direction mostly keep one intersecting pair from one
/// sample to the next. Where the hint no longer intersects, the curve where the surfaces cross
/// has mostly moved onto a triangle next to it: each hinted triangle against the neighbours of
/// the other (triangles sharing a vertex, [`TriMesh::leaf_neighbours`]), then the subtrees
/// around the hint, then everything. Knot2.8k penetration depths: 7%, 23% and 22% fewer
/// instructions at 1%, 5% and 20% of the radius than without the neighbours, the same depths
/// bit for bit; edge neighbours only (sharing two vertices) took 2%, 15% and 13% off, the
/// hierarchy's neighbouring leaf positions (no table) 4%, 6% and 4%. The same verdict as
/// [`collide`]: a hinted pair counts only when the same exact test finds it intersecting at
/// these poses. With a hint, the bodies were penetrating nearby: the searches visit the child
/// pairs whose volumes overlap most first (smallest distance between centres over the sum of
/// the volumes' reaches), which finds a pair sooner where one is there (callgrind,
/// `profile_depth` at 1% / 5% / 20% of the radius: knot2.8k 80.1M / 91.6M / 291.2M -> 80.6M /
/// 85.7M / 260.2M; knot11k at 5% / 20% -1% / -9%, duck -1% / -6% / -8%, bunny +2% / -5% / -6%,
/// the same depths); without one ([`collide`]), where the answer is as often "apart" and
/// every overlapping pair is visited anyway, in the lanes' order (ordered, `collide` near
/// touching cost 5 to 10% more: `examples/profile_collide.rs`).
pub(crate) fn intersecting_leaves(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    hint: Option<(u32, u32)>,
) -> Option<(u32, u32)> {
    let (bvh1, bvh2) = (mesh1.bvh(), mesh2.bvh());
    if let Some((l1, l2)) = hint {
        if let (Some(t1), Some(t2)) = (
            bvh1.leaf_triangles().get(l1 as usize),
            bvh2.leaf_triangles().get(l2 as usize),
        ) {
            let pos12 = pose1.inv_mul(pose2);
            let place = |t: &[Vec3; 3]| t.map(|p| pos12.rotation * p + pos12.translation);
            let t2 = place(t2);
            if intersect_triangle_triangle(t1, &t2) {
                return Some((l1, l2));
            }
            for &n1 in mesh1.leaf_neighbours().of(l1) {
                if intersect_triangle_triangle(&bvh1.leaf_triangles()[n1 as usize], &t2) {
                    return Some((n1, l2));
                }
            }
            for &n2 in mesh2.leaf_neighbours().of(l2) {
                if intersect_triangle_triangle(t1, &place(&bvh2.leaf_triangles()[n2 as usize])) {
                    return Some((l1, n2));
                }
            }
        }
    }
    // Then the subtrees of the hint's neighbourhood, then everything.
    let starts = hint.map(|(l1, l2)| {
        (
            ancestor(bvh1, l1, local(mesh1)),
            ancestor(bvh2, l2, local(mesh2)),
        )
    });
    for start in starts.into_iter().chain([(0, 0)]) {
        let mut found = None;
        traverse(
            mesh1,
            pose1,
            mesh2,
            pose2,
            (start, usize::MAX),
            hint.is_some(),
            &mut |l1, l2| {
                found = Some((l1, l2));
                false
            },
        );
        if found.is_some() {
            return found;
        }
    }
    None
}

/// Triangles (on each side) of the neighbourhood around a hint that [`intersecting_leaves`]
/// searches before the whole hierarchies: a 256th of the mesh, from 8 to 64. Measured on
/// penetration depths (`examples/profile_depth.rs`, 24 queries at 1%, 5% and 20% of the
/// radius, callgrind), after the vertex neighbours and with 128 samples per direction: a fixed
/// 64 against 8 / 16 took knot2.8k 88.2M / 102.5M / 356.7M against 83.3M / 99.6M / 345.4M and
/// 83.5M / 99.8M / 346.5M (4, 32 and 256 no better), bunny 78.0M / 98.6M / 300.7M against
/// 72.2M / 94.7M / 292.8M (8), but knot34k 188.7M / 238.5M / 987.5M against 190.3M / 248.0M /
/// 1,072.2M (8) and 189.4M / 243.1M / 1,039.8M (16): on a large mesh a small neighbourhood
/// misses more often, and the search from the roots costs more there. (Before the vertex
/// neighbours, on knot2.8k: 64 best, 16 and 256 a little slower, 1,024 twice as slow.)
fn local(mesh: &TriMesh) -> usize {
    (mesh.num_triangles() / 256).clamp(8, 64)
}

/// The largest subtree of at most `max` triangles holding leaf position `leaf` (the leaf's
/// node when `max` is 0 or 1).
fn ancestor(bvh: &crate::bvh::Bvh, leaf: u32, max: usize) -> u32 {
    let nodes = bvh.nodes();
    let mut n = 0u32;
    loop {
        let node = &nodes[n as usize];
        if node.is_leaf() || node.leaf_range().len() <= max {
            return n;
        }
        let (left, right) = node.children(n);
        n = if nodes[left as usize].leaf_range().contains(&(leaf as usize)) {
            left
        } else {
            right
        };
    }
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
    let (bvh1, bvh2) = (mesh1.bvh(), mesh2.bvh());
    traverse(
        mesh1,
        pose1,
        mesh2,
        pose2,
        ((0, 0), usize::MAX),
        false,
        &mut |l1, l2| {
            pairs.push([bvh1.triangle_index(l1), bvh2.triangle_index(l2)]);
            true
        },
    );
    pairs.sort_unstable();
    pairs
}

/// Whether the meshes collide as far as a search of at most `budget` node pairs tells:
/// `true` only where it found an intersecting (or touching) triangle pair, `false` where they
/// are apart or the budget ran out first. For the yes/no questions' probes
/// ([`crate::query::contact_time::probe`]), where a probe that finds nothing proves nothing:
/// in a close fit, a full test that proves the meshes apart visits thousands of pairs.
pub(crate) fn collides_within(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    budget: usize,
) -> bool {
    let mut found = false;
    traverse(
        mesh1,
        pose1,
        mesh2,
        pose2,
        ((0, 0), budget),
        false,
        &mut |_, _| {
            found = true;
            false
        },
    );
    found
}

/// Calls `on_pair` with the leaf positions of intersecting triangle pairs until it returns
/// false, or until it has popped `budget` node pairs.
///
/// A pair is on the stack only once its volumes are known to overlap (within the slack); when
/// two internal volumes meet, both are split and the four child pairs bounded together.
fn traverse(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    ((root1, root2), budget): ((u32, u32), usize),
    ordered: bool,
    on_pair: &mut dyn FnMut(u32, u32) -> bool,
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
    let (a, b) = (&nodes1[root1 as usize].rss, &nodes2[root2 as usize].rss);
    if apart(a, b, &RelativeRss::new(a, b, &rot12, trans12)) {
        return;
    }
    let lanes = Lanes4::detect();
    // Small subtree pairs whose volumes overlap are also bounded by projecting their corners
    // on the lane's near-points axis (as in the distance search): near-touching meshes whose
    // volumes overhang their triangles are told apart without descending to the leaves.
    let columns = ColumnPair::new(bvh1, bvh2, &pos12);
    let mut stack: Vec<(u32, u32)> = vec![(root1, root2)];
    let mut popped = 0usize;
    while let Some((n1, n2)) = stack.pop() {
        popped += 1;
        if popped > budget {
            return;
        }
        let Some(e) = Expansion::of(nodes1, n1, nodes2, n2) else {
            let (l1, l2) = (
                nodes1[n1 as usize].leaf_position(),
                nodes2[n2 as usize].leaf_position(),
            );
            let t1 = &bvh1.leaf_triangles()[l1 as usize];
            let t2 = bvh2.leaf_triangles()[l2 as usize].map(|p| rot12 * p + trans12);
            if intersect_triangle_triangle(t1, &t2) && !on_pair(l1, l2) {
                return;
            }
            continue;
        };
        // Two internal nodes are split together: four child pairs, one 4-lane bound.
        let bounds = lanes.expansion_bounds(&e, nodes1, nodes2, &rot12, trans12);
        // Ordered (a search for one pair where the bodies likely penetrate): the pairs whose
        // volumes overlap most (centres nearest against their reach) are visited first, pushed
        // last; else in lane order, pushed last first.
        let mut keep = [(0.0f64, 0u32, 0u32); 4];
        let mut kept = 0;
        for &k in e.lanes.iter().rev() {
            if bounds.gap[k] > slack {
                continue;
            }
            let (c1, c2) = e.pair(k);
            if let Some(c) = &columns {
                let (a, b) = (&nodes1[c1 as usize], &nodes2[c2 as usize]);
                let u = Vec3::new(bounds.axis[0][k], bounds.axis[1][k], bounds.axis[2][k]);
                if u != Vec3::ZERO
                    && both_at_most(a, b, PROJECT_MAX)
                    && c.gap(lanes, (c1, a), (c2, b), u) > slack
                {
                    continue;
                }
            }
            if ordered {
                let (a, b) = (&nodes1[c1 as usize].rss, &nodes2[c2 as usize].rss);
                let key = (rot12 * b.center + trans12 - a.center).length()
                    / (a.bounding_radius() + b.bounding_radius());
                // Insertion, largest first.
                let mut at = kept;
                while at > 0 && keep[at - 1].0 < key {
                    keep[at] = keep[at - 1];
                    at -= 1;
                }
                keep[at] = (key, c1, c2);
                kept += 1;
            } else {
                stack.push((c1, c2));
            }
        }
        stack.extend(keep[..kept].iter().map(|&(_, c1, c2)| (c1, c2)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::mesh;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Every leaf pair of the two hierarchies that the exact test finds intersecting.
    fn brute(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose) -> Vec<(u32, u32)> {
        let pos12 = p1.inv_mul(p2);
        let (t1, t2) = (m1.bvh().leaf_triangles(), m2.bvh().leaf_triangles());
        let mut out = Vec::new();
        for (i, a) in t1.iter().enumerate() {
            for (j, b) in t2.iter().enumerate() {
                let b = b.map(|p| pos12.rotation * p + pos12.translation);
                if intersect_triangle_triangle(a, &b) {
                    out.push((i as u32, j as u32));
                }
            }
        }
        out
    }

    /// The two knots both tests walk past each other.
    fn two_knots() -> (TriMesh, TriMesh) {
        (
            mesh::torus_knot(60, 6).unwrap_or_else(|e| unreachable!("{e}")),
            mesh::torus_knot(40, 5).unwrap_or_else(|e| unreachable!("{e}")),
        )
    }

    /// A random unit vector (`X` for the rare draw too short to normalise).
    fn unit(rng: &mut ChaCha8Rng) -> Vec3 {
        Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
        .try_normalize()
        .unwrap_or(Vec3::X)
    }

    /// The probes' budgeted test against brute force, on knots at random poses: with no budget
    /// to speak of, the same verdict; with a small one, a collision only where brute force
    /// finds one.
    #[test]
    fn budgeted_test_finds_only_real_collisions() {
        let mut rng = ChaCha8Rng::seed_from_u64(78);
        let (a, b) = two_knots();
        let (mut hits, mut stopped) = (0, 0);
        for k in 0..300 {
            let axis = unit(&mut rng);
            let offset = axis * rng.random_range(0.0..8.0);
            let p2 = Pose::from_axis_angle(axis.any_orthonormal_vector(), 0.1 * k as f64, offset);
            let truth = !brute(&a, &Pose::IDENTITY, &b, &p2).is_empty();
            assert_eq!(
                collides_within(&a, &Pose::IDENTITY, &b, &p2, usize::MAX),
                truth
            );
            let budget = rng.random_range(1..64);
            let found = collides_within(&a, &Pose::IDENTITY, &b, &p2, budget);
            assert!(
                !found || truth,
                "case {k}: a collision brute force does not see"
            );
            hits += usize::from(found);
            stopped += usize::from(truth && !found);
        }
        // Both ways: budgets that found collisions, and budgets that ran out before one.
        assert!(
            hits > 20 && stopped > 20,
            "{hits} found, {stopped} given up"
        );
    }

    /// `intersecting_leaves` against brute force over all triangle pairs, on knots at random
    /// poses walked in small steps (the hint is the pair found at the step before, as the
    /// penetration depth's samples use it), with no hint, and with random hints (mostly
    /// wrong, some out of range): the same verdict as brute force every time, and a named pair
    /// is one brute force lists.
    #[test]
    fn hinted_search_matches_brute_force() {
        let mut rng = ChaCha8Rng::seed_from_u64(77);
        let (a, b) = two_knots();
        let (n1, n2) = (a.num_triangles() as u32, b.num_triangles() as u32);
        let (mut hits, mut free) = (0, 0);
        // 40 steps from the same centre to well apart.
        let step = (a.bounding_radius() + b.bounding_radius()) / 25.0;
        for _ in 0..12 {
            let d = unit(&mut rng);
            let axis = unit(&mut rng);
            let angle = rng.random_range(0.0..6.0);
            let mut hint = None;
            for k in 0..40 {
                let p2 = Pose::from_axis_angle(axis, angle, d * (step * k as f64));
                let truth = brute(&a, &Pose::IDENTITY, &b, &p2);
                let random = (rng.random_range(0..n1 + 2), rng.random_range(0..n2 + 2));
                for h in [hint, None, Some(random)] {
                    let got = intersecting_leaves(&a, &Pose::IDENTITY, &b, &p2, h);
                    assert_eq!(got.is_some(), !truth.is_empty(), "step {k} hint {h:?}");
                    if let Some(pair) = got {
                        assert!(truth.contains(&pair), "{pair:?} does not intersect");
                    }
                }
                let found = intersecting_leaves(&a, &Pose::IDENTITY, &b, &p2, hint);
                if found.is_some() {
                    hits += 1;
                    hint = found;
                } else {
                    free += 1;
                }
            }
        }
        assert!(hits > 50 && free > 50, "{hits} intersecting, {free} free");
    }
}

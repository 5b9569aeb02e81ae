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
//! A mesh counts as a convex polytope when it is closed (every edge shared by exactly two
//! triangles) and every vertex lies behind every non-degenerate face's plane (within 1e-9 of
//! its size). The candidate count is `F_A + F_B + E_A E_B`; the path is used only when that
//! times the vertex count stays small ([`MAX_WORK`]).

use std::collections::HashMap;

use crate::math::{Pose, Vec3};
use crate::TriMesh;

/// Largest `candidates x vertices` the exact path takes on (above it, the local search).
pub const MAX_WORK: usize = 50_000_000;

/// A convex polytope's face normals and edge directions (body frame, unit).
#[derive(Clone, Debug)]
pub(crate) struct Polytope {
    normals: Vec<Vec3>,
    edges: Vec<Vec3>,
}

/// The mesh as a convex polytope, or `None` when it is open or not convex.
pub(crate) fn polytope(mesh: &TriMesh) -> Option<Polytope> {
    let v = mesh.vertices();
    // Every face's plane with all the used vertices on one side, first: a non-convex mesh
    // (the usual case) fails at its first faces, before the edges are hashed (knot34k: the
    // edge hashing was about 40M instructions of its first penetration depth).
    let scale = mesh.bounding_radius().max(f64::MIN_POSITIVE);
    let used: Vec<Vec3> = {
        let mut seen = vec![false; v.len()];
        for t in mesh.triangles() {
            for &i in t {
                seen[i as usize] = true;
            }
        }
        v.iter()
            .zip(seen)
            .filter_map(|(p, s)| s.then_some(*p))
            .collect()
    };
    let mut normals = Vec::new();
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|i| v[i as usize]);
        let Some(n) = (b - a).cross(c - a).try_normalize() else {
            continue;
        };
        let (lo, hi) = used
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let s = n.dot(*p - a);
                (lo.min(s), hi.max(s))
            });
        let eps = 1e-9 * scale;
        if hi <= eps {
            normals.push(n);
        } else if lo >= -eps {
            normals.push(-n);
        } else {
            return None;
        }
    }
    // Then closed: every edge in exactly two triangles, no triangle with a repeated corner.
    let mut edge_count: HashMap<(u32, u32), u32> = HashMap::new();
    for t in mesh.triangles() {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            if a == b {
                return None;
            }
            *edge_count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    if edge_count.values().any(|&c| c != 2) {
        return None;
    }
    let edges = edge_count
        .keys()
        .filter_map(|&(a, b)| (v[b as usize] - v[a as usize]).try_normalize())
        .collect();
    Some(Polytope { normals, edges })
}

/// The exact depth of convex `b` (placed by `pose_b`) into convex `a`: the overlap, the unit
/// direction to move `b` along, and the two support points (world), or `None` when the
/// candidates are too many ([`MAX_WORK`]).
pub(crate) fn exact_depth(
    a: &TriMesh,
    pa: &Polytope,
    pose_a: &Pose,
    b: &TriMesh,
    pb: &Polytope,
    pose_b: &Pose,
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

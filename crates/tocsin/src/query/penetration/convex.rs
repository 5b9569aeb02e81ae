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
//! Most edge pairs give no facet: the Minkowski difference has a facet along `e_A x e_B` only
//! where the two edges' arcs cross on the Gauss map (the arc of an edge of `A` runs between
//! its two faces' outward normals; that of an edge of `B`, in `A - B`, between its faces'
//! normals negated). Each edge pair is first put through that crossing test (a few dot
//! products, below), and only the pairs that pass have their support overlap computed; the
//! test is conservative (it keeps every pair within rounding of crossing), and a pair it keeps
//! needlessly only adds a candidate whose overlap is at least the depth. Edges between two
//! coplanar triangles (a triangulated face's diagonals) have a point for an arc and are left
//! out: a facet there has a face's normal, already a candidate.
//!
//! **The crossing test.** Arcs `(a, b)` and `(c, d)`, each shorter than a half circle, cross
//! when `c` and `d` lie on opposite sides of the plane through `a` and `b` (normal `u`, along
//! the first edge), `a` and `b` on opposite sides of the plane through `c` and `d` (normal `w`,
//! along the second edge), and the point where arc `cd` meets the great circle of `ab`,
//! `y = |d.u| c + |c.u| d`, is on arc `ab` and not its antipode. The two great circles meet in
//! `+-x` only, `x` on arc `ab` has `x.(a + b) > 0` and `-x` has it negative, so the last
//! condition is `y.(a + b) > 0`, and `y` gives the facet normal's sign. A closed mesh with a
//! degenerate triangle beside an edge, or two faces back to back (a flat mesh), has no arcs;
//! such a pair takes every edge pair, as before.
//!
//! A mesh counts as a convex polytope when it is closed (every edge shared by exactly two
//! triangles) and every vertex lies behind every non-degenerate face's plane (within 1e-9 of
//! its size). The work is `E_A E_B` crossing tests plus the support loops of the faces' and the
//! crossing pairs' normals; the path is used only when `E_A E_B + (F_A + F_B)(V_A + V_B)` stays
//! small ([`MAX_WORK`]).

use std::collections::HashMap;

use crate::math::{Pose, Vec3};
use crate::TriMesh;

/// Largest `E_A E_B + (F_A + F_B)(V_A + V_B)` the exact path takes on (above it, the local
/// search).
pub const MAX_WORK: usize = 50_000_000;

/// A convex polytope's face normals and edge directions (body frame, unit), and its edges'
/// arcs on the Gauss map.
#[derive(Clone, Debug)]
pub(crate) struct Polytope {
    /// Outward face normals: one per face where `arcs` are in use, else one per triangle.
    normals: Vec<Vec3>,
    edges: Vec<Vec3>,
    /// Every edge between two faces that are not coplanar (the normals are then one per face,
    /// coplanar triangles joined); `None` when a degenerate triangle
    /// or two faces back to back leave some edge without a proper arc (module docs).
    arcs: Option<Vec<Arc>>,
}

/// An edge's arc on the Gauss map: its two faces' outward unit normals and its unit direction
/// (body frame).
#[derive(Clone, Copy, Debug)]
struct Arc {
    from: Vec3,
    to: Vec3,
    edge: Vec3,
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
    // Each triangle's outward normal, `None` for a degenerate one.
    let mut outward = Vec::with_capacity(mesh.num_triangles());
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|i| v[i as usize]);
        let Some(n) = (b - a).cross(c - a).try_normalize() else {
            outward.push(None);
            continue;
        };
        let (lo, hi) = used
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let s = n.dot(*p - a);
                (lo.min(s), hi.max(s))
            });
        let eps = 1e-9 * scale;
        let n = if hi <= eps {
            n
        } else if lo >= -eps {
            -n
        } else {
            return None;
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
    let mut edges = Vec::with_capacity(beside.len());
    let mut arcs = Some(Vec::with_capacity(beside.len()));
    // Coplanar triangles joined into faces (union-find over the edges between them): one
    // normal per face is a candidate where the arcs are in use.
    let mut face: Vec<usize> = (0..outward.len()).collect();
    let root = |face: &mut Vec<usize>, mut k: usize| {
        while face[k] != k {
            face[k] = face[face[k]];
            k = face[k];
        }
        k
    };
    for (&(a, b), &(_, [k1, k2])) in &beside {
        let Some(edge) = (v[b as usize] - v[a as usize]).try_normalize() else {
            continue;
        };
        edges.push(edge);
        match (outward[k1], outward[k2]) {
            // Coplanar faces: a point for an arc (module docs).
            (Some(from), Some(to)) if from.cross(to).length() <= 1e-12 && from.dot(to) > 0.0 => {
                let (r1, r2) = (root(&mut face, k1), root(&mut face, k2));
                face[r1] = r2;
            }
            // A proper arc, shorter than a half circle.
            (Some(from), Some(to)) if from.dot(to) > -1.0 + 1e-9 => {
                if let Some(list) = arcs.as_mut() {
                    list.push(Arc { from, to, edge });
                }
            }
            _ => arcs = None,
        }
    }
    if arcs.is_some() {
        normals = (0..outward.len())
            .filter(|&k| root(&mut face, k) == k)
            .filter_map(|k| outward[k])
            .collect();
    }
    Some(Polytope {
        normals,
        edges,
        arcs,
    })
}

/// Whether arc `a` (of `A`) and arc `b` negated (of `-B`) cross, within rounding (module docs):
/// the crossing's side of the facet normal `e_A x e_B`, `+1.0` or `-1.0`, `0.0` when rounding
/// leaves it open (both signs are then tried), `None` when they do not cross.
#[inline]
fn crossing(a: &Arc, b: &Arc) -> Option<f64> {
    const ROUNDING: f64 = 1e-12;
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
    let vertices = a.num_vertices() + b.num_vertices();
    let faces = pa.normals.len() + pb.normals.len();
    let pairs = pa.edges.len().saturating_mul(pb.edges.len());
    let work = match (&pa.arcs, &pb.arcs) {
        (Some(_), Some(_)) => pairs.saturating_add(faces.saturating_mul(vertices)),
        _ => (faces.saturating_add(pairs)).saturating_mul(vertices),
    };
    if work > MAX_WORK {
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
    let mut consider = |n: Vec3, sides: &[f64]| {
        for &side in sides {
            let n = n * side;
            let (o, sa, sb) = overlap(n);
            if o < best.0 {
                best = (o, n, sa, sb);
            }
        }
    };
    const BOTH: [f64; 2] = [1.0, -1.0];
    // With arcs, the normals are outward and one per face: the facets of `A - B` have those of
    // `A` and those of `B` negated. Without (a flat mesh), both signs, as for the edge pairs.
    let sides = |p: &Polytope, outward: f64| {
        if p.arcs.is_some() {
            vec![outward]
        } else {
            BOTH.to_vec()
        }
    };
    let (sides_a, sides_b) = (sides(pa, 1.0), sides(pb, -1.0));
    for n in &pa.normals {
        consider(pose_a.rotation * *n, &sides_a);
    }
    for n in &pb.normals {
        consider(pose_b.rotation * *n, &sides_b);
    }
    match (&pa.arcs, &pb.arcs) {
        (Some(arcs_a), Some(arcs_b)) => {
            let world = |list: &[Arc], pose: &Pose| -> Vec<Arc> {
                let r = pose.rotation;
                list.iter()
                    .map(|x| Arc {
                        from: r * x.from,
                        to: r * x.to,
                        edge: r * x.edge,
                    })
                    .collect()
            };
            let (arcs_a, arcs_b) = (world(arcs_a, pose_a), world(arcs_b, pose_b));
            for x in &arcs_a {
                for y in &arcs_b {
                    let Some(side) = crossing(x, y) else {
                        continue;
                    };
                    if let Some(n) = x.edge.cross(y.edge).try_normalize() {
                        match side {
                            s if s > 0.0 => consider(n, &BOTH[..1]),
                            s if s < 0.0 => consider(n, &BOTH[1..]),
                            _ => consider(n, &BOTH),
                        }
                    }
                }
            }
        }
        _ => {
            for ea in &pa.edges {
                let ea = pose_a.rotation * *ea;
                for eb in &pb.edges {
                    if let Some(n) = ea.cross(pose_b.rotation * *eb).try_normalize() {
                        consider(n, &BOTH);
                    }
                }
            }
        }
    }
    Some(best)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;
    use crate::mesh;
    use crate::motion::sampling::unit;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A convex mesh under a random linear map (boxes, coarse UV spheres and cylinders,
    /// stretched and sheared: still convex, with every kind of dihedral angle).
    fn random_convex(rng: &mut ChaCha8Rng) -> TriMesh {
        let base = match rng.random_range(0..4) {
            0 => mesh::box_mesh(Vec3::new(0.5, 0.3, 0.8)),
            1 => mesh::sphere(0.6, rng.random_range(2..7), rng.random_range(3..10)),
            2 => mesh::cylinder(0.4, 1.0),
            _ => mesh::box_mesh(Vec3::new(0.9, 0.05, 0.4)),
        }
        .expect("mesh");
        let mut map = Mat3::IDENTITY;
        for k in 0..3 {
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

    /// Every edge pair, as before the Gauss-map test: the oracle.
    fn all_pairs(p: &Polytope) -> Polytope {
        Polytope {
            arcs: None,
            ..p.clone()
        }
    }

    /// The Gauss-map test drops only edge pairs that give no facet: on 600 random overlapping
    /// or nearly touching pairs of convex meshes (coarse spheres, boxes, cylinders, stretched
    /// and sheared), the depth equals that over every edge pair to 1e-12 relative, the sign
    /// (overlap or not) agrees on every pair, and the test keeps under 5% of the pairs (about
    /// 2% here).
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
            assert!(pa.arcs.is_some() && pb.arcs.is_some(), "case {case}");
            let pose_a =
                Pose::from_axis_angle(unit(&mut rng), rng.random_range(0.0..3.0), Vec3::ZERO);
            let reach = rng.random_range(0.0..1.6);
            let pose_b = Pose::from_axis_angle(
                unit(&mut rng),
                rng.random_range(0.0..3.0),
                unit(&mut rng) * reach,
            );
            let fast = exact_depth(&a, pa, &pose_a, &b, pb, &pose_b).expect("small");
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
                // The direction found separates by the depth: its overlap is the depth.
                assert!((fast.1.length() - 1.0).abs() < 1e-12);
            }
            let (arcs_a, arcs_b) = (pa.arcs.as_ref().unwrap(), pb.arcs.as_ref().unwrap());
            all += pa.edges.len() * pb.edges.len();
            for x in arcs_a {
                let x = Arc {
                    from: pose_a.rotation * x.from,
                    to: pose_a.rotation * x.to,
                    edge: pose_a.rotation * x.edge,
                };
                for y in arcs_b {
                    let y = Arc {
                        from: pose_b.rotation * y.from,
                        to: pose_b.rotation * y.to,
                        edge: pose_b.rotation * y.edge,
                    };
                    kept += usize::from(crossing(&x, &y).is_some());
                }
            }
        }
        assert!(overlapping >= 300, "{overlapping} overlapping pairs");
        assert!(kept * 20 < all, "{kept} of {all} edge pairs kept");
    }

    /// A box's face diagonals are coplanar edges and have no arc; a flat closed mesh (two
    /// faces back to back) has none at all and takes every edge pair.
    #[test]
    fn coplanar_and_flat_meshes() {
        let cube = mesh::box_mesh(Vec3::splat(0.5)).expect("box");
        let p = cube.convex_polytope().expect("convex");
        assert_eq!(p.edges.len(), 18);
        assert_eq!(p.normals.len(), 6);
        assert_eq!(p.arcs.as_ref().map(Vec::len), Some(12));
        let flat = TriMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            vec![[0, 1, 2], [0, 2, 1]],
        )
        .expect("flat");
        let q = flat
            .convex_polytope()
            .expect("a flat closed mesh is convex");
        assert!(q.arcs.is_none());
        let turned = Pose::from_axis_angle(Vec3::X, 0.3, Vec3::new(0.1, 0.1, 0.0));
        let d = exact_depth(&cube, p, &Pose::IDENTITY, &flat, q, &turned).expect("small");
        let e =
            exact_depth(&cube, &all_pairs(p), &Pose::IDENTITY, &flat, q, &turned).expect("small");
        assert_eq!(d.0, e.0);
        assert!(d.0 > 0.0);
    }
}

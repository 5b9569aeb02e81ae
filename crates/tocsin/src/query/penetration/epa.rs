//! The penetration depth of two convex polytopes by EPA (the expanding polytope algorithm,
//! van den Bergen 2001), certified, before the exact path over every facet candidate
//! ([`super::convex`]).
//!
//! The depth is the distance from the origin to the boundary of the Minkowski difference
//! `C = A - B`, the smallest of its support function `h_C(n)` over unit `n` ([`super::convex`]).
//! GJK ([`crate::query::distance::gjk`]) ends, where the solids overlap, with a tetrahedron of
//! points of `C` holding the origin. EPA grows it: the face nearest the origin gives a
//! direction `n`, the support of `C` along `n` (climbed, as GJK's) is added, the faces it sees
//! are replaced by the fan from it to their horizon, until the support adds nothing beyond the
//! face.
//!
//! **The certificate.** Every corner of the polytope `P` is a point of `C`, so `P` lies in `C`,
//! and a ball about the origin inside `P` is inside `C`: the depth is at least the distance
//! from the origin to `P`'s boundary. That distance is the smallest of the faces' plane
//! distances `d_f` when the faces are `P`'s hull: they close up (every edge in exactly one
//! face each way), every corner lies behind every face's plane (checked, within rounding) and
//! the origin in front of none. The support along the nearest face's normal `n` gives an upper
//! bound, `h_C(n)`, reached by the two support corners. The answer is taken when the two
//! bounds are within [`ROUNDING`] of the size: the depth the exact path gives, to that. Where
//! they are not (a flat or degenerate simplex, rounding that broke the hull, the iteration cap)
//! the exact path answers.

use crate::math::{Mat3, Vec3};
use crate::query::distance::gjk::{Corner, Gjk, ROUNDING};

use super::convex::Placed;

/// Most EPA iterations (corners added) before the exact path answers instead.
const MAX_ITERATIONS: usize = 256;

/// A face of the expanding polytope: its corners (indices into the corner list, counter-
/// clockwise seen from outside), its unit outward normal and its plane's distance from the
/// origin.
#[derive(Clone, Copy, Debug)]
struct Face {
    corners: [usize; 3],
    normal: Vec3,
    distance: f64,
}

impl Face {
    fn new(points: &[Corner], corners: [usize; 3]) -> Option<Self> {
        let [a, b, c] = corners.map(|i| points[i].w);
        let normal = (b - a).cross(c - a).try_normalize()?;
        Some(Self {
            corners,
            normal,
            distance: normal.dot(a),
        })
    }
}

/// The depth of two overlapping convex polytopes by certified EPA, as
/// [`super::convex::exact_depth`] gives it (overlap, world normal from `a` towards `b`'s
/// escape, `a`'s support point, `b`'s support point, world frame), or `None` where the solids
/// do not overlap or the certificate fails (the exact path then answers).
pub(crate) fn depth(
    (a, pa, pose_a): Placed<'_>,
    (b, pb, pose_b): Placed<'_>,
) -> Option<(f64, Vec3, Vec3, Vec3)> {
    let pos = pose_a.inv_mul(pose_b);
    let (rot, trans) = (pos.rotation, pos.translation);
    let mut gjk = Gjk::new(a, pa, b, pb, None, Default::default());
    if gjk.run(&rot, trans).is_some() {
        // Apart: the exact path reports the separation.
        return None;
    }
    let tet = gjk.tetrahedron()?;
    let scale = {
        let (ra, rb) = (a.bvh().root(), b.bvh().root());
        ra.corner_radius() + rb.corner_radius() + ((rot * rb.center + trans) - ra.center).length()
    };
    let (n, o, ia, ib) = expand(&mut gjk, &rot, trans, tet, scale)?;
    // `n` points out of `C`: the overlap `n.(p - q)` of `A`'s support along `n` over `B`'s
    // along `-n`, as the exact path orients its normals (moving `b` by the depth along `n`
    // separates the two).
    let (p, q) = (
        a.vertices()[ia as usize],
        rot * b.vertices()[ib as usize] + trans,
    );
    Some((
        o,
        pose_a.rotation * n,
        pose_a.transform_point(p),
        pose_a.transform_point(q),
    ))
}

/// EPA from the tetrahedron `tet` holding the origin: the certified depth's normal, the depth,
/// and the two support corners along the normal.
fn expand(
    gjk: &mut Gjk<'_>,
    rot: &Mat3,
    trans: Vec3,
    tet: [Corner; 4],
    scale: f64,
) -> Option<(Vec3, f64, u32, u32)> {
    let tiny = 1e-13 * scale;
    let mut points: Vec<Corner> = tet.to_vec();
    let mut faces: Vec<Face> = Vec::with_capacity(64);
    for (i, j, k, l) in [(0, 1, 2, 3), (0, 3, 1, 2), (0, 2, 3, 1), (1, 3, 2, 0)] {
        let mut f = Face::new(&points, [i, j, k])?;
        // Outward: the fourth corner behind the face.
        if f.normal.dot(points[l].w - points[i].w) > 0.0 {
            f = Face::new(&points, [i, k, j])?;
        }
        if f.distance <= tiny {
            return None;
        }
        faces.push(f);
    }
    let mut horizon: Vec<(usize, usize)> = Vec::new();
    // The faces kept by an iteration, swapped with `faces` (one buffer, not one per iteration).
    let mut kept: Vec<Face> = Vec::with_capacity(64);
    for _ in 0..MAX_ITERATIONS {
        let nearest = faces
            .iter()
            .enumerate()
            .min_by(|x, y| x.1.distance.total_cmp(&y.1.distance))?
            .0;
        let f = faces[nearest];
        let w = gjk.support(f.normal, rot, trans)?;
        let reach = f.normal.dot(w.w);
        let repeated = points.iter().any(|c| c.a == w.a && c.b == w.b);
        if repeated || reach - f.distance <= tiny {
            return certify(&points, &faces, f, reach, (w.a, w.b), scale);
        }
        // The faces `w` sees, replaced by the fan from `w` to their horizon.
        let k = points.len();
        points.push(w);
        horizon.clear();
        kept.clear();
        for g in &faces {
            if g.normal.dot(w.w - points[g.corners[0]].w) > tiny {
                for e in 0..3 {
                    let edge = (g.corners[e], g.corners[(e + 1) % 3]);
                    // An edge seen from both sides is inside the removed region.
                    if let Some(at) = horizon.iter().position(|&h| h == (edge.1, edge.0)) {
                        horizon.swap_remove(at);
                    } else {
                        horizon.push(edge);
                    }
                }
            } else {
                kept.push(*g);
            }
        }
        if kept.len() == faces.len() {
            // Rounding: the nearest face does not see the point that lies beyond it.
            return None;
        }
        for &(i, j) in &horizon {
            let g = Face::new(&points, [i, j, k])?;
            if g.distance <= tiny {
                return None;
            }
            kept.push(g);
        }
        std::mem::swap(&mut faces, &mut kept);
    }
    None
}

/// The certificate (module docs) for the faces `faces` of the polytope on `points`, the
/// nearest face `f` and the support's reach `reach` along its normal (at corners `at`): the
/// normal, the depth and the support corners when the bounds meet.
fn certify(
    points: &[Corner],
    faces: &[Face],
    f: Face,
    reach: f64,
    at: (u32, u32),
    scale: f64,
) -> Option<(Vec3, f64, u32, u32)> {
    let slack = 1e-13 * scale;
    // Closed: each directed edge once, and its reverse once.
    let mut edges: Vec<(usize, usize)> = faces
        .iter()
        .flat_map(|g| (0..3).map(move |e| (g.corners[e], g.corners[(e + 1) % 3])))
        .collect();
    edges.sort_unstable();
    if edges.windows(2).any(|w| w[0] == w[1])
        || edges
            .iter()
            .any(|&(i, j)| edges.binary_search(&(j, i)).is_err())
    {
        return None;
    }
    // Every corner behind every face's plane, the origin in front of none.
    let mut lower = f64::INFINITY;
    for g in faces {
        if g.distance <= 0.0 {
            return None;
        }
        if points
            .iter()
            .any(|c| g.normal.dot(c.w) - g.distance > slack)
        {
            return None;
        }
        lower = lower.min(g.distance);
    }
    (reach - (lower - slack) <= ROUNDING * scale).then_some((f.normal, reach, at.0, at.1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pose;
    use crate::motion::sampling::unit;
    use crate::query::penetration::convex::tests::{random_convex, rotation};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// On 600 random overlapping pairs of convex meshes (boxes, coarse spheres, cylinders,
    /// gridded boxes, stretched and sheared, a third turned by quarter turns only), EPA's
    /// certified depth equals the exact path's over every facet candidate to 1e-12 of the
    /// size, its points are supports along its normal, and it answers most pairs.
    #[test]
    fn agrees_with_the_exact_path() {
        let mut rng = ChaCha8Rng::seed_from_u64(23);
        let (mut overlapping, mut answered) = (0, 0);
        let mut by_kind = [(0, 0); 2];
        for case in 0..600 {
            let (a, b) = (random_convex(&mut rng), random_convex(&mut rng));
            let (Some(pa), Some(pb)) = (a.convex_polytope(), b.convex_polytope()) else {
                continue;
            };
            let pose_a = rotation(&mut rng, case % 3 == 0);
            let mut pose_b = rotation(&mut rng, case % 3 == 0);
            let reach = a.bounding_radius() + b.bounding_radius();
            pose_b.translation = unit(&mut rng) * reach * rng.random_range(0.0..0.5);
            let Some(exact) =
                super::super::convex::exact_depth_without_epa((&a, pa, &pose_a), (&b, pb, &pose_b))
            else {
                continue;
            };
            if exact.0 <= 1e-9 * reach {
                continue;
            }
            overlapping += 1;
            let kind = usize::from(case % 3 == 0);
            by_kind[kind].0 += 1;
            let Some(fast) = depth((&a, pa, &pose_a), (&b, pb, &pose_b)) else {
                continue;
            };
            answered += 1;
            by_kind[kind].1 += 1;
            assert!(
                (fast.0 - exact.0).abs() <= 1e-12 * reach,
                "case {case}: {} against {}",
                fast.0,
                exact.0
            );
            // The points are the supports along the normal: their overlap is the depth.
            assert!((fast.1.dot(fast.2 - fast.3) - fast.0).abs() <= 1e-12 * reach);
            assert!((fast.1.length() - 1.0).abs() < 1e-12);
        }
        eprintln!("EPA answered {answered} of {overlapping} ({by_kind:?}: random, quarter turns)");
        assert!(overlapping > 350 && answered * 10 >= overlapping * 8);
    }

    /// Prisms turned across each other, whose Minkowski difference has about `E_A E_B` facets:
    /// at 500 sides EPA's depth is the candidates' (which take 16 ms there); at 5,000, where
    /// the candidates give up after 10 million crossing tests, EPA still answers, and the
    /// depth is the 500-sided one's to the polygons' difference.
    #[test]
    fn prisms_turned_across_each_other() {
        use crate::query::penetration::convex::tests::prism;
        let turned = Pose::from_axis_angle(Vec3::X, 1.3, Vec3::new(0.3, 0.2, 0.1));
        let coarse = prism(500);
        let pc = coarse.convex_polytope().expect("convex");
        let id = Pose::IDENTITY;
        let fast = depth((&coarse, pc, &id), (&coarse, pc, &turned)).expect("EPA answers");
        let exact = super::super::convex::exact_depth_without_epa(
            (&coarse, pc, &id),
            (&coarse, pc, &turned),
        )
        .expect("the candidates answer");
        assert!(
            (fast.0 - exact.0).abs() <= 1e-12,
            "{} against {}",
            fast.0,
            exact.0
        );
        let fine = prism(5000);
        let pf = fine.convex_polytope().expect("convex");
        let d = depth((&fine, pf, &id), (&fine, pf, &turned)).expect("EPA answers");
        assert!((d.0 - exact.0).abs() < 1e-3, "{} against {}", d.0, exact.0);
    }
}

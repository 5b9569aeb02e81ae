//! The first contact of a pure translation, in one traversal: body 2 moves by `t D` (`t` in
//! `[0, 1]`, `D` a fixed displacement) while body 1 stays. The set of shifts at which two
//! triangles intersect is the convex polytope `T1 - T2` (their Minkowski difference), and the ray
//! `t D` enters it where the last of its facet planes is crossed: with every facet normal among
//! the axes `n1`, `n2`, `e_i x f_j`, `n1 x e_i`, `n2 x f_j` (the triangles' normals, the
//! cross products of their edges, and the in-plane edge normals that a flat difference needs), the
//! largest entry time over the axes is the exact first time of contact of the pair.
//!
//! Two volumes get a lower bound on the first contact of any pair under them: their distance
//! bound `g` closes at most at the speed `|D|`, and their gap along the near-points axis `u`
//! (from body 1 to body 2; the supports of the two volumes, or for small subtrees their
//! corners' projection) at the rate `-u . D`, so neither can reach 0 before `g / |D|` nor
//! before `gap_u / (-u . D)` (never, when `u . D >= 0`). (The lanes' distance bound is the
//! largest of four axes' separations, not the separation along `u`: only the undirected speed
//! may divide it.) A best-first search on that bound, pruned at the earliest pair time found,
//! gives the earliest over all triangle pairs. Where an axis set misses a facet (degenerate
//! triangles: a segment against a point), the pair's bound is only a lower bound; the caller
//! checks the pair's distance at the time it returns.
//!
//! Every bound is taken with both sides widened by `margin` (model units), so that rounding
//! cannot push a bound past a contact: the result is a lower bound on the first time the
//! meshes intersect.

use crate::bvh::{both_at_most, ColumnPair, Expansion, Lanes4, PROJECT_MAX};
use crate::math::{Pose, Vec3};
use crate::TriMesh;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// The earliest time found and the leaf pair (leaf positions) that realises it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hit {
    pub time: f64,
    pub pair: (u32, u32),
}

/// Narrows the time window `[lo, hi]` to where two sets' projections on an axis overlap while
/// body 2 moves by `t d`: `gap` is body 2's projected centre less body 1's at `t = 0`, `e` the
/// two half widths summed (margin included), `w` the axis dotted with `d`. False when the
/// window empties.
#[inline]
fn narrow(gap: f64, e: f64, w: f64, lo: &mut f64, hi: &mut f64) -> bool {
    // Overlap at t: -e <= gap + t w <= e.
    if w == 0.0 {
        return gap.abs() <= e;
    }
    let (a, b) = ((-e - gap) / w, (e - gap) / w);
    let (a, b) = if a <= b { (a, b) } else { (b, a) };
    *lo = lo.max(a);
    *hi = hi.min(b);
    *lo <= *hi
}

/// The 17 directions among which the facet normals of the Minkowski difference of triangles `p`
/// and `q` lie (module docs), unnormalised, each with the product of its factors' lengths: an
/// axis much shorter than that is rounding, not a direction.
fn difference_axes(p: &[Vec3; 3], q: &[Vec3; 3]) -> [(Vec3, f64); 17] {
    let e = [p[1] - p[0], p[2] - p[1], p[0] - p[2]];
    let f = [q[1] - q[0], q[2] - q[1], q[0] - q[2]];
    let (el, fl) = (e.map(|v| v.length()), f.map(|v| v.length()));
    let (n1, n2) = (e[0].cross(e[1]), f[0].cross(f[1]));
    let (s1, s2) = (el[0] * el[1], fl[0] * fl[1]);
    let mut axes = [(n1, s1); 17];
    axes[1] = (n2, s2);
    for i in 0..3 {
        for j in 0..3 {
            axes[2 + 3 * i + j] = (e[i].cross(f[j]), el[i] * fl[j]);
        }
        axes[11 + i] = (n1.cross(e[i]), s1 * el[i]);
        axes[14 + i] = (n2.cross(f[i]), s2 * fl[i]);
    }
    axes
}

/// The earliest time in `[0, hi]` at which triangles `p` and `q` (body 1's frame, `q` at
/// `t = 0`) intersect while `q` moves by `t d`, widened by `margin`: exact (up to the margin) for
/// triangles whose difference has its facets among the axes (module docs), a lower bound
/// otherwise; `None` when they do not meet by `hi`.
pub(crate) fn triangle_bound(
    p: &[Vec3; 3],
    q: &[Vec3; 3],
    d: Vec3,
    margin: f64,
    hi: f64,
) -> Option<f64> {
    triangle_window(p, q, d, margin, (0.0, hi)).map(|(lo, _)| lo)
}

/// The times within `[lo, hi]` at which triangles `p` and `q` (body 1's frame, `q` at `t = 0`),
/// widened by `margin`, overlap on every axis of [`difference_axes`] while `q` moves by `t d`:
/// where they intersect, for triangles whose difference has its facets among the axes (module
/// docs), a superset otherwise (a degenerate triangle's missing axes); `None` when empty.
pub(crate) fn triangle_window(
    p: &[Vec3; 3],
    q: &[Vec3; 3],
    d: Vec3,
    margin: f64,
    (mut lo, mut hi): (f64, f64),
) -> Option<(f64, f64)> {
    for (u, scale) in difference_axes(p, q) {
        let len = u.length();
        if len.is_nan() || len <= AXIS_RESOLUTION * scale {
            continue;
        }
        let u = u / len;
        let (pa, pb, pc) = (p[0].dot(u), p[1].dot(u), p[2].dot(u));
        let (qa, qb, qc) = (q[0].dot(u), q[1].dot(u), q[2].dot(u));
        let (plo, phi) = (pa.min(pb).min(pc), pa.max(pb).max(pc));
        let (qlo, qhi) = (qa.min(qb).min(qc), qa.max(qb).max(qc));
        let gap = 0.5 * ((qlo + qhi) - (plo + phi));
        let half = 0.5 * ((phi - plo) + (qhi - qlo)) + margin;
        if !narrow(gap, half, u.dot(d), &mut lo, &mut hi) {
            return None;
        }
    }
    Some((lo, hi))
}

/// The length, relative to its factors' product, below which a cross product is taken for
/// rounding and its axis skipped (parallel edges, a degenerate triangle's normal).
const AXIS_RESOLUTION: f64 = 1e-12;

/// The earliest time in `[0, 1]` at which mesh 2 (at `pose2`, then moved by `t disp`, world
/// frame) meets mesh 1 (at `pose1`), both widened by `margin` (module docs); `None` when they
/// do not by `t = 1`. `seed`: a leaf pair likely to meet early (a cache's), bounded first so
/// that the search prunes against it from the start.
pub(crate) fn first_hit(
    mesh1: &TriMesh,
    pose1: &Pose,
    mesh2: &TriMesh,
    pose2: &Pose,
    disp: Vec3,
    margin: f64,
    seed: Option<(u32, u32)>,
) -> Option<Hit> {
    let pos12 = pose1.inv_mul(pose2);
    let (rot, trans) = (pos12.rotation, pos12.translation);
    let rot21 = rot.transpose();
    let d = pose1.rotation.transpose() * disp;
    let speed = d.length();
    let (bvh1, bvh2) = (mesh1.bvh(), mesh2.bvh());
    let (nodes1, nodes2) = (bvh1.nodes(), bvh2.nodes());
    let leaf_bound = |(l1, l2): (u32, u32), limit: f64| {
        let p = bvh1.leaf_triangles().get(l1 as usize)?;
        let q = bvh2
            .leaf_triangles()
            .get(l2 as usize)?
            .map(|v| rot * v + trans);
        triangle_bound(p, &q, d, margin, limit)
    };
    let mut best: Option<Hit> = None;
    let mut limit = 1.0;
    if let Some(pair) = seed {
        if let Some(time) = leaf_bound(pair, limit) {
            (best, limit) = (Some(Hit { time, pair }), time);
        }
    }
    let mut heap = BinaryHeap::new();
    let lanes = Lanes4::detect();
    let columns = ColumnPair::new(bvh1, bvh2, &pos12);
    // Non-negative times order like their bits.
    heap.push(Reverse((0.0f64.to_bits(), 0u32, 0u32)));
    while let Some(Reverse((bits, n1, n2))) = heap.pop() {
        if f64::from_bits(bits) >= limit && best.is_some() {
            break;
        }
        let Some(e) = Expansion::of(nodes1, n1, nodes2, n2) else {
            let pair = (
                nodes1[n1 as usize].leaf_position(),
                nodes2[n2 as usize].leaf_position(),
            );
            if let Some(time) = leaf_bound(pair, limit) {
                if best.is_none() || time < limit {
                    (best, limit) = (Some(Hit { time, pair }), time);
                }
            }
            continue;
        };
        let bounds = lanes.expansion_bounds(&e, nodes1, nodes2, &rot, trans);
        for &k in e.lanes {
            let (c1, c2) = e.pair(k);
            let (a, b) = (&nodes1[c1 as usize], &nodes2[c2 as usize]);
            // The distance closes at most at the speed |d|; the gap along the near-points axis
            // u (from body 1 to body 2: the volumes' supports, or for small subtrees their
            // corners' projection) at the rate -u . d.
            let g = bounds.gap[k] - margin;
            let mut t = if g > 0.0 { g / speed } else { 0.0 };
            // Pruned by the distance alone: the directional bound could only prune it more.
            if t >= limit && best.is_some() {
                continue;
            }
            let u = Vec3::new(bounds.axis[0][k], bounds.axis[1][k], bounds.axis[2][k]);
            if u != Vec3::ZERO {
                let cb = rot * b.rss.center + trans;
                let mut g = u.dot(cb - a.rss.center) - a.rss.support(u) - b.rss.support(rot21 * u);
                if let Some(c) = &columns {
                    if both_at_most(a, b, PROJECT_MAX) {
                        g = g.max(c.gap(lanes, (c1, a), (c2, b), u));
                    }
                }
                let g = g - margin;
                if g > 0.0 {
                    let w = -u.dot(d);
                    if w <= 0.0 {
                        continue;
                    }
                    t = t.max(g / w);
                }
            }
            if t < limit || (best.is_none() && t <= limit) {
                heap.push(Reverse((t.to_bits(), c1, c2)));
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh;
    use crate::motion::sampling::unit;
    use crate::motion::Motion;
    use crate::query::collide::collide;
    use crate::query::contact_time::{
        advance_short_translation, validate, ContactCache, ContactOptions,
    };
    use crate::query::distance::{distance_triangle_triangle, search_distance, DistanceCache};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random point in the box `[-1, 1]^3`.
    fn point(rng: &mut ChaCha8Rng) -> Vec3 {
        Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    }

    /// Two triangles and a displacement of kind `case % 6`: general position, coplanar with an
    /// in-plane motion, parallel planes closing along the normal, edges parallel across the
    /// triangles, a degenerate triangle 1 (a segment), a degenerate triangle 2 (a point).
    fn pair(rng: &mut ChaCha8Rng, case: usize) -> ([Vec3; 3], [Vec3; 3], Vec3, bool) {
        let flat = |v: Vec3| Vec3::new(v.x, v.y, 0.0);
        let (mut p, mut q) = ([0; 3].map(|_| point(rng)), [0; 3].map(|_| point(rng)));
        let mut degenerate = false;
        match case % 6 {
            1 => {
                p = p.map(flat);
                q = q.map(flat);
            }
            2 => {
                p = p.map(flat);
                q = q.map(|v| flat(v) + Vec3::Z * 0.5);
            }
            3 => q[1] = q[0] + (p[1] - p[0]) * rng.random_range(-2.0..2.0),
            4 => {
                p[2] = p[0] + (p[1] - p[0]) * rng.random_range(-1.0..2.0);
                degenerate = true;
            }
            5 => {
                q = [q[0]; 3];
                degenerate = true;
            }
            _ => {}
        }
        // Start apart along a random direction, then move back across the first triangle.
        let u = if case % 6 == 1 {
            flat(unit(rng))
        } else {
            unit(rng)
        }
        .normalize();
        let d = if case % 6 == 2 {
            -Vec3::Z + flat(point(rng)) * 0.3
        } else {
            -u * rng.random_range(2.0..6.0)
                + if case % 6 == 1 {
                    flat(point(rng))
                } else {
                    point(rng)
                } * 0.5
        };
        let q = q.map(|v| v + u * 3.0 * (case % 6 != 2) as u8 as f64);
        (p, q, d, degenerate)
    }

    /// `triangle_bound` against the triangles' exact distance: on seeded random pairs of every
    /// kind in [`pair`], at scales 1e-6, 1 and 1e6, the bound is no later than the first contact
    /// found by dense sampling and bisection of the distance, and on non-degenerate pairs the
    /// triangles touch at the bound (so it is the first contact, not just a lower bound).
    #[test]
    fn triangle_bound_is_the_first_contact() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let (mut met, mut missed) = (0, 0);
        for case in 0..1800 {
            let scale = [1e-6, 1.0, 1e6][case % 3];
            let (p, q, d, degenerate) = pair(&mut rng, case / 3);
            let (p, q, d) = (p.map(|v| v * scale), q.map(|v| v * scale), d * scale);
            // In contact: rounding's distance; touching at the bound: the margin, over the angle
            // the difference's facets make where the motion enters.
            let (tol, touch) = (4e-12 * scale, 1e-9 * scale);
            let dist = |t: f64| distance_triangle_triangle(&p, &q.map(|v| v + d * t)).distance;
            let bound = triangle_bound(&p, &q, d, 1e-12 * scale, 1.0);
            // The oracle: the first of 400 samples in contact, then bisection back to its start
            // (the shifts at which two triangles meet form an interval).
            let first = (0..=400)
                .map(|k| k as f64 / 400.0)
                .find(|&t| dist(t) <= tol);
            if let Some(t1) = first {
                let (mut a, mut b) = ((t1 - 1.0 / 400.0).max(0.0), t1);
                if dist(a) <= tol {
                    b = a;
                }
                for _ in 0..60 {
                    let m = 0.5 * (a + b);
                    if dist(m) <= tol {
                        b = m;
                    } else {
                        a = m;
                    }
                }
                assert!(bound.is_some(), "case {case}: no bound, contact at {b}");
                let t = bound.unwrap_or(f64::INFINITY);
                assert!(
                    t <= b + 1e-9,
                    "case {case}: bound {t} after the contact at {b}"
                );
                met += 1;
            } else if bound.is_none() {
                missed += 1;
            }
            if let (Some(t), false) = (bound, degenerate) {
                assert!(
                    dist(t) <= touch,
                    "case {case} ({}): apart by {} at the bound {t}",
                    case / 3 % 6,
                    dist(t)
                );
            }
        }
        assert!(met > 700 && missed > 700, "{met} meeting, {missed} missing");
    }

    /// The earliest time over all triangle pairs, brute force, in the frame [`first_hit`] uses.
    fn brute_force(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose, disp: Vec3) -> Option<f64> {
        let pos12 = p1.inv_mul(p2);
        let d = p1.rotation.transpose() * disp;
        let mut best: Option<f64> = None;
        for a in m1.bvh().leaf_triangles() {
            for b in m2.bvh().leaf_triangles() {
                let q = b.map(|v| pos12.rotation * v + pos12.translation);
                if let Some(t) = triangle_bound(a, &q, d, 0.0, 1.0) {
                    best = Some(best.map_or(t, |s| s.min(t)));
                }
            }
        }
        best
    }

    /// A soup of `n` random triangles in the box `[-1, 1]^3`, every fourth a segment and every
    /// seventh a point.
    fn soup(rng: &mut ChaCha8Rng, n: usize) -> TriMesh {
        let mut vertices = Vec::new();
        for i in 0..n {
            let p = point(rng);
            let q = if i % 7 == 0 { p } else { point(rng) };
            let r = if i % 4 == 0 { q } else { point(rng) };
            vertices.extend([p, q, r]);
        }
        let triangles = (0..n as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        TriMesh::new(vertices, triangles).expect("soup")
    }

    /// The first time in `[0, 1]` the meshes intersect with mesh 2 moved by `t disp`: the first
    /// of 1,000 samples where `collide` says so, then bisection back to where it starts.
    fn first_contact(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose, disp: Vec3) -> Option<f64> {
        let at = |t: f64| {
            let p = Pose {
                rotation: p2.rotation,
                translation: p2.translation + disp * t,
            };
            collide(m1, p1, m2, &p)
        };
        let k = (0..=1000u32).find(|&k| at(f64::from(k) / 1000.0))?;
        if k == 0 {
            return Some(0.0);
        }
        let (mut a, mut b) = (f64::from(k - 1) / 1000.0, f64::from(k) / 1000.0);
        for _ in 0..50 {
            let m = 0.5 * (a + b);
            if at(m) {
                b = m;
            } else {
                a = m;
            }
        }
        Some(b)
    }

    /// `first_hit` on knots against the minimum of the pair bounds over all triangle pairs: the
    /// same verdict, and the same time but for the margin (never later); on soups with
    /// degenerate triangles, against the first contact by sampling and bisection: never later
    /// and never missing one. Passing through, grazing and missing each other along random
    /// translations (the hierarchy's bounds prune nothing they should not).
    #[test]
    fn first_hit_matches_brute_force() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let knots = (
            mesh::torus_knot(30, 4).expect("knot"),
            mesh::torus_knot(20, 5).expect("knot"),
        );
        let (mut hits, mut misses) = (0, 0);
        for case in 0..300 {
            let soups;
            let (a, b, reach) = if case % 2 == 0 {
                (&knots.0, &knots.1, 4.0)
            } else {
                soups = (soup(&mut rng, 60), soup(&mut rng, 40));
                (&soups.0, &soups.1, 1.0)
            };
            let turn = |rng: &mut ChaCha8Rng| rng.random_range(0.0..3.0);
            let p1 = Pose::from_axis_angle(unit(&mut rng), turn(&mut rng), point(&mut rng));
            let u = unit(&mut rng);
            let p2 = Pose::from_axis_angle(
                unit(&mut rng),
                turn(&mut rng),
                p1.translation + u * 2.0 * reach,
            );
            // Aimed at body 1, offset across by up to about twice its size.
            let disp = (-u * rng.random_range(1.0..3.0) + point(&mut rng) * 2.0) * reach;
            let fast = first_hit(a, &p1, b, &p2, disp, 1e-12, None);
            if case % 2 == 0 {
                let slow = brute_force(a, &p1, b, &p2, disp);
                assert_eq!(
                    fast.is_some(),
                    slow.is_some(),
                    "case {case}: {fast:?}, {slow:?}"
                );
                if let (Some(f), Some(s)) = (fast, slow) {
                    assert!(
                        f.time <= s && f.time >= s - 1e-9,
                        "case {case}: {} against {s}",
                        f.time
                    );
                }
            } else if let Some(s) = first_contact(a, &p1, b, &p2, disp) {
                // A degenerate pair's bound is only a lower bound (module docs): the soups'
                // oracle is the meshes' first contact.
                let f = fast.map_or(f64::INFINITY, |h| h.time);
                assert!(f <= s, "case {case}: hit at {f} after the contact at {s}");
            }
            if fast.is_some() {
                hits += 1;
            } else {
                misses += 1;
            }
        }
        assert!(hits > 100 && misses > 25, "{hits} hits, {misses} misses");
    }

    /// The query of two translating bodies (answered by the cast) against dense sampling
    /// with the exact distance: before its time the meshes are never closer than `delta / 2`,
    /// at it they are within `delta`, and where it finds nothing they never come within
    /// `delta / 2`; at the scales 1e-3, 1 and 1e3, both bodies moving, body 1 turned, with and
    /// without a warm cache (the seed pair); a start in contact ends at once (time 0).
    #[test]
    fn translations_stop_within_tolerance_and_never_late() {
        let knot = mesh::torus_knot(30, 5).expect("knot");
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        let (mut met, mut free, mut cast) = (0, 0, 0);
        for case in 0..60 {
            let s = [1e-3, 1.0, 1e3][case % 3];
            let m = TriMesh::new(
                knot.vertices().iter().map(|&v| v * s).collect(),
                knot.triangles().to_vec(),
            )
            .expect("mesh");
            let r1 = crate::math::Mat3::from_axis_angle(unit(&mut rng), 1.0);
            let r2 = crate::math::Mat3::from_axis_angle(unit(&mut rng), 2.0);
            let c1 = point(&mut rng) * s;
            let u = unit(&mut rng);
            // From 8 apart (or 0.5, in contact, every fifth case) to a random offset.
            let reach = if case % 5 == 0 { 0.5 } else { 8.0 };
            let motion1 = Motion::translation(
                Pose::new(r1, c1).expect("pose"),
                Pose::new(r1, c1 + point(&mut rng) * s).expect("pose"),
            )
            .expect("motion");
            let motion2 = Motion::translation(
                Pose::new(r2, c1 + u * reach * s).expect("pose"),
                Pose::new(r2, c1 + point(&mut rng) * 9.0 * s).expect("pose"),
            )
            .expect("motion");
            let options = ContactOptions::default();
            let delta = validate(&m, &motion1, &m, &motion2, &options).expect("options");
            let gap = |t: f64| {
                search_distance(
                    &m,
                    &motion1.pose_at(t),
                    &m,
                    &motion2.pose_at(t),
                    &Default::default(),
                    &mut DistanceCache::default(),
                )
                .distance
            };
            let mut cache = ContactCache::default();
            if case % 2 == 1 {
                cache.pair = Some((7, 11));
            }
            let ends = advance_short_translation(&m, &motion1, &m, &motion2, &options, &mut cache)
                .expect("advance");
            if collide(&m, &motion1.pose_at(0.0), &m, &motion2.pose_at(0.0)) {
                assert_eq!(ends.as_ref().map(|e| e.time), Some(0.0), "case {case}");
            }
            let end = ends.as_ref().map_or(1.0, |e| e.time);
            for k in 0..=200 {
                let t = end * f64::from(k) / 200.0;
                if t < end || ends.is_none() {
                    assert!(
                        gap(t) >= 0.5 * delta * (1.0 - 1e-9),
                        "case {case}: {} apart at {t}, before {end}, tolerance {delta}",
                        gap(t)
                    );
                }
            }
            match ends {
                Some(e) => {
                    assert!(gap(e.time) <= delta, "case {case}: {} apart", gap(e.time));
                    met += 1;
                    cast += usize::from(e.iterations == 1);
                }
                None => free += 1,
            }
        }
        assert!(
            met > 25 && free > 15 && cast > 25,
            "{met} met, {free} free, {cast} cast"
        );
    }
}

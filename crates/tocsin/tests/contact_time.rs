//! `time_of_contact` against an oracle independent of conservative advancement: exact
//! collision sampled at 1,200 times and refined by bisection, and the brute-force distance at
//! the reported time. Zero misses and zero late answers allowed.

#![allow(clippy::unwrap_used, clippy::panic)]

#[path = "../benches/common/mod.rs"]
mod bench_common;
mod common;
use common::*;
use rand::{Rng, SeedableRng};
use tocsin::{
    collide, distance, mesh, time_of_contact, ContactOptions, ContactStatus, DistanceOptions,
    Motion, Pose, TriMesh, Vec3, Witnesses,
};

const SAMPLES: usize = 1200;

struct Oracle {
    /// (last free time, first colliding time) around the first sampled collision.
    first_collision: Option<(f64, f64)>,
    /// Smallest sampled distance.
    closest: f64,
    /// The sampled times and distances, up to the first sampled collision.
    samples: Vec<(f64, f64)>,
}

fn oracle(m1: &TriMesh, mo1: &Motion, m2: &TriMesh, mo2: &Motion) -> Oracle {
    let hit = |t: f64| collide(m1, &mo1.pose_at(t), m2, &mo2.pose_at(t));
    let dist = |t: f64| {
        distance(
            m1,
            &mo1.pose_at(t),
            m2,
            &mo2.pose_at(t),
            &DistanceOptions::default(),
        )
        .unwrap()
        .distance
    };
    let mut closest = f64::INFINITY;
    let mut prev = 0.0;
    let mut samples = Vec::with_capacity(SAMPLES + 1);
    for i in 0..=SAMPLES {
        let t = i as f64 / SAMPLES as f64;
        let d = dist(t);
        closest = closest.min(d);
        samples.push((t, d));
        if hit(t) {
            if i == 0 {
                return Oracle {
                    first_collision: Some((0.0, 0.0)),
                    closest: 0.0,
                    samples,
                };
            }
            let (mut lo, mut hi) = (prev, t);
            for _ in 0..50 {
                let mid = 0.5 * (lo + hi);
                if hit(mid) {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            return Oracle {
                first_collision: Some((lo, hi)),
                closest,
                samples,
            };
        }
        prev = t;
    }
    Oracle {
        first_collision: None,
        closest,
        samples,
    }
}

/// Checks the semantics; returns whether a contact was reported.
fn check(
    m1: &TriMesh,
    mo1: &Motion,
    m2: &TriMesh,
    mo2: &Motion,
    tol: Option<f64>,
    label: &str,
) -> bool {
    let opts = ContactOptions {
        tolerance: tol,
        ..Default::default()
    };
    let delta = tocsin::query::contact_time::effective_tolerance(m1, mo1, m2, mo2, &opts);
    // The contact pair's points (`r`, checked below with the advancement) and the default
    // closest points at the same time (`exact`): the same advancement either way.
    let pair_opts = ContactOptions {
        witnesses: Witnesses::Contact,
        ..opts
    };
    let r = time_of_contact(m1, mo1, m2, mo2, &pair_opts).unwrap();
    let exact = time_of_contact(m1, mo1, m2, mo2, &opts).unwrap();
    assert_eq!(
        r.map(|c| (c.time, c.iterations, c.status)),
        exact.map(|c| (c.time, c.iterations, c.status)),
        "{label}: the witnesses changed the advancement"
    );
    // The planner's question gives the same answer, so the oracle checks below hold for it too.
    let free = tocsin::motion_is_free(m1, mo1, m2, mo2, &opts).unwrap();
    assert_eq!(free, r.is_none(), "{label}: motion_is_free disagrees");
    let o = oracle(m1, mo1, m2, mo2);
    match (&r, o.first_collision) {
        (None, Some((_, hi))) => panic!("{label}: missed a collision at t = {hi}"),
        // The contract: a contact whenever the meshes come closer than `delta / 2`; between
        // that and `delta` either answer (a rotation certificate may prove a close fit never
        // closer than half the tolerance). The samples' closest is at least the true one.
        (None, None) => assert!(
            o.closest > 0.5 * delta,
            "{label}: no contact reported but the sampled distance reaches {} <= delta / 2 \
             ({delta} / 2)",
            o.closest
        ),
        (Some(c), first) => {
            let (p1, p2) = (mo1.pose_at(c.time), mo2.pose_at(c.time));
            let (bd, _, _) = brute_distance(m1, &p1, m2, &p2);
            assert!(
                bd <= delta * (1.0 + 1e-9),
                "{label}: distance {bd} at t = {} exceeds delta {delta}",
                c.time
            );
            // The brute force works on world points, which round at the bodies' distance from
            // the origin (the query itself works in body 1's frame).
            let world = p1.translation.length()
                + p2.translation.length()
                + m1.bounding_radius()
                + m2.bounding_radius();
            let rounding = 16.0 * f64::EPSILON * world;
            let e = exact.expect("the same advancement");
            assert_rel(
                e.distance,
                bd,
                1e-9,
                1e-12 * delta + rounding,
                "reported closest distance",
            );
            // The contact pair's points: on the triangles named (to 1e-6 of the tolerance: the
            // oracle's projection onto a sliver rounds at 1e-11 of its size), as far apart as
            // the distance reported, which is at least the meshes' and within the tolerance.
            let on = |m: &TriMesh, p: &Pose, t: usize, x: Vec3| {
                oracle_point_triangle(x, &m.triangle(t).map(|v| p.transform_point(v)))
            };
            for (x, on) in [
                (c.point1, on(m1, &p1, c.triangle1, c.point1)),
                (c.point2, on(m2, &p2, c.triangle2, c.point2)),
            ] {
                assert!(
                    on <= 1e-6 * delta + rounding,
                    "{label}: contact point {x} is {on} off its triangle (delta {delta})"
                );
            }
            assert_rel(
                (c.point2 - c.point1).length(),
                c.distance,
                1e-9,
                rounding,
                &format!("{label}: the contact points' distance"),
            );
            assert!(
                c.distance >= bd * (1.0 - 1e-9) - rounding,
                "{label}: contact distance {} below the meshes' {bd}",
                c.distance
            );
            assert!(
                c.distance <= delta * (1.0 + 1e-9) + rounding,
                "{label}: contact distance {} above delta {delta}",
                c.distance
            );
            // The contract before the answer: no sampled time closer than half the tolerance.
            if let Some(&(t, d)) = o
                .samples
                .iter()
                .find(|&&(t, d)| t < c.time && d < 0.5 * delta * (1.0 - 1e-9) - rounding)
            {
                panic!(
                    "{label}: at t = {t} the distance {d} is under half the tolerance \
                     ({delta} / 2), before the contact reported at {}",
                    c.time
                );
            }
            if let Some((_, hi)) = first {
                assert!(
                    c.time <= hi,
                    "{label}: late: t = {} after the first collision at {hi}",
                    c.time
                );
            }
            if c.status == ContactStatus::StartedInContact {
                assert_eq!(c.time, 0.0);
                assert!(collide(m1, &p1, m2, &p2));
            } else {
                assert!(
                    !collide(m1, &p1, m2, &p2),
                    "{label}: reported time is in collision"
                );
                assert!((c.normal.length() - 1.0).abs() < 1e-9);
                assert!(
                    c.normal.dot(c.point2 - c.point1) >= 0.0,
                    "{label}: normal from body 1 to body 2"
                );
            }
            assert!((0.0..=1.0).contains(&c.time));
        }
    }
    r.is_some()
}

fn random_motion(rng: &mut impl Rng, kind: usize, start: Pose, end: Pose) -> Motion {
    match kind {
        0 => Motion::translation(
            start,
            Pose {
                rotation: start.rotation,
                translation: end.translation,
            },
        )
        .unwrap(),
        1 => {
            let c = Vec3::new(
                rng.random_range(-0.5..0.5),
                rng.random_range(-0.5..0.5),
                rng.random_range(-0.5..0.5),
            );
            Motion::interp(start, end, c).unwrap()
        }
        _ => Motion::screw(start, end).unwrap(),
    }
}

#[test]
fn random_soups_and_motions_against_sampling() {
    let mut rng = rng(50);
    let (mut hits, mut total) = (0, 0);
    for case in 0..90 {
        let scale = [1.0, 1e-3, 1e3][case % 3];
        let m1 = random_soup(&mut rng, 3 + case % 12, scale);
        let m2 = random_soup(&mut rng, 3 + (case * 5) % 13, scale);
        let kind = case % 3;
        let both_move = case % 2 == 0;
        // Body 1 flies from one side to the other, turning; body 2 sits near the middle or moves too.
        let dir = random_unit(&mut rng);
        let s1 = Pose {
            rotation: random_rotation(&mut rng),
            translation: -4.0 * scale * dir,
        };
        let e1 = Pose {
            rotation: random_rotation(&mut rng),
            translation: 4.0 * scale * dir
                + random_unit(&mut rng) * scale * rng.random_range(0.0..2.0),
        };
        let mo1 = random_motion(&mut rng, kind, s1, e1);
        let s2 = random_pose(&mut rng, 0.5 * scale);
        let mo2 = if both_move {
            let e2 = Pose {
                rotation: random_rotation(&mut rng),
                translation: s2.translation - dir * scale,
            };
            random_motion(&mut rng, kind, s2, e2)
        } else {
            Motion::stationary(s2)
        };
        let tol = [None, Some(1e-2 * scale)][case % 2];
        hits += usize::from(check(
            &m1,
            &mo1,
            &m2,
            &mo2,
            tol,
            &format!("case {case} kind {kind} scale {scale}"),
        ));
        total += 1;
    }
    assert_mixed(
        hits > 20 && hits < total,
        &format!("the sample should mix contacts and misses: {hits}/{total}"),
    );
}

/// Starts at the edge of contact, on every path (convex pairs, the same through the general
/// path, random soups): body 2 placed along a random direction where `collide` flips (by
/// bisection), then a little inside that, at it, and a little and a tolerance or two outside,
/// every motion kind, moving apart or not. The collision test at the start waits for the
/// first iteration (which proves the start free when it steps), so `check`'s
/// `StartedInContact` exactly where the start collides is the point here.
#[test]
fn starts_at_the_edge_of_contact_on_every_path() {
    let mut rng = rng(93);
    let mut started = 0;
    for case in 0..60 {
        let (m1, m2) = match case % 3 {
            0 => (random_convex(&mut rng), random_convex(&mut rng)),
            1 => (
                as_soup(&random_convex(&mut rng)),
                as_soup(&random_convex(&mut rng)),
            ),
            _ => (
                random_soup(&mut rng, 12, 1.0),
                random_soup(&mut rng, 12, 1.0),
            ),
        };
        let (r1, r2) = (random_rotation(&mut rng), random_rotation(&mut rng));
        let dir = random_unit(&mut rng);
        let at = |s: f64| Pose {
            rotation: r2,
            translation: dir * s,
        };
        let p1 = Pose {
            rotation: r1,
            translation: Vec3::ZERO,
        };
        let (mut lo, mut hi) = (0.0, m1.bounding_radius() + m2.bounding_radius() + 1.0);
        if !collide(&m1, &p1, &m2, &at(lo)) {
            continue;
        }
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if collide(&m1, &p1, &m2, &at(mid)) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let kind = case % 3;
        // Not `hi` itself: the meshes touch to rounding there, and the normal's direction is
        // noise (the distance's points are too).
        for (k, s) in [lo - 1e-3, lo, hi + 1e-6, hi + 1e-3, hi + 4e-3]
            .into_iter()
            .enumerate()
        {
            let s2 = at(s);
            let e1 = Pose {
                rotation: random_rotation(&mut rng),
                translation: random_unit(&mut rng) * rng.random_range(0.0..2.0),
            };
            let mo1 = random_motion(&mut rng, kind, p1, e1);
            let mo2 = if k % 2 == 0 {
                Motion::stationary(s2)
            } else {
                let e2 = Pose {
                    rotation: r2,
                    translation: dir * (s + rng.random_range(0.0..1.0)),
                };
                random_motion(&mut rng, kind, s2, e2)
            };
            // Not where the start is between half the tolerance and the tolerance apart: there
            // either answer keeps the contract, and `check` asks for a contact.
            let delta = tocsin::query::contact_time::effective_tolerance(
                &m1,
                &mo1,
                &m2,
                &mo2,
                &ContactOptions::default(),
            );
            let (d, _, _) = brute_distance(&m1, &p1, &m2, &s2);
            if d > 0.5 * delta && d <= delta {
                continue;
            }
            let label = format!("edge case {case} kind {kind} offset {k}");
            check(&m1, &mo1, &m2, &mo2, None, &label);
            let c = time_of_contact(&m1, &mo1, &m2, &mo2, &ContactOptions::default()).unwrap();
            started += usize::from(c.is_some_and(|c| c.status == ContactStatus::StartedInContact));
        }
    }
    assert!(started > 40, "{started} starts in contact");
}

/// A convex mesh (a box, a coarse sphere or a cylinder) under a random stretch and shear.
fn random_convex(rng: &mut impl Rng) -> TriMesh {
    let base = match rng.random_range(0..3) {
        0 => mesh::box_mesh(Vec3::new(0.5, 0.3, 0.8)).unwrap(),
        1 => mesh::sphere(0.6, rng.random_range(3..8), rng.random_range(4..12)).unwrap(),
        _ => mesh::cylinder(0.4, 1.0).unwrap(),
    };
    let mut columns = [Vec3::X, Vec3::Y, Vec3::Z];
    for c in &mut columns {
        *c = *c * rng.random_range(0.4..1.5) + random_unit(rng) * rng.random_range(0.0..0.3);
    }
    let map = tocsin::math::Mat3::from_cols(columns[0], columns[1], columns[2]);
    let vertices = base.vertices().iter().map(|p| map * *p).collect();
    TriMesh::new(vertices, base.triangles().to_vec()).unwrap()
}

/// The same surface with a degenerate triangle added at one corner: no longer a convex
/// polytope to the library, so its queries take the hierarchy's path (the general one).
fn as_soup(m: &TriMesh) -> TriMesh {
    let mut triangles = m.triangles().to_vec();
    triangles.push([0, 0, 0]);
    TriMesh::new(m.vertices().to_vec(), triangles).unwrap()
}

/// Body 1 crossing from 3 units before the origin to 3 past it along a random direction, up
/// to `offset` off the line, turning (motion kind `kind`); body 2 near the origin, still or
/// (`both_move`) moving half a unit back along the direction.
fn crossing(rng: &mut impl Rng, kind: usize, offset: f64, both_move: bool) -> (Motion, Motion) {
    let dir = random_unit(rng);
    let off = random_unit(rng).cross(dir) * rng.random_range(0.0..offset);
    let s1 = Pose {
        rotation: random_rotation(rng),
        translation: -3.0 * dir + off,
    };
    let e1 = Pose {
        rotation: random_rotation(rng),
        translation: 3.0 * dir + off,
    };
    let mo1 = random_motion(rng, kind, s1, e1);
    let s2 = random_pose(rng, 0.2);
    let mo2 = if both_move {
        let e2 = Pose {
            rotation: random_rotation(rng),
            translation: s2.translation - dir * 0.5,
        };
        random_motion(rng, kind, s2, e2)
    } else {
        Motion::stationary(s2)
    };
    (mo1, mo2)
}

/// Two convex meshes (the step from GJK's separation of the whole bodies): passes, grazes
/// and near misses of every motion kind, one or both bodies moving, against sampling; and the
/// same geometry through the general path (a degenerate triangle added) reports a contact on
/// the same passes wherever the sampled distance leaves no room for either answer.
#[test]
fn convex_bodies_against_sampling_and_the_general_path() {
    let mut rng = rng(77);
    let (mut hits, mut total, mut iterations) = (0, 0, (0, 0));
    for case in 0..120 {
        let (m1, m2) = (random_convex(&mut rng), random_convex(&mut rng));
        let kind = case % 3;
        let (mo1, mo2) = crossing(&mut rng, kind, 1.6, case % 2 == 0);
        let label = format!("convex case {case} kind {kind}");
        let hit = check(&m1, &mo1, &m2, &mo2, None, &label);
        let (g1, g2) = (as_soup(&m1), as_soup(&m2));
        let general = check(
            &g1,
            &mo1,
            &g2,
            &mo2,
            None,
            &format!("{label}, general path"),
        );
        let opts = ContactOptions::default();
        let delta = tocsin::query::contact_time::effective_tolerance(&m1, &mo1, &m2, &mo2, &opts);
        let closest = oracle(&m1, &mo1, &m2, &mo2).closest;
        if closest < 0.4 * delta || closest > 1.1 * delta {
            assert_eq!(hit, general, "{label}: the two paths disagree");
        }
        let count = |a: &TriMesh, b: &TriMesh| {
            time_of_contact(a, &mo1, b, &mo2, &opts)
                .unwrap()
                .map_or(0, |c| c.iterations)
        };
        if hit {
            iterations.0 += count(&m1, &m2);
            iterations.1 += count(&g1, &g2);
        }
        hits += usize::from(hit);
        total += 1;
    }
    eprintln!("convex: {hits}/{total} contacts; iterations {iterations:?} (GJK, general)");
    assert_mixed(
        hits > 30 && hits < total - 30,
        &format!("the sample should mix contacts and misses: {hits}/{total}"),
    );
}

/// A coarse sphere or capsule under a random stretch, its corners moved along their radius by
/// up to 0.3%: every corner on the hull, about half of the quads folded the wrong way (convex
/// but for its triangulation, as robot collision meshes are), so that its time of contact
/// takes the hulls' steps.
fn dented(rng: &mut impl Rng) -> TriMesh {
    let base = match rng.random_range(0..2) {
        0 => mesh::sphere(0.6, rng.random_range(5..9), rng.random_range(8..14)).unwrap(),
        _ => mesh::capsule(0.3, 0.8).unwrap(),
    };
    let stretch = Vec3::new(
        rng.random_range(0.6..1.4),
        rng.random_range(0.6..1.4),
        rng.random_range(0.6..1.4),
    );
    let vertices = base
        .vertices()
        .iter()
        .map(|p| *p * stretch * (1.0 + rng.random_range(-0.003..0.003)))
        .collect();
    TriMesh::new(vertices, base.triangles().to_vec()).unwrap()
}

/// `m` with each triangle's corners written apart (as some OBJ files write them).
fn corners_per_face(m: &TriMesh) -> TriMesh {
    let v = m
        .triangles()
        .iter()
        .flat_map(|t| t.map(|i| m.vertices()[i as usize]))
        .collect();
    let t = (0..m.num_triangles() as u32)
        .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
        .collect();
    TriMesh::new(v, t).unwrap()
}

/// `m` with a small triangle added inside it, near its centre: corners off its hull.
fn with_inner_triangle(m: &TriMesh) -> TriMesh {
    let mut v = m.vertices().to_vec();
    let mut t = m.triangles().to_vec();
    let k = v.len() as u32;
    v.extend([
        Vec3::new(0.2, 0.0, 0.0),
        Vec3::new(0.0, 0.2, 0.05),
        Vec3::new(-0.1, 0.0, 0.1),
    ]);
    t.push([k, k + 1, k + 2]);
    TriMesh::new(v, t).unwrap()
}

/// Meshes convex but for their triangulation, against each other and against convex ones
/// (a robot link beside a box): passes, grazes and near misses of every motion kind, one or
/// both bodies moving, against sampling. Their steps come from the hulls' direction with the
/// gap measured on the meshes (`traverse::StepSearch::hull_step`): climbed on the hull where it
/// keeps every corner (a dented mesh, and the same written with its corners per face, which
/// are told apart by position), searched on the mesh where it does not (a triangle inside).
#[test]
fn nearly_convex_bodies_against_sampling() {
    let mut rng = rng(78);
    let (mut hits, mut total) = (0, 0);
    for case in 0..120 {
        let m1 = match case % 4 {
            1 => corners_per_face(&dented(&mut rng)),
            3 => with_inner_triangle(&dented(&mut rng)),
            _ => dented(&mut rng),
        };
        let m2 = if case % 3 == 2 {
            random_convex(&mut rng)
        } else {
            dented(&mut rng)
        };
        let kind = case % 3;
        let (mo1, mo2) = crossing(&mut rng, kind, 1.4, case % 2 == 0);
        let tol = [None, Some(1e-3)][case % 2];
        let hit = check(
            &m1,
            &mo1,
            &m2,
            &mo2,
            tol,
            &format!("dented case {case} kind {kind}"),
        );
        hits += usize::from(hit);
        total += 1;
    }
    assert_mixed(
        hits > 25 && hits < total - 25,
        &format!("the sample should mix contacts and misses: {hits}/{total}"),
    );
}

/// A turning pass of motion kind `kind` along a random direction, from 12 units before the
/// origin to `reach` units past it and up to `spread` off the line.
fn random_pass(rng: &mut impl Rng, kind: usize, reach: f64, spread: f64) -> Motion {
    let dir = random_unit(rng);
    let s1 = Pose {
        rotation: random_rotation(rng),
        translation: -12.0 * dir,
    };
    let e1 = Pose {
        rotation: random_rotation(rng),
        translation: reach * dir + random_unit(rng) * rng.random_range(0.0..spread),
    };
    random_motion(rng, kind, s1, e1)
}

/// `cases` passes of `knot` (turning, every motion kind in turn) past a still copy from 12
/// units away, ending up to `spread` off the line, each checked against sampling; the number
/// that made contact.
fn knot_passes(knot: &TriMesh, seed: u64, cases: usize, spread: f64, label: &str) -> usize {
    let mut rng = rng(seed);
    let mut hits = 0;
    for case in 0..cases {
        let kind = case % 3;
        let mo1 = random_pass(&mut rng, kind, 12.0, spread);
        hits += usize::from(check(
            knot,
            &mo1,
            knot,
            &Motion::stationary(Pose::IDENTITY),
            None,
            &format!("{label} case {case} kind {kind}"),
        ));
    }
    hits
}

#[test]
fn knots_every_motion_kind() {
    let knot = mesh::torus_knot(60, 6).unwrap();
    knot_passes(&knot, 51, 24, 6.0, "knot");
}

/// A knot of long slivers (12 x 160 rings: triangles about 40 times longer than wide, crossing
/// at every contact far from their centres, where the RSS bound needs the long edges'
/// perpendicular), every motion kind, against sampling.
#[test]
fn sliver_knots_every_motion_kind() {
    let knot = mesh::torus_knot(12, 160).unwrap();
    let hits = knot_passes(&knot, 52, 9, 16.0, "sliver knot");
    assert_mixed(
        hits > 0 && hits < 9,
        &format!("contacts and misses should mix: {hits}"),
    );
}

#[test]
fn thin_plates_at_high_speed() {
    // Two zero-thickness plates; one crosses the other in a single step: 100 samples miss it.
    let plate = mesh::plate(1.0, 2).unwrap();
    let fixed = Motion::stationary(Pose::IDENTITY);
    // Parallel plates; samples at t = k / 100 put the moving one at z = k - 50.3, never 0.
    let below = Pose::from_translation(Vec3::new(0.1, 0.0, -50.3));
    let above = Pose::from_translation(Vec3::new(0.1, 0.0, 49.7));
    let turned = Pose::from_axis_angle(Vec3::Z, 0.5, above.translation); // stays parallel
    for mo in [
        Motion::translation(below, above).unwrap(),
        Motion::interp(below, turned, Vec3::ZERO).unwrap(),
        Motion::screw(below, turned).unwrap(),
    ] {
        assert!(check(&plate, &mo, &plate, &fixed, Some(1e-4), "thin plate"));
        let sampled = (0..=100).any(|k| {
            collide(
                &plate,
                &mo.pose_at(k as f64 / 100.0),
                &plate,
                &Pose::IDENTITY,
            )
        });
        assert!(!sampled, "100 samples should tunnel through the plate");
    }
}

#[test]
fn hand_cases() {
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let at = |x: f64| Pose::from_translation(Vec3::new(x, 0.0, 0.0));
    let still = Motion::stationary(Pose::IDENTITY);
    let opts = ContactOptions {
        tolerance: Some(1e-6),
        ..Default::default()
    };
    // Head-on translation: contact at x = 1, reached at t = 0.5 exactly (from below).
    let mo = Motion::translation(at(3.0), at(-1.0)).unwrap();
    let r = time_of_contact(&cube, &mo, &cube, &still, &opts)
        .unwrap()
        .unwrap();
    assert!(r.time <= 0.5 && r.time > 0.5 - 1e-6, "t = {}", r.time);
    assert!(
        r.normal.x < -0.99,
        "normal from the moving cube (body 1) towards body 2: {}",
        r.normal
    );
    check(&cube, &mo, &cube, &still, Some(1e-6), "head-on");
    // Both moving towards each other: contact at t = 0.25.
    let m1 = Motion::translation(at(-2.0), at(2.0)).unwrap();
    let m2 = Motion::translation(at(2.0), at(-2.0)).unwrap();
    let r = time_of_contact(&cube, &m1, &cube, &m2, &opts)
        .unwrap()
        .unwrap();
    assert!(r.time <= 0.375 && r.time > 0.375 - 1e-6, "t = {}", r.time);
    // Start touching, start overlapping.
    let touch = Motion::translation(at(1.0), at(5.0)).unwrap();
    assert_eq!(
        time_of_contact(&cube, &touch, &cube, &still, &opts)
            .unwrap()
            .unwrap()
            .status,
        ContactStatus::StartedInContact
    );
    let overlap = Motion::translation(at(0.3), at(5.0)).unwrap();
    let r = time_of_contact(&cube, &overlap, &cube, &still, &opts)
        .unwrap()
        .unwrap();
    assert_eq!(
        (r.status, r.time, r.distance),
        (ContactStatus::StartedInContact, 0.0, 0.0)
    );
    // Zero motion, apart: no contact; zero motion within tolerance: contact at 0.
    assert!(
        time_of_contact(&cube, &Motion::stationary(at(2.0)), &cube, &still, &opts)
            .unwrap()
            .is_none()
    );
    // Grazing near miss: passes 0.01 above, tolerance 1e-3 -> none; tolerance 0.1 -> contact.
    let graze = Motion::translation(
        Pose::from_translation(Vec3::new(-3.0, 0.0, 1.01)),
        Pose::from_translation(Vec3::new(3.0, 0.0, 1.01)),
    )
    .unwrap();
    assert!(time_of_contact(
        &cube,
        &graze,
        &cube,
        &still,
        &ContactOptions {
            tolerance: Some(1e-3),
            ..Default::default()
        }
    )
    .unwrap()
    .is_none());
    assert!(check(
        &cube,
        &graze,
        &cube,
        &still,
        Some(0.1),
        "grazing within tolerance"
    ));
    // Pure rotation in place: a long bar spinning about its centre hits a box beside it.
    let bar = mesh::box_mesh(Vec3::new(2.0, 0.1, 0.1)).unwrap();
    let spin = Motion::interp(
        Pose::IDENTITY,
        Pose::from_axis_angle(Vec3::Z, 1.5, Vec3::ZERO),
        Vec3::ZERO,
    )
    .unwrap();
    let post = Motion::stationary(Pose::from_translation(Vec3::new(0.0, 1.5, 0.0)));
    assert!(check(
        &bar,
        &spin,
        &cube,
        &post,
        Some(1e-5),
        "spin in place"
    ));
    // Rotation of exactly pi about z, the bar sweeps through the post.
    let half_turn = Motion::screw(
        Pose::IDENTITY,
        Pose::from_axis_angle(Vec3::Z, std::f64::consts::PI, Vec3::ZERO),
    )
    .unwrap();
    assert!(check(
        &bar,
        &half_turn,
        &cube,
        &post,
        Some(1e-5),
        "rotation of pi"
    ));
    // Scales 1e-3 and 1e3.
    for s in [1e-3, 1e3] {
        let small = mesh::box_mesh(Vec3::splat(0.5 * s)).unwrap();
        let mo = Motion::interp(
            Pose::from_translation(Vec3::new(3.0 * s, 0.1 * s, 0.0)),
            Pose::from_axis_angle(Vec3::Y, 1.0, Vec3::new(-3.0 * s, 0.0, 0.0)),
            Vec3::ZERO,
        )
        .unwrap();
        assert!(check(
            &small,
            &mo,
            &small,
            &still,
            None,
            &format!("scale {s}")
        ));
    }
}

#[test]
fn bad_options_are_errors() {
    let cube = mesh::box_mesh(Vec3::splat(0.5)).unwrap();
    let still = Motion::stationary(Pose::IDENTITY);
    for opts in [
        ContactOptions {
            tolerance: Some(0.0),
            ..Default::default()
        },
        ContactOptions {
            tolerance: Some(-1.0),
            ..Default::default()
        },
        ContactOptions {
            tolerance: Some(f64::NAN),
            ..Default::default()
        },
        ContactOptions {
            max_iterations: 0,
            ..Default::default()
        },
    ] {
        assert!(time_of_contact(&cube, &still, &cube, &still, &opts).is_err());
    }
}

#[test]
fn iteration_limit_returns_a_collision_free_time() {
    let knot = mesh::torus_knot(60, 6).unwrap();
    let mo = Motion::screw(
        Pose::from_translation(Vec3::new(-12.0, 0.5, 0.0)),
        Pose::from_axis_angle(Vec3::Z, 1.0, Vec3::new(12.0, 0.0, 0.0)),
    )
    .unwrap();
    let still = Motion::stationary(Pose::IDENTITY);
    let full = time_of_contact(&knot, &mo, &knot, &still, &ContactOptions::default())
        .unwrap()
        .unwrap();
    assert!(full.iterations > 2);
    let capped = ContactOptions {
        max_iterations: 2,
        ..Default::default()
    };
    // The cap is an error, never a contact: only [0, time_reached] is known to be free.
    let r = time_of_contact(&knot, &mo, &knot, &still, &capped);
    let Err(tocsin::ContactError::IterationLimit {
        iterations,
        time_reached,
    }) = r
    else {
        panic!("expected an iteration-limit error, got {r:?}");
    };
    assert_eq!(iterations, 2);
    assert!(time_reached < full.time && time_reached > 0.0);
    assert!(!collide(
        &knot,
        &mo.pose_at(time_reached),
        &knot,
        &Pose::IDENTITY
    ));
}

/// `motion_is_free` settles colliding motions with exact collision tests at a few times
/// (probes) beside the advancement. Under an iteration cap it must still run the very same
/// iterations as `time_of_contact`: unless a probe found a collision (and then the uncapped
/// time of contact is a contact), it gives the capped query's answer, or the same error with
/// the same time reached. A probe's "not free" must never be wrong, which `check` (the oracle)
/// covers on every other test's cases.
#[test]
fn motion_is_free_under_an_iteration_cap() {
    let knot = mesh::torus_knot(60, 6).unwrap();
    let still = Motion::stationary(Pose::IDENTITY);
    let mut rng = rng(57);
    let (mut settled_by_probes, mut capped_errors) = (0, 0);
    for case in 0..30 {
        let kind = case % 3;
        // Far past the still knot, or across it: collisions away from the middle and the end
        // (found by the advancement or the later probes), near misses and misses.
        let reach = rng.random_range(12.0..40.0);
        let mo = random_pass(&mut rng, kind, reach, 8.0);
        let full = time_of_contact(&knot, &mo, &knot, &still, &ContactOptions::default()).unwrap();
        for cap in 1..=8 {
            let opts = ContactOptions {
                max_iterations: cap,
                ..Default::default()
            };
            let label = format!("case {case} kind {kind} cap {cap}");
            let free = tocsin::motion_is_free(&knot, &mo, &knot, &still, &opts);
            match (free, time_of_contact(&knot, &mo, &knot, &still, &opts)) {
                (Ok(free), Ok(r)) => assert_eq!(free, r.is_none(), "{label}"),
                (Ok(false), Err(_)) => {
                    assert!(
                        full.is_some(),
                        "{label}: a probe called a free motion colliding"
                    );
                    settled_by_probes += 1;
                }
                (
                    Err(tocsin::ContactError::IterationLimit {
                        iterations: a,
                        time_reached: ta,
                    }),
                    Err(tocsin::ContactError::IterationLimit {
                        iterations: b,
                        time_reached: tb,
                    }),
                ) => {
                    assert_eq!((a, ta), (b, tb), "{label}");
                    assert_eq!(a, cap, "{label}");
                    capped_errors += 1;
                }
                (free, toc) => panic!("{label}: motion_is_free {free:?}, time_of_contact {toc:?}"),
            }
        }
    }
    // Both branches ran: passes through the middle are settled before any iteration, and the
    // others reach the cap.
    assert!(
        settled_by_probes > 0 && capped_errors > 0,
        "{settled_by_probes} settled by probes, {capped_errors} capped"
    );
}

#[test]
fn cache_across_queries_gives_the_same_answers() {
    use tocsin::{time_of_contact_with_cache, ContactCache};
    let knot = mesh::torus_knot(60, 6).unwrap();
    let still = Motion::stationary(Pose::IDENTITY);
    let mut cache = ContactCache::default();
    for k in 0..10 {
        let y = 0.1 * k as f64;
        let mo = Motion::interp(
            Pose::from_translation(Vec3::new(-12.0, y, 0.0)),
            Pose::from_axis_angle(Vec3::Y, 0.8, Vec3::new(12.0, y, 0.0)),
            Vec3::ZERO,
        )
        .unwrap();
        let cold = time_of_contact(&knot, &mo, &knot, &still, &ContactOptions::default()).unwrap();
        let warm = time_of_contact_with_cache(
            &knot,
            &mo,
            &knot,
            &still,
            &ContactOptions::default(),
            &mut cache,
        )
        .unwrap();
        // Both are valid answers; with the same steps they agree, and the warm one is never later
        // than the first collision either (checked by the oracle tests); here: same contact found.
        assert_eq!(cold.is_some(), warm.is_some());
        let (c, w) = (cold.unwrap(), warm.unwrap());
        assert!(
            (c.time - w.time).abs() < 1e-3,
            "cold {} warm {}",
            c.time,
            w.time
        );
        assert!(
            w.distance
                <= tocsin::query::contact_time::effective_tolerance(
                    &knot,
                    &mo,
                    &knot,
                    &still,
                    &ContactOptions::default()
                )
        );
    }
}

/// An open tube about the z axis: `n_around` x `n_along` quads, split in two.
fn tube(r: f64, length: f64, n_around: usize, n_along: usize) -> TriMesh {
    mesh::revolved(|_, _| r, length, n_around, n_along).unwrap()
}

fn turn(axis: Vec3, degrees: f64, translation: Vec3) -> Pose {
    Pose::from_axis_angle(axis, degrees.to_radians(), translation)
}

#[test]
fn turning_in_close_fits_against_sampling() {
    // A body turning about a fixed axis inside a still one: where the rotation certificates
    // (query/contact_time/shells.rs) decide. Clear fits must report nothing; tight fits, whose
    // facets cross as they turn, and slides into an end plate must report the first contact.
    let still = Motion::stationary(Pose::IDENTITY);
    let ball = mesh::sphere(1.0, 12, 24).unwrap();
    let mut cases: Vec<(String, TriMesh, Motion, TriMesh)> = Vec::new();
    for (socket_radius, axis) in [
        (1.02, Vec3::new(0.3, 0.2, 1.0)),
        (1.002, Vec3::new(0.3, 0.2, 1.0)),
        (1.002, Vec3::Z),
        (1.0005, Vec3::X),
    ] {
        let socket = mesh::sphere(socket_radius, 12, 24).unwrap();
        let mo = Motion::screw(Pose::IDENTITY, turn(axis, 90.0, Vec3::ZERO)).unwrap();
        cases.push((
            format!("ball in {socket_radius} socket, axis {axis}"),
            ball.clone(),
            mo,
            socket,
        ));
    }
    let shaft = tube(1.0, 4.0, 16, 4);
    for bore_radius in [1.1, 1.002] {
        let bore = tube(bore_radius, 6.0, 16, 4);
        let mo = Motion::screw(Pose::IDENTITY, turn(Vec3::Z, 180.0, Vec3::ZERO)).unwrap();
        cases.push((
            format!("shaft in {bore_radius} bore"),
            shaft.clone(),
            mo,
            bore,
        ));
    }
    // Screwing along the axis into a plate across the bore at z = 3.5.
    let wide = tube(1.1, 6.0, 16, 4);
    let plate = mesh::plate(4.0, 4).unwrap();
    let cap: Vec<Vec3> = plate
        .vertices()
        .iter()
        .map(|&p| p + Vec3::new(0.0, 0.0, 3.5))
        .collect();
    let capped = TriMesh::new(
        [wide.vertices(), &cap].concat(),
        wide.triangles()
            .iter()
            .copied()
            .chain(
                plate
                    .triangles()
                    .iter()
                    .map(|t| t.map(|i| i + wide.num_vertices() as u32)),
            )
            .collect(),
    )
    .unwrap();
    let screw_in = Motion::screw(
        Pose::IDENTITY,
        turn(Vec3::Z, 270.0, Vec3::new(0.0, 0.0, 2.0)),
    )
    .unwrap();
    cases.push((
        "shaft screwing into a capped bore".into(),
        shaft.clone(),
        screw_in,
        capped,
    ));
    // A 128-sided shaft half a turn in its bore, its corners 1.65 tolerances from the bore's
    // flat faces: clear, certified by the long triangles' exact distances from the axis (6 s
    // before, when those were the centroids' less the corners' spread).
    cases.push((
        "128-sided shaft in a 1.004 bore".into(),
        tube(1.0, 4.0, 128, 2),
        Motion::screw(Pose::IDENTITY, turn(Vec3::Z, 180.0, Vec3::ZERO)).unwrap(),
        tube(1.004, 6.0, 128, 2),
    ));
    // Tapers (radius 0.75 + c - z / 4 over z in [-1, 1], the bore 0.25 longer at the narrow
    // end): the meridian certificates decide, the axis-aligned ranges overlapping along the
    // slope. A 16-sided shaft 0.05 inside its bore is clear (its corners' sagitta is 0.02);
    // 0.002 inside, its corners meet the bore's faces as it turns; a 128-sided one 0.004
    // inside is clear (6.7 s before the meridian certificates, at 256 sides); pushed towards
    // the narrow end while turning, the 16-sided one meets the bore.
    let taper = |c: f64, sides: usize, rows: usize, length: f64| {
        let shift = (length - 2.0) / 2.0;
        let mesh = mesh::revolved(
            move |_, z| 0.75 + c - 0.25 * (z + shift),
            length,
            sides,
            rows,
        )
        .unwrap();
        let moved: Vec<Vec3> = mesh
            .vertices()
            .iter()
            .map(|&p| p + Vec3::new(0.0, 0.0, shift))
            .collect();
        TriMesh::new(moved, mesh.triangles().to_vec()).unwrap()
    };
    let half_turn = Motion::screw(Pose::IDENTITY, turn(Vec3::Z, 180.0, Vec3::ZERO)).unwrap();
    for (c, sides, rows) in [(0.05, 16, 4), (0.002, 16, 4), (0.004, 128, 2)] {
        cases.push((
            format!("{sides}-sided taper {c} inside its bore"),
            taper(0.0, sides, rows, 2.0),
            half_turn,
            taper(c, sides, rows, 2.5),
        ));
    }
    cases.push((
        "taper pushed into its bore while turning".into(),
        taper(0.0, 16, 4, 2.0),
        Motion::screw(
            Pose::IDENTITY,
            turn(Vec3::Z, 180.0, Vec3::new(0.0, 0.0, 0.5)),
        )
        .unwrap(),
        taper(0.05, 16, 4, 2.5),
    ));
    // Bolts screwed into nuts (a sinusoidal thread of pitch 0.5 and depth 0.05): along the
    // thread (170 degrees: a half turn's sense would be rounding's choice), where the helical
    // certificates decide (a 98K-triangle bolt in a 32K nut took 46 s before them); 0.06
    // wider the nut is clear, with the bolt's ends capped too (their
    // triangles reach the axis, where the helical invariants do not serve); 0.003 wider the
    // facets cross as it turns; screwed at twice the pitch, the flanks meet.
    let thread =
        |c: f64| move |a: f64, z: f64| 1.0 + c + 0.05 * (std::f64::consts::TAU * z / 0.5 - a).sin();
    let bolt = mesh::revolved(thread(0.0), 1.5, 32, 36).unwrap();
    let screw = |advance: f64| {
        Motion::screw(
            Pose::IDENTITY,
            turn(Vec3::Z, 170.0, Vec3::new(0.0, 0.0, advance)),
        )
        .unwrap()
    };
    let nut = |c: f64| mesh::revolved(thread(c), 0.5, 36, 12).unwrap();
    // The bolt with its ends closed by fans to a centre point on the axis.
    let capped = {
        let (n, rows) = (32u32, 36u32);
        let mut v = bolt.vertices().to_vec();
        let mut f = bolt.triangles().to_vec();
        for (j, z) in [(0, -0.75), (rows, 0.75)] {
            let centre = v.len() as u32;
            v.push(Vec3::new(0.0, 0.0, z));
            for i in 0..n {
                let (a, b) = (i * (rows + 1) + j, (i + 1) % n * (rows + 1) + j);
                f.push([centre, a, b]);
            }
        }
        TriMesh::new(v, f).unwrap()
    };
    cases.push((
        "bolt screwed into a 0.06 wider nut".into(),
        bolt.clone(),
        screw(0.5 * 170.0 / 360.0),
        nut(0.06),
    ));
    cases.push((
        "bolt screwed into a 0.003 wider nut".into(),
        bolt.clone(),
        screw(0.5 * 170.0 / 360.0),
        nut(0.003),
    ));
    cases.push((
        "capped bolt screwed into a 0.06 wider nut".into(),
        capped,
        screw(0.5 * 170.0 / 360.0),
        nut(0.06),
    ));
    // Threaded half a turn out of phase below z = -0.3: that part starts below the nut, out
    // of its reach along the axis, and meets the nut's thread as the screw carries it up (a
    // certificate that forgot the slide would settle it from where it starts).
    let stepped = mesh::revolved(
        |a: f64, z: f64| {
            let phase = if z < -0.3 { std::f64::consts::PI } else { 0.0 };
            1.0 + 0.05 * (std::f64::consts::TAU * z / 0.5 - a + phase).sin()
        },
        1.5,
        32,
        36,
    )
    .unwrap();
    cases.push((
        "bolt threaded out of phase below the nut, screwed up into it".into(),
        stepped,
        screw(0.5 * 170.0 / 360.0),
        nut(0.06),
    ));
    cases.push((
        "bolt screwed at twice the pitch".into(),
        bolt.clone(),
        screw(170.0 / 360.0),
        nut(0.06),
    ));
    // Starting in contact, in fits whose certificates are decided at the start: a ball in a
    // socket it pierces (tessellated otherwise: a scaled copy would nest), a bolt in a nut
    // whose thread is deeper (a narrower nut would nest too). The collision test at the start waits
    // for the first iteration, which must end within the tolerance, not step.
    let started = [
        (
            "ball in a 0.998 socket".to_string(),
            ball.clone(),
            Motion::screw(Pose::IDENTITY, turn(Vec3::Z, 90.0, Vec3::ZERO)).unwrap(),
            mesh::sphere(0.998, 16, 32).unwrap(),
        ),
        (
            "bolt screwed into a nut of deeper thread".into(),
            bolt.clone(),
            screw(0.5 * 170.0 / 360.0),
            mesh::revolved(
                |a: f64, z: f64| 1.0 + 0.08 * (std::f64::consts::TAU * z / 0.5 - a).sin(),
                0.5,
                36,
                12,
            )
            .unwrap(),
        ),
    ];
    for (label, turning, mo, fixed) in &started {
        assert!(
            collide(turning, &Pose::IDENTITY, fixed, &Pose::IDENTITY),
            "{label}"
        );
        for (m1, mo1, m2, mo2) in [(turning, mo, fixed, &still), (fixed, &still, turning, mo)] {
            assert!(check(m1, mo1, m2, mo2, None, label), "{label}: no contact");
            let c = time_of_contact(m1, mo1, m2, mo2, &ContactOptions::default());
            let status = c.unwrap().map(|c| c.status);
            assert_eq!(status, Some(ContactStatus::StartedInContact), "{label}");
        }
    }
    let mut contacts = 0;
    for (label, turning, mo, fixed) in &cases {
        contacts += check(turning, mo, fixed, &still, None, label) as usize;
        // The same with the bodies swapped: the still one is mesh 1.
        contacts += check(
            fixed,
            &still,
            turning,
            mo,
            None,
            &format!("{label}, swapped"),
        ) as usize;
    }
    // The tight fits, the capped bore, the pushed taper and the bolts at twice the pitch, out
    // of phase or in the 0.003 nut collide; the clear ones (1.02 socket, 1.1 bore, the 128-sided bore, the
    // 0.05 and 128-sided tapers, the bolts in the 0.06 nut) not.
    assert!(contacts >= 2 * (cases.len() - 7), "{contacts} contacts");
    // At the edge of the certificates: tolerances around the clear fits' closest approach.
    // With the closest at 0.4 of the tolerance a contact must be reported (a certificate
    // claiming more clearance than there is would miss it); at 0.9, none can be.
    for (label, turning, mo, fixed) in [
        &cases[0], &cases[4], &cases[7], &cases[8], &cases[10], &cases[12], &cases[14],
    ] {
        let closest = oracle(turning, mo, fixed, &still).closest;
        let must = check(turning, mo, fixed, &still, Some(closest / 0.4), label);
        assert!(must, "{label}: no contact at tolerance {}", closest / 0.4);
        check(turning, mo, fixed, &still, Some(closest / 0.9), label);
    }
}

/// Asserts that the query at tolerance `delta` answers within `cap` iterations.
fn answers_within(
    (m1, mo1, m2, mo2): (&TriMesh, &Motion, &TriMesh, &Motion),
    delta: f64,
    cap: usize,
    label: &str,
) {
    let capped = ContactOptions {
        tolerance: Some(delta),
        max_iterations: cap,
        ..Default::default()
    };
    let r = time_of_contact(m1, mo1, m2, mo2, &capped);
    assert!(r.is_ok(), "{label}: {r:?}");
}

/// A 32-sided shaft turning one and a half turns in its bore, whose faces clear the shaft's
/// corners by 0.3 to 1.3 tolerances at the angles where corners face faces. Below half the
/// tolerance the corners come within it: a contact. Above it the contract allows either answer
/// up to the tolerance, and the rotation certificates prove the fit never closer than half
/// the tolerance: when they asked for the whole tolerance, the fits between half and one
/// crawled to where corners face faces (a 64-sided shaft of radius 0.05, 0.84 tolerances
/// clear, through 29 iterations and 0.5 s), which the cap of 8 below stops.
#[test]
fn turning_within_the_tolerance_band() {
    let (n, delta) = (32usize, 2e-4);
    let still = Motion::stationary(Pose::IDENTITY);
    let shaft = tube(1.0, 4.0, n, 4);
    let spin = Motion::turn(
        Pose::IDENTITY,
        Vec3::ZERO,
        Vec3::Z * (3.0 * std::f64::consts::PI),
    )
    .unwrap();
    let half = std::f64::consts::PI / n as f64;
    for c in [0.3, 0.55, 0.8, 1.05, 1.3] {
        // The bore's faces lie at its corners' radius times cos(half).
        let bore = tube((1.0 + c * delta) / half.cos(), 6.0, n, 4);
        let label = format!("shaft in a bore {c} tolerances clear");
        for (m1, mo1, m2, mo2) in [
            (&shaft, &spin, &bore, &still),
            (&bore, &still, &shaft, &spin),
        ] {
            let hit = check(m1, mo1, m2, mo2, Some(delta), &label);
            if c < 0.5 {
                assert!(hit, "{label}: no contact");
            } else {
                answers_within((m1, mo1, m2, mo2), delta, 8, &label);
            }
        }
    }
}

/// A barrel (32 sides, radius `0.05 (1 + 0.03 sin 10z)`, so its faces widen along their length)
/// turning 4.4 rad about its axis beside a long triangle whose edge passes its corners
/// tangentially at height 0.08, slanted 0 to 0.4 rad, 0.3 to 1.3 tolerances (20 um) beyond
/// them. The triangles' ranges over their whole length never certified the slanted edge, and
/// the query crawled past each of the corners: at 1.04 tolerances it stopped at the
/// 1,000-iteration cap (21 ms); the slabs (`shells.rs`, `slab_gap`) certify it, here within
/// a cap of 30. Both orders of the bodies, against the oracle.
#[test]
fn a_barrel_turning_past_a_tangent_edge() {
    let delta = 2e-5;
    let radius = |z: f64| 0.05 * (1.0 + 0.03 * (10.0 * z).sin());
    let barrel = tocsin::mesh::revolved(|_, z| radius(z), 0.2, 32, 4).unwrap();
    let spin = Motion::turn(Pose::IDENTITY, Vec3::ZERO, Vec3::Z * 4.4).unwrap();
    let still = Motion::stationary(Pose::IDENTITY);
    // The corners' distance from the axis at height 0.08: along the straight corner edges
    // between the rows at 0.05 and 0.1.
    let f = (0.08 - 0.05) / 0.05;
    let corner = radius(0.05) + f * (radius(0.1) - radius(0.05));
    let (phi, mut contacts) = (0.3_f64, 0);
    let radial = Vec3::new(phi.cos(), phi.sin(), 0.0);
    for c in [0.3, 0.7, 1.04, 1.3] {
        for slant in [0.0_f64, 0.2, 0.4] {
            let centre = radial * (corner + c * delta) + Vec3::Z * 0.08;
            let along = Vec3::new(-phi.sin(), phi.cos(), 0.0) * slant.cos() + Vec3::Z * slant.sin();
            let far = radial * 0.4 + Vec3::Z * 0.18;
            let edge = TriMesh::new(
                vec![centre - along * 0.3, centre + along * 0.3, far],
                vec![[0, 1, 2]],
            )
            .unwrap();
            let label = format!("edge {c} tolerances away, slanted {slant}");
            for (m1, mo1, m2, mo2) in [
                (&barrel, &spin, &edge, &still),
                (&edge, &still, &barrel, &spin),
            ] {
                contacts += usize::from(check(m1, mo1, m2, mo2, Some(delta), &label));
                if c >= 1.0 {
                    answers_within((m1, mo1, m2, mo2), delta, 30, &label);
                }
            }
        }
    }
    assert!(
        contacts >= 6,
        "{contacts} contacts: at 0.3 tolerances each should be one"
    );
}

/// Close fits turning at random tolerances around their closest approach: a polygonal shaft
/// (12 to 24 sides) in a bore, a taper in its bore, a ball in a socket, each turning 90 to 270
/// degrees about its axis (tilted up to 0.2 rad for the ball), at a tolerance that puts the
/// sampled closest approach between 0.3 and 1.4 tolerances. Below half a tolerance a contact
/// is required, above the tolerance none is allowed, and in between the certificates (which
/// stop at half the tolerance) may answer either; `check` holds each against the oracle. The
/// certificates' give-up and their half-tolerance threshold change only step lengths: a
/// certificate claiming too much would miss a contact here.
#[test]
fn close_fits_at_random_tolerances_against_sampling() {
    let mut rng = rng(4701);
    let still = Motion::stationary(Pose::IDENTITY);
    let (mut contacts, mut band) = (0, 0);
    for case in 0..12 {
        let sides = rng.random_range(12..=24);
        // Beyond the facets' sagitta (a ball's facets sink by about twice it), so that the
        // corners pass the faces without touching.
        let sagitta = 1.0 - (std::f64::consts::PI / sides as f64).cos();
        let clear = 3.0 * sagitta + rng.random_range(0.001..0.01);
        let (turning, fixed, axis) = match case % 3 {
            0 => (
                tube(1.0, 3.0, sides, 3),
                tube(1.0 + clear, 4.0, sides, 3),
                Vec3::Z,
            ),
            1 => {
                let taper = |c: f64| {
                    mesh::revolved(move |_, z| 0.75 + c - 0.25 * z, 2.0, sides, 3).unwrap()
                };
                (taper(0.0), taper(clear), Vec3::Z)
            }
            _ => {
                let tilt = Vec3::new(rng.random_range(-0.2..0.2), 0.0, 1.0);
                (
                    mesh::sphere(1.0, sides / 2, sides).unwrap(),
                    mesh::sphere(1.0 + clear, sides / 2, sides).unwrap(),
                    tilt,
                )
            }
        };
        let degrees: f64 = rng.random_range(90.0..270.0);
        let mo = Motion::turn(
            Pose::IDENTITY,
            Vec3::ZERO,
            axis.normalize() * degrees.to_radians(),
        )
        .unwrap();
        let closest = oracle(&turning, &mo, &fixed, &still).closest;
        assert!(closest > 0.0, "case {case}: the fit collides");
        let at = rng.random_range(0.3..1.4);
        let tolerance = closest / at;
        let label =
            format!("case {case}: {sides} sides, clearance {clear}, closest {at} tolerances");
        let hit = check(&turning, &mo, &fixed, &still, Some(tolerance), &label);
        if at < 0.5 {
            assert!(hit, "{label}: no contact");
        }
        contacts += hit as usize;
        band += (0.5..=1.0).contains(&at) as usize;
    }
    assert_mixed(
        contacts >= 3 && band >= 3,
        &format!("{contacts} contacts, {band} in the band"),
    );
}

/// A mesh keeps the corner ranges the rotation certificates last worked out about an axis,
/// for the next query about the same one: queries about a few axes, interleaved on the same
/// meshes, give what the same queries give on fresh copies (which keep nothing).
#[test]
fn kept_ranges_about_an_axis_change_no_answer() {
    let shaft = tube(1.0, 4.0, 64, 4);
    let bore = tube(1.01, 6.0, 64, 4);
    let still = Motion::stationary(Pose::IDENTITY);
    let opts = ContactOptions::default();
    let motions: Vec<Motion> = [
        (Vec3::Z, 180.0, Vec3::ZERO),
        (Vec3::Z, 90.0, Vec3::ZERO),
        (Vec3::new(0.0, 0.05, 1.0), 120.0, Vec3::ZERO),
        (Vec3::Z, 180.0, Vec3::new(0.0, 0.0, 0.5)),
        (Vec3::X, 30.0, Vec3::ZERO),
    ]
    .into_iter()
    .map(|(axis, degrees, slide)| {
        Motion::screw(Pose::IDENTITY, turn(axis.normalize(), degrees, slide)).unwrap()
    })
    .collect();
    let key = |c: Option<tocsin::ContactTime>| c.map(|c| (c.time, c.iterations, c.status));
    let (mut contacts, mut free) = (0, 0);
    for round in 0..3 {
        for (k, mo) in motions.iter().enumerate() {
            let kept = time_of_contact(&shaft, mo, &bore, &still, &opts).unwrap();
            let fresh = time_of_contact(&shaft.clone(), mo, &bore.clone(), &still, &opts);
            assert_eq!(key(kept), key(fresh.unwrap()), "round {round}, motion {k}");
            let swapped = time_of_contact(&bore, &still, &shaft, mo, &opts).unwrap();
            let fresh = time_of_contact(&bore.clone(), &still, &shaft.clone(), mo, &opts);
            assert_eq!(
                key(swapped),
                key(fresh.unwrap()),
                "round {round}, motion {k}"
            );
            match kept {
                Some(_) => contacts += 1,
                None => free += 1,
            }
        }
    }
    assert!(contacts > 0 && free > 0, "{contacts} contacts, {free} free");
}

/// One case of [`far_from_the_origin_and_at_extreme_scales`]: the two soups, their motions and
/// a label.
fn extreme_scale_case(
    rng: &mut impl Rng,
    case: usize,
) -> (TriMesh, Motion, TriMesh, Motion, String) {
    let scale = 10f64.powi(rng.random_range(-7..=7));
    let offset = 10f64.powi(rng.random_range(0..=6)) * scale * random_unit(rng);
    let scale2 = if case % 3 == 0 {
        scale * 10f64.powi(rng.random_range(-3..=3))
    } else {
        scale
    };
    let n1 = 2 + rng.random_range(0..20);
    let m1 = random_soup(rng, n1, scale);
    let n2 = 2 + rng.random_range(0..20);
    let m2 = random_soup(rng, n2, scale2);
    let dir = random_unit(rng);
    let reach = scale.max(scale2) * rng.random_range(1.0..5.0);
    let s1 = Pose {
        rotation: random_rotation(rng),
        translation: offset - reach * dir,
    };
    let e1 = Pose {
        rotation: random_rotation(rng),
        translation: offset + reach * dir + random_unit(rng) * scale * rng.random_range(0.0..2.0),
    };
    let kind = case % 3;
    let mo1 = random_motion(rng, kind, s1, e1);
    let s2 = Pose {
        rotation: random_rotation(rng),
        translation: offset + random_unit(rng) * 0.3 * scale,
    };
    let mo2 = if case % 2 == 0 {
        Motion::stationary(s2)
    } else {
        let e2 = Pose {
            rotation: random_rotation(rng),
            translation: s2.translation - dir * scale,
        };
        Motion::screw(s2, e2).unwrap()
    };
    let label = format!(
        "case {case}: scale {scale:e} and {scale2:e}, {:e} from the origin, kind {kind}",
        offset.length()
    );
    (m1, mo1, m2, mo2, label)
}

#[test]
fn far_from_the_origin_and_at_extreme_scales() {
    // Soups of 1e-7 to 1e7 (the two bodies up to 1,000 times apart in size), up to 1e6 of
    // their size away from the origin, every motion kind: the contract as everywhere, and the
    // normal unit and pointing from body 1 to body 2 (it was off unit length by 3e-8 far from
    // the origin, when it was the world points' difference over the distance).
    let mut rng = rng(91);
    let mut hits = 0;
    let cases = 120;
    for case in 0..cases {
        let (m1, mo1, m2, mo2, label) = extreme_scale_case(&mut rng, case);
        hits += usize::from(check(&m1, &mo1, &m2, &mo2, None, &label));
    }
    assert_mixed(
        hits > cases / 4 && hits < cases,
        &format!("the sample should mix contacts and misses: {hits}/{cases}"),
    );
}

/// A contact 1.19e-11 apart between soups of 1e-7 and 1e-8, 0.1 from the origin (the tolerance
/// 1e-11): the normal was taken from an earlier iterate, as if that distance were rounding,
/// and pointed against `point2 - point1` (the direction of another pair). The direction there
/// is resolved to about 1e-6 (found by `make soak`: the case above on its seventeenth sample).
#[test]
fn a_normal_at_a_tiny_but_resolved_distance_is_that_distance_direction() {
    // The seed itself, not shifted on a soak run: this is the one case.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(91 + 17 * 7919);
    for case in 0..=21 {
        let (m1, mo1, m2, mo2, label) = extreme_scale_case(&mut rng, case);
        if case < 21 {
            continue;
        }
        let c = time_of_contact(&m1, &mo1, &m2, &mo2, &ContactOptions::default())
            .unwrap()
            .expect("a contact");
        let along = (c.point2 - c.point1) / c.distance;
        assert!(
            c.distance < 1e-10 && (c.normal - along).length() < 1e-4,
            "{label}: normal {} against {along} at distance {:e}",
            c.normal,
            c.distance
        );
        assert!(check(&m1, &mo1, &m2, &mo2, None, &label));
    }
}

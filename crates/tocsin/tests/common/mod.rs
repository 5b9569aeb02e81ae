//! Shared test helpers: seeded random soups and poses, and the slow, obviously-correct oracles.
#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tocsin::query::distance::{distance_triangle_triangle, intersect_triangle_triangle};
use tocsin::{Mat3, Pose, TriMesh, Vec3};

/// The seed offset of a soak run (`TOCSIN_SOAK=k`, `make soak`): 0 (unset) runs the seeds as
/// written; `k` shifts every seed drawn through [`rng`] by `7919 k`, a fresh sample of the same
/// generators and oracles (the broad phase's missed touching pair was found so).
pub fn soak() -> u64 {
    std::env::var("TOCSIN_SOAK")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0)
}

/// The random source of a test, seeded by `seed` (shifted on a soak run: [`soak`]).
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed.wrapping_add(soak().wrapping_mul(7919)))
}

/// A randomized test's check that its sample mixes the outcomes it means to exercise (the
/// counts its written seed gives). It checks no answer: on a soak run a fresh sample may lean
/// one way with every answer right, so there it only says so.
pub fn assert_mixed(mixed: bool, what: &str) {
    if soak() == 0 {
        assert!(mixed, "{what}");
    } else if !mixed {
        eprintln!("soak {}: the sample does not mix ({what})", soak());
    }
}

pub fn random_unit(rng: &mut impl Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let l = v.length();
        if l > 0.1 && l <= 1.0 {
            return v / l;
        }
    }
}

pub fn random_rotation(rng: &mut impl Rng) -> Mat3 {
    Mat3::from_axis_angle(
        random_unit(rng),
        rng.random_range(0.0..std::f64::consts::PI),
    )
}

pub fn random_pose(rng: &mut impl Rng, spread: f64) -> Pose {
    Pose {
        rotation: random_rotation(rng),
        translation: Vec3::new(
            rng.random_range(-spread..spread),
            rng.random_range(-spread..spread),
            rng.random_range(-spread..spread),
        ),
    }
}

/// `mesh` with every vertex multiplied by `size`.
pub fn scaled(mesh: &TriMesh, size: f64) -> TriMesh {
    TriMesh::new(
        mesh.vertices().iter().map(|&v| v * size).collect(),
        mesh.triangles().to_vec(),
    )
    .expect("a scaled mesh")
}

/// Two poses for a body and a copy of it of size `size` that overlap: the first turned at
/// the origin, the second turned and moved by 0.3 of the size in a random direction.
pub fn overlapping_poses(rng: &mut impl Rng, size: f64) -> (Pose, Pose) {
    let first = Pose {
        rotation: random_rotation(rng),
        translation: Vec3::ZERO,
    };
    let second = Pose {
        rotation: random_rotation(rng),
        translation: random_unit(rng) * 0.3 * size,
    };
    (first, second)
}

/// A random polygon soup of about `n` triangles in a cube of half side `scale`, with degenerate
/// (point and segment) triangles, duplicated triangles and isolated vertices mixed in.
pub fn random_soup(rng: &mut impl Rng, n: usize, scale: f64) -> TriMesh {
    let nv = 3 * n + 2;
    let vertices: Vec<Vec3> = (0..nv)
        .map(|_| {
            scale
                * Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                )
        })
        .collect();
    let mut triangles = Vec::new();
    for i in 0..n {
        let base = (3 * i) as u32;
        let kind = rng.random_range(0..10);
        let t = match kind {
            0 => [base, base, base],     // a point
            1 => [base, base + 1, base], // a segment
            2 if !triangles.is_empty() => triangles[rng.random_range(0..triangles.len())], // duplicate
            _ => [base, base + 1, base + 2],
        };
        triangles.push(t);
    }
    TriMesh::new(vertices, triangles).expect("valid soup")
}

/// Corners of triangle `i` of `mesh` in the world frame.
pub fn world_triangle(mesh: &TriMesh, pose: &Pose, i: usize) -> [Vec3; 3] {
    mesh.triangle(i).map(|p| pose.transform_point(p))
}

/// Brute force over all triangle pairs: (distance, triangle1, triangle2).
pub fn brute_distance(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose) -> (f64, usize, usize) {
    let mut best = (f64::INFINITY, 0, 0);
    for i in 0..m1.num_triangles() {
        let a = world_triangle(m1, p1, i);
        for j in 0..m2.num_triangles() {
            let d = distance_triangle_triangle(&a, &world_triangle(m2, p2, j)).distance;
            if d < best.0 {
                best = (d, i, j);
            }
        }
    }
    best
}

/// Brute force over all triangles: the distance from the world point `p` to the mesh.
pub fn brute_point_distance(p: Vec3, mesh: &TriMesh, pose: &Pose) -> f64 {
    (0..mesh.num_triangles())
        .map(|j| distance_triangle_triangle(&[p; 3], &world_triangle(mesh, pose, j)).distance)
        .fold(f64::INFINITY, f64::min)
}

/// Brute force: all intersecting triangle pairs, sorted.
pub fn brute_pairs(m1: &TriMesh, p1: &Pose, m2: &TriMesh, p2: &Pose) -> Vec<[usize; 2]> {
    let pos12 = p1.inv_mul(p2);
    let mut out = Vec::new();
    for i in 0..m1.num_triangles() {
        let a = m1.triangle(i);
        for j in 0..m2.num_triangles() {
            let b = m2.triangle(j).map(|p| pos12.transform_point(p));
            if intersect_triangle_triangle(&a, &b) {
                out.push([i, j]);
            }
        }
    }
    out
}

// ---- An independent triangle-pair distance: candidate critical points, no clamping logic ----

pub fn oracle_point_segment(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = b - a;
    let l = d.length_squared();
    let mut best = (p - a).length().min((p - b).length());
    if l > 0.0 {
        let s = (p - a).dot(d) / l;
        if s > 0.0 && s < 1.0 {
            best = best.min((p - (a + d * s)).length());
        }
    }
    best
}

pub fn oracle_point_triangle(p: Vec3, t: &[Vec3; 3]) -> f64 {
    let mut best = oracle_point_segment(p, t[0], t[1])
        .min(oracle_point_segment(p, t[1], t[2]))
        .min(oracle_point_segment(p, t[2], t[0]));
    // Interior critical point: solve the Gram system for barycentric (u, v).
    let (e0, e1, w) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (a, b, c) = (e0.dot(e0), e0.dot(e1), e1.dot(e1));
    let det = a * c - b * b;
    if det > 1e-12 * a * c {
        let (r0, r1) = (w.dot(e0), w.dot(e1));
        let u = (c * r0 - b * r1) / det;
        let v = (a * r1 - b * r0) / det;
        if u >= 0.0 && v >= 0.0 && u + v <= 1.0 {
            best = best.min((p - (t[0] + e0 * u + e1 * v)).length());
        }
    }
    best
}

pub fn oracle_segment_segment(p0: Vec3, p1: Vec3, q0: Vec3, q1: Vec3) -> f64 {
    let mut best = oracle_point_segment(p0, q0, q1)
        .min(oracle_point_segment(p1, q0, q1))
        .min(oracle_point_segment(q0, p0, p1))
        .min(oracle_point_segment(q1, p0, p1));
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, b, e) = (d1.dot(d1), d1.dot(d2), d2.dot(d2));
    let det = a * e - b * b;
    if det > 1e-12 * a * e && det > 0.0 {
        let (c, f) = (d1.dot(r), d2.dot(r));
        let s = (b * f - c * e) / det;
        let t = (a * f - b * c) / det;
        if s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0 {
            best = best.min(((p0 + d1 * s) - (q0 + d2 * t)).length());
        }
    }
    best
}

/// Whether segment [p, q] meets triangle t, by solving p + s (q - p) = t0 + u e0 + v e1.
pub fn oracle_segment_hits_triangle(p: Vec3, q: Vec3, t: &[Vec3; 3]) -> bool {
    let m = Mat3::from_cols(q - p, t[0] - t[1], t[0] - t[2]);
    let det = m.determinant();
    let scale = (q - p).length() * (t[1] - t[0]).length() * (t[2] - t[0]).length();
    if det.abs() <= 1e-12 * scale {
        return false; // parallel or degenerate: covered by the edge and vertex distances
    }
    let x = m.inverse() * (t[0] - p);
    let (s, u, v) = (x.x, x.y, x.z);
    (0.0..=1.0).contains(&s) && u >= 0.0 && v >= 0.0 && u + v <= 1.0
}

/// The independent formulation: 0 if an edge of one meets the other, else the minimum of the
/// 6 vertex-triangle and 9 edge-edge distances.
pub fn oracle_triangle_distance(a: &[Vec3; 3], b: &[Vec3; 3]) -> f64 {
    for i in 0..3 {
        let j = (i + 1) % 3;
        if oracle_segment_hits_triangle(a[i], a[j], b)
            || oracle_segment_hits_triangle(b[i], b[j], a)
        {
            return 0.0;
        }
    }
    let mut best = f64::INFINITY;
    for i in 0..3 {
        best = best
            .min(oracle_point_triangle(a[i], b))
            .min(oracle_point_triangle(b[i], a));
        for j in 0..3 {
            best = best.min(oracle_segment_segment(
                a[i],
                a[(i + 1) % 3],
                b[j],
                b[(j + 1) % 3],
            ));
        }
    }
    best
}

pub fn assert_rel(a: f64, b: f64, rel: f64, abs: f64, what: &str) {
    assert!(
        (a - b).abs() <= rel * a.abs().max(b.abs()) + abs,
        "{what}: {a} vs {b} (diff {:e})",
        (a - b).abs()
    );
}

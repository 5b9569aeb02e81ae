//! URDF primitives as conservative triangle meshes: the tessellation contains the true shape.
//!
//! A box is exact (12 triangles). Spheres, cylinders and capsules are convex polyhedra whose
//! vertices are pushed out radially until every face plane lies outside the true shape: for a
//! face with unit outer normal `m` and offset `d` (`m . x = d` on the face), the shape's support
//! along `m` is `max over the axis segment of m . c + r`, and the polyhedron contains the shape
//! when `d` is at least that for every face. With the vertices at radius `s r` around the axis
//! segment, each face's margin `d - max m . c` grows linearly in `s` (all of a face's corners
//! sit at the same radius, around one end of the segment or across it), so one pass measures
//! the margins at `s = 1` and scales by `s = r / min margin`. The slack this costs is at most
//! `r (s - 1)`: with the default 32 segments around and 8 rings per half sphere, `s - 1` is
//! 0.49% for a cylinder (`1 / cos(pi / 32) - 1`) and 2.0% for spheres and capsules, measured by
//! [`primitive_slack`] and documented in ARCHITECTURE.md. The tests sample the true surfaces and
//! check every point inside.

use crate::math::Vec3;

/// Points around the axis, per ring.
pub const SEGMENTS: usize = 32;
/// Rings per half sphere (spheres and capsule caps).
pub const RINGS: usize = 8;

/// A triangle soup under construction.
pub(crate) type Soup = (Vec<Vec3>, Vec<[u32; 3]>);

/// A box centred at the origin with the given full sizes.
pub(crate) fn box_soup(size: Vec3) -> Soup {
    let h = size * 0.5;
    let v = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        })
        .collect();
    let t = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    (v, t)
}

/// A cylinder of radius `r` and length `length` along z, centred at the origin, containing the
/// true cylinder.
pub(crate) fn cylinder_soup(r: f64, length: f64) -> Soup {
    round_soup(r, length, false)
}

/// A capsule (a cylinder of length `length` with half spheres of radius `r` on its ends, the
/// URDF convention), containing the true capsule.
pub(crate) fn capsule_soup(r: f64, length: f64) -> Soup {
    round_soup(r, length, true)
}

/// A sphere of radius `r` at the origin, containing the true sphere.
pub(crate) fn sphere_soup(r: f64) -> Soup {
    round_soup(r, 0.0, true)
}

/// The relative slack `s - 1` of the conservative tessellation (module docs): how far, as a
/// fraction of the radius, the mesh may reach beyond the true shape.
pub fn primitive_slack(capped: bool) -> f64 {
    let (v, t) = unit_soup(1.0, 1.0, capped);
    scale_for(&v, &t, 1.0, capped) - 1.0
}

fn round_soup(r: f64, length: f64, capped: bool) -> Soup {
    let (mut v, t) = unit_soup(r, length, capped);
    let s = scale_for(&v, &t, length, capped);
    let half = 0.5 * length;
    for p in &mut v {
        // Push out from the nearest point of the axis segment (the centre a vertex was made
        // around).
        let c = Vec3::new(0.0, 0.0, p.z.clamp(-half, half));
        *p = c + (*p - c) * (s / r.max(f64::MIN_POSITIVE)) * r;
    }
    (v, t)
}

/// The tessellation with vertices at distance `r` from the segment `z in [-L/2, L/2]`.
fn unit_soup(r: f64, length: f64, capped: bool) -> Soup {
    let half = 0.5 * length;
    let mut v = Vec::new();
    let mut t = Vec::new();
    // Rings from bottom to top: (z of the ring's centre, ring radius factor, z offset factor).
    let mut rings: Vec<(f64, f64, f64)> = Vec::new();
    if capped {
        for i in 1..RINGS {
            let a = -std::f64::consts::FRAC_PI_2
                + std::f64::consts::FRAC_PI_2 * i as f64 / RINGS as f64;
            rings.push((-half, a.cos(), a.sin()));
        }
        rings.push((-half, 1.0, 0.0));
        if length > 0.0 {
            rings.push((half, 1.0, 0.0));
        }
        for i in 1..RINGS {
            let a = std::f64::consts::FRAC_PI_2 * i as f64 / RINGS as f64;
            rings.push((half, a.cos(), a.sin()));
        }
    } else {
        rings.push((-half, 1.0, 0.0));
        rings.push((half, 1.0, 0.0));
    }
    for &(zc, f, dz) in &rings {
        for k in 0..SEGMENTS {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / SEGMENTS as f64;
            v.push(Vec3::new(r * f * phi.cos(), r * f * phi.sin(), zc + r * dz));
        }
    }
    let ring = |i: usize, k: usize| (i * SEGMENTS + k % SEGMENTS) as u32;
    for i in 0..rings.len() - 1 {
        for k in 0..SEGMENTS {
            t.push([ring(i, k), ring(i, k + 1), ring(i + 1, k + 1)]);
            t.push([ring(i, k), ring(i + 1, k + 1), ring(i + 1, k)]);
        }
    }
    // Ends: a pole vertex (capped) or a centre vertex (flat), fanned to the end rings.
    let last = rings.len() - 1;
    let (bottom, top) = if capped {
        (
            Vec3::new(0.0, 0.0, -half - r),
            Vec3::new(0.0, 0.0, half + r),
        )
    } else {
        (Vec3::new(0.0, 0.0, -half), Vec3::new(0.0, 0.0, half))
    };
    let b = v.len() as u32;
    v.push(bottom);
    v.push(top);
    for k in 0..SEGMENTS {
        t.push([b, ring(0, k + 1), ring(0, k)]);
        t.push([b + 1, ring(last, k), ring(last, k + 1)]);
    }
    (v, t)
}

/// The radial scale that puts every face plane at least `r` beyond the axis segment
/// (module docs); faces whose plane contains the segment direction's end caps (flat ends) are
/// exact and skipped.
fn scale_for(v: &[Vec3], t: &[[u32; 3]], length: f64, _capped: bool) -> f64 {
    let half = 0.5 * length;
    // The radius the vertices were made at: the largest distance of a ring vertex from the axis.
    let r = v
        .iter()
        .fold(0.0_f64, |m, p| m.max((p.x * p.x + p.y * p.y).sqrt()));
    let mut worst = f64::INFINITY;
    for tri in t {
        let [a, b, c] = tri.map(|i| v[i as usize]);
        let Some(m) = (b - a).cross(c - a).try_normalize() else {
            continue;
        };
        let m = if m.dot(a + b + c) < 0.0 { -m } else { m };
        if m.x.abs() + m.y.abs() < 1e-12 {
            continue; // a flat end: exact
        }
        let d = m.dot(a);
        let support = m.z.abs() * half;
        worst = worst.min(d - support);
    }
    if worst.is_finite() && worst > 0.0 {
        r / worst
    } else {
        1.0
    }
}

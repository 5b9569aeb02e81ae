//! Procedural models for tests, benchmarks and the demo, generated in code (no files).
//!
//! The (2,3) torus-knot tube with `n_u x n_v` segments has `2 n_u n_v` triangles; the sizes used
//! by the continuous-collision literature are 175x8 (2,800), 344x16 (11,008) and 680x25 (34,000).

use super::TriMesh;
use crate::error::MeshError;
use crate::math::Vec3;
use std::f64::consts::TAU;

/// Refuses sizes whose triangle count (`2 a b`) would not fit the mesh's 32-bit indices, before
/// anything is allocated.
fn check_size(a: usize, b: usize) -> Result<(), MeshError> {
    match a.checked_mul(b).and_then(|n| n.checked_mul(2)) {
        Some(n) if n <= super::MAX_ELEMENTS => super::reserve(n / 2 + a + b + 2, n),
        n => Err(MeshError::TooLarge {
            what: "triangles",
            count: n.unwrap_or(usize::MAX),
        }),
    }
}

fn build(vertices: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<TriMesh, MeshError> {
    // Indices are in range by construction; sizes or coordinates from bad parameters (a NaN
    // radius, billions of segments) are reported by the ordinary validation.
    TriMesh::new(vertices, triangles)
}

/// Quads of a periodic (in u, and in v when `wrap_v`) grid of `n_u x n_v` vertices, split in two.
fn grid_triangles(n_u: usize, n_v: usize, wrap_v: bool) -> Vec<[u32; 3]> {
    let id = |i: usize, j: usize| ((i % n_u) * n_v + (j % n_v)) as u32;
    let v_quads = if wrap_v { n_v } else { n_v - 1 };
    let mut t = Vec::with_capacity(2 * n_u * v_quads);
    for i in 0..n_u {
        for j in 0..v_quads {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    t
}

/// A surface of revolution about the z axis, open at its ends and centred on the origin:
/// `n_around` columns by `n_along` rows of quads, each split in two (`2 n_around n_along`
/// triangles), its radius at angle `a` (radians from +x towards +y) and height `z` given by
/// `radius(a, z)`, for `z` from `-length / 2` to `length / 2`. A tube where the radius is
/// constant, a taper where it follows `z`, a helical thread where it depends on `z - pitch a /
/// 2 pi`: the bodies turning or screwing in close fits of the continuous-collision benchmarks.
/// `n_around` is raised to at least 3 and `n_along` to at least 1.
pub fn revolved(
    radius: impl Fn(f64, f64) -> f64,
    length: f64,
    n_around: usize,
    n_along: usize,
) -> Result<TriMesh, MeshError> {
    let (n_around, n_along) = (n_around.max(3), n_along.max(1));
    check_size(n_around, n_along + 1)?;
    let mut vertices = Vec::with_capacity(n_around * (n_along + 1));
    for i in 0..n_around {
        let a = TAU * i as f64 / n_around as f64;
        for j in 0..=n_along {
            let z = length * (j as f64 / n_along as f64 - 0.5);
            let r = radius(a, z);
            vertices.push(Vec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    build(vertices, grid_triangles(n_around, n_along + 1, false))
}

/// A (2,3) torus-knot tube: `n_u` segments along the knot, `n_v` around the tube
/// (`2 n_u n_v` triangles). Knot radius about 3, tube radius 0.4, centred at the origin.
/// `n_u` and `n_v` are raised to at least 3.
pub fn torus_knot(n_u: usize, n_v: usize) -> Result<TriMesh, MeshError> {
    let (n_u, n_v) = (n_u.max(3), n_v.max(3));
    check_size(n_u, n_v)?;
    let (p, q, tube) = (2.0, 3.0, 0.4);
    let curve = |phi: f64| {
        let r = (q * phi).cos() + 2.0;
        Vec3::new(r * (p * phi).cos(), r * (p * phi).sin(), -(q * phi).sin())
    };
    let mut vertices = Vec::with_capacity(n_u * n_v);
    for i in 0..n_u {
        let phi = TAU * i as f64 / n_u as f64;
        let h = 1e-4;
        let (c, cp, cm) = (curve(phi), curve(phi + h), curve(phi - h));
        let tangent = (cp - cm).normalize();
        let accel = cp - 2.0 * c + cm;
        let normal = (accel - tangent * accel.dot(tangent)).normalize();
        let binormal = tangent.cross(normal);
        for j in 0..n_v {
            let theta = TAU * j as f64 / n_v as f64;
            vertices.push(c + tube * (theta.cos() * normal + theta.sin() * binormal));
        }
    }
    build(vertices, grid_triangles(n_u, n_v, true))
}

/// A UV sphere of the given radius centred at the origin, with `n_lat` rings and `n_lon`
/// meridians (raised to at least 2 and 3).
pub fn sphere(radius: f64, n_lat: usize, n_lon: usize) -> Result<TriMesh, MeshError> {
    let (n_lat, n_lon) = (n_lat.max(2), n_lon.max(3));
    check_size(n_lat, n_lon)?;
    let mut vertices = vec![Vec3::new(0.0, 0.0, radius), Vec3::new(0.0, 0.0, -radius)];
    for i in 1..n_lat {
        let polar = std::f64::consts::PI * i as f64 / n_lat as f64;
        for j in 0..n_lon {
            let az = TAU * j as f64 / n_lon as f64;
            vertices.push(
                radius * Vec3::new(polar.sin() * az.cos(), polar.sin() * az.sin(), polar.cos()),
            );
        }
    }
    let ring = |i: usize, j: usize| (2 + (i - 1) * n_lon + j % n_lon) as u32;
    let mut triangles = Vec::new();
    for j in 0..n_lon {
        triangles.push([0, ring(1, j), ring(1, j + 1)]);
        triangles.push([1, ring(n_lat - 1, j + 1), ring(n_lat - 1, j)]);
        for i in 1..n_lat - 1 {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i + 1, j),
                ring(i + 1, j + 1),
                ring(i, j + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    build(vertices, triangles)
}

/// An axis-aligned box centred at the origin with the given half extents (12 triangles).
pub fn box_mesh(half_extents: Vec3) -> Result<TriMesh, MeshError> {
    let h = half_extents;
    let vertices = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        })
        .collect();
    let triangles = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6], // z- and z+
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3], // y- and y+
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5], // x- and x+
    ];
    build(vertices, triangles)
}

/// A thin square plate in the z = 0 plane, `size` wide, as an open `n x n` grid of quads
/// (`2 n^2` triangles, zero thickness): the case where sampling poses tunnels.
pub fn plate(size: f64, n: usize) -> Result<TriMesh, MeshError> {
    let n = n.max(1);
    check_size(n, n)?;
    let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f64 / n as f64 - 0.5, j as f64 / n as f64 - 0.5);
            vertices.push(Vec3::new(size * x, size * y, 0.0));
        }
    }
    let id = |i: usize, j: usize| (i * (n + 1) + j) as u32;
    let mut triangles = Vec::with_capacity(2 * n * n);
    for i in 0..n {
        for j in 0..n {
            triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    build(vertices, triangles)
}

/// A cylinder of radius `radius` and length `length` along z, centred at the origin, as a
/// conservative tessellation that contains the true cylinder (radial slack below 0.5%; see
/// [`crate::robot::primitives`]). Refuses a non-positive or non-finite size.
pub fn cylinder(radius: f64, length: f64) -> Result<TriMesh, MeshError> {
    check_round(radius, length)?;
    let (v, t) = crate::robot::primitives::cylinder_soup(radius, length);
    build(v, t)
}

/// A capsule (URDF convention: a cylinder of length `length` along z capped by half spheres of
/// radius `radius`), containing the true capsule (slack about 2% of the radius).
pub fn capsule(radius: f64, length: f64) -> Result<TriMesh, MeshError> {
    check_round(radius, length.max(f64::MIN_POSITIVE))?;
    let (v, t) = crate::robot::primitives::capsule_soup(radius, length.max(0.0));
    build(v, t)
}

fn check_round(radius: f64, length: f64) -> Result<(), MeshError> {
    for (name, value) in [("radius", radius), ("length", length)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(MeshError::BadSize { name, value });
        }
    }
    Ok(())
}

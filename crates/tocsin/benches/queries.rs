//! Criterion benches: BVH build, distance, collide and within_distance on the torus knots.
//! Seeded, named models; run with `make bench`.

#![allow(clippy::unwrap_used, clippy::panic)]

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::hint::black_box;
use tocsin::{collide, distance, mesh, within_distance, DistanceOptions, Pose, TriMesh, Vec3};

fn knot(name: &str) -> TriMesh {
    let (u, v) = match name {
        "knot2.8k" => (175, 8),
        "knot11k" => (344, 16),
        _ => (680, 25),
    };
    mesh::torus_knot(u, v).expect("knot")
}

/// Pose of the second copy, rotated, moved along `dir` until the distance is `target`.
fn pose_at_separation(m: &TriMesh, rot: Pose, dir: Vec3, target: f64) -> Pose {
    let (mut lo, mut hi) = (0.0, 4.0 * m.bounding_radius() + target);
    let pose = |s: f64| Pose {
        rotation: rot.rotation,
        translation: dir * s,
    };
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let d = distance(
            m,
            &Pose::IDENTITY,
            m,
            &pose(mid),
            &DistanceOptions::default(),
        )
        .expect("distance")
        .distance;
        if d < target {
            lo = mid
        } else {
            hi = mid
        }
    }
    pose(hi)
}

fn bench_build(c: &mut Criterion) {
    let mut g = c.benchmark_group("build");
    g.sample_size(10);
    for (name, u, v) in [("knot34k", 680, 25), ("knot1M", 2000, 250)] {
        let m = mesh::torus_knot(u, v).expect("knot");
        let (verts, tris) = (m.vertices().to_vec(), m.triangles().to_vec());
        g.bench_function(name, |b| {
            b.iter(|| TriMesh::new(verts.clone(), tris.clone()).expect("mesh"))
        });
    }
    g.finish();
}

fn bench_queries(c: &mut Criterion) {
    let rot = Pose::from_axis_angle(Vec3::new(0.2, 0.5, 1.0), 0.7, Vec3::ZERO);
    let dir = Vec3::new(1.0, 0.3, 0.1).normalize();
    for name in ["knot2.8k", "knot11k", "knot34k"] {
        let m = knot(name);
        let r = m.bounding_radius();
        let mut g = c.benchmark_group(format!("distance/{name}"));
        for frac in [0.01, 0.1, 1.0] {
            let p2 = pose_at_separation(&m, rot, dir, frac * r);
            g.bench_with_input(BenchmarkId::from_parameter(frac), &p2, |b, p2| {
                b.iter(|| {
                    distance(
                        &m,
                        &Pose::IDENTITY,
                        &m,
                        black_box(p2),
                        &DistanceOptions::default(),
                    )
                })
            });
        }
        g.finish();
        let mut g = c.benchmark_group(format!("collide/{name}"));
        for (label, frac) in [("apart-0.01", 0.01), ("overlap", -0.5)] {
            let p2 = if frac > 0.0 {
                pose_at_separation(&m, rot, dir, frac * r)
            } else {
                Pose {
                    rotation: rot.rotation,
                    translation: dir * 0.5,
                }
            };
            g.bench_function(label, |b| {
                b.iter(|| collide(&m, &Pose::IDENTITY, &m, black_box(&p2)))
            });
        }
        g.finish();
        let p2 = pose_at_separation(&m, rot, dir, 0.05 * r);
        c.bench_function(&format!("within_distance/{name}/0.1R"), |b| {
            b.iter(|| within_distance(&m, &Pose::IDENTITY, &m, black_box(&p2), 0.1 * r))
        });
    }
}

criterion_group!(benches, bench_build, bench_queries);
criterion_main!(benches);

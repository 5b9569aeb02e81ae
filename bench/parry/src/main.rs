//! tocsin's time of contact next to parry3d-f64's `cast_shapes_nonlinear` (interp motions with
//! centre 0, which is parry's `NonlinearRigidMotion` with local centre 0, `linvel = p1 - p0`,
//! `angvel = rotvec(R1 R0^T)`) and `cast_shapes` (translations), on the same seeded queries:
//! body 1 driven through body 2 (fixed at the identity) with a 30 to 90 degree rotation.
//! Usage: cargo run --release -- [queries per model (default 5)] [model names...]

use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::{
    cast_shapes, cast_shapes_nonlinear, NonlinearRigidMotion, ShapeCastOptions,
};
use parry3d_f64::shape::TriMesh as ParryMesh;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

// The same seeded directions as the contact-time bench, from the same helper.
#[path = "../../../crates/tocsin/benches/common/mod.rs"]
mod common;
use common::unit;
use tocsin::{mesh, time_of_contact, ContactOptions, Mat3, Motion, Pose as TPose, TriMesh, Vec3};

fn to_parry(m: &TriMesh) -> ParryMesh {
    let v = m
        .vertices()
        .iter()
        .map(|p| Vector::new(p.x, p.y, p.z))
        .collect();
    ParryMesh::new(v, m.triangles().to_vec()).expect("parry mesh")
}

fn parry_pose(p: &TPose) -> Pose {
    let q = glam_quat(&p.rotation);
    Pose::from_parts(
        Vector::new(p.translation.x, p.translation.y, p.translation.z),
        q,
    )
}

fn glam_quat(r: &Mat3) -> parry3d_f64::math::Rotation {
    let c = r.to_cols_array();
    let m = parry3d_f64::math::Matrix::from_cols_array(&c);
    parry3d_f64::math::Rotation::from_mat3(&m)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(5);
    let wanted: Vec<&str> = args.iter().skip(1).map(String::as_str).collect();
    let models = [
        ("knot2.8k", 175, 8),
        ("knot11k", 344, 16),
        ("knot34k", 680, 25),
    ];
    println!("| model | motion | queries | tocsin median (us) | parry median (us) | parry / tocsin | tocsin <= parry time |");
    println!("|---|---|---:|---:|---:|---:|---|");
    for (name, u, v) in models {
        if !wanted.is_empty() && !wanted.contains(&name) {
            continue;
        }
        let m = mesh::torus_knot(u, v).expect("knot");
        let pm = to_parry(&m);
        let r = m.bounding_radius();
        for (label, translate) in [
            ("interp / nonlinear", false),
            ("translation / linear", true),
        ] {
            let mut rng = ChaCha8Rng::seed_from_u64(11);
            let (mut ours, mut theirs, mut ok) = (Vec::new(), Vec::new(), 0);
            for _ in 0..n {
                let d = unit(&mut rng);
                let axis = unit(&mut rng);
                let angle = if translate {
                    0.0
                } else {
                    rng.random_range(30f64..90.0).to_radians()
                };
                let lateral = unit(&mut rng).cross(d).normalize() * rng.random_range(0.0..0.2) * r;
                let r0 = Mat3::from_axis_angle(axis.any_orthonormal_vector(), 0.4);
                let start = TPose {
                    rotation: r0,
                    translation: -2.5 * r * d + lateral,
                };
                let end = TPose {
                    rotation: Mat3::from_axis_angle(axis, angle) * r0,
                    translation: 2.5 * r * d - lateral,
                };
                let mo = if translate {
                    Motion::translation(start, end)
                } else {
                    Motion::interp(start, end, Vec3::ZERO)
                }
                .expect("motion");
                let still = Motion::stationary(TPose::IDENTITY);
                // tocsin's query is cheap: the median of 21 runs, so one cold run does not decide.
                let mut runs = Vec::with_capacity(21);
                let mut c = None;
                for _ in 0..21 {
                    let t0 = Instant::now();
                    c = time_of_contact(&m, &mo, &m, &still, &ContactOptions::default())
                        .expect("query");
                    runs.push(t0.elapsed().as_secs_f64() * 1e6);
                }
                runs.sort_by(f64::total_cmp);
                ours.push(runs[10]);
                let lin = end.translation - start.translation;
                let linvel = Vector::new(lin.x, lin.y, lin.z);
                let t0 = Instant::now();
                let hit = if translate {
                    let opts = ShapeCastOptions {
                        max_time_of_impact: 1.0,
                        ..ShapeCastOptions::default()
                    };
                    cast_shapes(
                        &parry_pose(&start),
                        linvel,
                        &pm,
                        &Pose::IDENTITY,
                        Vector::ZERO,
                        &pm,
                        opts,
                    )
                } else {
                    let w = mo.angular_velocity();
                    let m1 = NonlinearRigidMotion::new(
                        parry_pose(&start),
                        Vector::ZERO,
                        linvel,
                        Vector::new(w.x, w.y, w.z),
                    );
                    let m2 = NonlinearRigidMotion::constant_position(Pose::IDENTITY);
                    cast_shapes_nonlinear(&m1, &pm, &m2, &pm, 0.0, 1.0, true)
                };
                theirs.push(t0.elapsed().as_secs_f64() * 1e6);
                let parry_time = hit.ok().flatten().map(|h| h.time_of_impact);
                ok += usize::from(match (c, parry_time) {
                    (Some(c), Some(p)) => c.time <= p + 1e-9,
                    (None, None) => true,
                    _ => false,
                });
            }
            let med = |v: &mut Vec<f64>| {
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            };
            let (a, b) = (med(&mut ours), med(&mut theirs));
            println!(
                "| {name} | {label} | {n} | {a:.0} | {b:.0} | {:.0}x | {ok}/{n} |",
                b / a
            );
        }
    }
}

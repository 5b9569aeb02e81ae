//! The continuous-collision issue's pathological cases, timed once each (knot34k's median is
//! about 0.5 ms for scale): a ball turning 90 degrees in a concentric socket at 0.3% clearance,
//! a shaft turning 180 degrees in a bore at 0.4%, a knot of long slivers, knot34k on a far
//! 180-degree screw, UV spheres meeting pole to pole. Usage: `profile_pathological [name]`.
use std::time::Instant;
use tocsin::{mesh, time_of_contact, ContactOptions, Mat3, Motion, Pose, TriMesh, Vec3};

fn tube(r: f64, length: f64, n_around: usize, n_along: usize) -> Option<TriMesh> {
    let mut v = Vec::new();
    for i in 0..=n_along {
        let h = -length / 2.0 + length * i as f64 / n_along as f64;
        for j in 0..n_around {
            let a = std::f64::consts::TAU * j as f64 / n_around as f64;
            v.push(Vec3::new(r * a.cos(), r * a.sin(), h));
        }
    }
    let mut f = Vec::new();
    for i in 0..n_along {
        for j in 0..n_around {
            let p = (i * n_around + j) as u32;
            let q = (i * n_around + (j + 1) % n_around) as u32;
            let n = n_around as u32;
            f.push([p, q, q + n]);
            f.push([p, q + n, p + n]);
        }
    }
    TriMesh::new(v, f).ok()
}

fn rot(axis: Vec3, deg: f64) -> Pose {
    Pose::from_axis_angle(axis, deg.to_radians(), Vec3::ZERO)
}

fn run(name: &str, m1: &TriMesh, mo1: &Motion, m2: &TriMesh, mo2: &Motion) {
    // How many iterations: the smallest cap that still answers.
    let answers = |cap: usize| {
        let opts = ContactOptions {
            max_iterations: cap,
            ..ContactOptions::default()
        };
        time_of_contact(m1, mo1, m2, mo2, &opts).is_ok()
    };
    let mut cap = 1;
    while cap < 1 << 12 && !answers(cap) {
        cap *= 2;
    }
    println!("{name}: answers within {cap} iterations");
    let t = Instant::now();
    let r = time_of_contact(m1, mo1, m2, mo2, &ContactOptions::default());
    let ms = t.elapsed().as_secs_f64() * 1e3;
    match r {
        Ok(Some(c)) => println!(
            "{name}: {ms:.2} ms, contact at {:.6} after {} iterations",
            c.time, c.iterations
        ),
        Ok(None) => println!("{name}: {ms:.2} ms, no contact"),
        Err(e) => println!("{name}: {ms:.2} ms, {e}"),
    }
}

fn main() {
    let only = std::env::args().nth(1);
    let want = |n: &str| only.as_deref().is_none_or(|o| o == n);
    let still = Motion::stationary(Pose::IDENTITY);
    if want("ball") {
        if let (Ok(ball), Ok(socket)) = (mesh::sphere(1.0, 64, 128), mesh::sphere(1.003, 64, 128)) {
            if let Ok(mo) = Motion::screw(Pose::IDENTITY, rot(Vec3::new(0.3, 0.2, 1.0), 90.0)) {
                run("ball", &ball, &mo, &socket, &still);
            }
        }
    }
    if want("shaft") {
        if let (Some(shaft), Some(bore)) = (tube(1.0, 4.0, 256, 8), tube(1.004, 6.0, 256, 8)) {
            if let Ok(mo) = Motion::screw(Pose::IDENTITY, rot(Vec3::Z, 180.0)) {
                run("shaft", &shaft, &mo, &bore, &still);
            }
        }
    }
    if want("slivers") {
        if let Ok(k) = mesh::torus_knot(30, 600) {
            let e = rot(Vec3::new(1.0, 1.0, 0.0), 60.0);
            let start = Pose::from_translation(Vec3::new(-14.0, 1.0, 0.5));
            let end = Pose {
                rotation: e.rotation,
                translation: Vec3::new(14.0, -0.5, 0.0),
            };
            if let Ok(mo) = Motion::interp(start, end, Vec3::ZERO) {
                run("slivers", &k, &mo, &k, &still);
            }
        }
    }
    if want("far_screw") {
        if let Ok(k) = mesh::torus_knot(680, 25) {
            // A half turn about an axis 52 units away: the knot sweeps an arc of radius 40
            // past the other, at 12 units (about 1.5 R apart) half way.
            let centre = Vec3::new(0.0, 52.0, 0.0);
            let start = Pose::from_translation(centre + Vec3::new(-40.0, 0.0, 0.0));
            let turn = Mat3::from_axis_angle(Vec3::Z, std::f64::consts::PI);
            let end = Pose {
                rotation: turn,
                translation: centre + turn * (start.translation - centre),
            };
            if let Ok(mo) = Motion::screw(start, end) {
                run("far_screw", &k, &mo, &k, &still);
            }
        }
    }
    if want("poles") {
        if let Ok(s) = mesh::sphere(1.0, 32, 1024) {
            let fly = Motion::translation(
                Pose::from_translation(Vec3::new(0.0, 0.0, -3.0)),
                Pose::from_translation(Vec3::new(0.0, 0.0, 3.0)),
            );
            if let Ok(fly) = fly {
                run("poles", &s, &fly, &s, &still);
            }
        }
    }
}

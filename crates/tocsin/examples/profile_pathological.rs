//! The continuous-collision issue's pathological cases, timed once each or as the median of
//! `REPEATS` calls in a row (knot34k's median, the scale: 0.5 ms when it was filed, 0.14
//! now): a ball turning 90 degrees in a concentric socket at 0.3% clearance, a shaft turning 180
//! degrees in a bore at 0.4%, a knot of long slivers, knot34k on a far 180-degree screw, UV spheres
//! meeting pole to pole; and two found since: a tapered shaft turning in its bore, a threaded bolt
//! screwed in its nut. Usage: `[REPEATS=n] profile_pathological [name]`.
use std::time::Instant;
use tocsin::mesh::revolved;
use tocsin::{mesh, time_of_contact, ContactOptions, Mat3, Motion, Pose, TriMesh, Vec3};

fn tube(r: f64, length: f64, n_around: usize, n_along: usize) -> Option<TriMesh> {
    revolved(|_, _| r, length, n_around, n_along).ok()
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
    // `REPEATS` calls in a row (a user's loop), their median reported.
    let repeats: usize = std::env::var("REPEATS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(1)
        .max(1);
    let mut times = Vec::with_capacity(repeats);
    let mut r = None;
    for _ in 0..repeats {
        let t = Instant::now();
        r = Some(time_of_contact(
            m1,
            mo1,
            m2,
            mo2,
            &ContactOptions::default(),
        ));
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    let ms = times[times.len() / 2];
    let Some(r) = r else { return };
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
    if want("taper") {
        // A shaft tapering from radius 1 to 0.5 over its length 2, in a bore of the same taper
        // 0.004 wider, turning half a turn.
        let taper = |c: f64| move |_: f64, z: f64| 0.75 + c - 0.25 * z;
        if let (Ok(shaft), Ok(bore)) = (
            revolved(taper(0.0), 2.0, 256, 8),
            revolved(taper(0.004), 2.0, 256, 8),
        ) {
            if let Ok(mo) = Motion::screw(Pose::IDENTITY, rot(Vec3::Z, 180.0)) {
                run("taper", &shaft, &mo, &bore, &still);
            }
        }
    }
    if want("nut") {
        // A bolt with a sinusoidal thread (pitch 0.5, depth 0.1) in a nut 0.01 wider, screwed
        // 170 degrees along its thread (a half turn's sense would be rounding's choice).
        let pitch = 0.5;
        let thread = move |c: f64| {
            move |a: f64, z: f64| 1.0 + c + 0.1 * (std::f64::consts::TAU * z / pitch - a).sin()
        };
        if let (Ok(bolt), Ok(nut)) = (
            revolved(thread(0.0), 3.0, 256, 192),
            revolved(thread(0.01), 1.0, 256, 64),
        ) {
            let end = Pose {
                translation: Vec3::new(0.0, 0.0, pitch * 170.0 / 360.0),
                ..rot(Vec3::Z, 170.0)
            };
            if let Ok(mo) = Motion::screw(Pose::IDENTITY, end) {
                run("nut", &bolt, &mo, &nut, &still);
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

//! `collide` on a torus knot against a turned copy near touching, for profiling:
//! `FS=0.01,0.001,-0.01 profile_collide n_u n_v`. For each fraction `f` of `FS` (default
//! `0.01,0.001,-0.01`) and 50 directions, the copy comes in along the direction to its first
//! contact, is moved `f` times the radius back out (apart) or, for negative `f`, further in
//! (penetrating), and `collide` is called 20 times there. Prints how many calls found contact.
use tocsin::{collide, mesh, time_of_contact, ContactOptions, Mat3, Motion, Pose, Vec3};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n_u: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(175);
    let n_v: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(8);
    let fractions: Vec<f64> = std::env::var("FS")
        .unwrap_or_else(|_| "0.01,0.001,-0.01".into())
        .split(',')
        .filter_map(|x| x.parse().ok())
        .collect();
    let m = mesh::torus_knot(n_u, n_v).expect("knot");
    let r = m.bounding_radius();
    let still = Motion::stationary(Pose::IDENTITY);
    let mut hits = 0;
    for &f in &fractions {
        for k in 0..50 {
            let a = k as f64 * 2.399;
            let u = Vec3::new(
                a.cos() * (1.0 - (k as f64 / 50.0)),
                a.sin() * 0.8,
                (k as f64 / 50.0) - 0.5,
            )
            .normalize();
            let rot = Mat3::from_axis_angle(Vec3::new(0.3, 1.0, -0.2).normalize(), 0.7 * k as f64);
            let far = 4.0 * r + 1.0;
            let start = Pose::new(rot, u * far).expect("pose");
            let end = Pose::new(rot, Vec3::ZERO).expect("pose");
            let motion = Motion::translation(start, end).expect("motion");
            let contact = time_of_contact(&m, &still, &m, &motion, &ContactOptions::default())
                .expect("time of contact");
            let Some(c) = contact else { continue };
            let p2 = Pose::new(rot, u * (far * (1.0 - c.time) + f * r)).expect("pose");
            for _ in 0..20 {
                if std::hint::black_box(collide(&m, &Pose::IDENTITY, &m, &p2)) {
                    hits += 1;
                }
            }
        }
    }
    println!("{hits} calls found contact");
}

//! Distance on knot34k at random poses (8 per separation of 1%, 10% and 100% of the bounding
//! radius, as in `bench/compare_fcl.py`), for profiling: prints the mean of the per-pose best
//! times per separation. Usage: `profile_distance [repeats per pose] [only this separation]`.
use tocsin::{distance, mesh, DistanceOptions, Pose, Vec3};

fn main() {
    let Ok(m) = mesh::torus_knot(680, 25) else {
        return;
    };
    let repeats: u32 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(10);
    let mut seed = 2026u64;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut unit = || loop {
        let v = Vec3::new(next(), next(), next()) * 2.0 - Vec3::ONE;
        if (1e-3..=1.0).contains(&v.length_squared()) {
            break v.normalize();
        }
    };
    let opts = DistanceOptions::default();
    let dist = |p: &Pose| distance(&m, &Pose::IDENTITY, &m, p, &opts).map_or(0.0, |d| d.distance);
    let radius = m.bounding_radius();
    let only: Option<f64> = std::env::args().nth(2).and_then(|a| a.parse().ok());
    for frac in [0.01, 0.1, 1.0] {
        let mut total = 0.0;
        for _ in 0..8 {
            let (axis, angle, dir) = (unit(), 0.3 + 2.8 * unit().x.abs(), unit());
            let at = |s: f64| Pose::from_axis_angle(axis, angle, dir * s);
            // Offset along `dir` at which the distance is frac * radius (bisection).
            let (mut lo, mut hi) = (0.0, 7.0 * radius);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if dist(&at(mid)) < frac * radius {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let pose = at(hi);
            if only.is_some_and(|o| o != frac) {
                continue;
            }
            let mut best = f64::INFINITY;
            for _ in 0..5 {
                let t = std::time::Instant::now();
                for _ in 0..repeats {
                    std::hint::black_box(dist(&pose));
                }
                best = best.min(t.elapsed().as_secs_f64() / f64::from(repeats));
            }
            total += best;
        }
        println!("separation {frac} R: mean {:.1} us", total / 8.0 * 1e6);
    }
}

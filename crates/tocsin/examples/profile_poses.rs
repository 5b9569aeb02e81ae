//! Distance on knot34k at poses read from a file (lines: fraction, then 16 numbers of a
//! row-major 4x4 pose), printing each pose's best time. For profiling at the exact poses of
//! `bench/compare_fcl.py`, which writes them with `--poses-out FILE`.
//! Usage: `profile_poses FILE [repeats] [only this fraction]`.
use tocsin::{distance, mesh, DistanceOptions, Mat4, Pose};

fn main() {
    let Ok(m) = mesh::torus_knot(680, 25) else {
        return;
    };
    let args: Vec<String> = std::env::args().collect();
    let Some(text) = args
        .get(1)
        .and_then(|path| std::fs::read_to_string(path).ok())
    else {
        eprintln!("usage: profile_poses FILE [repeats] [only this fraction] (a readable FILE)");
        return;
    };
    let repeats: u32 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(20);
    let only: Option<f64> = args.get(3).and_then(|a| a.parse().ok());
    let opts = DistanceOptions::default();
    let mut per: std::collections::BTreeMap<String, Vec<f64>> = Default::default();
    for line in text.lines() {
        let v: Vec<f64> = line
            .split_whitespace()
            .filter_map(|s| s.parse().ok())
            .collect();
        if v.len() != 17 || only.is_some_and(|o| o != v[0]) {
            continue;
        }
        let Ok(pose) = Pose::from_matrix(&Mat4::from_cols_slice(&v[1..]).transpose(), 1e-6) else {
            continue;
        };
        let mut best = f64::INFINITY;
        for _ in 0..5 {
            let t = std::time::Instant::now();
            for _ in 0..repeats {
                std::hint::black_box(distance(&m, &Pose::IDENTITY, &m, &pose, &opts).ok());
            }
            best = best.min(t.elapsed().as_secs_f64() / f64::from(repeats));
        }
        per.entry(format!("{}", v[0])).or_default().push(best * 1e6);
        if std::env::var("WARM").is_ok() {
            let mut cache = tocsin::DistanceCache::default();
            let _ = tocsin::distance_with_cache(&m, &Pose::IDENTITY, &m, &pose, &opts, &mut cache);
            let mut bw = f64::INFINITY;
            for _ in 0..5 {
                let t = std::time::Instant::now();
                for _ in 0..repeats {
                    let mut c = cache;
                    std::hint::black_box(
                        tocsin::distance_with_cache(&m, &Pose::IDENTITY, &m, &pose, &opts, &mut c)
                            .ok(),
                    );
                }
                bw = bw.min(t.elapsed().as_secs_f64() / f64::from(repeats));
            }
            per.entry(format!("{}w", v[0])).or_default().push(bw * 1e6);
        }
    }
    for (frac, t) in per {
        let mut s = t.clone();
        s.sort_by(f64::total_cmp);
        let med = 0.5 * (s[s.len() / 2] + s[(s.len() - 1) / 2]);
        let shown: Vec<String> = t.iter().map(|x| format!("{x:.0}")).collect();
        println!("{frac} R: median {med:.1} us; per pose {}", shown.join(" "));
    }
}
